//! A torque about the tangent at u, on the roll coordinate: T b_k(u).
use crate::constraint::catalogue::{FieldInfo, FieldType::*};
use super::{ForceField, LoadInfo, LoadLaw};
use crate::error::{Error, Result};
use crate::handles::RodHandle;
use crate::rod::Rod;
use serde::{Deserialize, Serialize};

/// Torque (force × length) about the tangent at u, on the roll coordinate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointTorque {
    pub rod: RodHandle,
    pub u: f64,
    pub torque: f64,
}

impl ForceField for PointTorque {
    fn add_force(&self, rod: &Rod, _time: f64, f: &mut [f64]) -> Result<()> {
        let (ctrl, b) = rod.basis_at(self.u)?;
        for k in 0..4 {
            f[ctrl[k] * 4 + 3] += b[0][k] * self.torque;
        }
        Ok(())
    }
    fn potential(&self, rod: &Rod, time: f64) -> Result<f64> {
        super::linear_potential(self, rod, time)
    }
}

impl LoadLaw for PointTorque {
    const INFO: LoadInfo = LoadInfo {
        name: "PointTorque",
        helper: "point_torque",
        doc: "Torque (force × length) about the tangent at u, on the roll coordinate (rods with roll).",
        fields: &[
            FieldInfo::new("rod", Rod, "", "the rod it acts on"),
            FieldInfo::new("u", Abscissa, "u", "abscissa (spline parameter)"),
            FieldInfo::new("torque", Scalar, "force × length", "torque about the tangent"),
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
        rod.knots().locate(crate::error::finite("point torque abscissa u", self.u)?)?;
        if rod.dofs() == 3 {
            return Err(Error::input("point torque: the rod has no roll coordinate (3 coordinates per control point)"));
        }
        crate::error::finite("point torque", self.torque).map(|_| ())
    }
}
