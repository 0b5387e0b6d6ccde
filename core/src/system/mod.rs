//! The banded KKT system (SPEC §4–§5, thesis IV.A).
pub mod kkt;
pub mod layout;

pub use kkt::{Coefficients, KktSystem, LinearSolver};
pub use layout::Layout;
