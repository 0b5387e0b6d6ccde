//! Relative constraints between two rods, or two points of one rod
//! (III.55–III.66): relative position, relative orientation (+ roll),
//! relative distance. Entries on the first rod are tagged 0, on the second 1;
//! multipliers are the force / moment on the first rod (the second receives
//! the opposite).
use super::{finite3, perpendicular_pair, ConstraintKind, Reaction, Row};
use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::Vector3;

pub fn is_relative(k: &ConstraintKind) -> bool {
    abscissae(k).is_some()
}

pub fn abscissae(k: &ConstraintKind) -> Option<(f64, f64)> {
    match k {
        ConstraintKind::RelativePosition { ua, ub, .. }
        | ConstraintKind::RelativeOrientation { ua, ub, .. }
        | ConstraintKind::RelativeDistance { ua, ub, .. }
        | ConstraintKind::Contact { ua, ub, .. }
        | ConstraintKind::CoplanarClamp { ua, ub, .. } => Some((*ua, *ub)),
        _ => None,
    }
}

pub fn validate(k: &ConstraintKind, rods: &[&Rod]) -> Result<()> {
    let (ua, ub) = abscissae(k).ok_or_else(|| Error::input("not a relative constraint"))?;
    rods[0].knots().locate(crate::error::finite("constraint abscissa ua", ua)?)?;
    rods[1].knots().locate(crate::error::finite("constraint abscissa ub", ub)?)?;
    match k {
        ConstraintKind::RelativePosition { axes, offset, .. } => {
            if !axes.iter().any(|a| *a) {
                return Err(Error::input("relative position constraint selects no axis"));
            }
            if axes[3] && (rods[0].dofs() == 3 || rods[1].dofs() == 3) {
                return Err(Error::input("relative roll on a rod without roll coordinate"));
            }
            finite3(&[offset[0], offset[1], offset[2]], "relative position offset")?;
            crate::error::finite("relative roll offset", offset[3])?;
        }
        ConstraintKind::RelativeOrientation { roll, .. } => {
            if *roll && (rods[0].dofs() == 3 || rods[1].dofs() == 3) {
                return Err(Error::input("relative roll on a rod without roll coordinate"));
            }
        }
        ConstraintKind::CoplanarClamp { alpha, .. } => {
            crate::error::finite("coplanar clamp alpha", alpha[0])?;
            crate::error::finite("coplanar clamp alpha", alpha[1])?;
        }
        ConstraintKind::RelativeDistance { distance, .. } | ConstraintKind::Contact { distance, .. } => {
            crate::error::positive("relative distance (use RelativePosition for zero)", *distance)?;
        }
        _ => {}
    }
    Ok(())
}

/// Rows Σ_k b(ua) q_a − Σ_k b(ub) q_b along per-row 3-vectors `dirs`
/// (position part) with right-hand sides `rhs`.
fn point_rows(rods: &[&Rod], ua: f64, ub: f64, dirs: &[Vector3<f64>], rhs: &[f64], rows: &mut [Row]) -> Result<()> {
    let (ca, ba) = rods[0].basis_at(ua)?;
    let (cb, bb) = rods[1].basis_at(ub)?;
    for ((row, n), e) in rows.iter_mut().zip(dirs).zip(rhs) {
        for k in 0..4 {
            for a in 0..3 {
                row.push_on(0, ca[k] * rods[0].dofs() + a, ba[0][k] * n[a]);
                row.push_on(1, cb[k] * rods[1].dofs() + a, -bb[0][k] * n[a]);
            }
        }
        row.rhs = *e;
    }
    Ok(())
}

/// Unit tangent and 1/|r'| at u.
fn tangent(rod: &Rod, u: f64) -> Result<(Vector3<f64>, f64)> {
    let d = rod.eval(u, 1)?;
    let v = Vector3::new(d[0], d[1], d[2]);
    let n = v.norm();
    if n == 0.0 {
        return Err(Error::singular(format!("zero tangent at u = {u}")));
    }
    Ok((v / n, 1.0 / n))
}

/// The two directions across which the tangents are compared.
fn orientation_frame(ta: &Vector3<f64>, tb: &Vector3<f64>) -> Result<(Vector3<f64>, Vector3<f64>)> {
    let m = ta + tb;
    if m.norm() < 1e-6 {
        return Err(Error::singular("relative orientation: the tangents are opposite"));
    }
    Ok(perpendicular_pair(&m.normalize()))
}

pub fn linearize(k: &ConstraintKind, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
    match k {
        ConstraintKind::RelativePosition { ua, ub, axes, offset } => {
            let (pa, pb) = (rods[0].eval(*ua, 0)?, rods[1].eval(*ub, 0)?);
            let (ca, ba) = rods[0].basis_at(*ua)?;
            let (cb, bb) = rods[1].basis_at(*ub)?;
            let mut r = 0;
            for a in 0..4 {
                if !axes[a] {
                    continue;
                }
                for j in 0..4 {
                    rows[r].push_on(0, ca[j] * rods[0].dofs() + a, ba[0][j]);
                    rows[r].push_on(1, cb[j] * rods[1].dofs() + a, -bb[0][j]);
                }
                rows[r].rhs = offset[a] - (pa[a] - pb[a]);
                r += 1;
            }
            Ok(())
        }
        ConstraintKind::RelativeDistance { ua, ub, distance } | ConstraintKind::Contact { ua, ub, distance } => {
            let v = rods[0].position(*ua)? - rods[1].position(*ub)?;
            let len = v.norm();
            if len < 1e-12 * rods[0].rest_length() {
                return Err(Error::singular("relative distance: the two points coincide, direction undefined"));
            }
            point_rows(rods, *ua, *ub, &[v / len], &[distance - len], rows)
        }
        ConstraintKind::CoplanarClamp { ua, ub, alpha } => {
            // g = r_a(ua) − r_b(ub) − α0 r_a'(ua) − α1 r_b'(ub), linear in q (III.62–III.65).
            let (ca, ba) = rods[0].basis_at(*ua)?;
            let (cb, bb) = rods[1].basis_at(*ub)?;
            let (pa, pb) = (rods[0].eval(*ua, 0)?, rods[1].eval(*ub, 0)?);
            let (ta, tb) = (rods[0].eval(*ua, 1)?, rods[1].eval(*ub, 1)?);
            for (a, row) in rows.iter_mut().enumerate().take(3) {
                for j in 0..4 {
                    row.push_on(0, ca[j] * rods[0].dofs() + a, ba[0][j] - alpha[0] * ba[1][j]);
                    row.push_on(1, cb[j] * rods[1].dofs() + a, -bb[0][j] - alpha[1] * bb[1][j]);
                }
                row.rhs = -(pa[a] - pb[a] - alpha[0] * ta[a] - alpha[1] * tb[a]);
            }
            Ok(())
        }
        ConstraintKind::RelativeOrientation { ua, ub, roll } => {
            // g_i = e_i · (t_a × t_b), e_i ⟂ (t_a + t_b): ≈ the relative
            // rotation angle about e_i, so Λ is a moment.
            let (ta, ia) = tangent(rods[0], *ua)?;
            let (tb, ib) = tangent(rods[1], *ub)?;
            let (e1, e2) = orientation_frame(&ta, &tb)?;
            let (ca, ba) = rods[0].basis_at(*ua)?;
            let (cb, bb) = rods[1].basis_at(*ub)?;
            let pa = nalgebra::Matrix3::identity() - ta * ta.transpose();
            let pb = nalgebra::Matrix3::identity() - tb * tb.transpose();
            let c = ta.cross(&tb);
            for (row, e) in rows.iter_mut().zip([e1, e2]) {
                let ga = pa * tb.cross(&e) * ia;
                let gb = pb * e.cross(&ta) * ib;
                for j in 0..4 {
                    for a in 0..3 {
                        row.push_on(0, ca[j] * rods[0].dofs() + a, ba[1][j] * ga[a]);
                        row.push_on(1, cb[j] * rods[1].dofs() + a, bb[1][j] * gb[a]);
                    }
                }
                row.rhs = -e.dot(&c);
            }
            if *roll {
                let row = &mut rows[2];
                for j in 0..4 {
                    row.push_on(0, ca[j] * 4 + 3, ba[0][j]);
                    row.push_on(1, cb[j] * 4 + 3, -bb[0][j]);
                }
                row.rhs = -(rods[0].eval(*ua, 0)?[3] - rods[1].eval(*ub, 0)?[3]);
            }
            Ok(())
        }
        _ => Err(Error::input("not a relative constraint")),
    }
}

pub fn reaction(k: &ConstraintKind, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
    match k {
        ConstraintKind::RelativePosition { axes, .. } => Ok(super::position::reaction(axes, lambda)),
        ConstraintKind::CoplanarClamp { .. } => Ok(Reaction { force: [lambda[0], lambda[1], lambda[2]], torque: [0.0; 3] }),
        ConstraintKind::RelativeDistance { ua, ub, .. } | ConstraintKind::Contact { ua, ub, .. } => {
            let v = rods[0].position(*ua)? - rods[1].position(*ub)?;
            Ok(Reaction { force: (v.normalize() * lambda[0]).into(), torque: [0.0; 3] })
        }
        ConstraintKind::RelativeOrientation { ua, ub, roll } => {
            let (ta, _) = tangent(rods[0], *ua)?;
            let (tb, _) = tangent(rods[1], *ub)?;
            let (e1, e2) = orientation_frame(&ta, &tb)?;
            // g ≈ −φ for a rotation φ of rod a about e: the moment is −Λ e.
            let mut m = -(e1 * lambda[0] + e2 * lambda[1]);
            if *roll {
                m += ta * lambda[2];
            }
            Ok(Reaction { force: [0.0; 3], torque: m.into() })
        }
        _ => Err(Error::input("not a relative constraint")),
    }
}
