//! Sliding point (III.37–III.42): the rod passes through a fixed point p at
//! an abscissa u that is itself an unknown. Rows r(u) − p = 0 linearised in
//! both the coordinates and Δu (column r'(u)); the Δu unknown carries the
//! viscous friction c (tangential force −c v_s, v_s = |r'| u̇) and the
//! second-order terms of the Lagrangian −Λ·∂²g (III.40: −Λ·r''(u) on the
//! diagonal, −Λ_α b'_k(u) coupling Δu with the coordinates), with Λ from the
//! previous solve.
use super::{Row, SlidingBlocks};
use crate::error::Result;
use crate::rod::Rod;
use nalgebra::Vector3;

pub fn linearize(rod: &Rod, u: f64, point: &[f64; 3], rows: &mut [Row]) -> Result<()> {
    let (ctrl, b) = rod.basis_at(u)?;
    let (p, d1) = (rod.eval(u, 0)?, rod.eval(u, 1)?);
    for (a, row) in rows.iter_mut().enumerate().take(3) {
        for k in 0..4 {
            row.push(ctrl[k] * rod.dofs() + a, b[0][k]);
        }
        row.push_on(2, 0, d1[a]);
        row.rhs = point[a] - p[a];
    }
    Ok(())
}

pub fn blocks(rod: &Rod, u: f64, friction: f64, lambda: &[f64], friction_coeff: f64, out: &mut SlidingBlocks) -> Result<()> {
    let (ctrl, b) = rod.basis_at(u)?;
    let (d1, d2) = (rod.eval(u, 1)?, rod.eval(u, 2)?);
    let lam = Vector3::new(lambda[0], lambda[1], lambda[2]);
    let speed2 = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2];
    out.diag[0] = friction_coeff * friction * speed2 - lam.dot(&Vector3::new(d2[0], d2[1], d2[2]));
    for k in 0..4 {
        for a in 0..3 {
            out.coupling.push_on(0, ctrl[k] * rod.dofs() + a, -lam[a] * b[1][k]);
        }
    }
    Ok(())
}

/// Oriented sliding point (III.43–III.49): the sliding point's rows plus
/// two rows e_i · t(u) = 0 (e_i ⟂ `direction`) at the same moving u; the
/// Δu column of the tangent rows is e_i · P r''(u) / |r'(u)|.
pub fn linearize_oriented(rod: &Rod, u: f64, point: &[f64; 3], direction: &[f64; 3], rows: &mut [Row]) -> Result<()> {
    linearize(rod, u, point, &mut rows[..3])?;
    super::tangent::linearize(rod, u, direction, &mut rows[3..5])?;
    let (d1, d2) = (rod.eval(u, 1)?, rod.eval(u, 2)?);
    let r1 = Vector3::new(d1[0], d1[1], d1[2]);
    let r2 = Vector3::new(d2[0], d2[1], d2[2]);
    let t = r1.normalize();
    let (e1, e2) = super::perpendicular_pair(&super::unit(direction, "oriented slider direction")?);
    for (row, e) in rows[3..5].iter_mut().zip([e1, e2]) {
        let g = (e - t * e.dot(&t)) / r1.norm();
        row.push_on(2, 0, g.dot(&r2));
    }
    Ok(())
}

/// Closest points between rod a near `ua` and rod b near `ub`: alternating
/// one-dimensional Newton steps on |r_a(ua) − r_b(ub)|², each abscissa kept
/// in its domain (an end point is a valid closest point).
pub fn closest_points(a: &Rod, b: &Rod, mut ua: f64, mut ub: f64) -> Result<(f64, f64)> {
    let v3 = |d: [f64; 4]| Vector3::new(d[0], d[1], d[2]);
    let newton = |rod: &Rod, u: f64, target: Vector3<f64>| -> Result<f64> {
        let d = v3(rod.eval(u, 0)?) - target;
        let (r1, r2) = (v3(rod.eval(u, 1)?), v3(rod.eval(u, 2)?));
        let h = r1.dot(&r1) + d.dot(&r2);
        let (lo, hi) = rod.domain();
        Ok(if h > 0.0 { (u - d.dot(&r1) / h).clamp(lo, hi) } else { u })
    };
    for _ in 0..30 {
        let (oa, ob) = (ua, ub);
        ua = newton(a, ua, v3(b.eval(ub, 0)?))?;
        ub = newton(b, ub, v3(a.eval(ua, 0)?))?;
        if (ua - oa).abs() + (ub - ob).abs() < 1e-14 * (1.0 + ua.abs() + ub.abs()) {
            break;
        }
    }
    Ok((ua, ub))
}
