//! Constraints of a rod point against fixed geometry (III.27–III.34):
//! distance to a point, plane, axis (two planes), and curvature r''(u0).
//! Rows are normalised so that Λ is the force along each row's unit normal.
use super::{perpendicular_pair, unit, Reaction, Row};
use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::Vector3;

/// Writes rows n_i · r(u) with right-hand sides `rhs[i]`.
fn point_rows(rod: &Rod, u: f64, normals: &[Vector3<f64>], rhs: &[f64], rows: &mut [Row]) -> Result<()> {
    let (ctrl, b) = rod.basis_at(u)?;
    for ((row, n), e) in rows.iter_mut().zip(normals).zip(rhs) {
        for k in 0..4 {
            for a in 0..3 {
                row.push(ctrl[k] * rod.dofs() + a, b[0][k] * n[a]);
            }
        }
        row.rhs = *e;
    }
    Ok(())
}

/// |r(u) − p| = d (III.28). Multiplier: force along (r − p)/|r − p|
/// (negative = the link pulls the rod towards p, i.e. tension).
pub fn distance(rod: &Rod, u: f64, point: &[f64; 3], d: f64, rows: &mut [Row]) -> Result<()> {
    let r = rod.position(u)?;
    let v = r - Vector3::from(*point);
    let len = v.norm();
    if len < 1e-12 * rod.rest_length() {
        return Err(Error::singular(format!("distance constraint at u = {u}: the point coincides with the anchor, direction undefined")));
    }
    point_rows(rod, u, &[v / len], &[d - len], rows)
}

pub fn distance_reaction(rod: &Rod, u: f64, point: &[f64; 3], lambda: &[f64]) -> Result<Reaction> {
    let v = rod.position(u)? - Vector3::from(*point);
    Ok(Reaction { force: (v.normalize() * lambda[0]).into(), torque: [0.0; 3] })
}

/// (r(u) − p0)·n = 0 (III.31). Multiplier: normal force.
pub fn plane(rod: &Rod, u: f64, origin: &[f64; 3], normal: &[f64; 3], rows: &mut [Row]) -> Result<()> {
    let n = unit(normal, "plane normal")?;
    let g = (rod.position(u)? - Vector3::from(*origin)).dot(&n);
    point_rows(rod, u, &[n], &[-g], rows)
}

/// r(u) on the line through p0 along `direction` (III.34: two planes).
pub fn axis(rod: &Rod, u: f64, origin: &[f64; 3], direction: &[f64; 3], rows: &mut [Row]) -> Result<()> {
    let (n1, n2) = perpendicular_pair(&unit(direction, "axis direction")?);
    let v = rod.position(u)? - Vector3::from(*origin);
    point_rows(rod, u, &[n1, n2], &[-v.dot(&n1), -v.dot(&n2)], rows)
}

pub fn axis_reaction(direction: &[f64; 3], lambda: &[f64]) -> Result<Reaction> {
    let (n1, n2) = perpendicular_pair(&unit(direction, "axis direction")?);
    Ok(Reaction { force: (n1 * lambda[0] + n2 * lambda[1]).into(), torque: [0.0; 3] })
}

/// r''(u) = target (III.27), three rows on the second parametric
/// derivative (length per u²). Multipliers are the generalised forces
/// conjugate to r'' (force × u²), reported as `force`.
pub fn curvature(rod: &Rod, u: f64, target: &[f64; 3], rows: &mut [Row]) -> Result<()> {
    let (ctrl, b) = rod.basis_at(u)?;
    let now = rod.eval(u, 2)?;
    for (a, row) in rows.iter_mut().enumerate().take(3) {
        for k in 0..4 {
            row.push(ctrl[k] * rod.dofs() + a, b[2][k]);
        }
        row.rhs = target[a] - now[a];
    }
    Ok(())
}
