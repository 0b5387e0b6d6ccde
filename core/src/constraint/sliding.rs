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
