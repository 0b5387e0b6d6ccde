//! Linear algebra kernels: the band LU of the KKT system (SPEC §5).
pub mod band;
pub mod csc;
pub mod sparse;
pub mod synthetic;

pub use band::{solve_refined, BandFactor, BandLdlt, BandLu, BandMatrix, LdltDecline};

/// A right-hand side must have `n` finite entries.
pub(crate) fn check_rhs(b: &[f64], n: usize) -> crate::error::Result<()> {
    use crate::error::Error;
    if b.len() != n {
        return Err(Error::input(format!("right-hand side has length {}, the matrix has {n} rows", b.len())));
    }
    if let Some(i) = b.iter().position(|v| !v.is_finite()) {
        return Err(Error::input(format!("right-hand side entry {i} is {}", b[i])));
    }
    Ok(())
}
