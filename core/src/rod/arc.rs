//! Rest arc length along a rod (for the free length of IV.15).
use super::{samples, Rod};
use crate::error::Result;
use crate::quadrature::gauss_legendre;
use crate::spline::KnotKind;

impl Rod {
    /// Rest arc length from the start of the domain to abscissa `u`
    /// (length unit; 8-point Gauss–Legendre on the partial segment).
    pub fn rest_arc_length(&self, u: f64) -> Result<f64> {
        let seg = self.knots.locate(u)?;
        let c = &self.cache;
        let before: f64 = c.samples[..c.seg_start[seg]].iter().map(|s| s.w).sum();
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
