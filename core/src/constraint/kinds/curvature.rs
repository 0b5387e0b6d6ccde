//! Curvature constraint (III.27): r''(u) = target, three rows on the second
//! parametric derivative (length per u²), linear in q. The multipliers are
//! the generalised forces conjugate to r'' (force × u²): they exert no net
//! force, and the moment r''(u) × Λ on rigid rotations.
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{finite3, ConstraintLaw, Reaction, Row, Side};
use crate::error::Result;
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// r''(u) = `target` (length per u², three rows). Reaction: the couple
/// r''(u) × Λ (force × length); the multipliers themselves are conjugate to r''.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Curvature {
    pub u: f64,
    pub target: [f64; 3],
}

impl ConstraintLaw for Curvature {
    const INFO: KindInfo = KindInfo {
        name: "Curvature",
        helper: "curvature",
        rods: 1,
        doc: "r''(u) = `target` (length per u², three rows). Reaction: the couple r''(u) × Λ.",
        fields: &[
            FieldInfo::new("u", Abscissa, "u", "abscissa (spline parameter)"),
            FieldInfo::new("target", Vec3, "length/u²", "second parametric derivative to impose"),
        ],
    };
    fn n_rows(&self) -> usize {
        3
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        f(0, self.u)
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.u)
    }
    fn validate(&self, _rods: &[&Rod]) -> Result<()> {
        finite3(&self.target, "curvature target")
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let rod = rods[0];
        let (ctrl, b) = rod.basis_at(self.u)?;
        let now = rod.eval(self.u, 2)?;
        for (a, row) in rows.iter_mut().enumerate().take(3) {
            for k in 0..4 {
                row.push(ctrl[k] * rod.dofs() + a, b[2][k]);
            }
            row.rhs = self.target[a] - now[a];
        }
        Ok(())
    }
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        let r2 = rods[0].eval(self.u, 2)?;
        let couple = Vector3::new(r2[0], r2[1], r2[2]).cross(&Vector3::new(lambda[0], lambda[1], lambda[2]));
        Ok(Reaction::torque(couple))
    }
}
