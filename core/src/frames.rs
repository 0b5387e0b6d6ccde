//! Rotation-minimising frames along a rod (SPEC §1.3), rotated by the roll θ.
//!
//! The thesis propagates a frame by projection (Sloan/Bloomenthal, II.37);
//! we use the double reflection method of Wang, Jüttler, Zheng & Liu
//! (*Computation of rotation minimizing frames*, ACM TOG 27(1), 2008), the
//! standard RMF: fourth-order accurate and free of the projection's
//! degeneracy when consecutive tangents are nearly opposite.
//!
//! The display frame is RMF rotated by θ(u): d1 = cos θ r + sin θ s,
//! d2 = t × d1. (The Frenet model's material frame is the Frenet frame
//! rotated by θ; it differs from this one by the integrated torsion, which
//! matters only for the orientation of non-circular sections on display.)
use crate::error::{Error, Result};
use crate::rod::Rod;
use crate::spline::KnotKind;
use nalgebra::Vector3;

/// An orthonormal frame at a point of the centreline: `tangent` (unit r'),
/// directors `d1`, `d2` with d1 × d2 = tangent; `point` in length unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    pub u: f64,
    pub point: Vector3<f64>,
    pub tangent: Vector3<f64>,
    pub d1: Vector3<f64>,
    pub d2: Vector3<f64>,
}

/// `n` ≥ 2 parameters evenly spread over the rod's domain, ends included.
pub fn uniform_params(rod: &Rod, n: usize) -> Result<Vec<f64>> {
    if n < 2 {
        return Err(Error::input(format!("need at least 2 frame parameters, got {n}")));
    }
    let (a, b) = rod.domain();
    Ok((0..n).map(|i| if i + 1 == n { b } else { a + (b - a) * i as f64 / (n - 1) as f64 }).collect())
}

/// A unit vector ⟂ t (the start of the propagation when no reference is given).
pub(crate) fn perpendicular(t: &Vector3<f64>) -> Vector3<f64> {
    let helper = if t.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
    (helper - t * t.dot(&helper)).normalize()
}

/// Rotation-minimising frames at the increasing parameters `us`, rotated by
/// θ(u) on rods with roll. `reference` (projected ⟂ the first tangent) fixes
/// the first frame's d1 before the roll; None picks a perpendicular. On a
/// closed (periodic) rod sampled from domain start to end, the holonomy
/// (the RMF's angular mismatch after one loop) is spread linearly so that
/// the frames close up.
pub fn rotation_minimising(rod: &Rod, us: &[f64], reference: Option<[f64; 3]>) -> Result<Vec<Frame>> {
    if us.is_empty() {
        return Ok(Vec::new());
    }
    if let Some(i) = us.windows(2).position(|w| w[1].partial_cmp(&w[0]).is_none_or(|o| o.is_lt())) {
        return Err(Error::input(format!(
            "frame parameters must be increasing, got u = {} then {}",
            us[i],
            us[i + 1]
        )));
    }
    let mut pts = Vec::with_capacity(us.len());
    let mut tan = Vec::with_capacity(us.len());
    let mut roll = Vec::with_capacity(us.len());
    for &u in us {
        let q = rod.eval(u, 0)?;
        pts.push(Vector3::new(q[0], q[1], q[2]));
        tan.push(rod.tangent(u)?);
        roll.push(if rod.dofs() == 4 { q[3] } else { 0.0 });
    }
    let r0 = match reference {
        Some(v) => {
            let v = Vector3::from(v);
            let p = v - tan[0] * tan[0].dot(&v);
            let n = p.norm();
            if !n.is_finite() || n <= 1e-12 * v.norm() {
                return Err(Error::input(format!(
                    "frame reference {v:?} must be finite and not parallel to the tangent {:?}",
                    tan[0]
                )));
            }
            p / n
        }
        None => perpendicular(&tan[0]),
    };
    // Double reflection (Wang et al. 2008, algorithm 1).
    let mut refs = Vec::with_capacity(us.len());
    refs.push(r0);
    for i in 0..us.len() - 1 {
        let r = refs[i];
        let v1 = pts[i + 1] - pts[i];
        let c1 = v1.dot(&v1);
        // Coincident points: the first reflection is the identity.
        let (r_l, t_l) = if c1 > 0.0 {
            (r - v1 * (2.0 / c1 * v1.dot(&r)), tan[i] - v1 * (2.0 / c1 * v1.dot(&tan[i])))
        } else {
            (r, tan[i])
        };
        let v2 = tan[i + 1] - t_l;
        let c2 = v2.dot(&v2);
        let mut next = if c2 > 0.0 { r_l - v2 * (2.0 / c2 * v2.dot(&r_l)) } else { r_l };
        // Re-orthonormalise against round-off drift over many steps.
        next -= tan[i + 1] * tan[i + 1].dot(&next);
        let n = next.norm();
        next = if n > 1e-300 { next / n } else { perpendicular(&tan[i + 1]) };
        refs.push(next);
    }
    // Closed rods: spread the holonomy angle so the last frame equals the first.
    let (ua, ub) = rod.domain();
    let closes = rod.knots().kind() == KnotKind::Periodic
        && us.len() > 2
        && (us[0] - ua).abs() <= 1e-12 * (ub - ua)
        && (us[us.len() - 1] - ub).abs() <= 1e-12 * (ub - ua);
    let mut correction = vec![0.0; us.len()];
    if closes {
        let (t, first, last) = (tan[0], refs[0], refs[us.len() - 1]);
        let mismatch = t.dot(&last.cross(&first)).atan2(last.dot(&first));
        for (c, &u) in correction.iter_mut().zip(us) {
            *c = mismatch * (u - ua) / (ub - ua);
        }
    }
    Ok((0..us.len())
        .map(|i| {
            let (t, r) = (tan[i], refs[i]);
            let s = t.cross(&r);
            let a = roll[i] + correction[i];
            let d1 = r * a.cos() + s * a.sin();
            Frame { u: us[i], point: pts[i], tangent: t, d1, d2: t.cross(&d1) }
        })
        .collect())
}

/// Frames at the rod's sample (Gauss) points, the beads of trajectories.
pub fn sample_frames(rod: &Rod, reference: Option<[f64; 3]>) -> Result<Vec<Frame>> {
    rotation_minimising(rod, &rod.sample_params(), reference)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;
    use crate::rod::RodBuilder;
    use crate::section::Section;
    use crate::spline::KnotKind;

    fn builder(b: RodBuilder) -> Rod {
        b.control_points(24)
            .section(Section::circle(0.01).unwrap())
            .material(Material::preset("nylon").unwrap())
            .build()
            .unwrap()
    }

    fn orthonormal(f: &Frame) {
        for (a, b) in [(f.tangent, f.d1), (f.tangent, f.d2), (f.d1, f.d2)] {
            assert!(a.dot(&b).abs() < 1e-12);
        }
        for v in [f.tangent, f.d1, f.d2] {
            assert!((v.norm() - 1.0).abs() < 1e-12);
        }
        assert!((f.d1.cross(&f.d2) - f.tangent).norm() < 1e-12);
    }

    /// A straight rod: the RMF does not turn at all.
    #[test]
    fn straight_rod_frames_are_constant() {
        let rod = builder(RodBuilder::straight(Vector3::zeros(), Vector3::new(1.0, 2.0, 0.5)));
        let f = rotation_minimising(&rod, &uniform_params(&rod, 50).unwrap(), Some([0.0, 0.0, 1.0])).unwrap();
        for g in &f {
            orthonormal(g);
            assert!((g.d1 - f[0].d1).norm() < 1e-12);
        }
        assert!(f[0].d1.dot(&f[0].tangent).abs() < 1e-12 && f[0].d1.z > 0.9);
    }

    /// A planar curve: the RMF keeps the plane normal as a director (no twist
    /// about the tangent), unlike a frame that would wind.
    #[test]
    fn planar_curve_keeps_binormal() {
        let rod = builder(RodBuilder::curve(3.0, |s| Vector3::new(s.cos(), s.sin(), 0.0)));
        let f = rotation_minimising(&rod, &uniform_params(&rod, 200).unwrap(), Some([0.0, 0.0, 1.0])).unwrap();
        for g in &f {
            orthonormal(g);
            assert!((g.d1 - Vector3::z()).norm() < 1e-9, "{:?}", g.d1);
        }
    }

    /// Helix: the RMF rotates relative to the Frenet frame by −∫τ ds
    /// (Bishop 1975). τ = c/(a² + c²), arc length s = φ √(a² + c²).
    #[test]
    fn helix_rmf_angle_matches_integrated_torsion() {
        let (a, pitch, turns) = (1.0, 0.8, 1.0);
        let rod = builder(RodBuilder::helix(a, pitch, turns));
        let us = uniform_params(&rod, 400).unwrap();
        let f = rotation_minimising(&rod, &us, None).unwrap();
        let c = pitch / (2.0 * std::f64::consts::PI);
        let frenet_n = |p: &Vector3<f64>| Vector3::new(-p.x, -p.y, 0.0).normalize();
        let angle = |g: &Frame| {
            let n = frenet_n(&g.point);
            let b = g.tangent.cross(&n);
            g.d1.dot(&b).atan2(g.d1.dot(&n))
        };
        let (a0, a1) = (angle(&f[0]), angle(&f[f.len() - 1]));
        let mut turned = a1 - a0;
        turned -= 2.0 * std::f64::consts::PI * (turned / (2.0 * std::f64::consts::PI)).round();
        let tau_len = c / (a * a + c * c) * 2.0 * std::f64::consts::PI * turns * (a * a + c * c).sqrt();
        let mut expected = -tau_len;
        expected -= 2.0 * std::f64::consts::PI * (expected / (2.0 * std::f64::consts::PI)).round();
        // The spline helix is an approximation (24 control points): 1e-3 rad.
        assert!((turned - expected).abs() < 1e-3, "turned {turned}, expected {expected}");
    }

    /// θ rotates the directors about the tangent.
    #[test]
    fn roll_rotates_directors() {
        let theta = 0.7;
        let rod = builder(
            RodBuilder::straight(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0)).roll(vec![theta; 24]),
        );
        let f = rotation_minimising(&rod, &[rod.domain().0], Some([0.0, 1.0, 0.0])).unwrap();
        assert!((f[0].d1 - Vector3::new(0.0, theta.cos(), theta.sin())).norm() < 1e-12);
    }

    /// A closed ring out of its plane: frames close up after one loop.
    #[test]
    fn periodic_frames_close() {
        let rod = Section::circle(0.01)
            .and_then(|s| {
                RodBuilder::curve(2.0 * std::f64::consts::PI, |s| {
                    Vector3::new(s.cos(), s.sin(), 0.3 * (2.0 * s).sin())
                })
                .control_points(30)
                .knots(KnotKind::Periodic)
                .section(s)
                .material(Material::preset("nylon")?)
                .build()
            })
            .unwrap();
        let f = rotation_minimising(&rod, &uniform_params(&rod, 121).unwrap(), None).unwrap();
        assert!((f[0].d1 - f[120].d1).norm() < 1e-9);
        f.iter().for_each(orthonormal);
    }

    #[test]
    fn bad_parameters_are_errors() {
        let rod = builder(RodBuilder::straight(Vector3::zeros(), Vector3::x()));
        let (_, b) = rod.domain();
        assert!(matches!(rotation_minimising(&rod, &[b + 1.0], None), Err(Error::InvalidInput { .. })));
        assert!(matches!(rotation_minimising(&rod, &[1.0, 0.5], None), Err(Error::InvalidInput { .. })));
        assert!(matches!(rotation_minimising(&rod, &[0.0], Some([1.0, 0.0, 0.0])), Err(Error::InvalidInput { .. })));
        assert!(matches!(uniform_params(&rod, 1), Err(Error::InvalidInput { .. })));
    }
}
