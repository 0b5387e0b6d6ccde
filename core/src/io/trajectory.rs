//! Trajectories for molecular viewers (SPEC §8): PDB (+CONECT), PSF, DCD. (To be written.)
