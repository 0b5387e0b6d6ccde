//! A harmonic trap (an optical or magnetic tweezers, a spring to a moving
//! support): F = k (p(t) − r(u)) with the trap centre moving at constant
//! velocity, p(t) = anchor + velocity (t − t0). Its stiffness −∂F/∂q is
//! k b_i(u) b_j(u) on each position axis, so the implicit step treats the
//! trap implicitly and stays stable at any k.
use crate::constraint::catalogue::{FieldInfo, FieldType::*};
use super::{finite_all, spread, ForceField, LoadInfo, LoadLaw, StiffnessSink};
use crate::error::Result;
use crate::handles::RodHandle;
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Harmonic trap of `stiffness` k (force/length) at r(u), centred at
/// `anchor` + `velocity` (t − `t0`) (length, length/time, time).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Trap {
    pub rod: RodHandle,
    pub u: f64,
    pub anchor: [f64; 3],
    #[serde(default)]
    pub velocity: [f64; 3],
    pub stiffness: f64,
    #[serde(default)]
    pub t0: f64,
}

impl Trap {
    /// Trap centre at time t (length unit).
    pub fn centre(&self, t: f64) -> Vector3<f64> {
        Vector3::from(self.anchor) + Vector3::from(self.velocity) * (t - self.t0)
    }
    /// The force the trap exerts on the rod now (force unit).
    pub fn force(&self, rod: &Rod, t: f64) -> Result<Vector3<f64>> {
        Ok((self.centre(t) - rod.position(self.u)?) * self.stiffness)
    }
}

impl ForceField for Trap {
    fn add_force(&self, rod: &Rod, time: f64, f: &mut [f64]) -> Result<()> {
        let (ctrl, b) = rod.basis_at(self.u)?;
        spread(f, rod.dofs(), &ctrl, &b[0], &self.force(rod, time)?.into());
        Ok(())
    }
    /// ½ k |p(t) − r(u)|².
    fn potential(&self, rod: &Rod, time: f64) -> Result<f64> {
        Ok(0.5 * self.stiffness * (self.centre(time) - rod.position(self.u)?).norm_squared())
    }
    fn add_stiffness(&self, rod: &Rod, _time: f64, k: &mut StiffnessSink<'_>) -> Result<()> {
        let (ctrl, b) = rod.basis_at(self.u)?;
        let d = rod.dofs();
        for i in 0..4 {
            for j in 0..4 {
                for a in 0..3 {
                    k(ctrl[i] * d + a, ctrl[j] * d + a, self.stiffness * b[0][i] * b[0][j]);
                }
            }
        }
        Ok(())
    }
}

impl LoadLaw for Trap {
    const INFO: LoadInfo = LoadInfo {
        name: "Trap",
        helper: "trap",
        doc: "Harmonic trap of `stiffness` (force/length) pulling r(u) towards anchor + velocity·(t − t0) \
              (length, length/time, time): an optical trap moving at constant speed, a spring to a moving support.",
        fields: &[
            FieldInfo::new("rod", Rod, "", "the rod it acts on"),
            FieldInfo::new("u", Abscissa, "u", "abscissa of the trapped point"),
            FieldInfo::new("anchor", Vec3, "length", "trap centre at t0"),
            FieldInfo::new("stiffness", Scalar, "force/length", "trap stiffness k (> 0)"),
            FieldInfo::new("velocity", Vec3, "length/time", "velocity of the trap centre").default("[0, 0, 0]"),
            FieldInfo::new("t0", Scalar, "time", "time at which the centre is at anchor").default("0.0"),
        ],
    };
    fn rod(&self) -> RodHandle {
        self.rod
    }
    fn rod_mut(&mut self) -> &mut RodHandle {
        &mut self.rod
    }
    fn abscissa_mut(&mut self) -> Option<&mut f64> {
        Some(&mut self.u)
    }
    fn validate(&self, rod: &Rod) -> Result<()> {
        rod.knots().locate(crate::error::finite("trap abscissa u", self.u)?)?;
        finite_all("trap anchor", &self.anchor)?;
        finite_all("trap velocity", &self.velocity)?;
        crate::error::finite("trap t0", self.t0)?;
        crate::error::positive("trap stiffness", self.stiffness).map(|_| ())
    }
}
