//! Tangent-direction constraint (III.23, two-row form): g_i = e_i · r'/|r'|
//! for e1, e2 ⟂ the target direction. Rows are dimensionless (≈ angles), so
//! Λ1 e1 + Λ2 e2 = M × t and the clamp moment is M = t × (Λ1 e1 + Λ2 e2).
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{perpendicular_pair, tangent_of, unit, Anchoring, ConstraintLaw, Reaction, Row, Side};
use crate::error::Result;
use crate::rod::Rod;
use serde::{Deserialize, Serialize};

/// r'(u) parallel to `direction` (two rows ⟂ direction). Multiplier: the
/// moment vector ⟂ tangent (force × length).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tangent {
    pub u: f64,
    pub direction: [f64; 3],
}

impl ConstraintLaw for Tangent {
    const INFO: KindInfo = KindInfo {
        name: "Tangent",
        helper: "tangent",
        rods: 1,
        doc: "Tangent r'(u) parallel to `direction` (two rows). Multiplier: the moment (force × length) ⟂ the tangent.",
        fields: &[
            FieldInfo::new("u", Abscissa, "u", "abscissa (spline parameter)"),
            FieldInfo::new("direction", Direction, "", "target tangent direction"),
        ],
    };
    fn n_rows(&self) -> usize {
        2
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        f(0, self.u)
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.u)
    }
    fn validate(&self, _rods: &[&Rod]) -> Result<()> {
        unit(&self.direction, "tangent direction").map(|_| ())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        tangent_rows(rods[0], self.u, &self.direction, rows)
    }
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        tangent_reaction(rods[0], self.u, &self.direction, lambda)
    }
    fn anchoring(&self) -> Anchoring {
        Anchoring::Orientation
    }
}

/// The two rows e_i · t(u) = 0 (shared with the oriented slider).
pub(crate) fn tangent_rows(rod: &Rod, u: f64, direction: &[f64; 3], rows: &mut [Row]) -> Result<()> {
    let target = unit(direction, "tangent direction")?;
    let (e1, e2) = perpendicular_pair(&target);
    let (ctrl, b) = rod.basis_at(u)?;
    let (t, speed) = tangent_of(rod, u)?;
    for (row, e) in rows.iter_mut().zip([e1, e2]) {
        // ∂(e·t)/∂r' = (e − (e·t) t) / |r'|
        let g = (e - t * e.dot(&t)) / speed;
        for k in 0..4 {
            for a in 0..3 {
                row.push(ctrl[k] * rod.dofs() + a, b[1][k] * g[a]);
            }
        }
        row.rhs = -e.dot(&t);
    }
    Ok(())
}

pub(crate) fn tangent_reaction(rod: &Rod, u: f64, direction: &[f64; 3], lambda: &[f64]) -> Result<Reaction> {
    let target = unit(direction, "tangent direction")?;
    let (e1, e2) = perpendicular_pair(&target);
    let t = rod.tangent(u)?;
    Ok(Reaction::torque(t.cross(&(e1 * lambda[0] + e2 * lambda[1]))))
}
