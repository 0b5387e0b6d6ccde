//! Perfect plasticity and rupture detection per sample and per deformation
//! mode (SPEC §6, thesis II.C, algorithms 1–3).
//!
//! The relative strain of a sample is ε_r = ε_e − ε⁰ (stretch ε; material
//! curvatures κ1, κ2; twist ω, each minus its rest value). With the plastic
//! offset Δε_p, the elastic part ε = ε_r − Δε_p is kept inside the yield
//! limits [ε_A−, ε_A+] by moving Δε_p (perfect plasticity, II.103); the
//! offsets enter W as shifted rest values (II.104). Yielding the other way
//! reduces (and can reset) the offset. Rupture looks at ε_r itself (the
//! plastic offset does not move the rupture point, II.C.2.c).
use super::{samples, Rod};
use crate::energy::{self, Strains};
use crate::error::{Error, Result};
use crate::material::StrainLimits;
use serde::{Deserialize, Serialize};

/// A deformation mode, as named in events and reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum StrainMode {
    Stretch,
    /// Material curvature κ1 (about director d1's partner axis).
    Bend1,
    Bend2,
    Twist,
}

/// What one plastic update did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PlasticUpdate {
    /// Samples whose offset moved in at least one mode.
    pub yielded: usize,
    /// Largest offset increment: |Δε_p| of stretch (dimensionless) and of
    /// curvature or twist (1/length) times the rest length (dimensionless).
    pub max_increment: f64,
}

/// Where a rod exceeds its rupture strain most (relative to the limit).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RuptureSite {
    pub sample: usize,
    /// Spline abscissa of that sample.
    pub u: f64,
    pub mode: StrainMode,
    /// Relative strain ε_r and the limit it passed (same unit: 1 or 1/length).
    pub strain: f64,
    pub limit: f64,
}

fn as_array(s: &Strains) -> [f64; 4] {
    [s.eps, s.kappa1, s.kappa2, s.omega]
}
fn from_array(a: [f64; 4]) -> Strains {
    Strains { eps: a[0], kappa1: a[1], kappa2: a[2], omega: a[3] }
}
const MODES: [StrainMode; 4] = [StrainMode::Stretch, StrainMode::Bend1, StrainMode::Bend2, StrainMode::Twist];
/// (negative, positive) limit of each of the four modes.
fn limits(l: &StrainLimits) -> [(f64, f64); 4] {
    [l.stretch, l.bend, l.bend, l.twist]
}

/// Relative excess over a yield limit taken as round-off (not a yield).
const YIELD_ROUNDOFF: f64 = 1e-12;

impl Rod {
    /// Relative strains ε_r = ε_e − ε⁰ at every sample (stretch
    /// dimensionless, curvatures and twist in 1/length), in sample order.
    pub fn relative_strains(&self) -> Vec<Strains> {
        (0..self.cache.samples.len()).map(|i| self.relative_strain(i)).collect()
    }

    fn relative_strain(&self, i: usize) -> Strains {
        let s = &self.cache.samples[i];
        let ls = samples::local_state(&self.q, self.dofs, &self.cache.seg_ctrl[s.seg], &s.basis);
        let e = energy::strains(&ls, &s.consts, self.frame_state(i), self.opts.model);
        Strains { eps: e.eps, kappa1: e.kappa1 - s.rest[0], kappa2: e.kappa2 - s.rest[1], omega: e.omega - s.rest[2] }
    }

    /// Plastic offsets Δε_p at every sample (zeros if the rod never yielded).
    pub fn plastic_offsets(&self) -> Vec<Strains> {
        let n = self.cache.samples.len();
        (0..n).map(|i| self.plastic.get(i).copied().unwrap_or_default()).collect()
    }

    /// Sets the plastic offsets (one per sample, finite), e.g. to restore a
    /// pre-worked state; the energy uses them from the next solve on.
    pub fn set_plastic_offsets(&mut self, offsets: &[Strains]) -> Result<()> {
        let n = self.cache.samples.len();
        if offsets.len() != n {
            return Err(Error::input(format!("plastic offsets: expected one per sample ({n}), got {}", offsets.len())));
        }
        if let Some(i) = offsets.iter().position(|s| as_array(s).iter().any(|x| !x.is_finite())) {
            return Err(Error::input(format!("plastic offset of sample {i} is not finite")));
        }
        if self.opts.stretch_at_greville && offsets.iter().any(|s| s.eps != 0.0) {
            return Err(Error::input("plastic offsets: a stretch offset has no effect with stretch_at_greville (the stretch lives at the Greville samples)"));
        }
        self.plastic = offsets.to_vec();
        self.cache.refresh_plastic(&self.plastic);
        Ok(())
    }

    /// Replaces the material's yield and rupture limits (validated: rupture
    /// at or beyond yield). Offsets already accumulated are kept.
    pub fn set_strain_limits(&mut self, yield_limits: Option<StrainLimits>, rupture_limits: Option<StrainLimits>) -> Result<()> {
        let mut m = self.material.clone();
        m.yield_limits = yield_limits;
        m.rupture_limits = rupture_limits;
        m.validate()?;
        super::samples::check_greville(self.opts.stretch_at_greville, &m, self.opts.poisson_update)?;
        self.material = m;
        Ok(())
    }

    /// Algorithm 1: moves the plastic offsets so that every sample's elastic
    /// strain is back inside the yield limits. No-op without yield limits.
    pub fn update_plasticity(&mut self) -> PlasticUpdate {
        self.algorithm_3(false, true).0
    }

    /// Algorithm 2: the sample whose relative strain lies furthest beyond
    /// the rupture limits (largest ε_r / ε_B on the side it leaves), if any.
    pub fn rupture_site(&self) -> Option<RuptureSite> {
        let lim = limits(self.material.rupture_limits.as_ref()?);
        let mut best = None;
        for i in 0..self.cache.samples.len() {
            self.check_rupture(i, &as_array(&self.relative_strain(i)), &lim, &mut best);
        }
        best.map(|b| b.1)
    }

    /// Algorithm 3: the rupture site (of the strains before the plastic
    /// update) and the plastic update, in one pass over the samples (one
    /// strain evaluation per sample).
    pub fn update_inelastic(&mut self) -> (PlasticUpdate, Option<RuptureSite>) {
        self.algorithm_3(true, true)
    }

    fn algorithm_3(&mut self, rupture: bool, plastic: bool) -> (PlasticUpdate, Option<RuptureSite>) {
        let mut out = PlasticUpdate::default();
        let ylim = self.material.yield_limits.as_ref().filter(|_| plastic).map(limits);
        let blim = self.material.rupture_limits.as_ref().filter(|_| rupture).map(limits);
        if ylim.is_none() && blim.is_none() {
            return (out, None);
        }
        let l0 = self.rest_length();
        let n = self.cache.samples.len();
        let mut best = None;
        for i in 0..n {
            let ra = as_array(&self.relative_strain(i));
            if let Some(b) = &blim {
                self.check_rupture(i, &ra, b, &mut best);
            }
            let Some(lim) = &ylim else { continue };
            let mut pa = as_array(&self.plastic.get(i).copied().unwrap_or_default());
            let mut moved = false;
            for m in 0..4 {
                let e = ra[m] - pa[m];
                // ε_+ = ε − ε_A+ > 0 or ε_− = ε − ε_A− < 0 is added to Δε_p.
                let (excess, limit) = if e > lim[m].1 { (e - lim[m].1, lim[m].1) } else if e < lim[m].0 { (e - lim[m].0, lim[m].0) } else { continue };
                // A sample the previous round left at its limit sits there
                // up to round-off: that is no yield (it would count the
                // sample again, and the count would depend on round-off).
                if excess.abs() <= YIELD_ROUNDOFF * limit.abs() {
                    continue;
                }
                pa[m] += excess;
                moved = true;
                out.max_increment = out.max_increment.max(excess.abs() * if m == 0 { 1.0 } else { l0 });
            }
            if moved {
                out.yielded += 1;
                if self.plastic.len() != n {
                    self.plastic.resize(n, Strains::default()); // once, at the first yield
                }
                self.plastic[i] = from_array(pa);
                self.cache.refresh_plastic_at(i, &self.plastic[i]);
            }
        }
        (out, best.map(|b: (f64, RuptureSite)| b.1))
    }

    /// Keeps in `best` the sample furthest beyond a rupture limit (ratio ε_r / ε_B).
    fn check_rupture(&self, i: usize, ra: &[f64; 4], lim: &[(f64, f64); 4], best: &mut Option<(f64, RuptureSite)>) {
        for (m, &x) in ra.iter().enumerate() {
            let limit = if x > 0.0 { lim[m].1 } else { lim[m].0 };
            let ratio = x / limit; // > 1 beyond the limit on either side
            if ratio > 1.0 && best.as_ref().is_none_or(|b| ratio > b.0) {
                let u = self.cache.samples[i].u;
                *best = Some((ratio, RuptureSite { sample: i, u, mode: MODES[m], strain: x, limit }));
            }
        }
    }
}
