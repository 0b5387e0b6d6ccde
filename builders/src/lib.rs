//! Structure builders on top of strandkit-core (SPEC §9): each builder is a
//! pure function from parameters (with units) to an
//! [`strandkit_core::Assembly`], inserted into a world with
//! `World::insert`. The rope bridge, necklace, spring, cable, DNA and knit
//! builders are the open issues that follow the engine seams.
pub use strandkit_core::Assembly;
