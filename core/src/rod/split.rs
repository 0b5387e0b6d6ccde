//! Material rupture of one rod (SPEC §6, thesis II.C.2.b): a knot of
//! multiplicity 4 at the rupture abscissa cuts the spline into two clamped
//! pieces that reproduce the pre-rupture centreline exactly (Boehm insertion
//! is exact). The same insertion is applied to everything that lives on the
//! control points — velocities, rest shape, section sizes — so each piece
//! keeps the rest state, the kinetic state and the section of its part of
//! the rod. Plastic offsets live on samples; each piece's samples take the
//! offsets of the old samples at the same abscissa (unchanged segments have
//! the same Gauss points) and interpolate linearly in u inside the two cut
//! segments.
use super::Rod;
use crate::energy::Strains;
use crate::error::Result;
use crate::section::Section;
use crate::spline::{open_ring_at, split_at, KnotKind, KnotVector};

/// Values carried per control point through the insertion: q (4), v (4),
/// rest q (4), section sizes (4), rest section sizes (4).
const PACK: usize = 20;

/// The result of cutting a rod.
pub enum Cut {
    /// An open rod: the pieces on [a, u] and [u, b], keeping their abscissae.
    Two(Box<[Rod; 2]>),
    /// A ring opened at u: one rod whose abscissa s maps to ring abscissa
    /// u + s (modulo the ring's period).
    Opened(Box<Rod>),
}

impl Rod {
    /// Cuts the rod at abscissa `u` (strictly inside the domain).
    pub fn cut_at(&self, u: f64) -> Result<Cut> {
        let packed = self.pack();
        let old_u: Vec<f64> = self.sample_params();
        let old_p = self.plastic_offsets();
        if self.knots.kind() == KnotKind::Periodic {
            let (k, c) = open_ring_at(&self.knots, &packed, u)?;
            let map = |s: f64| self.knots.wrap(s + u);
            let mut rod = self.piece(k, &c, map, &old_u, &old_p)?;
            if self.excess_link != 0.0 {
                // The imposed link is a rest-twist shift of the ring (the
                // Frenet model cannot wind θ around a ring); the opened rod
                // keeps it as the same shift of its rest twist (a plastic ω
                // offset), so the cut changes no energy. Its free ends then
                // let θ relax the twist.
                let shift = self.link_twist_shift(self.rest_length());
                let mut p = rod.plastic_offsets();
                p.iter_mut().for_each(|x| x.omega -= shift);
                rod.set_plastic_offsets(&p)?;
            }
            return Ok(Cut::Opened(Box::new(rod)));
        }
        let [(kl, cl), (kr, cr)] = split_at(&self.knots, &packed, u)?;
        let same = |s: f64| s;
        Ok(Cut::Two(Box::new([self.piece(kl, &cl, same, &old_u, &old_p)?, self.piece(kr, &cr, same, &old_u, &old_p)?])))
    }

    fn pack(&self) -> Vec<[f64; PACK]> {
        let d = self.dofs;
        (0..self.n_ctrl())
            .map(|i| {
                let mut p = [0.0; PACK];
                for a in 0..d {
                    p[a] = self.q[i * d + a];
                    p[4 + a] = self.v[i * d + a];
                    p[8 + a] = self.q_rest[i * d + a];
                }
                p[12..16].copy_from_slice(&self.sections[i].sizes());
                p[16..20].copy_from_slice(&self.rest_sections()[i].sizes());
                p
            })
            .collect()
    }

    /// A piece with knots and packed control values `c`; `old_abscissa`
    /// maps its abscissae to the old rod's, whose samples are at `old_u`
    /// with offsets `old_p`.
    fn piece(&self, knots: KnotVector, c: &[[f64; PACK]], old_abscissa: impl Fn(f64) -> f64, old_u: &[f64], old_p: &[Strains]) -> Result<Rod> {
        let d = self.dofs;
        let flat = |off: usize| c.iter().flat_map(|p| p[off..off + d].to_vec()).collect::<Vec<f64>>();
        let shape = self.sections[0];
        let sections: Vec<Section> = c.iter().map(|p| shape.with_sizes([p[12], p[13], p[14], p[15]])).collect();
        let rest_sections: Vec<Section> = c.iter().map(|p| shape.with_sizes([p[16], p[17], p[18], p[19]])).collect();
        // Same curvature threshold as the parent (its default is relative to
        // the rest length), so the pieces carry the same energy.
        let mut opts = self.opts;
        opts.curvature_threshold = self.curvature_threshold();
        let mut rod = Rod::new(knots, d, flat(8), rest_sections.clone(), self.material.clone(), opts)?;
        rod.q = flat(0);
        rod.v = flat(4);
        rod.rest_sections = rest_sections;
        rod.sections = sections;
        rod.cache.refresh_stiffness(&rod.sections, rod.material.young, rod.material.shear_modulus())?;
        if !self.plastic.is_empty() {
            let p: Vec<Strains> = rod.sample_params().into_iter().map(|s| interpolate(old_u, old_p, old_abscissa(s))).collect();
            rod.set_plastic_offsets(&p)?;
        }
        // The frame model's state follows the material: each new sample
        // takes the state of the old sample nearest its abscissa.
        if !self.frames.is_empty() {
            rod.frames = rod.sample_params().into_iter().map(|s| self.frames[self.nearest_sample(old_abscissa(s))].clone()).collect();
            // Rest values are measured in the rest directors, which the
            // piece's own construction would restart (a Bishop frame from
            // its first sample): keep the parent's, interpolated like the
            // offsets, so that the copied directors and the rest values
            // still agree. A ring's link shift leaves them (cut_at carries
            // it as a plastic offset).
            let shift = self.link_twist_shift(self.rest_length());
            let old_rest: Vec<Strains> = self.cache.samples.iter().map(|s| Strains { eps: 0.0, kappa1: s.rest[0], kappa2: s.rest[1], omega: s.rest[2] + shift }).collect();
            for (k, s) in rod.sample_params().into_iter().enumerate() {
                let r = interpolate(old_u, &old_rest, old_abscissa(s));
                rod.cache.samples[k].rest = [r.kappa1, r.kappa2, r.omega];
            }
            rod.cache.refresh_plastic(&rod.plastic);
        }
        Ok(rod)
    }
}

/// Offsets at `u`: the old sample's value where one sits at `u`, else linear
/// between the neighbouring old samples (constant beyond the first/last).
fn interpolate(us: &[f64], ps: &[Strains], u: f64) -> Strains {
    let i = us.partition_point(|&x| x < u);
    if i < us.len() && us[i] == u {
        return ps[i];
    }
    if i == 0 {
        return ps[0];
    }
    if i == us.len() {
        return ps[i - 1];
    }
    let t = (u - us[i - 1]) / (us[i] - us[i - 1]);
    let (a, b) = (ps[i - 1], ps[i]);
    let l = |x: f64, y: f64| x + t * (y - x);
    Strains { eps: l(a.eps, b.eps), kappa1: l(a.kappa1, b.kappa1), kappa2: l(a.kappa2, b.kappa2), omega: l(a.omega, b.omega) }
}
