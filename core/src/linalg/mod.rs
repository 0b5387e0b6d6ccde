//! Linear algebra kernels: the band LU of the KKT system (SPEC §5).
pub mod band;
pub mod sparse;

pub use band::{solve_refined, BandFactor, BandLdlt, BandLu, BandMatrix, LdltDecline};

/// A right-hand side must have `n` finite entries.
pub(crate) fn check_rhs(b: &[f64], n: usize) -> crate::error::Result<()> {
    use crate::error::Error;
    if b.len() != n {
        return Err(Error::InvalidInput(format!("right-hand side has length {}, the matrix has {n} rows", b.len())));
    }
    if let Some(i) = b.iter().position(|v| !v.is_finite()) {
        return Err(Error::InvalidInput(format!("right-hand side entry {i} is {}", b[i])));
    }
    Ok(())
}

/// Helpers shared by the linear-algebra tests.
#[cfg(test)]
pub(crate) mod test_util {
    /// Small deterministic generator in [−1, 1) (no `rand` dependency).
    pub struct Lcg(pub u64);
    impl Lcg {
        pub fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        }
    }
}
