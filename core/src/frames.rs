//! Rotation-minimising frames along a rod (Sloan/Bloomenthal, II.37), rotated by the roll θ. (To be written.)
