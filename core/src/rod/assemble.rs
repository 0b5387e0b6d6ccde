//! Per-segment energy, gradient and stiffness (SPEC §2, IV.1–IV.2): the
//! chain rule through the basis functions,
//!   ∂U/∂q_(k,α) = Σ_s w Σ_a β_k^a ∂W/∂d_(a,α),
//!   K_(kα)(lβ)  = Σ_s w Σ_{a,b} β_k^a β_l^b ∂²W/∂d_(a,α)∂d_(b,β),
//! where slot a of a position coordinate takes r', r'', r''' (β = b', b'', b''')
//! and of θ takes θ, θ' (β = b, b'). Only the upper half of each 16×16
//! (12×12) block is computed; segments run in parallel (rayon).
use super::samples::local_state;
use super::Rod;
use crate::energy::density;
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
    Energy,
    Gradient,
    Hessian,
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
            blocks.par_iter_mut().enumerate().with_min_len(16).for_each(|(s, b)| self.segment(first + s, b, need));
        } else {
            blocks.iter_mut().enumerate().for_each(|(s, b)| self.segment(first + s, b, need));
        }
    }

    /// Elastic energy U (energy unit).
    pub fn elastic_energy(&self) -> f64 {
        let mut b = SegBlock::default();
        (0..self.n_segments())
            .map(|s| {
                self.segment(s, &mut b, Need::Energy);
                b.energy
            })
            .sum()
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

    fn segment(&self, seg: usize, out: &mut SegBlock, need: Need) {
        let dofs = self.dofs;
        let nl = 4 * dofs;
        out.energy = 0.0;
        if need != Need::Energy {
            out.grad[..nl].iter_mut().for_each(|g| *g = 0.0);
        }
        if need == Need::Hessian {
            out.hess.iter_mut().for_each(|h| *h = 0.0);
        }
        let c = &self.cache;
        let ctrl = &c.seg_ctrl[seg];
        for s in &c.samples[c.seg_start[seg]..c.seg_start[seg + 1]] {
            let b = &s.basis;
            let ls = local_state(&self.q, dofs, ctrl, b);
            let e = density(&ls, &s.consts, self.opts.terms, self.opts.model, need != Need::Energy);
            out.energy += s.w * e.w;
            if need == Need::Energy {
                continue;
            }
            // slots[c] = the (d-index, β) pairs that local coordinate c feeds.
            let mut slots = [[(0usize, 0.0f64); 3]; 16];
            for k in 0..4 {
                for a in 0..3 {
                    slots[k * dofs + a] = [(a, b[1][k]), (3 + a, b[2][k]), (6 + a, b[3][k])];
                }
                if dofs == 4 {
                    slots[k * 4 + 3] = [(9, b[0][k]), (10, b[1][k]), (10, 0.0)];
                }
            }
            for (ci, sl) in slots.iter().enumerate().take(nl) {
                out.grad[ci] += s.w * sl.iter().map(|&(a, beta)| beta * e.grad[a]).sum::<f64>();
            }
            if need != Need::Hessian {
                continue;
            }
            // T = H B (11 × nl), then K = Bᵀ T on the upper half.
            let mut t = [[0.0f64; 11]; 16];
            for (ci, sl) in slots.iter().enumerate().take(nl) {
                for &(a, beta) in sl {
                    let col = e.hess.column(a);
                    for r in 0..11 {
                        t[ci][r] += beta * col[r];
                    }
                }
            }
            for (ci, sl) in slots.iter().enumerate().take(nl) {
                let row = &mut out.hess[ci * 16..ci * 16 + 16];
                for cj in ci..nl {
                    let tj = &t[cj];
                    row[cj] += s.w * sl.iter().map(|&(a, beta)| beta * tj[a]).sum::<f64>();
                }
            }
        }
    }
}
