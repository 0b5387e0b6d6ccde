//! Absolute roll of the material frame at u (the roll part of a clamp): the
//! angle of director d1 about the tangent, measured from `reference`
//! projected ⟂ tangent, equals `angle`. The rod's frame model says what that
//! angle is (`FrameKinematics::material_angle`; in the Frenet model θ plus
//! the angle of the Frenet normal, so it needs a curved rod at u) and gives
//! its exact derivative, so the row is g = ψ(q) − angle wrapped to (−π, π].
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{unit, ConstraintLaw, Reaction, Row, Side};
use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Absolute roll of the cross-section at u: director d1 at `angle` (rad)
/// about the tangent from `reference`. A real clamp of the cross-section,
/// unlike a `Position` roll axis in the Frenet model. Multiplier: torque
/// about the tangent (force × length).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MaterialRoll {
    pub u: f64,
    pub reference: [f64; 3],
    pub angle: f64,
}

impl ConstraintLaw for MaterialRoll {
    const INFO: KindInfo = KindInfo {
        name: "MaterialRoll",
        helper: "material_roll",
        rods: 1,
        doc: "Absolute roll of the cross-section: director d1 at `angle` (rad) from `reference` about the tangent \
              (the Frenet model needs a curved rod at u). Multiplier: torque about the tangent (force × length).",
        fields: &[
            FieldInfo::new("u", Abscissa, "u", "abscissa (spline parameter)"),
            FieldInfo::new("reference", Direction, "", "direction the angle is measured from (projected ⟂ tangent)"),
            FieldInfo::new("angle", Scalar, "rad", "roll angle of director d1").default("0.0"),
        ],
    };
    fn n_rows(&self) -> usize {
        1
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        f(0, self.u)
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.u)
    }
    fn validate(&self, rods: &[&Rod]) -> Result<()> {
        if rods[0].dofs() == 3 {
            return Err(Error::input("material roll constraint: the rod has no roll coordinate (3 coordinates per control point)"));
        }
        unit(&self.reference, "material roll reference")?;
        crate::error::finite("material roll angle", self.angle).map(|_| ())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let rod = rods[0];
        let m = rod.material_angle(self.u, &unit(&self.reference, "material roll reference")?)?;
        let (ctrl, b) = rod.basis_at(self.u)?;
        let row = &mut rows[0];
        for k in 0..4 {
            for a in 0..3 {
                row.push(ctrl[k] * 4 + a, b[1][k] * m.d_r1[a] + b[2][k] * m.d_r2[a] + m.sample_b1[k] * m.d_r1_sample[a]);
            }
            row.push(ctrl[k] * 4 + 3, b[0][k] * m.d_th);
        }
        row.rhs = wrap(self.angle - m.angle);
        Ok(())
    }
    /// The resultant of Λ ∂ψ/∂q: the moment of the position part on rigid
    /// rotations (r' × ∂ψ/∂r' + r'' × ∂ψ/∂r''), ⟂ t, plus Λ about t (the
    /// roll coordinate's share).
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        let rod = rods[0];
        let m = rod.material_angle(self.u, &unit(&self.reference, "material roll reference")?)?;
        let s = rod.local_state(self.u)?;
        let t = s.r1.normalize();
        let (ctrl, _) = rod.basis_at(self.u)?;
        let q = rod.coords();
        let r1_sample: Vector3<f64> = (0..4).map(|k| Vector3::new(q[ctrl[k] * 4], q[ctrl[k] * 4 + 1], q[ctrl[k] * 4 + 2]) * m.sample_b1[k]).sum();
        let rigid = (s.r1.cross(&m.d_r1) + s.r2.cross(&m.d_r2) + r1_sample.cross(&m.d_r1_sample)) * lambda[0];
        Ok(Reaction::torque(rigid - t * t.dot(&rigid) + t * (m.d_th * lambda[0])))
    }
}

/// Angle wrapped to (−π, π].
pub fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(2.0 * PI);
    if w > PI {
        w - 2.0 * PI
    } else {
        w
    }
}
