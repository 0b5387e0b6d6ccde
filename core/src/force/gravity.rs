//! Gravity: the body force μ g per unit rest length, ∫ μ g b_k ds0 on each
//! control point (III.1–III.10); the weights ∫ μ b_k ds0 are precomputed per
//! segment with the mass matrix.
use super::ForceField;
use crate::error::Result;
use crate::rod::Rod;

/// Uniform gravity g (length/time²) acting on every rod.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gravity(pub [f64; 3]);

impl ForceField for Gravity {
    fn add_force(&self, rod: &Rod, _time: f64, f: &mut [f64]) -> Result<()> {
        if self.0 == [0.0; 3] {
            return Ok(());
        }
        let c = rod.cache();
        for (s, ctrl) in c.seg_ctrl.iter().enumerate() {
            super::spread(f, rod.dofs(), ctrl, &c.seg_mass_weight[s], &self.0);
        }
        Ok(())
    }
    fn potential(&self, rod: &Rod, time: f64) -> Result<f64> {
        super::linear_potential(self, rod, time)
    }
}
