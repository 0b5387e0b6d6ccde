//! Position (and roll-coordinate) constraint at u0 (III.20): q(u0) = target.
//! Linear in q: row = b_i(u0) on the constrained coordinate, so Λ is the
//! point force (or the torque about the tangent for θ).
use super::{Reaction, Row};
use crate::error::Result;
use crate::rod::Rod;

pub fn linearize(rod: &Rod, u: f64, axes: &[bool; 4], target: &[f64; 4], rows: &mut [Row]) -> Result<()> {
    let (ctrl, b) = rod.basis_at(u)?;
    let now = rod.eval(u, 0)?;
    let d = rod.dofs();
    let mut r = 0;
    for a in 0..4 {
        if !axes[a] {
            continue;
        }
        for k in 0..4 {
            rows[r].push(ctrl[k] * d + a, b[0][k]);
        }
        rows[r].rhs = target[a] - now[a];
        r += 1;
    }
    Ok(())
}

pub fn reaction(axes: &[bool; 4], lambda: &[f64]) -> Reaction {
    let mut out = Reaction::default();
    let mut r = 0;
    for a in 0..4 {
        if axes[a] {
            if a < 3 {
                out.force[a] = lambda[r];
            } else {
                out.torque[0] = lambda[r]; // about the tangent; see ConstraintKind::Position
            }
            r += 1;
        }
    }
    out
}
