//! Tangent-direction constraint (III.23, two-row form): g_i = e_i · r'/|r'|
//! for e1, e2 ⟂ the target direction. Rows are dimensionless (≈ angles), so
//! Λ1 e1 + Λ2 e2 = M × t and the clamp moment is M = t × (Λ1 e1 + Λ2 e2).
use super::{perpendicular_pair, unit, Reaction, Row};
use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::Vector3;

pub fn linearize(rod: &Rod, u: f64, direction: &[f64; 3], rows: &mut [Row]) -> Result<()> {
    let target = unit(direction, "tangent direction")?;
    let (e1, e2) = perpendicular_pair(&target);
    let (ctrl, b) = rod.basis_at(u)?;
    let d1 = rod.eval(u, 1)?;
    let r1 = Vector3::new(d1[0], d1[1], d1[2]);
    let speed = r1.norm();
    if speed == 0.0 {
        return Err(Error::singular(format!("tangent constraint at u = {u}: zero tangent")));
    }
    let t = r1 / speed;
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

pub fn reaction(rod: &Rod, u: f64, direction: &[f64; 3], lambda: &[f64]) -> Result<Reaction> {
    let target = unit(direction, "tangent direction")?;
    let (e1, e2) = perpendicular_pair(&target);
    let t = rod.tangent(u)?;
    let m = t.cross(&(e1 * lambda[0] + e2 * lambda[1]));
    Ok(Reaction { force: [0.0; 3], torque: m.into() })
}
