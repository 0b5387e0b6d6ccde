//! Twist, writhe and link of a closed rod, and imposing a link on a ring.
//!
//! Călugăreanu–White–Fuller: Lk = Tw + Wr for a closed ribbon, with
//! Wr = (1/4π) ∬ (t₁ × t₂)·(r₁ − r₂)/|r₁ − r₂|³ ds₁ ds₂ (Gauss integral of
//! the centreline) and Tw = (1/2π) ∮ ω ds. In the Frenet model the material
//! frame is the Frenet frame turned by the periodic roll θ, so
//! Tw = (1/2π) ∮ τ ds (∮ θ' = 0 on a ring) and its link is the Frenet
//! ribbon's, an integer fixed while the ring has no inflection. In the
//! reference model Tw integrates the material twist of the energy; Lk is
//! conserved because the reference directors are transported continuously
//! (SPEC §2.3), whatever the ring's inflections. An imposed
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

/// A quadrature point of the centreline: point, unit tangent, weight (or
/// speed) in current arc length, Frenet torsion where the curve bends,
/// unit binormal (zero where straight).
struct CentrelinePoint {
    p: Vector3<f64>,
    t: Vector3<f64>,
    w: f64,
    tau: Option<f64>,
    binormal: Vector3<f64>,
}

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

    /// Point, unit tangent, current speed |r′| and Frenet data at u in `seg`.
    fn centreline_at(&self, seg: usize, u: f64) -> CentrelinePoint {
        let ctrl = self.knots.segment_ctrl(seg);
        let b = self.knots.basis(seg, u);
        let s = super::samples::local_state(&self.q, self.dofs, &ctrl, &b);
        let p = super::samples::point(&self.q, self.dofs, &ctrl, &b[0]);
        let speed = s.r1.norm();
        let c = s.cross();
        let c2 = c.norm_squared();
        // τ = (r′×r″)·r‴ / |r′×r″|², defined where the curve bends.
        let tau = (c2 > 1e-24 * speed.powi(6)).then(|| c.dot(&s.r3) / c2);
        let binormal = if c2 > 0.0 { c / c2.sqrt() } else { Vector3::zeros() };
        CentrelinePoint { p: Vector3::new(p[0], p[1], p[2]), t: s.r1 / speed, w: speed, tau, binormal }
    }

    /// Gauss points of the current centreline on [a, b] within segment
    /// `seg`, their weights in current arc length.
    fn centreline_points_on(&self, seg: usize, a: f64, b: f64, gx: &[f64], gw: &[f64]) -> impl Iterator<Item = CentrelinePoint> + '_ {
        let (gx, gw) = (gx.to_vec(), gw.to_vec());
        (0..gx.len()).map(move |k| {
            let mut c = self.centreline_at(seg, 0.5 * (a + b) + 0.5 * (b - a) * gx[k]);
            c.w *= gw[k] * 0.5 * (b - a);
            c
        })
    }

    /// Gauss points of every segment (`per_segment` each, segment by segment).
    fn centreline_points(&self, per_segment: usize) -> Result<Vec<CentrelinePoint>> {
        let n = self.n_segments().saturating_mul(per_segment);
        if n > MAX_WRITHE_POINTS {
            return Err(Error::invalid("writhe quadrature points", n, format!("at most {MAX_WRITHE_POINTS} (the double sum costs their square)")));
        }
        let (gx, gw) = gauss_legendre(per_segment)?;
        let mut out = Vec::with_capacity(n);
        for seg in 0..self.n_segments() {
            let (u0, u1) = self.knots.segment_interval(seg);
            out.extend(self.centreline_points_on(seg, u0, u1, &gx, &gw));
        }
        Ok(out)
    }

    /// Writhe of a closed rod's centreline (turns): the Gauss double
    /// integral, 8 Gauss points per segment. The integrand is continuous
    /// but has a kink |s₁ − s₂| on the diagonal, where a product rule
    /// converges as h² only; so on a segment paired with itself the inner
    /// integral is split at s₁ (each side smooth) and the rule converges as
    /// fast as the curve is smooth.
    pub fn writhe(&self) -> Result<f64> {
        self.require_ring("writhe")?;
        const PER: usize = 8;
        let pts = self.centreline_points(PER)?;
        let kernel = |a: &CentrelinePoint, b: &CentrelinePoint| {
            let d = a.p - b.p;
            let r = d.norm();
            a.t.cross(&b.t).dot(&d) / (r * r * r) * a.w * b.w
        };
        let mut sum = 0.0;
        // Distinct segments: the product rule, (i, j) and (j, i) at once.
        for (i, p1) in pts.iter().enumerate() {
            for p2 in &pts[(i / PER + 1) * PER..] {
                sum += 2.0 * kernel(p1, p2);
            }
        }
        // A segment with itself: for each outer point u, Gauss on [u0, u] and on [u, u1].
        let (gx, gw) = gauss_legendre(PER)?;
        for (seg, outer) in pts.chunks(PER).enumerate() {
            let (u0, u1) = self.knots.segment_interval(seg);
            for (x, o) in gx.iter().zip(outer) {
                let u = 0.5 * (u0 + u1) + 0.5 * (u1 - u0) * x;
                for inner in self.centreline_points_on(seg, u0, u, &gx, &gw).chain(self.centreline_points_on(seg, u, u1, &gx, &gw)) {
                    sum += kernel(o, &inner);
                }
            }
        }
        Ok(sum / (4.0 * PI))
    }

    /// Twist (turns), plus the imposed excess link. Frenet model (rings
    /// only): (1/2π) ∮ τ ds with the exact Frenet torsion (not the
    /// regularised one of the energy); errors where the ring has an
    /// inflection (τ undefined). Reference model (rings and open rods):
    /// (1/2π) ∫ ω ds with the material twist ω = θ′/|r′| + ω_ref of the
    /// energy (SPEC §2.3) on the energy's quadrature, defined everywhere
    /// (∮ θ′ du = 0 on a ring; on an open rod, which needs the roll
    /// coordinate, it includes θ(end) − θ(start)).
    pub fn twist(&self) -> Result<f64> {
        if self.opts.model == crate::energy::FrameModel::Reference {
            if self.dofs != 4 {
                // Without roll only a ring's (reference) twist is defined.
                self.require_ring("twist")?;
            }
            let strains = self.strains();
            let mut sum = 0.0;
            for (s, st) in self.cache.samples.iter().zip(&strains) {
                let ls = super::samples::local_state(&self.q, self.dofs, &self.cache.seg_ctrl[s.seg], &s.basis);
                // s.w is the rest arc-length weight; the current one scales by |r′| / |r′⁰|.
                sum += s.w / s.consts.speed0 * ls.r1.norm() * st.omega;
            }
            return Ok(sum / (2.0 * PI) + self.excess_link);
        }
        self.require_ring("twist")?;
        let undefined = || Error::singular("twist: the ring has an inflection (straight somewhere), so its Frenet torsion (and the Frenet model's twist) is undefined there");
        let mut sum = 0.0;
        let pts = self.centreline_points(8)?;
        for (k, c) in pts.iter().enumerate() {
            // An inflection between two points flips the binormal.
            if c.binormal.dot(&pts[(k + 1) % pts.len()].binormal) <= 0.0 {
                return Err(undefined());
            }
            sum += c.w * c.tau.ok_or_else(undefined)?;
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
