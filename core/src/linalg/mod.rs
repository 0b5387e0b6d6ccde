//! Linear algebra kernels: the band LU of the KKT system (SPEC §5).
pub mod band;
pub mod sparse;

pub use band::{solve_refined, BandLu, BandMatrix};
