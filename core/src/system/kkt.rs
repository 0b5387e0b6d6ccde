//! Assembly and solution of the displacement-level KKT system (SPEC §4):
//!
//!   [ A   Lᵀ ] [ ΔX ]   [ B ]      A = c_m M + c_d D + K
//!   [ L  −C  ] [ −Λ ] = [ E ]      B = c_v M V + F + P
//!
//! (implicit Euler: c_m = 1/h², c_d = c_v = 1/h; statics: c_m = c_d = c_v = 0,
//! with relax's Levenberg–Marquardt damping added to the diagonal). Segment blocks are
//! scattered into the matrix (they overlap: summed); all buffers are reused
//! across steps.
use super::layout::Layout;
use super::matrix::{KktMatrix, Storage};
use crate::constraint::{ConstraintKind, Row, SlidingBlocks};
use crate::error::{Error, Result};
use crate::linalg::band::{solve_refined, BandColumnsMut, BandLdlt, BandLu};
use crate::linalg::sparse::{prefer_sparse, SparseLu};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Which factorisation solves the KKT system (SPEC §5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum LinearSolver {
    /// Narrow bands: band LDLᵀ where it applies (steps whose inertia is
    /// felt), else the pivoting band LU, then sparse; from half-bandwidth
    /// 40 on (measured crossover, `core/examples/band_vs_sparse.rs`):
    /// sparse first, band LU as the fallback. See [`Factorisation`].
    #[default]
    Auto,
    /// Band LDLᵀ where it applies, else (or when it declines) the band LU.
    Band,
    /// Always the pivoting band LU (for comparisons and diagnostics).
    BandLu,
    /// faer's sparse LDLᵀ (regularised), or its LU when that fails.
    Sparse,
}
/// The factorisation that solved a system. The chain tried is: for
/// `LinearSolver::Auto` on a narrow band, band LDLᵀ (where it applies) →
/// band LU → sparse; on a wide band (half-bandwidth ≥ 40), sparse → band LU;
/// `Band`: LDLᵀ → LU; `BandLu` and `Sparse` alone.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Factorisation {
    /// Unpivoted band LDLᵀ (systems with inertia).
    BandLdlt,
    /// Band LU with partial pivoting (LAPACK dgbtrf-style).
    #[default]
    BandLu,
    /// faer's sparse LDLᵀ (regularised) or LU with a fill-reducing ordering.
    Sparse,
}

/// What a successful solve used.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Solved {
    /// Relative residual after one step of iterative refinement.
    pub residual: f64,
    pub factorisation: Factorisation,
    /// Factorisations of the chain that failed before it.
    pub fallbacks: u8,
}

/// A kernel's zero pivot at row i becomes the named unknown of row i.
fn name_unknown(e: Error, describe: &impl Fn(usize) -> crate::error::Unknown) -> Error {
    match e {
        Error::Singular { unknown: Some(crate::error::Unknown::Index { index }), constraints, detail } => {
            Error::Singular { unknown: Some(describe(index)), constraints, detail }
        }
        other => other,
    }
}
use crate::rod::assemble::{assemble_ranges, Need, SegRange};
use crate::rod::drag::{Drag, SegDrag};
use crate::rod::{Rod, SegBlock};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coefficients {
    /// c_m on the mass matrix, c_d on the drag, c_v on the momentum M V of
    /// the right-hand side, c_k on the stiffness (elastic and force fields),
    /// c_f on the elastic forces P of the right-hand side.
    pub mass: f64,
    pub drag: f64,
    pub momentum: f64,
    pub stiffness: f64,
    pub force: f64,
    /// The stiffness leaves out compression's negative transverse stretch
    /// term (a linearised implicit step; see
    /// [`crate::rod::assemble::Need::StepHessian`]).
    pub step_stiffness: bool,
}

/// A constraint as the system sees it.
#[derive(Debug)]
pub struct ConstraintRef<'a> {
    /// Positions of its rods in the layout (the same twice for one rod).
    pub rods: [usize; 2],
    pub kind: &'a ConstraintKind,
    pub compliance: f64,
    /// Multipliers of the previous solve (for the sliders' second-order blocks).
    pub lambda: &'a [f64],
    /// A violation up to this much (the measure's unit) is held rather
    /// than corrected (contact rows in dynamics; 0 elsewhere).
    pub slack: f64,
    /// A compliant constraint that is an elastic energy ½ g²/α (a world
    /// constraint without sliders): weighted like the rods' elastic forces,
    /// c_k of its force at the solve's end (compliance α/c_k) and the rest
    /// at the step's start, so that the trapezoidal rule averages it as it
    /// does them. False: held at the solve's end (rigid rows, contacts,
    /// friction's regularised rows).
    pub elastic: bool,
}

/// A bead whose abscissa is an unknown (statics): load F (force unit) and mass.
pub struct BeadRef {
    pub rod: usize,
    pub u: f64,
    pub load: [f64; 3],
    pub mass: f64,
}

/// Segments per kernel batch: one thread keeps 16 × 2.2 KB in L1; with
/// rayon a batch must be large enough to pay for waking the pool, and
/// below `PAR_MIN_SEGMENTS` in all the pool is not woken at all. Measured
/// on 2 cores (BENCHMARKS.md §16): with batches of 512 segments a 400-point
/// rod stepped 10 % slower on two threads than on one, 10,000 points 8 %
/// faster; with 4096, 10,000 points (one rod or 400 rods) 11–20 % faster.
/// (Free rods on a pool of two now assemble in two halves instead, each
/// in one-thread batches: [`band_cut`], BENCHMARKS.md §37.)
const SEQ_BATCH: usize = 16;
const PAR_BATCH: usize = 4096;
pub(crate) const PAR_MIN_SEGMENTS: usize = 2048;

/// The next kernel batch into `ranges`: up to `batch` segments from rod
/// `at.0`'s segment `at.1` on, spanning rods; `at` moves past them. Returns
/// the number of segments.
fn next_batch(rods: &[&Rod], batch: usize, at: &mut (usize, usize), ranges: &mut Vec<SegRange>) -> usize {
    ranges.clear();
    let mut filled = 0;
    let (r, first) = at;
    while filled < batch && *r < rods.len() {
        let nseg = rods[*r].n_segments();
        let m = (batch - filled).min(nseg - *first);
        if m > 0 {
            ranges.push(SegRange { rod: *r, first: *first, offset: filled, len: m });
        }
        filled += m;
        *first += m;
        if *first == nseg {
            *r += 1;
            *first = 0;
        }
    }
    filled
}

/// Adds c_m m b_k b_l I₃, a bead's mass on its segment's control points,
/// to the segment's block (upper half, rows of `d` dofs per point).
fn add_point_mass(blk: &mut SegBlock, d: usize, c_m: f64, pm: &PointMass) {
    let mb = c_m * pm.mass;
    for kk in 0..4 {
        for ll in kk..4 {
            let w = mb * pm.b[kk] * pm.b[ll];
            for a in 0..3 {
                let row = (kk * d + a) * 16 + ll * d;
                // The diagonal of I₃ (the upper half of a diagonal block too).
                blk.hess[row + a] += w;
            }
        }
    }
}

/// Turns a segment's stiffness block K into c_k K + c_m M + c_d D on each
/// axis (II.70–II.75, III.10), upper half only (M, J, D are symmetric, so
/// the upper half carries them).
fn add_inertia(blk: &mut SegBlock, d: usize, k: Coefficients, m: &[[f64; 4]; 4], j: &[[f64; 4]; 4], drag: Option<&SegDrag>) {
    if k.stiffness != 1.0 {
        let n = 4 * d;
        for row in 0..n {
            for x in &mut blk.hess[row * 16 + row..row * 16 + n] {
                *x *= k.stiffness;
            }
        }
    }
    for kk in 0..4 {
        for l in kk..4 {
            let (dt, dr) = drag.map_or((0.0, 0.0), |g| (k.drag * g.trans[kk][l], k.drag * g.roll[kk][l]));
            let t = k.mass * m[kk][l] + dt;
            for a in 0..3 {
                blk.hess[(kk * d + a) * 16 + l * d + a] += t;
            }
            if d == 4 {
                blk.hess[(kk * 4 + 3) * 16 + l * 4 + 3] += k.mass * j[kk][l] + dr;
            }
            // The tangential drag's 3×3 blocks (upper triangle of the
            // 16×16 block: all of (kk, l > kk), a ≤ b on the diagonal).
            if let Some(ax) = drag.and_then(|g| g.axial.as_ref()) {
                for a in 0..3 {
                    for b in if l == kk { a } else { 0 }..3 {
                        blk.hess[(kk * d + a) * 16 + l * d + b] += k.drag * ax[kk][l][a][b];
                    }
                }
            }
        }
    }
}

/// Where segment blocks go: the matrix (`M`: all of it, or a range of band
/// columns), the right-hand side from unknown `rhs_first` on and, when
/// recorded, the rods' elastic forces from rod `rod_first` on.
struct Sink<'a, M> {
    matrix: M,
    rhs: &'a mut [f64],
    rhs_first: usize,
    forces: Option<&'a mut [Vec<f64>]>,
    rod_first: usize,
}

/// A matrix, or part of one, that takes symmetric blocks.
trait BlockSink {
    fn add_sym_block(&mut self, idx: &[usize], upper: &[f64], stride: usize);
}

impl BlockSink for &mut KktMatrix {
    fn add_sym_block(&mut self, idx: &[usize], upper: &[f64], stride: usize) {
        KktMatrix::add_sym_block(self, idx, upper, stride);
    }
}

impl BlockSink for BandColumnsMut<'_> {
    fn add_sym_block(&mut self, idx: &[usize], upper: &[f64], stride: usize) {
        BandColumnsMut::add_sym_block(self, idx, upper, stride);
    }
}

/// What [`assemble_part`] reads.
struct Part<'a> {
    rods: &'a [&'a Rod],
    layout: &'a Layout,
    drags: &'a [Drag],
    /// External generalised forces per rod (rod-local).
    ext: &'a [Vec<f64>],
    point_masses: &'a [PointMass],
    k: Coefficients,
    need: Need,
}

/// Kernels and scatter of the rods `span` (their point masses `pm`, in
/// (rod, segment) order) into `sink`, in batches of `batch` segments. With
/// `next` buffers the kernels run on the pool and each batch is scattered
/// while the next one's run. `energy` takes each segment's energy in rod
/// and segment order.
#[allow(clippy::too_many_arguments)]
fn assemble_part<M: BlockSink + Send>(
    p: &Part,
    span: std::ops::Range<usize>,
    pm: &[usize],
    sink: &mut Sink<'_, M>,
    batch: usize,
    bufs: (&mut Vec<SegBlock>, &mut Vec<SegRange>),
    next: Option<(&mut Vec<SegBlock>, &mut Vec<SegRange>)>,
    energy: &mut (impl FnMut(f64) + Send),
) {
    let total: usize = p.rods[span.clone()].iter().map(|r| r.n_segments()).sum();
    let rods = &p.rods[..span.end];
    let mut at = (span.start, 0);
    let mut next_pm = 0;
    let mut scatter = |sink: &mut Sink<'_, M>, blocks: &mut [SegBlock], ranges: &[SegRange]| {
        for g in ranges {
            for (s, blk) in (g.first..).zip(blocks[g.offset..g.offset + g.len].iter_mut()) {
                energy(blk.energy);
                let drag = p.drags.get(g.rod).filter(|d| p.k.drag != 0.0 && **d != Drag::default());
                // The beads on this segment: their mass joins its block.
                let start = next_pm;
                while pm.get(next_pm).is_some_and(|&q| (p.point_masses[q].rod, p.point_masses[q].seg) <= (g.rod, s)) {
                    next_pm += 1;
                }
                let on_segment = pm[start..next_pm].iter().map(|&q| &p.point_masses[q]).filter(|b| (b.rod, b.seg) == (g.rod, s));
                scatter_segment(sink, p.layout, g.rod, p.rods[g.rod], s, blk, p.k, drag, on_segment);
            }
        }
    };
    let (mut blocks, mut ranges) = bufs;
    blocks.resize(batch.min(total), SegBlock::default());
    let filled = next_batch(rods, batch, &mut at, ranges);
    assemble_ranges(p.rods, ranges, &mut blocks[..filled], p.need, next.is_some());
    let Some((mut next_blocks, mut next_ranges)) = next else {
        loop {
            scatter(sink, blocks, ranges);
            if at.0 >= rods.len() {
                return;
            }
            let filled = next_batch(rods, batch, &mut at, ranges);
            assemble_ranges(p.rods, ranges, &mut blocks[..filled], p.need, false);
        }
    };
    next_blocks.resize(batch.min(total), SegBlock::default());
    loop {
        if at.0 >= rods.len() {
            scatter(sink, blocks, ranges);
            return;
        }
        let next_filled = next_batch(rods, batch, &mut at, next_ranges);
        // This batch is scattered (in rod and segment order) while the
        // next one's kernels run: on two threads the scatter, about a
        // tenth of a 400-rod step's CPU time, no longer waits for them
        // nor they for it.
        rayon::join(|| scatter(sink, blocks, ranges), || assemble_ranges(p.rods, next_ranges, &mut next_blocks[..next_filled], p.need, true));
        std::mem::swap(&mut blocks, &mut next_blocks);
        std::mem::swap(&mut ranges, &mut next_ranges);
    }
}

/// The right-hand side's rod part for the rods `span`: external forces
/// plus the momentum c_v M V (`mv` scratch), and their recorded forces
/// cleared.
fn rods_rhs<M>(p: &Part, span: std::ops::Range<usize>, sink: &mut Sink<'_, M>, mv: &mut Vec<f64>) {
    let k = p.k;
    for r in span {
        let rod = p.rods[r];
        let d = rod.dofs;
        if let Some(f) = sink.forces.as_deref_mut() {
            let f = &mut f[r - sink.rod_first];
            f.clear();
            f.resize(rod.v.len(), 0.0);
        }
        // Momentum term c_v M V.
        mv.resize(rod.v.len(), 0.0);
        if k.momentum != 0.0 {
            rod.mass_times(&rod.v, mv);
        }
        for i in 0..rod.n_ctrl() {
            for a in 0..d {
                let local = i * d + a;
                sink.rhs[p.layout.cp_index[r][i] + a - sink.rhs_first] += p.ext[r][local] + if k.momentum != 0.0 { k.momentum * mv[local] } else { 0.0 };
            }
        }
    }
}

/// Where the assembly may split in two for a pool of two threads: a rod k and a column c
/// such that the rods before k touch only columns < c and the others only
/// columns ≥ c (free rods laid out one after another), with at least a
/// quarter of the segments on each side; the one nearest the middle.
/// `first_col` is scratch.
fn band_cut(layout: &Layout, rods: &[&Rod], total: usize, first_col: &mut Vec<usize>) -> Option<(usize, usize)> {
    let n = rods.len();
    // first_col[r]: the first column of rods r.. (a suffix minimum).
    first_col.clear();
    first_col.resize(n + 1, usize::MAX);
    for r in (0..n).rev() {
        let lo = layout.cp_index[r].iter().copied().min().unwrap_or(usize::MAX);
        first_col[r] = first_col[r + 1].min(lo);
    }
    let (mut last, mut segs, mut best) = (0usize, 0usize, None::<(usize, usize, usize)>);
    for r in 0..n.saturating_sub(1) {
        if let Some(&hi) = layout.cp_index[r].iter().max() {
            last = last.max(hi + layout.dofs[r] - 1);
        }
        segs += rods[r].n_segments();
        let c = first_col[r + 1];
        if last < c && 4 * segs >= total && 4 * (total - segs) >= total {
            let off = segs.abs_diff(total - segs);
            if best.is_none_or(|(o, _, _)| off < o) {
                best = Some((off, r + 1, c));
            }
        }
    }
    best.map(|(_, k, c)| (k, c))
}

/// One segment's block into the right-hand side (−c_f ∂U/∂q) and the
/// matrix (c_k K + c_m M + c_d D, and the mass of the `beads` on it).
#[allow(clippy::too_many_arguments)]
fn scatter_segment<'p, M: BlockSink>(sink: &mut Sink<'_, M>, layout: &Layout, r: usize, rod: &Rod, s: usize, blk: &mut SegBlock, k: Coefficients, drag: Option<&Drag>, beads: impl Iterator<Item = &'p PointMass>) {
    let d = rod.dofs;
    let nl = 4 * d;
    let cache = &rod.cache;
    let ctrl = &cache.seg_ctrl[s];
    let mut idx = [0usize; 16];
    for kk in 0..4 {
        for a in 0..d {
            idx[kk * d + a] = layout.cp_index[r][ctrl[kk]] + a;
        }
    }
    let rhs0 = sink.rhs_first;
    if k.force == 1.0 {
        for (&gi, &g) in idx[..nl].iter().zip(&blk.grad[..nl]) {
            sink.rhs[gi - rhs0] -= g;
        }
    } else {
        for (&gi, &g) in idx[..nl].iter().zip(&blk.grad[..nl]) {
            sink.rhs[gi - rhs0] -= k.force * g;
        }
    }
    if let Some(f) = sink.forces.as_deref_mut() {
        let p = &mut f[r - sink.rod_first];
        for kk in 0..4 {
            for a in 0..d {
                p[ctrl[kk] * d + a] -= blk.grad[kk * d + a];
            }
        }
    }
    let drag = drag.map(|dr| rod.seg_drag(dr, s));
    add_inertia(blk, d, k, &cache.seg_mass[s], &cache.seg_inertia[s], drag.as_ref());
    for pm in beads {
        add_point_mass(blk, d, k.mass, pm);
    }
    sink.matrix.add_sym_block(&idx[..nl], &blk.hess, 16);
}

/// The storage an assembly uses: sparse where the sparse factorisation
/// comes first in the chain (a wide band, or asked for), band otherwise.
pub fn storage_for(layout: &Layout, solver: LinearSolver) -> Storage {
    let wide = solver == LinearSolver::Sparse || solver == LinearSolver::Auto && prefer_sparse(layout.n, layout.bandwidth);
    if wide && layout.n <= crate::linalg::csc::MAX_ORDER {
        Storage::Sparse
    } else {
        Storage::Band
    }
}

/// Largest relative residual accepted from the LDLᵀ path (after one step of
/// refinement) before falling back to the LU: an SPD solve lands at ~1e-17,
/// as the pivoting LU does; far above means A was not symmetric, or too
/// indefinite for the unpivoted factorisation.
const LDLT_MAX_RESIDUAL: f64 = 1e-14;

#[derive(Clone, Debug, Default)]
pub struct KktSystem {
    /// The assembled matrix, in band or sparse storage ([`storage_for`]).
    pub matrix: KktMatrix,
    /// The solver preference the next assembly picks its storage for.
    pub linear_solver: LinearSolver,
    pub lu: BandLu,
    /// Symmetric factorisation tried first when there are no multiplier rows.
    pub ldlt: BandLdlt,
    pub sparse: SparseLu,
    /// The factorisation of the last successful solve.
    pub used: Factorisation,
    pub rhs: Vec<f64>,
    pub sol: Vec<f64>,
    work: Vec<f64>,
    pub(crate) scale: Vec<f64>,
    /// Scratch of `equilibrate`: unknown i is a multiplier row.
    is_row: Vec<bool>,
    /// Point masses in (rod, segment) order ([`Self::assemble`]'s scratch).
    pm_order: Vec<usize>,
    /// Which unknowns are slider abscissae ([`Self::equilibrate`]'s scratch).
    is_extra: Vec<bool>,
    /// The last assembly had a positive mass coefficient c_m.
    inertia: bool,
    /// c_m × the largest mass per control point of the last assembly, and
    /// the smallest nonzero coordinate diagonal |A_ii| (from the
    /// equilibration): whether the inertia is felt on the softest unknown.
    mass_scale: f64,
    diag_min: f64,
    /// Kernel outputs of one batch of segments (reused).
    blocks: Vec<SegBlock>,
    /// The (rod, segments) pieces of the current kernel batch.
    ranges: Vec<SegRange>,
    /// The next batch's, computed while the current one is scattered.
    next_blocks: Vec<SegBlock>,
    next_ranges: Vec<SegRange>,
    rows: Vec<Row>,
    mv: Vec<f64>,
    /// When set, `assemble` keeps each rod's elastic forces P (rod-local
    /// coordinates) in `elastic_forces`.
    pub(crate) record_forces: bool,
    pub(crate) elastic_forces: Vec<Vec<f64>>,
    /// c_k of the last assembly: an elastic constraint's solved unknown is
    /// c_k × its multiplier ([`ConstraintRef::elastic`]).
    pub(crate) elastic_share: f64,
    /// The last assembly ran on rayon's pool (its passes over the band may too).
    parallel: bool,
    /// The split assembly's tail's c_v M V scratch.
    mv_tail: Vec<f64>,
    /// A split assembly's tail energies, per segment ([`Self::assemble`]).
    tail_energy: Vec<f64>,
    /// [`band_cut`]'s scratch.
    cut_scratch: Vec<usize>,
    /// Where the last assembly split its rods and columns (rod k, column c).
    pub(crate) assembly_cut: Option<(usize, usize)>,
}

/// A point mass (bead) on a rod: `mass` at the point of segment `seg` of
/// the rod at position `rod` in the layout whose basis is `b` on control
/// points `ctrl` (evaluated once by the caller, which spreads the bead's
/// force with it too). A sliding bead's motion along the rod is the
/// abscissa unknown of [`crate::pipeline::beads`], coupled to these
/// coordinates there. Its mass block joins its segment's before that is
/// scattered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointMass {
    pub rod: usize,
    /// The segment holding it (its control points are that segment's).
    pub seg: usize,
    pub ctrl: [usize; 4],
    pub b: [f64; 4],
    pub mass: f64,
}

impl KktSystem {
    /// Assembles A and B for `rods` (in layout order) with external
    /// generalised forces `ext[r]` and drag `drags[r]` (none when shorter).
    /// Returns the total elastic energy.
    pub fn assemble(
        &mut self,
        layout: &Layout,
        rods: &[&Rod],
        drags: &[Drag],
        ext: &[Vec<f64>],
        cons: &[ConstraintRef],
        point_masses: &[PointMass],
        field_stiffness: &[(usize, usize, usize, f64)],
        k: Coefficients,
        parallel: bool,
    ) -> Result<f64> {
        let bw = layout.bandwidth;
        // Drag holds the rigid modes as mass does (Brownian dynamics has no mass).
        let drag_of = |i: usize| drags.get(i).map_or(0.0, |d| d.trans);
        self.inertia = k.mass > 0.0 || k.drag > 0.0 && (0..rods.len()).all(|i| drag_of(i) > 0.0);
        self.mass_scale = rods
            .iter()
            .enumerate()
            .fold(0.0f64, |m, (i, r)| m.max((k.mass * r.mass() + k.drag * drag_of(i) * r.rest_length()) / r.n_ctrl() as f64));
        let total: usize = rods.iter().map(|r| r.n_segments()).sum();
        let parallel = parallel && total >= PAR_MIN_SEGMENTS;
        self.parallel = parallel;
        self.ldlt.set_parallel(parallel);
        self.matrix.reset(layout.n, bw, storage_for(layout, self.linear_solver), parallel);
        self.rhs.clear();
        self.rhs.resize(layout.n, 0.0);
        if self.record_forces {
            self.elastic_forces.resize_with(rods.len(), Vec::new);
        }
        self.elastic_share = k.stiffness;
        // Kernels in batches that stay in cache, each scattered at once in
        // rod and segment order. A batch spans rods, so that with rayon
        // many small rods (a fabric's yarns) run in parallel too.
        let mut energy = 0.0;
        let need = if k.step_stiffness { Need::StepHessian } else { Need::Hessian };
        let mut pm_order = std::mem::take(&mut self.pm_order);
        pm_order.clear();
        pm_order.extend(0..point_masses.len());
        pm_order.sort_unstable_by_key(|&p| (point_masses[p].rod, point_masses[p].seg, p));
        let part = Part { rods, layout, drags, ext, point_masses, k, need };
        // Two halves, one a thread, fit a pool of two (what was measured);
        // a larger pool keeps the pipelined kernels, which use it all.
        let cut = if parallel && rayon::current_num_threads() == 2 { band_cut(layout, rods, total, &mut self.cut_scratch) } else { None };
        let forces = self.record_forces.then_some(&mut self.elastic_forces[..]);
        self.assembly_cut = None;
        match cut.and_then(|(kr, c)| self.matrix.split_band_columns(c).map(|m| (kr, c, m))) {
            Some((kr, c, (head, tail))) => {
                self.assembly_cut = Some((kr, c));
                // Free rods side by side: each half's right-hand side,
                // kernels and scatter on a thread of its own, in the
                // one-thread batches; the tail's energies are added after
                // the head's, in the serial order.
                let (rhs_head, rhs_tail) = self.rhs.split_at_mut(c);
                let (f_head, f_tail) = match forces {
                    Some(f) => {
                        let (a, b) = f.split_at_mut(kr);
                        (Some(a), Some(b))
                    }
                    None => (None, None),
                };
                let mut head = Sink { matrix: head, rhs: rhs_head, rhs_first: 0, forces: f_head, rod_first: 0 };
                let mut tail = Sink { matrix: tail, rhs: rhs_tail, rhs_first: c, forces: f_tail, rod_first: kr };
                let (pm_head, pm_tail) = pm_order.split_at(pm_order.partition_point(|&p| point_masses[p].rod < kr));
                let tail_energy = &mut self.tail_energy;
                tail_energy.clear();
                let (b0, r0, b1, r1) = (&mut self.blocks, &mut self.ranges, &mut self.next_blocks, &mut self.next_ranges);
                let (mv0, mv1) = (&mut self.mv, &mut self.mv_tail);
                rayon::join(
                    || {
                        rods_rhs(&part, 0..kr, &mut head, mv0);
                        assemble_part(&part, 0..kr, pm_head, &mut head, SEQ_BATCH, (b0, r0), None, &mut |e| energy += e)
                    },
                    || {
                        rods_rhs(&part, kr..rods.len(), &mut tail, mv1);
                        assemble_part(&part, kr..rods.len(), pm_tail, &mut tail, SEQ_BATCH, (b1, r1), None, &mut |e| tail_energy.push(e))
                    },
                );
                for e in tail_energy.iter() {
                    energy += e;
                }
            }
            None => {
                let mut all = Sink { matrix: &mut self.matrix, rhs: &mut self.rhs, rhs_first: 0, forces, rod_first: 0 };
                rods_rhs(&part, 0..rods.len(), &mut all, &mut self.mv);
                let (batch, next) = if parallel { (PAR_BATCH, Some((&mut self.next_blocks, &mut self.next_ranges))) } else { (SEQ_BATCH, None) };
                assemble_part(&part, 0..rods.len(), &pm_order, &mut all, batch, (&mut self.blocks, &mut self.ranges), next, &mut |e| energy += e);
            }
        }
        self.pm_order = pm_order;
        // Point masses (beads): c_m m b_i b_j I₃ and c_v m b_i v(u).
        for pm in point_masses {
            let rod = rods[pm.rod];
            let (d, b) = (rod.dofs, &pm.b);
            let mut v = Vector3::zeros();
            for (kk, &i) in pm.ctrl.iter().enumerate() {
                v += Vector3::new(rod.v[i * d], rod.v[i * d + 1], rod.v[i * d + 2]) * b[kk];
            }
            // Its mass block went in with its segment's (scatter above).
            for kk in 0..4 {
                for a in 0..3 {
                    let gi = layout.cp_index[pm.rod][pm.ctrl[kk]] + a;
                    self.rhs[gi] += k.momentum * pm.mass * b[kk] * v[a];
                }
            }
        }
        // Stiffness −∂F/∂q of the force fields (harmonic traps), rod-local entries.
        for &(r, i, j, v) in field_stiffness {
            self.matrix.add(layout.dof(r, i), layout.dof(r, j), k.stiffness * v);
        }
        for (c, cr) in cons.iter().enumerate() {
            let nr = cr.kind.n_rows();
            self.rows.resize(nr.max(self.rows.len()), Row::default());
            let pair = [rods[cr.rods[0]], rods[cr.rods[1]]];
            cr.kind.linearize(&pair, &mut self.rows[..nr])?;
            let gx = layout.extra_index[c];
            if cr.kind.n_extra() > 0 {
                let mut sb = SlidingBlocks::default();
                cr.kind.sliding_blocks(&pair, cr.lambda, k.drag, &mut sb)?;
                for e in 0..cr.kind.n_extra() {
                    self.matrix.add(gx + e, gx + e, sb.diag[e]);
                    self.rhs[gx + e] = sb.rhs[e];
                }
                for &(w, local, v) in sb.coupling.entries() {
                    let gj = layout.dof(cr.rods[w as usize], local);
                    self.matrix.add(gj, gx, v);
                    self.matrix.add(gx, gj, v);
                }
            }
            for (i, row) in self.rows[..nr].iter().enumerate() {
                let gi = layout.row_index[c] + i;
                for &(w, local, v) in row.entries() {
                    let gj = if w == 2 { gx + local } else { layout.dof(cr.rods[w as usize], local) };
                    self.matrix.add(gi, gj, v);
                    self.matrix.add(gj, gi, v);
                }
                if cr.elastic {
                    // Unknown y = c_k g_end/α: c_k of the force −Lᵀg/α at
                    // the end; the rest, (1 − c_k) of it at the start, on
                    // the first solve of a step (later ones have it in the
                    // recorded forces' share, like the rods' P).
                    self.matrix.add(gi, gi, -cr.compliance / k.stiffness);
                    if self.record_forces {
                        for &(w, local, v) in row.entries() {
                            let f = v * row.rhs / cr.compliance;
                            self.elastic_forces[cr.rods[w as usize]][local] += f;
                            self.rhs[layout.dof(cr.rods[w as usize], local)] += (1.0 - k.stiffness) * f;
                        }
                    }
                } else {
                    self.matrix.add(gi, gi, -cr.compliance);
                }
                self.rhs[gi] = row.rhs - row.rhs.clamp(0.0, cr.slack);
            }
        }
        Ok(energy)
    }

    /// Levenberg–Marquardt damping: A_ii += λ max(|A_ii|, floor) on the
    /// coordinates and bead abscissae. Scale-free, unlike a mass term, so a
    /// heavy bead on a light string is damped as well as a uniform rod. Not
    /// on multiplier rows, nor on slider abscissae: their rows fix them, and
    /// damping them makes the rod move against its tension instead.
    pub fn damp(&mut self, layout: &Layout, lambda: f64) {
        let n = layout.n;
        let mut is_row = vec![false; n];
        for (c, &r0) in layout.row_index.iter().enumerate() {
            if layout.row_count[c] == 0 {
                continue; // a bead: its abscissa is damped
            }
            // The rows and the slider abscissae after them.
            for i in r0..layout.extra_index[c] + layout.extra_count[c] {
                is_row[i] = true;
            }
        }
        self.matrix.finish();
        let dmax = (0..n).filter(|&i| !is_row[i]).map(|i| self.matrix.diag(i).abs()).fold(0.0, f64::max);
        for i in (0..n).filter(|&i| !is_row[i]) {
            let a = self.matrix.diag(i).abs().max(1e-9 * dmax);
            self.matrix.add_diag(i, lambda * a);
        }
    }

    /// b − A ŷ, where ŷ is `z` on the multiplier rows and zero elsewhere:
    /// the generalised forces left once the constraint forces of `z`'s
    /// multipliers act (coordinate rows), and −c(q) + C y (multiplier
    /// rows). `scaled`: the matrix holds D A D (after a solve), undone here.
    pub fn residual_less_rows(&self, layout: &Layout, z: &[f64], scaled: bool) -> Vec<f64> {
        let mut r = self.rhs.clone();
        let d = |i: usize| if scaled { self.scale[i] } else { 1.0 };
        for (c, &r0) in layout.row_index.iter().enumerate() {
            for j in r0..r0 + layout.row_count[c] {
                if z[j] == 0.0 {
                    continue;
                }
                self.matrix.for_column(j, |i, a| {
                    if a != 0.0 {
                        r[i] -= a / (d(i) * d(j)) * z[j];
                    }
                });
            }
        }
        r
    }

    /// Which unknowns are multipliers (from the last solve's equilibration).
    pub fn multiplier_rows(&self) -> &[bool] {
        &self.is_row
    }

    /// Solves for the right-hand side now in `rhs` with the factors (and
    /// equilibration) of the last successful solve: a second right-hand
    /// side on that matrix, even after `matrix` was assembled anew (so
    /// without refinement).
    pub fn resolve(&mut self) -> Result<()> {
        self.sol.clear();
        self.sol.extend(self.rhs.iter().zip(&self.scale).map(|(b, d)| b * d));
        match self.used {
            Factorisation::BandLdlt => self.ldlt.solve_in_place(&mut self.sol)?,
            Factorisation::BandLu => self.lu.solve_in_place(&mut self.sol)?,
            Factorisation::Sparse => self.sparse.solve_in_place(&mut self.sol)?,
        }
        for (x, d) in self.sol.iter_mut().zip(&self.scale) {
            *x *= d;
        }
        if self.sol.iter().any(|x| !x.is_finite()) {
            return Err(Error::NonFinite { rod: None, detail: "re-solve with the last factors: non-finite solution".into() });
        }
        Ok(())
    }

    /// Bead abscissa unknowns (slots after the `n_cons` constraints):
    /// Π_b(u) = −F·r(u) gives rhs F·r'(u), diagonal −F·r''(u) + c_m m |r'|²
    /// (the bead's pseudo-inertia along the rod) and coupling −F_α b'_k(u).
    pub fn assemble_beads(&mut self, layout: &Layout, rods: &[&Rod], n_cons: usize, beads: &[BeadRef], k: Coefficients) -> Result<()> {
        for (j, b) in beads.iter().enumerate() {
            let g = layout.extra_index[n_cons + j];
            let rod = rods[b.rod];
            let (ctrl, bs) = rod.basis_at(b.u)?;
            let (d1, d2) = (rod.eval(b.u, 1)?, rod.eval(b.u, 2)?);
            let f = b.load;
            let dot = |v: [f64; 4]| f[0] * v[0] + f[1] * v[1] + f[2] * v[2];
            let speed2 = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2];
            self.matrix.add(g, g, -dot(d2) + k.mass * b.mass * speed2);
            self.rhs[g] = dot(d1);
            for kk in 0..4 {
                for a in 0..3 {
                    let gj = layout.cp_index[b.rod][ctrl[kk]] + a;
                    self.matrix.add(gj, g, -f[a] * bs[1][kk]);
                    self.matrix.add(g, gj, -f[a] * bs[1][kk]);
                }
            }
        }
        Ok(())
    }

    /// Entries stored by the last factorisation, fill included.
    pub fn factor_entries(&self) -> usize {
        match (self.used, self.matrix.as_band()) {
            (Factorisation::Sparse, _) | (_, None) => self.sparse.factor_nnz().unwrap_or(0),
            (_, Some(b)) => b.n() * (2 * b.kl() + b.ku() + 1),
        }
    }

    /// Symmetric scaling D A D: unit diagonal on coordinates, rows of unit
    /// max-norm on multipliers. Without it the multiplier pivots, O(L²/A),
    /// are ~1e-20 of the largest entry of a stiff rod and look singular.
    fn equilibrate(&mut self, layout: &Layout) {
        let n = layout.n;
        self.scale.clear();
        self.scale.resize(n, 1.0);
        // Reused across steps: no allocation in the time loop.
        let mut is_row = std::mem::take(&mut self.is_row);
        is_row.clear();
        is_row.resize(n, false);
        for (c, &r0) in layout.row_index.iter().enumerate() {
            for i in 0..layout.row_count[c] {
                is_row[r0 + i] = true;
            }
        }
        self.diag_min = f64::INFINITY;
        for i in 0..n {
            let a = self.matrix.diag(i).abs();
            if !is_row[i] && a > 0.0 {
                self.scale[i] = 1.0 / a.sqrt();
                self.diag_min = self.diag_min.min(a);
            }
        }
        // Slider abscissae: a frictionless one on a straight rod has a
        // diagonal of round-off (−λ·r″), whose scale would dwarf the rod's
        // entries of its rows (their pivots would vanish before it).
        let mut is_extra = std::mem::take(&mut self.is_extra);
        is_extra.clear();
        is_extra.resize(n, false);
        for (c, &x0) in layout.extra_index.iter().enumerate() {
            for i in 0..layout.extra_count.get(c).copied().unwrap_or(0) {
                is_extra[x0 + i] = true;
            }
        }
        for i in (0..n).filter(|&i| is_row[i]) {
            // Row i read as column i (contiguous): the assembly writes every
            // constraint entry with its transpose, so the KKT matrix is
            // symmetric (the LDLᵀ path relies on it too). Scaled by its rod
            // entries, where it has any.
            let (mut m, mut m_extra) = (0.0f64, 0.0f64);
            let scale = &self.scale;
            self.matrix.for_column(i, |r, a| {
                if is_extra[r] {
                    m_extra = m_extra.max((a * scale[r]).abs());
                } else if !is_row[r] {
                    m = m.max((a * scale[r]).abs());
                }
            });
            if m == 0.0 {
                m = m_extra;
            }
            if m > 0.0 {
                self.scale[i] = 1.0 / m;
            }
        }
        self.is_row = is_row;
        self.is_extra = is_extra;
        self.matrix.scale_symmetric(&self.scale, self.parallel);
        for (b, d) in self.rhs.iter_mut().zip(&self.scale) {
            *b *= d;
        }
    }

    /// The factorisations to try, in order, for this system and preference.
    fn chain(&self, layout: &Layout, solver: LinearSolver) -> ([Option<Factorisation>; 3], usize) {
        use Factorisation::*;
        // Without multiplier rows and with inertia (c_m > 0: dynamics and
        // pseudo-transient statics), A = c_m M + c_d D + K is symmetric and,
        // for a well-posed step, positive definite (mildly indefinite when
        // compression softens K): LDLᵀ does ¼ of the LU's work. With
        // multiplier rows the matrix is a saddle point, but the layout puts
        // each constraint's rows after at least half of the control points
        // it touches (IV.3), so its pivot is −(part of L A⁻¹ Lᵀ) < 0, not
        // zero: the unpivoted LDLᵀ still goes through on these
        // quasi-definite orderings (`factor_quasi_definite` expects those
        // negative pivots) — while the inertia is felt on the softest
        // coordinate (c_m m ≥ 1e-12 min|A_ii|; the largest diagonal, a
        // bending or torsion term growing like Δs⁻³…Δs⁻⁵, says nothing of
        // the rigid modes the mass holds): a step of 1e6 s is statics in
        // disguise, whose ill-conditioned saddle point the unpivoted
        // factorisation fails on.
        // Pure Newton statics (c_m = 0) start with the LU: a free rod's K is
        // singular only up to rounding, which the LU's zero-pivot test reports.
        let felt = layout.n_rows == 0 || self.mass_scale >= 1e-12 * self.diag_min;
        let ldlt = self.inertia && felt;
        // The band LU as a last resort for a wide band, while its storage
        // (n (3 bw + 1) entries) stays below 50 M entries (400 MB).
        let band_ok = layout.n.saturating_mul(3 * layout.bandwidth + 1) <= 50_000_000;
        let mut c = [None; 3];
        let mut k = 0;
        let mut push = |f: Factorisation| {
            c[k] = Some(f);
            k += 1;
        };
        match solver {
            LinearSolver::Auto if prefer_sparse(layout.n, layout.bandwidth) => {
                push(Sparse);
                if band_ok {
                    push(BandLu);
                }
            }
            LinearSolver::Auto | LinearSolver::Band => {
                if ldlt {
                    push(BandLdlt);
                }
                push(BandLu);
                if solver == LinearSolver::Auto {
                    push(Sparse);
                }
            }
            LinearSolver::BandLu => push(BandLu),
            LinearSolver::Sparse => {
                push(Sparse);
                // Before a failure is called singular, the band LU (exact
                // zero-pivot test, names the dependent row) where it fits.
                if band_ok {
                    push(BandLu);
                }
            }
        }
        (c, k)
    }

    /// Factorises and solves, trying the factorisations of the chain in
    /// order (see [`Factorisation`]) until one gives a solution whose
    /// residual and constraint rows check out. Zero pivots become
    /// `Error::Singular` naming the unknown; a truly singular system is
    /// reported with the last factorisation's diagnosis.
    pub fn solve(&mut self, layout: &Layout, solver: LinearSolver, describe: impl Fn(usize) -> crate::error::Unknown) -> Result<Solved> {
        // A right-hand side at underflow level (a system at exact rest) is
        // zero: its relative residual would only measure denormal noise.
        if self.rhs.iter().all(|b| b.abs() < f64::MIN_POSITIVE.sqrt()) {
            self.rhs.iter_mut().for_each(|b| *b = 0.0);
        }
        self.matrix.finish();
        self.equilibrate(layout);
        self.sol.resize(self.rhs.len(), 0.0);
        let (chain, len) = self.chain(layout, solver);
        let mut fallbacks = 0u8;
        let mut last = None;
        for f in chain[..len].iter().flatten() {
            match self.attempt(*f, layout, &describe) {
                Ok(res) => {
                    self.used = *f;
                    let res = self.finish_solve(res);
                    return Ok(Solved { residual: res, factorisation: *f, fallbacks });
                }
                Err(e) => {
                    if std::env::var_os("STRANDKIT_DEBUG").is_some() {
                        eprintln!("solve: {f:?} failed: {e}");
                    }
                    fallbacks += 1;
                    // The most informative diagnosis is reported: a zero
                    // pivot at a constraint row, then at another unknown
                    // (the first such), then an overflow (the entries are
                    // beyond range), then any other verdict (the latest).
                    let rank = |e: &Error| match e {
                        Error::Singular { unknown: Some(crate::error::Unknown::Multiplier { .. }), .. } => 4,
                        Error::Singular { unknown: Some(_), .. } => 3,
                        Error::NonFinite { .. } => 2,
                        _ => 1,
                    };
                    if last.as_ref().is_none_or(|l| rank(&e) > rank(l) || (rank(&e) == rank(l) && rank(l) < 3)) {
                        last = Some(e);
                    }
                }
            }
        }
        Err(last.unwrap_or_else(|| Error::singular("no factorisation applies")))
    }

    /// One factorisation: factor, solve with one step of refinement, check
    /// the residual and every constraint row. Returns the relative residual.
    fn attempt(&mut self, f: Factorisation, layout: &Layout, describe: &impl Fn(usize) -> crate::error::Unknown) -> Result<f64> {
        let mut res = match f {
            Factorisation::BandLdlt => {
                let band = self.matrix.band();
                self.ldlt.factor_quasi_definite(band, &self.is_row).map_err(|d| {
                    let at = match d {
                        crate::linalg::LdltDecline::Pivot { row, .. } => format!(" at {}", describe(row)),
                        _ => String::new(),
                    };
                    Error::singular(format!("band LDLᵀ declined: {d:?}{at}"))
                })?;
                let res = solve_refined(band, &self.ldlt, &self.rhs, &mut self.sol, &mut self.work, 1)?;
                if !(res <= LDLT_MAX_RESIDUAL) {
                    return Err(Error::singular(format!("band LDLᵀ residual {res:.3e}")));
                }
                res
            }
            Factorisation::BandLu => {
                let band = self.matrix.band();
                self.lu.factor(band).map_err(|e| name_unknown(e, describe))?;
                solve_refined(band, &self.lu, &self.rhs, &mut self.sol, &mut self.work, 1)?
            }
            Factorisation::Sparse => {
                match self.matrix.as_csc() {
                    Some(c) => self.sparse.factor_csc(c),
                    None => self.sparse.factor(self.matrix.band()),
                }
                .map_err(|e| name_unknown(e, describe))?;
                self.sol.copy_from_slice(&self.rhs);
                self.sparse.solve_refined_in_place(&mut self.sol)?
            }
        };
        if let Some(x) = self.sol.iter().position(|x| !x.is_finite()) {
            // The factorisation passed its pivot checks: the magnitudes
            // overflowed (loads or steps beyond the floating-point range).
            let unknown = describe(x);
            // With moderate entries a non-finite solution is a singular
            // system that slipped past the pivot checks.
            let big = |v: f64| !(v.abs() < 1e100);
            if !self.rhs.iter().any(|&b| big(b)) && !(0..layout.n).any(|i| big(self.matrix.diag(i))) {
                return Err(Error::Singular {
                    unknown: Some(unknown),
                    constraints: Vec::new(),
                    detail: format!("{f:?}: the solution is not finite though the system's entries are moderate: contradictory or dependent constraints, or a free motion"),
                });
            }
            let rod = match unknown {
                crate::error::Unknown::Coordinate { rod, .. } => Some(rod),
                _ => None,
            };
            return Err(Error::NonFinite {
                rod,
                detail: format!("{f:?}: the solution is not finite at {unknown} (loads, masses or the time step beyond the floating-point range?)"),
            });
        }
        // Each constraint row must hold on its own scale: contradictory
        // dependent rows are "solved" with huge multipliers and a violated
        // row, which the global relative residual hides. A regularised
        // sparse LDLᵀ's footprint δ y on rows whose terms are small beside
        // the system's (a Newton iterate near convergence) is not that:
        // refined row-wise, they hold.
        let mut rows = self.rows_hold(layout, describe);
        if rows.is_err() && f == Factorisation::Sparse {
            self.sol.copy_from_slice(&self.rhs);
            res = self.sparse.solve_refined_rowwise_in_place(&mut self.sol)?;
            rows = self.rows_hold(layout, describe);
        }
        rows?;
        if !(res < 1e-6) {
            return Err(Error::singular(format!("linear solve residual {res:.3e}: system numerically singular")));
        }
        Ok(res)
    }

    /// Every constraint row of the solution in `sol` holds to 1e-6 of its
    /// terms (or to 1e-12 in the equilibrated system's units).
    fn rows_hold(&self, layout: &Layout, describe: &impl Fn(usize) -> crate::error::Unknown) -> Result<()> {
        for (c, &r0) in layout.row_index.iter().enumerate() {
            for i in r0..r0 + layout.row_count[c] {
                let (mut acc, mut mag) = (-self.rhs[i], self.rhs[i].abs());
                let sol = &self.sol;
                self.matrix.for_row(i, |j, a| {
                    let t = a * sol[j];
                    acc += t;
                    mag += t.abs();
                });
                if acc.abs() > 1e-6 * mag.max(1e-300) && acc.abs() > 1e-12 {
                    let unknown = describe(i);
                    let constraints = match unknown {
                        crate::error::Unknown::Multiplier { constraint, .. } => vec![constraint],
                        _ => Vec::new(),
                    };
                    return Err(Error::Singular {
                        unknown: Some(unknown),
                        constraints,
                        detail: format!(
                            "constraint rows cannot all be met (row off by {:.1e} of its terms): contradictory or linearly dependent constraints",
                            acc.abs() / mag
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    /// Undoes the equilibration on the solution and the right-hand side
    /// (callers read constraint violations from the latter); returns `res`.
    fn finish_solve(&mut self, res: f64) -> f64 {
        for ((x, b), d) in self.sol.iter_mut().zip(self.rhs.iter_mut()).zip(&self.scale) {
            *x *= d;
            *b /= d;
        }
        res
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Material, RodBuilder, RodOptions, Section};

    /// The band's drag blocks (`add_inertia` with c_d = 1, the anisotropic
    /// 3×3 blocks included) against `Rod::drag_times`, on a 3-D helix with
    /// roll and a sampling length, its tangents frozen.
    #[test]
    fn assembled_drag_blocks_match_drag_times() {
        let mut rod = RodBuilder::helix(5.0, 3.0, 1.5)
            .control_points(9)
            .with_roll(true)
            .section(Section::circle(1.0).unwrap())
            .material(Material::new("dna", 300.0, 0.3, 1.7e-3).unwrap())
            .options(RodOptions { model: crate::energy::FrameModel::Reference, sampling_length: 2.0, roll_drag: 0.3, ..Default::default() })
            .build()
            .unwrap();
        rod.freeze_drag_frame();
        let drag = rod.drag(1.0).unwrap();
        assert!(drag.axial < 0.0);
        let (d, n) = (rod.dofs, rod.coords().len());
        let mut full = vec![vec![0.0; n]; n];
        let k = Coefficients { mass: 0.0, drag: 1.0, momentum: 0.0, stiffness: 1.0, force: 1.0, step_stiffness: false };
        for s in 0..rod.n_segments() {
            let mut blk = SegBlock::default();
            let sd = rod.seg_drag(&drag, s);
            add_inertia(&mut blk, d, k, &rod.cache.seg_mass[s], &rod.cache.seg_inertia[s], Some(&sd));
            let ctrl = rod.cache.seg_ctrl[s];
            for a in 0..4 * d {
                for b in a..4 * d {
                    let (i, j) = (ctrl[a / d] * d + a % d, ctrl[b / d] * d + b % d);
                    let v = blk.hess[a * 16 + b];
                    full[i][j] += v;
                    if a != b {
                        full[j][i] += v;
                    }
                }
            }
        }
        let mut worst: f64 = 0.0;
        let mut scale: f64 = 0.0;
        for j in 0..n {
            let mut e = vec![0.0; n];
            e[j] = 1.0;
            let mut y = vec![0.0; n];
            rod.drag_times(&drag, &e, &mut y);
            for i in 0..n {
                worst = worst.max((y[i] - full[i][j]).abs());
                scale = scale.max(y[i].abs());
            }
        }
        assert!(worst <= 1e-13 * scale, "band vs drag_times: {worst} of {scale}");
    }
}
