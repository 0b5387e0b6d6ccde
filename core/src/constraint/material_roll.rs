//! Absolute roll of the material frame at u0 (the roll part of a clamp).
//! Frenet model: d1 is at angle θ + φ_n about t, φ_n the angle of the
//! Frenet normal n = b × t, i.e. φ_b − π/2 with φ_b = atan2(C·e2, C·e1),
//! C = r' × r''. g = θ(u0) + φ_b − π/2 − angle, wrapped to (−π, π].
//! The Jacobian treats (e1, e2) as fixed: exact when the tangent is also
//! clamped, otherwise it only slows Newton down (the residual is exact).
use super::{unit, Row};
use crate::error::{Error, Result};
use crate::rod::Rod;
use std::f64::consts::PI;

pub fn linearize(rod: &Rod, u: f64, reference: &[f64; 3], angle: f64, rows: &mut [Row]) -> Result<()> {
    let s = rod.local_state(u)?;
    let t = s.r1.normalize();
    let r = unit(reference, "material roll reference")?;
    let e1p = r - t * r.dot(&t);
    if e1p.norm() < 1e-6 {
        return Err(Error::input(format!("material roll at u = {u}: the reference is parallel to the tangent")));
    }
    let e1 = e1p.normalize();
    let e2 = t.cross(&e1);
    let c = s.cross();
    let (c1, c2) = (c.dot(&e1), c.dot(&e2));
    let cc = c1 * c1 + c2 * c2;
    // κ |r'|³ = |C|: require a curvature above the rod's threshold.
    let kappa = cc.sqrt() / s.r1.norm().powi(3);
    if !(kappa > 1e-9 / rod.rest_length()) {
        return Err(Error::singular(format!(
            "material roll at u = {u}: the rod is straight there, so the Frenet frame (and the absolute roll) is undefined"
        )));
    }
    let g_c = (e2 * c1 - e1 * c2) / cc;
    let (d_r1, d_r2) = (s.r2.cross(&g_c), g_c.cross(&s.r1));
    let (ctrl, b) = rod.basis_at(u)?;
    let row = &mut rows[0];
    for k in 0..4 {
        for a in 0..3 {
            row.push(ctrl[k] * 4 + a, b[1][k] * d_r1[a] + b[2][k] * d_r2[a]);
        }
        row.push(ctrl[k] * 4 + 3, b[0][k]);
    }
    let psi = s.th + c2.atan2(c1) - 0.5 * PI;
    row.rhs = wrap(angle - psi);
    Ok(())
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
