//! The banded KKT system (SPEC §4–§5, thesis IV.A): the ordering of the
//! unknowns, their layout in the band, assembly and the factorisation chain.
pub mod kkt;
pub mod layout;
pub mod matrix;
pub mod ordering;
pub mod workspace;

pub use kkt::{Coefficients, Factorisation, KktSystem, LinearSolver, Solved};
pub use layout::Layout;
pub use workspace::Workspace;
