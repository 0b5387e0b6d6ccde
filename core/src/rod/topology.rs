//! Twist, writhe and link of a closed rod, and imposing a link on a ring.
//!
//! Călugăreanu–White–Fuller: Lk = Tw + Wr for a closed ribbon, with
//! Wr = (1/4π) ∬ (t₁ × t₂)·(r₁ − r₂)/|r₁ − r₂|³ ds₁ ds₂ (Gauss integral of
//! the centreline) and Tw = (1/2π) ∮ ω ds. In the Frenet model the material
//! frame is the Frenet frame turned by the periodic roll θ, so
//! Tw = (1/2π) ∮ τ ds (∮ θ' = 0 on a ring) and its link is the Frenet
//! ribbon's, an integer fixed while the ring has no inflection. An imposed
//! excess link ΔLk turns the material frame ΔLk more times around the ring
//! than its rest shape does: it enters the energy as the rest twist
//! ω⁰ − 2π ΔLk / L (uniform in rest arc length), and Tw includes it.
use super::Rod;
use crate::error::{Error, Result};
use crate::quadrature::gauss_legendre;
use crate::spline::KnotKind;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// Largest number of quadrature points of the writhe's double sum (its cost
/// is their square).
pub const MAX_WRITHE_POINTS: usize = 200_000;

impl Rod {
    fn require_ring(&self, what: &str) -> Result<()> {
        if self.knots.kind() != KnotKind::Periodic {
            return Err(Error::invalid(
                what,
                "an open rod",
                "a closed rod (periodic knots); an open rod closed by a self-link carries its twist in the roll coordinate θ",
            ));
        }
        Ok(())
    }

    /// The excess link ΔLk (turns) imposed on this ring (0 unless set).
    pub fn excess_link(&self) -> f64 {
        self.excess_link
    }

    /// Imposes an excess link of `turns` on a closed rod with roll
    /// coordinate: its material frame turns `turns` more times around the
    /// ring than in the rest shape (a DNA minicircle's ΔLk, a twisted
    /// elastic ring). Replaces any previous value. The twist stiffness GJ
    /// then acts on ω − (ω⁰ − 2π ΔLk / L).
    pub fn set_excess_link(&mut self, turns: f64) -> Result<()> {
        crate::error::finite("excess link", turns)?;
        self.require_ring("excess link")?;
        if self.dofs != 4 {
            return Err(Error::invalid("excess link", "a rod without roll coordinate", "a rod with roll (with_roll=True): twist needs θ"));
        }
        self.excess_link = turns;
        self.prepare()
    }

    /// The rest-twist shift of the imposed link (rad per length unit).
    pub(crate) fn link_twist_shift(&self, rest_length: f64) -> f64 {
        2.0 * PI * self.excess_link / rest_length
    }

    /// Quadrature points of the current centreline: (point, unit tangent,
    /// current arc-length weight, Frenet torsion if the curve bends there,
    /// unit binormal or zero).
    #[allow(clippy::type_complexity)]
    fn centreline_points(&self, per_segment: usize) -> Result<Vec<(Vector3<f64>, Vector3<f64>, f64, Option<f64>, Vector3<f64>)>> {
        let n = self.n_segments().saturating_mul(per_segment);
        if n > MAX_WRITHE_POINTS {
            return Err(Error::invalid("writhe quadrature points", n, format!("at most {MAX_WRITHE_POINTS} (the double sum costs their square)")));
        }
        let (gx, gw) = gauss_legendre(per_segment)?;
        let mut out = Vec::with_capacity(n);
        for seg in 0..self.n_segments() {
            let (u0, u1) = self.knots.segment_interval(seg);
            let ctrl = self.knots.segment_ctrl(seg);
            for (x, w) in gx.iter().zip(gw.iter()) {
                let u = 0.5 * (u0 + u1) + 0.5 * (u1 - u0) * x;
                let b = self.knots.basis(seg, u);
                let s = super::samples::local_state(&self.q, self.dofs, &ctrl, &b);
                let p = super::samples::point(&self.q, self.dofs, &ctrl, &b[0]);
                let speed = s.r1.norm();
                let c = s.cross();
                let c2 = c.norm_squared();
                // τ = (r'×r'')·r''' / |r'×r''|², defined where the curve bends.
                let tau = (c2 > 1e-24 * speed.powi(6)).then(|| c.dot(&s.r3) / c2);
                let binormal = if c2 > 0.0 { c / c2.sqrt() } else { Vector3::zeros() };
                out.push((Vector3::new(p[0], p[1], p[2]), s.r1 / speed, w * 0.5 * (u1 - u0) * speed, tau, binormal));
            }
        }
        Ok(out)
    }

    /// Writhe of a closed rod's centreline (turns): the Gauss double
    /// integral on 8 Gauss points per segment (the integrand is smooth,
    /// its diagonal limit finite, so the product rule converges fast).
    pub fn writhe(&self) -> Result<f64> {
        self.require_ring("writhe")?;
        let pts = self.centreline_points(8)?;
        let mut sum = 0.0;
        for (i, (p1, t1, w1, _, _)) in pts.iter().enumerate() {
            for (p2, t2, w2, _, _) in &pts[i + 1..] {
                let d = p1 - p2;
                let r = d.norm();
                sum += 2.0 * t1.cross(t2).dot(&d) / (r * r * r) * w1 * w2; // (i, j) and (j, i)
            }
        }
        Ok(sum / (4.0 * PI))
    }

    /// Twist of a closed rod (turns): (1/2π) ∮ τ ds with the exact Frenet
    /// torsion (not the regularised one of the energy), plus the imposed
    /// excess link. Errors where the ring has an inflection (τ undefined).
    pub fn twist(&self) -> Result<f64> {
        self.require_ring("twist")?;
        let undefined = || Error::singular("twist: the ring has an inflection (straight somewhere), so its Frenet torsion (and the Frenet model's twist) is undefined there");
        let mut sum = 0.0;
        let pts = self.centreline_points(8)?;
        for (k, (_, _, w, tau, _)) in pts.iter().enumerate() {
            // An inflection between two points flips the binormal.
            let (b0, b1) = (pts[k].4, pts[(k + 1) % pts.len()].4);
            if b0.dot(&b1) <= 0.0 {
                return Err(undefined());
            }
            sum += w * tau.ok_or_else(undefined)?;
        }
        Ok(sum / (2.0 * PI) + self.excess_link)
    }

    /// Link of a closed rod (turns): twist + writhe. In the Frenet model
    /// this is the imposed excess link plus an integer (the Frenet ribbon's
    /// link, 0 for a ring that is planar at rest) while no inflection occurs.
    pub fn link(&self) -> Result<f64> {
        Ok(self.twist()? + self.writhe()?)
    }
}
