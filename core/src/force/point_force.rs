//! A force applied at r(u): generalised force f b_k(u) on the position
//! coordinates of the four control points of u (III.1).
use crate::constraint::catalogue::{FieldInfo, FieldType::*};
use super::{finite_all, spread, ForceField, LoadInfo, LoadLaw};
use crate::error::Result;
use crate::handles::RodHandle;
use crate::rod::Rod;
use serde::{Deserialize, Serialize};

/// Force (force unit) applied at r(u).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointForce {
    pub rod: RodHandle,
    pub u: f64,
    pub force: [f64; 3],
}

impl ForceField for PointForce {
    fn add_force(&self, rod: &Rod, _time: f64, f: &mut [f64]) -> Result<()> {
        let (ctrl, b) = rod.basis_at(self.u)?;
        spread(f, rod.dofs(), &ctrl, &b[0], &self.force);
        Ok(())
    }
    fn potential(&self, rod: &Rod, time: f64) -> Result<f64> {
        super::linear_potential(self, rod, time)
    }
}

impl LoadLaw for PointForce {
    const INFO: LoadInfo = LoadInfo {
        name: "PointForce",
        helper: "point_force",
        doc: "Force (force unit, 3 values) applied at r(u) of `rod`.",
        fields: &[
            FieldInfo::new("rod", Rod, "", "the rod it acts on"),
            FieldInfo::new("u", Abscissa, "u", "abscissa (spline parameter)"),
            FieldInfo::new("force", Vec3, "force", "the force"),
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
        rod.knots().locate(crate::error::finite("point force abscissa u", self.u)?)?;
        finite_all("point force", &self.force)
    }
}
