//! Rest arc length along a rod (for the free length of IV.15), the rod's
//! point nearest a given point, and the local geometry and motion at a
//! point (what the bead passes read).
use super::{samples, Rod};
use crate::error::Result;
use nalgebra::Vector3;
use crate::quadrature::gauss_legendre;
use crate::spline::KnotKind;

/// The centreline and its motion at one abscissa u: r, r′, r″ (u
/// derivatives, length unit) and the velocity v and ∂v/∂u (length/time).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Jet {
    pub position: Vector3<f64>,
    pub d1: Vector3<f64>,
    pub d2: Vector3<f64>,
    pub velocity: Vector3<f64>,
    pub d_velocity: Vector3<f64>,
}

impl Rod {
    /// [`Jet`] at u (checked) from one basis evaluation: five queries for
    /// the price of one `eval`.
    pub fn jet(&self, u: f64) -> Result<Jet> {
        let (ctrl, b) = self.basis_at(u)?;
        let mut j = Jet::default();
        for (k, &i) in ctrl.iter().enumerate() {
            let (q, v) = (&self.q[i * self.dofs..i * self.dofs + 3], &self.v[i * self.dofs..i * self.dofs + 3]);
            let (q, v) = (Vector3::new(q[0], q[1], q[2]), Vector3::new(v[0], v[1], v[2]));
            j.position += q * b[0][k];
            j.d1 += q * b[1][k];
            j.d2 += q * b[2][k];
            j.velocity += v * b[0][k];
            j.d_velocity += v * b[1][k];
        }
        Ok(j)
    }

    /// r, r′ and the velocity (what the bead passes read) from a basis
    /// already evaluated ([`Rod::basis_at`]).
    #[inline]
    pub(crate) fn motion_from(&self, ctrl: &[usize; 4], b: &[[f64; 4]; 4]) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
        let (mut x, mut d1, mut v) = (Vector3::zeros(), Vector3::zeros(), Vector3::zeros());
        for (k, &i) in ctrl.iter().enumerate() {
            let (q, w) = (&self.q[i * self.dofs..i * self.dofs + 3], &self.v[i * self.dofs..i * self.dofs + 3]);
            let (q, w) = (Vector3::new(q[0], q[1], q[2]), Vector3::new(w[0], w[1], w[2]));
            x += q * b[0][k];
            d1 += q * b[1][k];
            v += w * b[0][k];
        }
        (x, d1, v)
    }

    /// The abscissa of the rod's point nearest `x`, and its distance
    /// (length unit): from the nearest sample, by Newton on
    /// (r(u) − x)·r'(u) = 0 (samples alone miss a point between two).
    pub fn closest_point(&self, x: &nalgebra::Vector3<f64>) -> Result<(f64, f64)> {
        let c = &self.cache;
        let mut u = self.domain().0;
        let mut best = f64::INFINITY;
        for s in &c.samples {
            let p = samples::point(&self.q, self.dofs, &c.seg_ctrl[s.seg], &s.basis[0]);
            let d = (nalgebra::Vector3::new(p[0], p[1], p[2]) - x).norm_squared();
            if d < best {
                (best, u) = (d, s.u);
            }
        }
        let (lo, hi) = self.domain();
        for _ in 0..20 {
            let (r, d1, d2) = (self.eval(u, 0)?, self.eval(u, 1)?, self.eval(u, 2)?);
            let v = nalgebra::Vector3::new(r[0], r[1], r[2]) - x;
            let (t, k) = (nalgebra::Vector3::new(d1[0], d1[1], d1[2]), nalgebra::Vector3::new(d2[0], d2[1], d2[2]));
            let h = t.dot(&t) + v.dot(&k);
            if !(h > 0.0) {
                break;
            }
            let du = v.dot(&t) / h;
            u = (u - du).clamp(lo, hi);
            if du.abs() < 1e-14 * (1.0 + u.abs()) {
                break;
            }
        }
        Ok((u, (self.position(u)? - x).norm()))
    }

    /// Rest arc length from the start of the domain to abscissa `u`
    /// (length unit; 8-point Gauss–Legendre on the partial segment).
    pub fn rest_arc_length(&self, u: f64) -> Result<f64> {
        // The end of a ring's domain is its start again for `locate`.
        if u == self.domain().1 {
            return Ok(self.rest_length());
        }
        let seg = self.knots.locate(u)?;
        let c = &self.cache;
        let before = c.seg_arc[seg];
        let (u0, _) = self.knots.segment_interval(seg);
        let (x, w) = gauss_legendre(8)?;
        let ctrl = c.seg_ctrl[seg];
        let half = 0.5 * (u - u0);
        let partial: f64 = x
            .iter()
            .zip(w)
            .map(|(x, w)| {
                let t = u0 + half * (1.0 + x);
                let b = self.knots.basis(seg, t);
                w * half * samples::local_state(&self.q_rest, self.dofs, &ctrl, &b).r1.norm()
            })
            .sum();
        Ok(before + partial)
    }

    /// The abscissa u at rest arc length `s` from the start of the domain
    /// (length unit, 0 ≤ s ≤ rest length): the inverse of
    /// [`Rod::rest_arc_length`], a material coordinate that deformation
    /// does not move (base pair i of a strand, a stitch along a yarn).
    /// Newton on ds/du = |r0'(u)|, safeguarded by bisection; accurate to
    /// 1e-12 of the rest length.
    pub fn u_at_rest_arc_length(&self, s: f64) -> Result<f64> {
        let total = self.rest_length();
        crate::error::finite("arc length s", s)?;
        if !(0.0..=total * (1.0 + 1e-12)).contains(&s) {
            return Err(crate::error::Error::invalid("arc length s", s, format!("in [0, {total}] (the rod's rest length)")));
        }
        let (mut lo, mut hi) = self.domain();
        let mut u = lo + (hi - lo) * (s / total).min(1.0);
        for _ in 0..100 {
            let f = self.rest_arc_length(u)? - s;
            if f.abs() <= 1e-12 * total {
                return Ok(u);
            }
            if f > 0.0 {
                hi = u;
            } else {
                lo = u;
            }
            let seg = self.knots.locate(u)?;
            let speed = samples::local_state(&self.q_rest, self.dofs, &self.cache.seg_ctrl[seg], &self.knots.basis(seg, u)).r1.norm();
            let newton = u - f / speed;
            u = if speed > 0.0 && newton > lo && newton < hi { newton } else { 0.5 * (lo + hi) };
        }
        Ok(u)
    }

    /// Longest rest arc between consecutive abscissae of `cuts` (and the
    /// ends of an open rod; cyclically on a ring). `cuts` is sorted in place.
    pub fn longest_free_arc(&self, cuts: &mut [f64]) -> Result<f64> {
        let periodic = self.knots.kind() == KnotKind::Periodic;
        let mut s: Vec<f64> = Vec::with_capacity(cuts.len() + 2);
        for u in cuts.iter() {
            let u = if periodic { self.knots.wrap(*u) } else { *u };
            s.push(self.rest_arc_length(u)?);
        }
        s.sort_by(f64::total_cmp);
        let total = self.rest_length();
        if s.is_empty() {
            return Ok(total);
        }
        let mut longest = s.windows(2).map(|p| p[1] - p[0]).fold(0.0, f64::max);
        longest = if periodic {
            longest.max(total - s[s.len() - 1] + s[0])
        } else {
            longest.max(s[0]).max(total - s[s.len() - 1])
        };
        Ok(longest)
    }
}
