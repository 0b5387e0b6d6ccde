//! Linear algebra kernels: the band LU of the KKT system (SPEC §5).
pub mod band;
pub mod sparse;

pub use band::{solve_refined, BandLu, BandMatrix};

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
