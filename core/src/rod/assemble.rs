//! Per-segment energy, gradient and stiffness (SPEC §2, IV.1–IV.2): the
//! chain rule through the basis functions,
//!   ∂U/∂q_(k,α) = Σ_s w Σ_a β_k^a ∂W/∂d_(a,α),
//!   K_(kα)(lβ)  = Σ_s w Σ_{a,b} β_k^a β_l^b ∂²W/∂d_(a,α)∂d_(b,β),
//! where slot a of a position coordinate takes r', r'', r''' (β = b', b'', b''')
//! and of θ takes θ, θ' (β = b, b'). Only the slots the energy terms use
//! are visited ([`ActiveSlots`]); the upper half of each 16×16 (12×12) block
//! is returned; segments run in parallel (rayon).
use super::samples::local_state;
use super::Rod;
use crate::energy::invariants::{Mat11, TH, TH1};
use crate::energy::stretch::{leave_out_compression, mixed_geometric_stiffness};
use crate::energy::{density_into, energy_density, ActiveSlots, EnergyTerms, FrameModel, FrameState, LocalEnergy};

/// The terms of a Greville stretch sample.
const STRETCH_ONLY: EnergyTerms = EnergyTerms { stretch: true, bend: false, twist: false };
use rayon::prelude::*;

/// One segment's contribution. Local index k*dofs + α (k = 0..4).
#[derive(Clone, Debug)]
pub struct SegBlock {
    pub energy: f64,
    /// ∂U/∂q over the segment's 4 control points.
    pub grad: [f64; 16],
    /// Upper half (j ≥ i) of ∂²U/∂q², row-major with stride 16.
    pub hess: [f64; 256],
}

impl Default for SegBlock {
    fn default() -> Self {
        SegBlock { energy: 0.0, grad: [0.0; 16], hess: [0.0; 256] }
    }
}

/// What to compute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Need {
    Gradient,
    Hessian,
    /// The matrix of a linearised implicit step: the Hessian without the
    /// negative transverse stretch stiffness of compressed samples
    /// ([`crate::energy::stretch::leave_out_compression`]).
    StepHessian,
}

impl Need {
    fn hessian(self) -> bool {
        self != Need::Gradient
    }
}

impl Rod {
    /// Evaluates every segment into `blocks` (resized to the segment count).
    /// `parallel` spreads segments over rayon's pool.
    pub fn assemble(&self, blocks: &mut Vec<SegBlock>, need: Need, parallel: bool) {
        blocks.resize(self.n_segments(), SegBlock::default());
        self.assemble_range(0, blocks, need, parallel);
    }

    /// Evaluates segments `first .. first + blocks.len()` into `blocks`, so
    /// that a caller can assemble in cache-sized batches (a 40000-point rod's
    /// blocks would take 87 MB). `parallel` spreads them over rayon's pool.
    ///
    /// # Panics
    /// If the range goes past the last segment (a programming error).
    pub fn assemble_range(&self, first: usize, blocks: &mut [SegBlock], need: Need, parallel: bool) {
        assert!(first + blocks.len() <= self.n_segments(), "Rod::assemble_range: segment range out of bounds");
        if parallel {
            blocks
                .par_iter_mut()
                .enumerate()
                .with_min_len(16)
                .for_each_init(Scratch::default, |sc, (s, b)| self.segment(first + s, b, need, sc));
        } else {
            let mut sc = Scratch::default();
            blocks.iter_mut().enumerate().for_each(|(s, b)| self.segment(first + s, b, need, &mut sc));
        }
    }

    /// Elastic energy U (energy unit).
    pub fn elastic_energy(&self) -> f64 {
        // The densities alone: no chain-rule accumulators (this runs in
        // every step's divergence guard).
        (0..self.cache.seg_ctrl.len()).map(|seg| self.segment_energy_of(seg)).sum()
    }

    /// Elastic energy of segment `seg` alone (energy unit; the segments'
    /// energies sum to `elastic_energy`). A move that changes a few control
    /// points changes only the segments they span: Monte Carlo samplers
    /// can update the energy locally.
    pub fn segment_energy(&self, seg: usize) -> crate::error::Result<f64> {
        if seg >= self.cache.seg_ctrl.len() {
            return Err(crate::error::Error::invalid("segment", seg, format!("< {} (the rod's segments)", self.cache.seg_ctrl.len())));
        }
        Ok(self.segment_energy_of(seg))
    }

    fn segment_energy_of(&self, seg: usize) -> f64 {
        let c = &self.cache;
        let ctrl = &c.seg_ctrl[seg];
        let mut u = 0.0;
        for i in c.seg_start[seg]..c.seg_start[seg + 1] {
            let s = &c.samples[i];
            let ls = local_state(&self.q, self.dofs, ctrl, &s.basis);
            u += s.w * energy_density(&ls, &s.consts, self.frame_state(i), self.opts.terms, self.opts.model);
        }
        let stretch = if self.opts.terms.stretch { &c.stretch[c.seg_stretch_start[seg]..c.seg_stretch_start[seg + 1]] } else { &[] };
        for s in stretch {
            let ls = local_state(&self.q, self.dofs, ctrl, &s.basis);
            u += s.w * energy_density(&ls, &s.consts, &FrameState::None, STRETCH_ONLY, FrameModel::Frenet);
        }
        u
    }

    /// Internal generalised forces P = −∂U/∂q (flat like the coordinates).
    pub fn internal_forces(&self) -> Vec<f64> {
        let mut blocks = Vec::new();
        self.assemble(&mut blocks, Need::Gradient, false);
        let mut p = vec![0.0; self.q.len()];
        for (s, b) in blocks.iter().enumerate() {
            for (k, &i) in self.cache.seg_ctrl[s].iter().enumerate() {
                for a in 0..self.dofs {
                    p[i * self.dofs + a] -= b.grad[k * self.dofs + a];
                }
            }
        }
        p
    }

    /// One segment into `out`; `scratch` is reused across segments (T rows
    /// are written before they are read, K is cleared here).
    fn segment(&self, seg: usize, out: &mut SegBlock, need: Need, scratch: &mut Scratch) {
        let Scratch { acc, e } = scratch;
        let dofs = self.dofs;
        let nl = 4 * dofs;
        out.energy = 0.0;
        out.grad[..nl].iter_mut().for_each(|g| *g = 0.0);
        let act = ActiveSlots::of(self.opts.terms, self.opts.model);
        // Roll slots carry nothing without a roll coordinate.
        let (th, th1) = (dofs == 4 && act.theta, dofs == 4 && act.theta1);
        let np = act.positions;
        acc.k = [[[0.0; 4]; 4]; 16];
        let c = &self.cache;
        let ctrl = &c.seg_ctrl[seg];
        // ∂U/∂q_(k,α) = w Σ_a β_k^a ∂W/∂d_(a,α), over all three position
        // slots (fixed bounds; the inactive slots' entries are zero).
        let mut add = |out: &mut SegBlock, e: &LocalEnergy, b: &[[f64; 4]; 4], w: f64, np: usize, th: bool, th1: bool| {
            out.energy += w * e.w;
            let g = &e.grad;
            for k in 0..4 {
                for al in 0..3 {
                    let v = b[1][k] * g[al] + b[2][k] * g[3 + al] + b[3][k] * g[6 + al];
                    out.grad[k * dofs + al] += w * v;
                }
                if dofs == 4 {
                    out.grad[k * 4 + 3] += w * (b[0][k] * g[TH] + b[1][k] * g[TH1]);
                }
            }
            if need.hessian() {
                acc.add_sample(&e.hess, b, w, np, th, th1);
            }
        };
        let step = need == Need::StepHessian;
        for (i, s) in c.samples[c.seg_start[seg]..c.seg_start[seg + 1]].iter().enumerate() {
            let ls = local_state(&self.q, dofs, ctrl, &s.basis);
            let state = self.frame_state(c.seg_start[seg] + i);
            density_into(&ls, &s.consts, state, self.opts.terms, self.opts.model, true, e);
            if step && self.opts.terms.stretch {
                leave_out_compression(&ls.r1, &s.consts, &mut e.hess);
            }
            // (Relax keeps tangents only for rods with stretch energy.)
            if let (true, Some(t)) = (need.hessian(), self.mixed_previous(c.seg_start[seg] + i)) {
                mixed_geometric_stiffness(&ls.r1, t, &s.consts, &mut e.hess);
            }
            add(out, e, &s.basis, s.w, np, th, th1);
        }
        // Greville stretch samples (empty unless `stretch_at_greville`): r' only.
        let stretch = if self.opts.terms.stretch { &c.stretch[c.seg_stretch_start[seg]..c.seg_stretch_start[seg + 1]] } else { &[] };
        for (j, s) in stretch.iter().enumerate() {
            let ls = local_state(&self.q, dofs, ctrl, &s.basis);
            density_into(&ls, &s.consts, &FrameState::None, STRETCH_ONLY, FrameModel::Frenet, true, e);
            if step {
                leave_out_compression(&ls.r1, &s.consts, &mut e.hess);
            }
            if let (true, Some(t)) = (need.hessian(), self.mixed_previous(c.samples.len() + c.seg_stretch_start[seg] + j)) {
                mixed_geometric_stiffness(&ls.r1, t, &s.consts, &mut e.hess);
            }
            add(out, e, &s.basis, s.w, 1, false, false);
        }
        if need.hessian() {
            acc.write_upper(out, dofs);
        }
    }
}

/// Segments `first .. first + len` of rod `rod` go to `blocks[offset ..
/// offset + len]` of a batch.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SegRange {
    pub rod: usize,
    pub first: usize,
    pub offset: usize,
    pub len: usize,
}

/// Evaluates a batch of segment ranges (of several rods) into `blocks`
/// (`ranges` sorted by offset, covering `blocks`). `parallel` spreads the
/// whole batch over rayon's pool, across rod boundaries.
pub(crate) fn assemble_ranges(rods: &[&Rod], ranges: &[SegRange], blocks: &mut [SegBlock], need: Need, parallel: bool) {
    if parallel && ranges.len() > 1 {
        blocks.par_iter_mut().enumerate().with_min_len(16).for_each_init(Scratch::default, |sc, (i, b)| {
            let g = &ranges[ranges.partition_point(|g| g.offset + g.len <= i)];
            rods[g.rod].segment(g.first + i - g.offset, b, need, sc);
        });
    } else {
        for g in ranges {
            rods[g.rod].assemble_range(g.first, &mut blocks[g.offset..g.offset + g.len], need, parallel);
        }
    }
}

/// The Hessian chain rule of the module doc for one segment, laid out so
/// that every inner operation is a 4-wide axpy over the segment's control
/// points l (basis rows b[·] are 4-vectors): with β^a = b^(a+1) for the
/// position slots (r′, r″, r‴) and ρ^0 = b, ρ^1 = b′ for θ, θ′,
///   T[r][γ][l] = Σ_c H[r][3c+γ] β^c_l          (γ < 3: position column (l, γ))
///   T[r][3][l] = H[r][θ] ρ^0_l + H[r][θ′] ρ^1_l (roll column l)
///   K[(k,α)][γ][l] += w Σ_a β^a_k T[3a+α][γ][l],  K[(k,3)][γ][l] += w Σ_s ρ^s_k T[s][γ][l].
/// The position part of the basis is b ⊗ I₃, so T needs 11 axpys per row of
/// H instead of a dense 11×16 product; only active slots are visited.
#[derive(Default)]
struct ChainAcc {
    /// K[(k, α)][l][γ] with row k·4 + α (α = 3: roll), summed over samples;
    /// only the blocks l ≥ k are formed.
    k: [[[f64; 4]; 4]; 16],
    /// T[r][l][γ] of the current sample (scratch: each sample writes the
    /// rows it reads, so it is not cleared between samples).
    t: [[[f64; 4]; 4]; 11],
}

/// Per-thread scratch of the segment kernel, reused across segments.
#[derive(Default)]
struct Scratch {
    acc: ChainAcc,
    /// The current sample's energy density and derivatives (overwritten).
    e: LocalEnergy,
}

#[inline(always)]
fn axpy4(y: &mut [f64; 4], a: f64, x: &[f64; 4]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += a * xi;
    }
}

impl ChainAcc {
    /// Dispatches to a version compiled for the active slots (fixed loop
    /// bounds let the compiler unroll and vectorise the 4-wide axpys).
    /// Kept out of the segment loop: inlined there (as an unrelated change
    /// of the crate once made the compiler do), the beads-on-spring step
    /// ran 12 % slower.
    #[inline(never)]
    fn add_sample(&mut self, h: &Mat11, b: &[[f64; 4]; 4], w: f64, np: usize, th: bool, th1: bool) {
        match (np, th, th1) {
            (3, true, true) => self.add_sample_fixed::<3, true, true>(h, b, w),
            (3, false, true) => self.add_sample_fixed::<3, false, true>(h, b, w),
            (2, true, false) => self.add_sample_fixed::<2, true, false>(h, b, w),
            (2, false, false) => self.add_sample_fixed::<2, false, false>(h, b, w),
            (1, false, false) => self.add_sample_fixed::<1, false, false>(h, b, w),
            _ => self.add_sample_any(h, b, w, np, th, th1),
        }
    }

    #[inline(always)]
    fn add_sample_fixed<const NP: usize, const TH_ON: bool, const TH1_ON: bool>(
        &mut self,
        h: &Mat11,
        b: &[[f64; 4]; 4],
        w: f64,
    ) {
        self.add_sample_any(h, b, w, NP, TH_ON, TH1_ON);
    }

    #[inline(always)]
    fn add_sample_any(&mut self, h: &Mat11, b: &[[f64; 4]; 4], w: f64, np: usize, th: bool, th1: bool) {
        // T[r][l] = (H B)[r][(l, ·)] for the rows K reads: active position
        // slots, then θ, θ′. Formed as 4-wide axpys over l (the basis rows
        // b[·] are 4-vectors), T[r][γ][l] = Σ_c H[r][3c+γ] b^(c+1)_l, then
        // transposed so that K's axpys run over γ. H is symmetric: row r is
        // column r, contiguous in nalgebra's storage.
        let t = &mut self.t;
        let hs = h.as_slice();
        let mut rows = [0usize; 11];
        let mut nr = 0;
        for r in (0..3 * np).chain(th.then_some(TH)).chain(th1.then_some(TH1)) {
            rows[nr] = r;
            nr += 1;
        }
        for &r in &rows[..nr] {
            let hr = &hs[11 * r..11 * r + 11];
            let mut tt = [[0.0f64; 4]; 4];
            for c in 0..np {
                for (g, tg) in tt.iter_mut().take(3).enumerate() {
                    axpy4(tg, hr[3 * c + g], &b[c + 1]);
                }
            }
            if th {
                axpy4(&mut tt[3], hr[TH], &b[0]);
            }
            if th1 {
                axpy4(&mut tt[3], hr[TH1], &b[1]);
            }
            for (l, tl) in t[r].iter_mut().enumerate() {
                *tl = [tt[0][l], tt[1][l], tt[2][l], tt[3][l]];
            }
        }
        // K[(k, α)][l] += w Σ_a β^a_k T[3a+α][l] on the upper blocks l ≥ k,
        // the sum over a formed in registers (one store per block row).
        for k in 0..4 {
            let mut wb = [0.0f64; 3];
            for (a, x) in wb.iter_mut().enumerate().take(np) {
                *x = w * b[a + 1][k];
            }
            for al in 0..3 {
                let row = &mut self.k[k * 4 + al];
                for l in k..4 {
                    let mut acc = [0.0f64; 4];
                    for (a, &x) in wb.iter().enumerate().take(np) {
                        axpy4(&mut acc, x, &t[3 * a + al][l]);
                    }
                    axpy4(&mut row[l], 1.0, &acc);
                }
            }
            if th || th1 {
                let (w0, w1) = (w * b[0][k], w * b[1][k]);
                let row = &mut self.k[k * 4 + 3];
                for l in k..4 {
                    let mut acc = [0.0f64; 4];
                    if th {
                        axpy4(&mut acc, w0, &t[TH][l]);
                    }
                    if th1 {
                        axpy4(&mut acc, w1, &t[TH1][l]);
                    }
                    axpy4(&mut row[l], 1.0, &acc);
                }
            }
        }
    }

    /// Upper half of the 4·dofs block, row-major with stride 16.
    fn write_upper(&self, out: &mut SegBlock, dofs: usize) {
        for k in 0..4 {
            for al in 0..dofs {
                let ci = k * dofs + al;
                let row = &self.k[k * 4 + al];
                for l in k..4 {
                    for g in 0..dofs {
                        let cj = l * dofs + g;
                        if cj >= ci {
                            out.hess[ci * 16 + cj] = row[l][g];
                        }
                    }
                }
            }
        }
    }
}
