//! Thermal fluctuations (SPEC §3): the random generalised force R of
//! Langevin dynamics, ⟨R Rᵀ⟩ = 2 kT D / h for a step of h, D the rod's drag
//! matrix, so that fluctuation and dissipation match (equilibrium at kT).
//! D is a sum of per-segment blocks D_s (4 control points × each axis), so
//! R = √(2kT/h) Σ_s L_s ξ_s with L_s the Cholesky factor of D_s and ξ_s
//! standard normals: independent per segment, exact for open and closed
//! rods alike, and cheaper than a factorisation of the whole band.
//!
//! The normals are drawn once per step (`Stream`) and held for its solves:
//! a trapezoidal step applies R whole over the step (½ at each end), which
//! keeps the stationary covariance of linear systems exact at any h.
use super::ForceField;
use crate::error::{Error, Result};
use crate::rod::drag::Drag;
use crate::rod::Rod;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::{Deserialize, Serialize};

/// Boltzmann's constant in joules per kelvin (SI, exact since 2019).
pub const BOLTZMANN_SI: f64 = 1.380649e-23;

/// The thermal force on one rod for one step: kT (energy unit), the step h,
/// the rod's drag and the step's normals (`normals_per_rod` of them).
#[derive(Clone, Copy, Debug)]
pub struct Thermal<'a> {
    pub kt: f64,
    pub h: f64,
    pub drag: Drag,
    pub normals: &'a [f64],
}

/// Standard normals one step draws for `rod` under `drag`: 4 control
/// points × dofs per segment, then with anisotropic drag 3 per Gauss sample
/// (6 with a sampling length: the two factors of its block).
pub fn normals_per_rod(rod: &Rod, drag: &Drag) -> usize {
    let factors = if drag.axial == 0.0 { 0 } else if rod.options().sampling_length > 0.0 { 2 } else { 1 };
    rod.n_segments() * 4 * rod.dofs() + 3 * factors * rod.cache.samples.len()
}

/// Lower Cholesky factor of a symmetric positive semi-definite 4×4 block
/// (a zero pivot, as from a rank-deficient quadrature, zeroes its column:
/// for a PSD matrix that column is zero below the pivot too).
pub(crate) fn cholesky4(a: &[[f64; 4]; 4]) -> [[f64; 4]; 4] {
    let mut l = [[0.0; 4]; 4];
    let scale = (0..4).fold(0.0f64, |m, i| m.max(a[i][i]));
    for j in 0..4 {
        let d = a[j][j] - (0..j).map(|k| l[j][k] * l[j][k]).sum::<f64>();
        if d <= 1e-14 * scale {
            continue;
        }
        let ljj = d.sqrt();
        l[j][j] = ljj;
        for i in j + 1..4 {
            l[i][j] = (a[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>()) / ljj;
        }
    }
    l
}

impl ForceField for Thermal<'_> {
    fn add_force(&self, rod: &Rod, _time: f64, f: &mut [f64]) -> Result<()> {
        let d = rod.dofs();
        let need = normals_per_rod(rod, &self.drag);
        if self.normals.len() != need {
            return Err(Error::input(format!("thermal force: {} normals for a rod that needs {need}", self.normals.len())));
        }
        let (t, a) = (self.drag.trans, self.drag.axial);
        if !(t.is_finite() && a.is_finite() && a <= 0.0 && t + a >= 0.0 && self.kt >= 0.0 && self.h > 0.0) {
            return Err(Error::input(format!(
                "thermal force: drag trans {t}, axial {a}, kT {}, h {} (need axial ≤ 0 ≤ trans + axial, kT ≥ 0, h > 0)",
                self.kt, self.h
            )));
        }
        let c = (2.0 * self.kt / self.h).sqrt();
        // D = (c_t + c_a) seg_bb ⊗ I + (−c_a) Σ_g G_g ⊗ (I − t tᵀ) (both
        // positive: c_a = γ_∥ − γ_⊥ ≤ 0, c_t + c_a = own + γ_∥). The first
        // block's factor is √(c_t + c_a) times the rod's cached Cholesky
        // factor; only the roll's (two blocks mixed) is factored here.
        let ct = c * (self.drag.trans + self.drag.axial).sqrt();
        for (s, ctrl) in rod.cache.seg_ctrl.iter().enumerate() {
            let lt = &rod.cache.seg_bb_chol[s];
            let lr = if d == 4 { cholesky4(&rod.seg_roll_drag(&self.drag, s)) } else { [[0.0; 4]; 4] };
            let xi = &self.normals[s * 4 * d..(s + 1) * 4 * d];
            for k in 0..4 {
                for l in 0..=k {
                    for a in 0..3 {
                        f[ctrl[k] * d + a] += ct * lt[k][l] * xi[l * d + a];
                    }
                    if d == 4 {
                        f[ctrl[k] * d + 3] += c * lr[k][l] * xi[l * d + 3];
                    }
                }
            }
        }
        if self.drag.axial != 0.0 {
            // Per sample and factor φ ∈ {u, v} of G_g: √(−c_a) φ ⊗ (I − t tᵀ) ξ.
            let ca = c * (-self.drag.axial).sqrt();
            let factors = if rod.options().sampling_length > 0.0 { 2 } else { 1 };
            let mut xi = self.normals[rod.n_segments() * 4 * d..].chunks_exact(3);
            for (g, smp) in rod.cache.samples.iter().enumerate() {
                let ctrl = &rod.cache.seg_ctrl[smp.seg];
                let t = rod.drag_tangent(g);
                let (u, v) = rod.drag_factors(g);
                for phi in [u, v].iter().take(factors) {
                    // invariant: normals_per_rod sized the slice for every factor
                    let x = xi.next().expect("normals sized by normals_per_rod");
                    let tx = t[0] * x[0] + t[1] * x[1] + t[2] * x[2];
                    let p = [x[0] - tx * t[0], x[1] - tx * t[1], x[2] - tx * t[2]];
                    for k in 0..4 {
                        for a in 0..3 {
                            f[ctrl[k] * d + a] += ca * phi[k] * p[a];
                        }
                    }
                }
            }
        }
        Ok(())
    }
    /// A random force has no potential.
    fn potential(&self, _rod: &Rod, _time: f64) -> Result<f64> {
        Ok(0.0)
    }
}

/// The world's random stream: ChaCha8 from a 64-bit seed, positioned by the
/// number of 32-bit words used so far. Both are in the snapshot, so a
/// restarted run draws the same numbers (bit-exact); different seeds give
/// independent streams.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Stream {
    pub seed: u64,
    /// Words of the stream already used (ChaCha's word position).
    pub words: u128,
}

impl Stream {
    /// Fills `out` with standard normals from the stream's position;
    /// returns the stream after them (the caller keeps it once the step
    /// that used them succeeds).
    pub fn draw(&self, out: &mut [f64]) -> Stream {
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        rng.set_word_pos(self.words);
        for x in out.iter_mut() {
            *x = StandardNormal.sample(&mut rng);
        }
        Stream { seed: self.seed, words: rng.get_word_pos() }
    }
}
