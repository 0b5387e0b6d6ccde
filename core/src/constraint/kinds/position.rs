//! Position (and roll-coordinate) constraint at u (III.20): q(u) = target on
//! the selected axes. Linear in q: row = b_k(u) on the constrained
//! coordinate, so Λ is the point force (x, y, z) or the torque about the
//! tangent on the roll coordinate θ.
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{Anchoring, ConstraintLaw, Reaction, Row, Side};
use crate::error::{Error, Result};
use crate::rod::Rod;
use serde::{Deserialize, Serialize};

/// r(u) (and θ(u), the roll coordinate) equal to `target` on the axes
/// selected by `axes` = [x, y, z, θ]. Multipliers: force (x, y, z), torque
/// about the tangent (θ). In the Frenet model θ is measured from the Frenet
/// normal, so the roll axis alone does not hold the cross-section of a
/// curved rod (see [`super::MaterialRoll`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Position {
    pub u: f64,
    pub axes: [bool; 4],
    pub target: [f64; 4],
}

impl ConstraintLaw for Position {
    const INFO: KindInfo = KindInfo {
        name: "Position",
        helper: "position",
        rods: 1,
        doc: "Fix r(u) to `target` (length) on the selected `axes` (x, y, z; \"r\" for the roll coordinate θ, \
              relative to the Frenet frame: use material_roll for an absolute clamp of the cross-section). \
              Multipliers: force (x, y, z), torque about the tangent (roll).",
        fields: &[
            FieldInfo::new("u", Abscissa, "u", "abscissa (spline parameter)"),
            FieldInfo::new("target", Vec4, "length, rad", "target point (x, y, z) and roll").default("[0, 0, 0, 0]").roll_keyword("roll"),
            FieldInfo::new("axes", Axes, "", "constrained axes").default("[true, true, true, false]"),
        ],
    };
    fn n_rows(&self) -> usize {
        self.axes.iter().filter(|a| **a).count()
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        f(0, self.u)
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.u)
    }
    fn validate(&self, rods: &[&Rod]) -> Result<()> {
        if !self.axes.iter().any(|a| *a) {
            return Err(Error::invalid("position constraint axes", "none selected", "at least one of x, y, z, roll"));
        }
        if self.axes[3] && rods[0].dofs() == 3 {
            return Err(Error::invalid("position constraint axes", "roll", "x, y, z only (the rod has no roll coordinate)"));
        }
        for (a, t) in self.axes.iter().zip(&self.target) {
            if *a {
                crate::error::finite("position target", *t)?;
            }
        }
        Ok(())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let rod = rods[0];
        let (ctrl, b) = rod.basis_at(self.u)?;
        let now = rod.eval(self.u, 0)?;
        let d = rod.dofs();
        let mut r = 0;
        for a in 0..4 {
            if !self.axes[a] {
                continue;
            }
            for k in 0..4 {
                rows[r].push(ctrl[k] * d + a, b[0][k]);
            }
            rows[r].rhs = self.target[a] - now[a];
            r += 1;
        }
        Ok(())
    }
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        axes_reaction(rods[0], self.u, &self.axes, lambda)
    }
    fn anchoring(&self) -> Anchoring {
        if self.axes[..3].iter().all(|a| *a) {
            Anchoring::Point
        } else {
            Anchoring::None
        }
    }
    fn duplicates(&self, other: &Self) -> bool {
        (self.u - other.u).abs() <= 1e-12 * (1.0 + self.u.abs()) && self.axes.iter().zip(&other.axes).any(|(p, q)| *p && *q)
    }
}

/// Reaction of rows on the selected axes: force components, and the roll
/// row's torque about the tangent at u.
pub(crate) fn axes_reaction(rod: &Rod, u: f64, axes: &[bool; 4], lambda: &[f64]) -> Result<Reaction> {
    let mut out = Reaction::default();
    let mut r = 0;
    for a in 0..4 {
        if axes[a] {
            if a < 3 {
                out.force[a] = lambda[r];
            } else {
                let t = rod.tangent(u)?;
                out.torque = (t * lambda[r]).into();
            }
            r += 1;
        }
    }
    Ok(out)
}
