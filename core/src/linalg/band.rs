//! General band matrix in LAPACK `dgbtrf` storage, a hand-written band LU
//! with partial pivoting (SPEC §5: the KKT matrix is banded, symmetric but
//! indefinite once it has multiplier rows, so Cholesky/LDLᵀ without pivoting
//! hits zero pivots), and an unpivoted band LDLᵀ ([`BandLdlt`]) for the
//! symmetric positive definite systems without multiplier rows, which
//! declines anything else so that the caller falls back to the LU.
//!
//! Storage (LAPACK `dgbmv`, 0-based): in a [`BandMatrix`], `A[i][j]` lives at
//! row `ku + i - j` of column `j` of an `ldab × n` column-major array,
//! `ldab = kl + ku + 1`. [`BandLu`] copies it into the `dgbtrf` layout
//! (`2 kl + ku + 1` rows, `A[i][j]` at row `kl + ku + i - j`), whose first `kl`
//! rows take the fill-in of U caused by row interchanges; keeping those rows
//! out of the matrix itself saves a third of the memory traffic of every
//! pass over it (assembly, equilibration, matvec).

use crate::error::{Error, Result};

/// Relative pivot threshold: a pivot is "zero" when `|p| <= PIVOT_TOL * max|a_ij|`.
/// (1e-15: the Frenet twist makes KKT matrices legitimately ill-conditioned,
/// ~1e14 after equilibration, near low-curvature points; callers check the residual.)
const PIVOT_TOL: f64 = 1e-15;

/// A general `n × n` band matrix with `kl` sub- and `ku` super-diagonals.
#[derive(Clone, Debug, Default)]
pub struct BandMatrix {
    n: usize,
    kl: usize,
    ku: usize,
    /// `kl + ku + 1`.
    ldab: usize,
    /// Column-major, `ldab * n` entries.
    data: Vec<f64>,
}

impl BandMatrix {
    /// A zero `n × n` matrix with `kl` sub- and `ku` super-diagonals.
    pub fn new(n: usize, kl: usize, ku: usize) -> Self {
        let mut m = Self::default();
        m.reshape(n, kl, ku);
        m
    }

    /// Change the shape and zero every entry; reuses the allocation when it is
    /// large enough (so a time loop allocates only on its first step).
    pub fn reshape(&mut self, n: usize, kl: usize, ku: usize) {
        self.n = n;
        self.kl = kl;
        self.ku = ku;
        self.ldab = kl + ku + 1;
        self.data.clear();
        self.data.resize(self.ldab * n, 0.0);
    }

    /// [`Self::reshape`], the zeros written on rayon's pool when `parallel`
    /// and the matrix is large (a memory-bound pass of a many-rod step).
    pub fn reshape_on(&mut self, n: usize, kl: usize, ku: usize, parallel: bool) {
        if !parallel {
            return self.reshape(n, kl, ku);
        }
        (self.n, self.kl, self.ku, self.ldab) = (n, kl, ku, kl + ku + 1);
        self.data.resize((kl + ku + 1) * n, 0.0);
        self.for_column_halves(true, |mut c| c.fill_zero());
    }

    /// `f` on the columns, in two halves on rayon's pool when `parallel`
    /// and the matrix is large (for passes whose entries are independent).
    pub fn for_column_halves(&mut self, parallel: bool, f: impl Fn(BandColumnsMut<'_>) + Sync) {
        if parallel && self.data.len() >= PAR_PASS_ENTRIES {
            let (head, tail) = self.split_columns_mut(self.n / 2);
            rayon::join(|| f(head), || f(tail));
        } else {
            f(self.columns_mut());
        }
    }

    /// Zero every entry, keeping the shape.
    pub fn fill_zero(&mut self) {
        self.data.fill(0.0);
    }

    pub fn n(&self) -> usize {
        self.n
    }
    pub fn kl(&self) -> usize {
        self.kl
    }
    pub fn ku(&self) -> usize {
        self.ku
    }

    /// True when `(i, j)` is inside the matrix and its band (`j - ku <= i <= j + kl`).
    #[inline]
    pub fn in_band(&self, i: usize, j: usize) -> bool {
        i < self.n && j < self.n && i <= j + self.kl && j <= i + self.ku
    }

    /// Column `j`'s in-band entries, rows `j − ku ..= j + kl` clipped to
    /// the matrix (contiguous in the column-major storage), and the first
    /// row.
    pub fn column(&self, j: usize) -> (usize, &[f64]) {
        let (i0, i1) = (j.saturating_sub(self.ku), (j + self.kl).min(self.n.saturating_sub(1)));
        let start = self.idx(i0, j);
        (i0, &self.data[start..start + (i1 + 1 - i0)])
    }

    /// Row `i`'s stored entries: the first column `j0` and the values of
    /// columns `j0..`, in order. Row i of column j sits at j·(ldab − 1) +
    /// ku + i: one stride through the columns, no per-entry band test.
    pub fn row(&self, i: usize) -> (usize, impl Iterator<Item = f64> + '_) {
        let (j0, j1) = (i.saturating_sub(self.kl), (i + self.ku + 1).min(self.n));
        let start = if j0 < j1 { self.idx(i, j0) } else { 0 };
        // (A diagonal matrix, ldab = 1, has one entry a row: any stride.)
        (j0, self.data[start..].iter().step_by((self.ldab - 1).max(1)).take(j1.saturating_sub(j0)).copied())
    }

    /// Index of `(i, j)` in `data`; caller guarantees `in_band(i, j)`.
    #[inline]
    fn idx(&self, i: usize, j: usize) -> usize {
        // ku + i - j >= 0 because j <= i + ku.
        j * self.ldab + self.ku + i - j
    }

    /// Entry `(i, j)`; 0 outside the band or the matrix.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        if self.in_band(i, j) {
            self.data[self.idx(i, j)]
        } else {
            0.0
        }
    }

    /// `A[i][j] += v`. Out-of-band writes are a caller bug: they trip a
    /// debug assertion and are ignored in release builds.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(
            self.in_band(i, j),
            "BandMatrix::add({i}, {j}) outside the band (n={}, kl={}, ku={})",
            self.n,
            self.kl,
            self.ku
        );
        if self.in_band(i, j) {
            let k = self.idx(i, j);
            self.data[k] += v;
        }
    }

    /// `A[i][j] = v`. Same out-of-band policy as [`BandMatrix::add`].
    #[inline]
    pub fn set(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(
            self.in_band(i, j),
            "BandMatrix::set({i}, {j}) outside the band (n={}, kl={}, ku={})",
            self.n,
            self.kl,
            self.ku
        );
        if self.in_band(i, j) {
            let k = self.idx(i, j);
            self.data[k] = v;
        }
    }

    /// [`Self::matvec`] for a matrix that falls apart at column `c` (no
    /// entry couples columns < c with columns ≥ c; 0: not split): the two
    /// diagonal blocks' products on rayon's pool. Entries across `c` are
    /// not read: the caller vouches that they are zero. The serial product
    /// only adds exact zeros there, so for a finite `x` the result is its
    /// own bit for bit (y starts at +0, and adding ±0 never makes −0).
    pub fn matvec_split(&self, x: &[f64], y: &mut [f64], c: usize) {
        if c == 0 || c >= self.n || x.len() != self.n || y.len() != self.n {
            return self.matvec(x, y);
        }
        let (y0, y1) = y.split_at_mut(c);
        rayon::join(|| self.matvec_block(x, y0, 0, c), || self.matvec_block(x, y1, c, self.n));
    }

    /// Rows and columns `first..end` of `A x` into `y` (columns in turn).
    fn matvec_block(&self, x: &[f64], y: &mut [f64], first: usize, end: usize) {
        y.fill(0.0);
        for j in first..end {
            let xj = x[j];
            if xj == 0.0 {
                continue;
            }
            let i0 = j.saturating_sub(self.ku).max(first);
            let i1 = (j + self.kl).min(end - 1);
            let base = j * self.ldab + self.ku - j;
            for (yi, &a) in y[i0 - first..=i1 - first].iter_mut().zip(&self.data[base + i0..=base + i1]) {
                *yi += a * xj;
            }
        }
    }

    /// `y = A x`.
    ///
    /// # Panics
    /// If `x` or `y` does not have length `n` (a programming error, not user input).
    pub fn matvec(&self, x: &[f64], y: &mut [f64]) {
        assert!(
            x.len() == self.n && y.len() == self.n,
            "BandMatrix::matvec: length mismatch"
        );
        y.fill(0.0);
        // Column-oriented axpy: each column's band is contiguous.
        for (j, &xj) in x.iter().enumerate() {
            if xj == 0.0 {
                continue;
            }
            let i0 = j.saturating_sub(self.ku);
            let i1 = (j + self.kl).min(self.n - 1);
            let base = j * self.ldab + self.ku - j;
            let col = &self.data[base + i0..=base + i1];
            for (yi, &a) in y[i0..=i1].iter_mut().zip(col) {
                *yi += a * xj;
            }
        }
    }

    /// Largest `|a_ij|` (NaN entries are ignored by `f64::max`).
    pub fn max_abs(&self) -> f64 {
        self.data.iter().fold(0.0, |m, v| m.max(v.abs()))
    }

    /// `||A||_inf` (largest absolute row sum).
    fn norm_inf(&self, rows: &mut [f64]) -> f64 {
        rows.fill(0.0);
        for j in 0..self.n {
            let i0 = j.saturating_sub(self.ku);
            let i1 = (j + self.kl).min(self.n - 1);
            let base = j * self.ldab + self.ku - j;
            for (r, &a) in rows[i0..=i1]
                .iter_mut()
                .zip(&self.data[base + i0..=base + i1])
            {
                *r += a.abs();
            }
        }
        rows.iter().fold(0.0, |m, &v| m.max(v))
    }
}

/// LU factors `P A = L U` of a [`BandMatrix`] (LAPACK `dgbtf2` algorithm).
#[derive(Clone, Debug, Default)]
pub struct BandLu {
    n: usize,
    kl: usize,
    ku: usize,
    ldab: usize,
    /// L multipliers below the diagonal, U (with kl extra super-diagonals of fill) above.
    ab: Vec<f64>,
    /// Row `j` was interchanged with row `ipiv[j] >= j` at step `j`.
    ipiv: Vec<usize>,
    factored: bool,
    pivot_ratio: f64,
}

impl BandLu {
    pub fn new() -> Self {
        Self::default()
    }

    /// Copies `a` and factors it (dgbtf2-style: partial pivoting, fill within
    /// the kl extra rows). Allocates only when `a` is larger than any matrix
    /// factored before by this object.
    ///
    /// Errors: `InvalidInput` if an entry is NaN or infinite; `Singular("zero
    /// pivot at row k ...")` when at step `k` the largest candidate pivot is
    /// `<= 1e-15 * max|a_ij|` (column/unknown `k` depends linearly on the
    /// previous ones).
    pub fn factor(&mut self, a: &BandMatrix) -> Result<()> {
        let (n, kl, ku) = (a.n, a.kl, a.ku);
        let kv = kl + ku;
        let ldab = 2 * kl + ku + 1;
        self.factored = false;
        self.n = n;
        self.kl = kl;
        self.ku = ku;
        self.ldab = ldab;
        let mut amax = 0.0f64;
        for (k, &v) in a.data.iter().enumerate() {
            if !v.is_finite() {
                let (j, r) = (k / a.ldab, k % a.ldab);
                let i = (r + j) as isize - ku as isize;
                return Err(Error::input(format!(
                    "band matrix entry ({i}, {j}) is {v}"
                )));
            }
            amax = amax.max(v.abs());
        }
        // dgbtrf layout: kl zero rows of fill room above each column's band.
        self.ab.clear();
        self.ab.resize(ldab * n, 0.0);
        for (dst, src) in self.ab.chunks_exact_mut(ldab).zip(a.data.chunks_exact(a.ldab)) {
            dst[kl..].copy_from_slice(src);
        }
        self.ipiv.clear();
        self.ipiv.resize(n, 0);
        if n == 0 {
            self.factored = true;
            self.pivot_ratio = 1.0;
            return Ok(());
        }
        let tol = PIVOT_TOL * amax;

        // ju: last column touched by the U rows produced so far (dgbtf2).
        let mut ju = 0usize;
        for j in 0..n {
            let km = kl.min(n - 1 - j);
            let cj = j * ldab;
            // Partial pivoting: largest |entry| among the diagonal and km rows below.
            let mut jp = 0usize;
            let mut best = self.ab[cj + kv].abs();
            for (r, v) in self.ab[cj + kv + 1..=cj + kv + km].iter().enumerate() {
                if v.abs() > best {
                    best = v.abs();
                    jp = r + 1;
                }
            }
            self.ipiv[j] = j + jp;
            if !best.is_finite() || best <= tol {
                return Err(Error::pivot(
                    j,
                    format!("zero pivot at row {j} (|pivot| = {best:.3e} <= 1e-15 * max|a_ij| = {tol:.3e}): unknown {j} is linearly dependent on the previous ones"),
                ));
            }
            ju = ju.max((j + ku + jp).min(n - 1));
            if jp != 0 {
                // Swap rows j and j+jp over columns j..=ju; row j of column c
                // sits at offset kv + j - c (c - j <= kv, see ju).
                for c in j..=ju {
                    let base = c * ldab + kv + j - c;
                    self.ab.swap(base, base + jp);
                }
            }
            if km > 0 {
                let (head, tail) = self.ab.split_at_mut(cj + ldab);
                let inv = 1.0 / head[cj + kv];
                let l = &mut head[cj + kv + 1..=cj + kv + km];
                for v in l.iter_mut() {
                    *v *= inv;
                }
                let l = &*l;
                // Rank-1 update of the trailing block, one contiguous column at a time.
                for c in j + 1..=ju {
                    let base = (c - j - 1) * ldab + kv + j - c;
                    let t = tail[base];
                    if t != 0.0 {
                        for (d, &m) in tail[base + 1..=base + km].iter_mut().zip(l) {
                            *d -= m * t;
                        }
                    }
                }
            }
        }
        let (mut pmin, mut pmax) = (f64::INFINITY, 0.0f64);
        for col in self.ab.chunks_exact(ldab) {
            let p = col[kv].abs();
            pmin = pmin.min(p);
            pmax = pmax.max(p);
        }
        self.pivot_ratio = pmin / pmax;
        self.factored = true;
        Ok(())
    }

    /// Overwrites `b` with `A⁻¹ b` (LAPACK `dgbtrs`, no transpose).
    pub fn solve_in_place(&self, b: &mut [f64]) -> Result<()> {
        if !self.factored {
            return Err(Error::input(
                "BandLu::solve_in_place called without a successful factor()",
            ));
        }
        let (n, kl, ldab) = (self.n, self.kl, self.ldab);
        let kv = kl + self.ku;
        super::check_rhs(b, n)?;
        // Forward: apply P and L (unit lower, kl multipliers per column).
        if kl > 0 {
            for j in 0..n.saturating_sub(1) {
                let l = self.ipiv[j];
                if l != j {
                    b.swap(l, j);
                }
                let bj = b[j];
                if bj != 0.0 {
                    let lm = kl.min(n - 1 - j);
                    let c = j * ldab + kv;
                    for (bi, &m) in b[j + 1..=j + lm].iter_mut().zip(&self.ab[c + 1..=c + lm]) {
                        *bi -= m * bj;
                    }
                }
            }
        }
        // Backward: U has kv = kl + ku super-diagonals after fill-in.
        for j in (0..n).rev() {
            let c = j * ldab + kv;
            b[j] /= self.ab[c];
            let t = b[j];
            if t != 0.0 {
                let i0 = j.saturating_sub(kv);
                for (bi, &u) in b[i0..j].iter_mut().zip(&self.ab[c - (j - i0)..c]) {
                    *bi -= u * t;
                }
            }
        }
        Ok(())
    }

    /// Smallest |pivot| / largest |pivot| of the last successful factorisation
    /// (1 for an empty matrix, 0 when nothing is factored).
    pub fn pivot_ratio(&self) -> f64 {
        if self.factored {
            self.pivot_ratio
        } else {
            0.0
        }
    }
}

/// Relative pivot threshold of [`BandLdlt`]: pivot `d_j` must exceed
/// `LDLT_TOL * a_jj`. LDLᵀ of a positive definite matrix is backward stable
/// whatever the pivots, so this only sends numerically singular and
/// indefinite matrices to the pivoting [`BandLu`] (whose own threshold is
/// 1e-15 of the largest entry, i.e. of the unit diagonal after the KKT
/// equilibration), which then reports them as before. Legitimate pivots are
/// small: a 40000-point steel rod at dt = 1e-3 has d_j / a_jj ≈ 1e-9.5
/// (mass / h² against EA / Δs).
const LDLT_TOL: f64 = 1e-14;

/// Once a pivot is negative (A indefinite: e.g. a compressed string whose
/// negative geometric stiffness exceeds its mass term, or a quasi-definite
/// ordering), LDLᵀ without pivoting is no longer backward stable by itself:
/// entries of L grow like 1/|d_j|. Every pivot from there on must then
/// satisfy `|d_j| > LDLT_INDEF_TOL * a_jj`, or (a positive pivot) make an
/// update no larger than a_jj / LDLT_INDEF_TOL (growth ≤ 1e6); the caller's
/// residual check after refinement decides whether the result is kept.
const LDLT_INDEF_TOL: f64 = 1e-6;

/// Smallest |pivot| of a multiplier row in [`BandLdlt::factor_quasi_definite`]
/// (after the KKT equilibration; see there).
const LDLT_ROW_TOL: f64 = 1e-12;

/// Why [`BandLdlt::factor`] declined a matrix (the caller falls back to [`BandLu`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LdltDecline {
    /// `kl != ku`: not the band of a symmetric matrix.
    NotSymmetricBand,
    /// An entry of the lower band is NaN or infinite.
    NonFinite,
    /// Pivot `d` at row `row` is too small: `d <= LDLT_TOL * a_jj` while A
    /// looks positive definite, `|d| <= LDLT_INDEF_TOL * a_jj` (with a growth
    /// above 1e6 for a positive pivot) once a negative
    /// pivot was met, or NaN.
    Pivot { row: usize, d: f64 },
}

/// `A = L D Lᵀ` of a symmetric [`BandMatrix`] without pivoting (L unit lower
/// with `kd = kl` sub-diagonals, D diagonal). SPEC §5: a KKT matrix without
/// multiplier rows is `c_m M + c_d D + K`, symmetric and, for a well-posed
/// dynamic step, positive definite, so the symmetric factorisation (n·kd²
/// flops against the LU's 2·n·kl·(kl+ku)) applies. Mildly indefinite
/// matrices are factored too (see `LDLT_INDEF_TOL`); small pivots are
/// declined and the caller uses [`BandLu`]. Only the lower band of `A` is
/// read: the caller guarantees symmetry (the KKT assembly adds every
/// off-diagonal entry twice), and must check the residual against the full
/// `A` (as [`solve_refined`] reports it) before trusting the solution.
#[derive(Clone, Debug, Default)]
pub struct BandLdlt {
    n: usize,
    kd: usize,
    /// `kd + 1`: column j holds D_j then L[j+1..=j+kd][j] (LAPACK `pbtrf` 'L' layout).
    ld: usize,
    l: Vec<f64>,
    /// ‖A‖_inf, from the copy pass (A symmetric: row sums = column sums).
    anorm: f64,
    rows: Vec<f64>,
    factored: bool,
    pivot_ratio: f64,
    /// Whether a matrix that falls apart in two may be factored and solved
    /// on rayon's pool ([`Self::set_parallel`]).
    parallel: bool,
    /// 0, or the column c at which the last matrix fell apart: no entry
    /// couples columns < c with columns ≥ c (many free rods), so the two
    /// diagonal blocks are factored and solved independently.
    split: usize,
}

/// Smallest band (stored entries) whose elementwise passes (zeros,
/// scaling, products) run in halves on the pool when asked: 2 MB.
const PAR_PASS_ENTRIES: usize = 1 << 18;

/// Smallest matrix (n · (kd + 1) stored entries) whose halves go to two
/// threads: below it waking the pool costs more than half a factorisation.
const PAR_MIN_ENTRIES: usize = 1 << 16;

impl BandLdlt {
    pub fn new() -> Self {
        Self::default()
    }

    /// Lets the factorisation and the solves of a matrix that falls apart in
    /// two diagonal blocks run the blocks on rayon's pool. The result is the
    /// serial one (an exact zero's sign aside): eliminating a column never
    /// touches the other block, where the serial loop only subtracts exact
    /// zeros.
    pub fn set_parallel(&mut self, parallel: bool) {
        self.parallel = parallel;
    }

    /// The column at which the last factored matrix fell apart (0: none, or
    /// not looked for).
    pub fn split(&self) -> usize {
        if self.factored {
            self.split
        } else {
            0
        }
    }

    /// Negative pivots of the last factorisation: by Sylvester's law of
    /// inertia, the number of negative eigenvalues of the factored matrix.
    pub fn negative_pivots(&self) -> usize {
        if !self.factored {
            return 0;
        }
        (0..self.n).filter(|&j| self.l[j * self.ld] < 0.0).count()
    }

    /// Copies the lower band of `a` (with ‖A‖_inf and a finiteness check in the
    /// same pass) and factors it in place. Allocates only when `a` is larger
    /// than any matrix factored before by this object.
    pub fn factor(&mut self, a: &BandMatrix) -> std::result::Result<(), LdltDecline> {
        self.factor_with(a, LDLT_TOL, LDLT_INDEF_TOL, &[])
    }

    /// `factor` for a quasi-definite KKT matrix [[H, Lᵀ], [L, −C]] in an
    /// interleaved order: `negative[j]` marks the multiplier rows, whose
    /// pivots are expected negative (−L H⁻¹ Lᵀ − C restricted to what is
    /// eliminated before them). Such a matrix has an LDLᵀ in any symmetric
    /// order with H positive definite (Vanderbei 1995), stable when H and
    /// the Schur complement are not too ill-conditioned (Gill, Saunders &
    /// Shinnerl 1996; the caller's residual check decides): a negative pivot
    /// at a row is therefore no sign of indefiniteness, and only a negative
    /// pivot at a coordinate switches to the stricter `LDLT_INDEF_TOL`. A
    /// row's pivot must be below −`LDLT_ROW_TOL` (rows are scaled to unit
    /// max-norm and coordinates to unit diagonal, so an independent row's
    /// pivot is O(1/bandwidth)); ≈ 0 means a dependent row.
    pub fn factor_quasi_definite(&mut self, a: &BandMatrix, negative: &[bool]) -> std::result::Result<(), LdltDecline> {
        self.factor_with(a, LDLT_TOL, LDLT_INDEF_TOL, negative)
    }

    /// The factorisation for counting the inertia ([`Self::negative_pivots`])
    /// rather than solving: a pivot counts as long as its sign is above
    /// round-off (|d| > 1e-12 a_jj), where `factor` asks 1e-6 of an
    /// indefinite matrix for a stable solve.
    pub fn factor_for_inertia(&mut self, a: &BandMatrix) -> std::result::Result<(), LdltDecline> {
        self.factor_with(a, 1e-12, 1e-12, &[])
    }

    fn factor_with(&mut self, a: &BandMatrix, tol_pd: f64, tol_indef: f64, negative: &[bool]) -> std::result::Result<(), LdltDecline> {
        self.factored = false;
        if a.kl != a.ku {
            return Err(LdltDecline::NotSymmetricBand);
        }
        let (n, kd) = (a.n, a.kl);
        let ld = kd + 1;
        self.n = n;
        self.kd = kd;
        self.ld = ld;
        self.copy_lower(a)?;
        let mut d_min = f64::INFINITY;
        let mut d_max = 0.0f64;
        let mut indefinite = false;
        // Eliminate every column first, then judge the pivots in order: the
        // verdict on pivot j depends on columns ≤ j only, which later steps
        // do not touch, so it is the verdict of a check made in passing (a
        // declined factorisation has only wasted the rest of the work).
        let c = self.split;
        if c > 0 {
            let (head, tail) = self.l.split_at_mut(c * ld);
            rayon::join(|| eliminate_all(head, c, kd), || eliminate_all(tail, n - c, kd));
        } else {
            eliminate_all(&mut self.l, n, kd);
        }
        for j in 0..n {
            let d = self.l[j * ld];
            let ajj = a.data[j * a.ldab + a.ku].abs();
            let ok = if negative.get(j).copied().unwrap_or(false) {
                d < -LDLT_ROW_TOL
            } else if d < 0.0 {
                indefinite = true;
                -d > tol_indef * ajj
            } else {
                // Once A showed indefinite, a small positive pivot is kept
                // if the update it makes stays small: |L| |D| |Lᵀ| (the
                // backward error's bound) grows by max a_ij² / d_j. A soft
                // mode's pivot at a stiff rod's end (the tip of a clamped
                // 1000-point rod: d ≈ 1e-9 a_jj, coupled only weakly to
                // what follows) passes; a pivot that would amplify its
                // neighbours does not.
                d > tol_pd * ajj && (!indefinite || d > tol_indef * ajj || self.growth(j) * tol_indef <= ajj)
            };
            if !ok {
                return Err(LdltDecline::Pivot { row: j, d });
            }
            d_min = d_min.min(d.abs());
            d_max = d_max.max(d.abs());
        }
        self.pivot_ratio = if n == 0 { 1.0 } else { d_min / d_max };
        self.factored = true;
        Ok(())
    }

    /// Lower band of `a` into `l` (column j: A[j..=j+kd][j], contiguous in
    /// both layouts), accumulating the absolute row sums on the way.
    fn copy_lower(&mut self, a: &BandMatrix) -> std::result::Result<(), LdltDecline> {
        let (n, kd, ld) = (self.n, self.kd, self.ld);
        let kv = a.ku;
        // Every entry of `l` is written below (no zero-fill pass first).
        self.l.resize(n * ld, 0.0);
        self.rows.clear();
        self.rows.resize(n, 0.0);
        // The split nearest the middle: a column c past the last row any
        // column before it reaches (its last nonzero).
        let look = self.parallel && n * ld >= PAR_MIN_ENTRIES;
        let (mut reach, mut split) = (0usize, 0usize);
        for (j, dst) in self.l.chunks_exact_mut(ld).enumerate() {
            let m = kd.min(n - 1 - j);
            let src = &a.data[j * a.ldab + kv..=j * a.ldab + kv + m];
            dst[..=m].copy_from_slice(src);
            dst[m + 1..].fill(0.0);
            if look {
                if let Some(last) = src.iter().rposition(|&v| v != 0.0) {
                    reach = reach.max(j + last);
                }
                if reach <= j && j + 1 < n && (j + 1).abs_diff(n / 2) < split.abs_diff(n / 2) {
                    split = j + 1;
                }
            }
            // Row j gets the whole column (symmetry: row j's upper part is
            // column j's lower part); rows below get their entry in column j.
            let mut col_sum = 0.0;
            for (r, &v) in self.rows[j + 1..=j + m].iter_mut().zip(&src[1..]) {
                *r += v.abs();
                col_sum += v.abs();
            }
            self.rows[j] += col_sum + src[0].abs();
        }
        // NaN and ±inf propagate into the sums of absolute values.
        let mut anorm = 0.0f64;
        for &r in &self.rows {
            if !r.is_finite() {
                return Err(LdltDecline::NonFinite);
            }
            anorm = anorm.max(r);
        }
        self.anorm = anorm;
        // Halves of very unequal size gain little on two threads.
        self.split = if 4 * split.min(n - split) >= n { split } else { 0 };
        Ok(())
    }

    /// The growth max_c a_c² / |d_j| of elimination step j (column j of A
    /// after the earlier steps), from the stored L[·][j] = a_c / d_j as
    /// |d_j| max_c L_c². Asked only when a small pivot must be judged.
    fn growth(&self, j: usize) -> f64 {
        let km = self.kd.min(self.n - 1 - j);
        let col = &self.l[j * self.ld..=j * self.ld + km];
        col[0].abs() * col[1..].iter().fold(0.0f64, |m, &l| m.max(l * l))
    }

    /// Smallest |D_j| / largest |D_j| of the last successful factorisation.
    pub fn pivot_ratio(&self) -> f64 {
        if self.factored {
            self.pivot_ratio
        } else {
            0.0
        }
    }

    /// A direction of negative curvature of the factored matrix, if it has
    /// one: x = L⁻ᵀ e_j for the most negative pivot j, so that
    /// xᵀ A x = D_j < 0.
    pub fn negative_direction(&self) -> Option<Vec<f64>> {
        if !self.factored {
            return None;
        }
        let (n, kd, ld) = (self.n, self.kd, self.ld);
        let j = (0..n).filter(|&j| self.l[j * ld] < 0.0).min_by(|&a, &b| self.l[a * ld].total_cmp(&self.l[b * ld]))?;
        let mut x = vec![0.0; n];
        x[j] = 1.0;
        for i in (0..j).rev() {
            let km = kd.min(n - 1 - i);
            let c = &self.l[i * ld + 1..=i * ld + km];
            x[i] = -c.iter().zip(&x[i + 1..=i + km]).map(|(m, v)| m * v).sum::<f64>();
        }
        Some(x)
    }

    /// Overwrites `b` with `A⁻¹ b`: L y = b, y /= D, Lᵀ x = y.
    pub fn solve_in_place(&self, b: &mut [f64]) -> Result<()> {
        if !self.factored {
            return Err(Error::input(
                "BandLdlt::solve_in_place called without a successful factor()",
            ));
        }
        let (n, kd, ld) = (self.n, self.kd, self.ld);
        super::check_rhs(b, n)?;
        let c = self.split;
        if c > 0 {
            let (l0, l1) = self.l.split_at(c * ld);
            let (b0, b1) = b.split_at_mut(c);
            rayon::join(|| ldlt_solve(l0, c, kd, b0), || ldlt_solve(l1, n - c, kd, b1));
        } else {
            ldlt_solve(&self.l, n, kd, b);
        }
        Ok(())
    }
}

/// Step j of the right-looking LDLᵀ on `l` (n columns, half-bandwidth kd,
/// `pbtrf` 'L' layout): D_j = updated a_jj; the trailing block gets
/// A[j+c..][j+c] −= A[j+c..][j] A[j+c][j] / D_j; column j is then scaled to
/// L[·][j] = A[·][j] / D_j (D_j stays at L[j][j], unchecked).
#[inline]
fn eliminate(l: &mut [f64], n: usize, kd: usize, j: usize) {
    let ld = kd + 1;
    let km = kd.min(n - 1 - j);
    let (head, tail) = l.split_at_mut((j + 1) * ld);
    let col = &mut head[j * ld..];
    let d = col[0];
    let inv = 1.0 / d;
    // Column j + c of the trailing block starts (c − 1) * ld into `tail`;
    // rows j + c ..= j + km of it are updated (lengths ≤ kd).
    for c in 1..=km {
        let t = col[c] * inv;
        if t != 0.0 {
            let dst = &mut tail[(c - 1) * ld..(c - 1) * ld + km - c + 1];
            for (x, &v) in dst.iter_mut().zip(&col[c..=km]) {
                *x -= t * v;
            }
        }
    }
    for v in &mut col[1..=km] {
        *v *= inv;
    }
}

/// Every elimination step of `l` (n columns, half-bandwidth kd). Interior
/// columns (j + kd < n) of the common half-bandwidths (a rod with 3 or 4
/// coordinates per control point: 11 or 15; 12–14 where constraint rows
/// interleave, as in the necklace's 14) run a kernel compiled for that
/// width. (256-bit vectors through runtime dispatch measured no faster
/// here: the elimination is bound by the pivot's division chain, not by
/// vector width.)
fn eliminate_all(l: &mut [f64], n: usize, kd: usize) {
    for j in 0..n {
        match kd {
            11 if j + kd < n => eliminate_fixed::<11, 12>(l, j),
            12 if j + kd < n => eliminate_fixed::<12, 13>(l, j),
            13 if j + kd < n => eliminate_fixed::<13, 14>(l, j),
            14 if j + kd < n => eliminate_fixed::<14, 15>(l, j),
            15 if j + kd < n => eliminate_fixed::<15, 16>(l, j),
            _ => eliminate(l, n, kd, j),
        }
    }
}

/// [`eliminate`] for a column with all KD sub-diagonal entries (j + KD < n)
/// at half-bandwidth KD = LD − 1. The same operations in the same order,
/// zero multipliers skipped as there (the KKT band is sparse where
/// constraint rows interleave: ≈2 % of the necklace's step).
#[inline(always)]
fn eliminate_fixed<const KD: usize, const LD: usize>(l: &mut [f64], j: usize) {
    debug_assert!(LD == KD + 1 && (j + KD + 1) * LD <= l.len());
    // The unrolled update below reaches c = 15 only.
    const { assert!(KD <= 15) };
    let (head, tail) = l.split_at_mut((j + 1) * LD);
    let col: &mut [f64; LD] = (&mut head[j * LD..]).try_into().expect("column j has LD entries (j < n)");
    let d = col[0];
    let inv = 1.0 / d;
    // Column j + c gets rows j + c ..= j + KD: KD + 1 − c entries, a
    // length known at compile time for each c (the macro unrolls c).
    macro_rules! update {
        ($($c:literal)*) => {$(
            if $c < LD {
                let len = LD - $c;
                let t = col[$c] * inv;
                if t != 0.0 {
                    let dst = &mut tail[($c - 1) * LD..($c - 1) * LD + len];
                    for (x, &v) in dst.iter_mut().zip(&col[$c..]) {
                        *x -= t * v;
                    }
                }
            }
        )*};
    }
    // c up to 15: the widest KD `eliminate_all` dispatches here.
    update!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15);
    for v in &mut col[1..] {
        *v *= inv;
    }
}

/// Overwrites `b` with the solution of L D Lᵀ x = b for the factor `l` (n
/// columns, half-bandwidth kd): L y = b, y /= D, Lᵀ x = y.
fn ldlt_solve(l: &[f64], n: usize, kd: usize, b: &mut [f64]) {
    let ld = kd + 1;
    // Forward (column axpy: L's columns are contiguous).
    for j in 0..n {
        let km = kd.min(n - 1 - j);
        let bj = b[j];
        if bj != 0.0 {
            let c = &l[j * ld + 1..=j * ld + km];
            for (bi, &m) in b[j + 1..=j + km].iter_mut().zip(c) {
                *bi -= m * bj;
            }
        }
    }
    for (bj, col) in b.iter_mut().zip(l.chunks_exact(ld)) {
        *bj /= col[0];
    }
    // Backward (dot products with the same columns, in four partial
    // sums: one running sum is a chain of kd dependent additions).
    for j in (0..n).rev() {
        let km = kd.min(n - 1 - j);
        let c = &l[j * ld + 1..=j * ld + km];
        b[j] -= dot4(&b[j + 1..=j + km], c);
    }
}

/// x · y in four interleaved partial sums (the lanes a vector unit keeps).
#[inline(always)]
fn dot4(x: &[f64], y: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let (xc, yc) = (x.chunks_exact(4), y.chunks_exact(4));
    let (xr, yr) = (xc.remainder(), yc.remainder());
    for (a, b) in xc.zip(yc) {
        for k in 0..4 {
            acc[k] += a[k] * b[k];
        }
    }
    for (k, (a, b)) in xr.iter().zip(yr).enumerate() {
        acc[k] += a * b;
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

/// A factorisation [`solve_refined`] can use.
pub trait BandFactor {
    /// Overwrites `b` with `A⁻¹ b`.
    fn solve_in_place(&self, b: &mut [f64]) -> Result<()>;
    /// True when this is a successful factorisation of a matrix of `a`'s shape.
    fn fits(&self, a: &BandMatrix) -> bool;
    /// ‖A‖_inf if the factorisation already computed it (saves a pass).
    fn anorm(&self) -> Option<f64> {
        None
    }
    /// The column at which the factored matrix falls apart, for the
    /// residual's product on rayon's pool (0: one block). The LDLᵀ finds
    /// it in the lower band, whose transpose is the upper one in the
    /// symmetric matrices it factors.
    fn split(&self) -> usize {
        0
    }
}

impl BandFactor for BandLu {
    fn solve_in_place(&self, b: &mut [f64]) -> Result<()> {
        BandLu::solve_in_place(self, b)
    }
    fn fits(&self, a: &BandMatrix) -> bool {
        self.factored && self.n == a.n && self.kl == a.kl && self.ku == a.ku
    }
}

impl BandFactor for BandLdlt {
    fn solve_in_place(&self, b: &mut [f64]) -> Result<()> {
        BandLdlt::solve_in_place(self, b)
    }
    fn fits(&self, a: &BandMatrix) -> bool {
        self.factored && self.n == a.n && self.kd == a.kl && a.kl == a.ku
    }
    fn anorm(&self) -> Option<f64> {
        Some(self.anorm)
    }
    fn split(&self) -> usize {
        BandLdlt::split(self)
    }
}

/// A relative residual at which refinement has nothing left to gain
/// (≈ 45 ulps of backward error): a refinement step costs a second solve
/// and residual, ≈ 5 % of a small scene's step, and the swinging
/// necklace's first solves land at 0.7–3e-14.
const REFINED_ENOUGH: f64 = 1e-14;

/// Solve `A x = b` with the factorisation `lu` of `a`, then `refine` steps of
/// iterative refinement (stopping early once the residual is at rounding
/// level, [`REFINED_ENOUGH`]). Returns the final relative residual
/// `||A x - b||_inf / (||A||_inf ||x||_inf + ||b||_inf)` (0 when that is 0/0).
/// `work` is scratch space, grown to `2 n` on first use. `lu` must be the
/// factorisation of `a` itself, not of another matrix of its shape: the
/// residual's product takes the blocks `a` falls apart into from it
/// ([`BandFactor::split`]).
pub fn solve_refined<F: BandFactor>(
    a: &BandMatrix,
    lu: &F,
    b: &[f64],
    x: &mut [f64],
    work: &mut Vec<f64>,
    refine: usize,
) -> Result<f64> {
    let n = a.n;
    if !lu.fits(a) {
        return Err(Error::input(
            "solve_refined: the factorisation does not belong to this matrix (factor it first)",
        ));
    }
    if b.len() != n || x.len() != n {
        return Err(Error::input(format!(
            "solve_refined: b has length {}, x has {}, the matrix has {n} rows",
            b.len(),
            x.len()
        )));
    }
    work.clear();
    work.resize(2 * n, 0.0);
    let (r, rows) = work.split_at_mut(n);
    let anorm = match lu.anorm() {
        Some(v) => v,
        None => a.norm_inf(rows),
    };
    let bnorm = inf_norm(b);
    x.copy_from_slice(b);
    lu.solve_in_place(x)?;
    let mut step = 0;
    loop {
        a.matvec_split(x, r, lu.split());
        for (ri, &bi) in r.iter_mut().zip(b) {
            *ri = bi - *ri;
        }
        let denom = anorm * inf_norm(x) + bnorm;
        let rnorm = inf_norm(r);
        let rel = if denom > 0.0 { rnorm / denom } else { rnorm };
        if step >= refine || rel <= REFINED_ENOUGH || !rel.is_finite() {
            return Ok(rel);
        }
        lu.solve_in_place(r)?;
        for (xi, &d) in x.iter_mut().zip(r.iter()) {
            *xi += d;
        }
        step += 1;
    }
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // dense reference code reads best with indices
mod tests {
    use super::*;

    use crate::linalg::synthetic::Lcg;

    /// Dense Gaussian elimination with partial pivoting (reference).
    fn dense_solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Vec<f64> {
        let n = b.len();
        for k in 0..n {
            let p = (k..n)
                .max_by(|&i, &j| a[i][k].abs().partial_cmp(&a[j][k].abs()).unwrap())
                .unwrap();
            a.swap(k, p);
            b.swap(k, p);
            for i in k + 1..n {
                let f = a[i][k] / a[k][k];
                for j in k..n {
                    a[i][j] -= f * a[k][j];
                }
                b[i] -= f * b[k];
            }
        }
        let mut x = vec![0.0; n];
        for i in (0..n).rev() {
            let s: f64 = (i + 1..n).map(|j| a[i][j] * x[j]).sum();
            x[i] = (b[i] - s) / a[i][i];
        }
        x
    }

    fn to_band(d: &[Vec<f64>]) -> BandMatrix {
        let n = d.len();
        let (mut kl, mut ku) = (0, 0);
        for i in 0..n {
            for j in 0..n {
                if d[i][j] != 0.0 {
                    kl = kl.max(i.saturating_sub(j));
                    ku = ku.max(j.saturating_sub(i));
                }
            }
        }
        let mut m = BandMatrix::new(n, kl, ku);
        for i in 0..n {
            for j in 0..n {
                if d[i][j] != 0.0 {
                    m.set(i, j, d[i][j]);
                }
            }
        }
        m
    }

    fn random_band(rng: &mut Lcg, n: usize, kl: usize, ku: usize, diag: f64) -> Vec<Vec<f64>> {
        let mut d = vec![vec![0.0; n]; n];
        for i in 0..n {
            for j in i.saturating_sub(kl)..(i + ku + 1).min(n) {
                d[i][j] = rng.next();
            }
            d[i][i] += diag;
        }
        d
    }

    fn check_against_dense(d: Vec<Vec<f64>>, rng: &mut Lcg) {
        let n = d.len();
        let a = to_band(&d);
        let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        let xref = dense_solve(d, b.clone());
        let mut lu = BandLu::new();
        lu.factor(&a).unwrap();
        let mut x = b.clone();
        lu.solve_in_place(&mut x).unwrap();
        let scale = inf_norm(&xref).max(1.0);
        for (xi, ri) in x.iter().zip(&xref) {
            assert!((xi - ri).abs() <= 1e-10 * scale, "{xi} vs {ri}");
        }
        let mut x2 = vec![0.0; n];
        let mut work = Vec::new();
        let res = solve_refined(&a, &lu, &b, &mut x2, &mut work, 2).unwrap();
        assert!(res < 1e-14, "relative residual {res}");
    }

    #[test]
    fn diagonally_dominant_matches_dense() {
        let mut rng = Lcg(1);
        for &(n, kl, ku) in &[
            (1, 0, 0),
            (5, 1, 1),
            (30, 2, 5),
            (30, 5, 2),
            (40, 0, 3),
            (40, 3, 0),
            (60, 7, 7),
        ] {
            let d = random_band(&mut rng, n, kl, ku, (kl + ku + 1) as f64 + 1.0);
            check_against_dense(d, &mut rng);
        }
    }

    #[test]
    fn general_random_needs_pivoting_matches_dense() {
        let mut rng = Lcg(7);
        for &(n, kl, ku) in &[(20, 3, 1), (25, 1, 4), (50, 4, 4)] {
            // No diagonal boost: pivots are chosen by value, rows get swapped.
            let d = random_band(&mut rng, n, kl, ku, 0.0);
            check_against_dense(d, &mut rng);
        }
    }

    /// KKT matrix [[K, Lᵀ], [L, 0]] ordered as in SPEC §5: each constraint row
    /// right after the last unknown it touches; zero diagonal blocks force pivoting.
    fn saddle_point(rng: &mut Lcg, n_ctrl: usize, every: usize) -> Vec<Vec<f64>> {
        let mut order = Vec::new(); // Some(ctrl index) or None for a constraint
        let mut cons = Vec::new(); // (position of the constraint, touched ctrl indices)
        for i in 0..n_ctrl {
            order.push(i);
            if i >= 2 && i % every == 0 {
                cons.push((order.len(), [i - 2, i - 1, i]));
                order.push(usize::MAX);
            }
        }
        let n = order.len();
        let pos: Vec<usize> = (0..n_ctrl)
            .map(|c| order.iter().position(|&o| o == c).unwrap())
            .collect();
        let mut d = vec![vec![0.0; n]; n];
        for c in 0..n_ctrl {
            let p = pos[c];
            d[p][p] = 4.0 + rng.next().abs();
            if c + 1 < n_ctrl {
                let q = pos[c + 1];
                let v = -1.0 + 0.1 * rng.next();
                d[p][q] = v;
                d[q][p] = v;
            }
        }
        for (row, touched) in cons {
            for &c in &touched {
                let v = rng.next();
                d[row][pos[c]] = v;
                d[pos[c]][row] = v;
            }
        }
        d
    }

    #[test]
    fn saddle_point_kkt_matches_dense() {
        let mut rng = Lcg(3);
        for &(n_ctrl, every) in &[(12, 2), (40, 3), (80, 2)] {
            let d = saddle_point(&mut rng, n_ctrl, every);
            assert!((0..d.len()).any(|i| d[i][i] == 0.0));
            check_against_dense(d, &mut rng);
        }
    }

    #[test]
    fn permutation_matrix_zero_diagonal() {
        let mut a = BandMatrix::new(2, 1, 1);
        a.set(0, 1, 2.0);
        a.set(1, 0, 3.0);
        let mut lu = BandLu::new();
        lu.factor(&a).unwrap();
        let mut b = [4.0, 9.0];
        lu.solve_in_place(&mut b).unwrap();
        assert_eq!(b, [3.0, 2.0]);
    }

    #[test]
    fn n_equals_one_and_zero() {
        let mut a = BandMatrix::new(1, 0, 0);
        a.set(0, 0, 4.0);
        let mut lu = BandLu::new();
        lu.factor(&a).unwrap();
        let mut b = [2.0];
        lu.solve_in_place(&mut b).unwrap();
        assert_eq!(b, [0.5]);
        assert_eq!(lu.pivot_ratio(), 1.0);
        lu.factor(&BandMatrix::new(0, 2, 2)).unwrap();
        lu.solve_in_place(&mut []).unwrap();
    }

    #[test]
    fn singular_matrix_reports_row() {
        // Rows 0..3 of a tridiagonal matrix with column 2 = column 1.
        let mut a = BandMatrix::new(4, 2, 2);
        for i in 0..4 {
            a.set(i, i, 1.0);
        }
        a.set(0, 1, 1.0);
        a.set(0, 2, 1.0);
        a.set(1, 2, 1.0);
        a.set(2, 1, 1.0);
        let mut lu = BandLu::new();
        match lu.factor(&a) {
            Err(e @ Error::Singular { .. }) => { let msg = e.to_string(); assert!(msg.contains("zero pivot at row 2"), "{msg}") }
            other => panic!("expected Singular, got {other:?}"),
        }
        assert!(lu.solve_in_place(&mut [0.0; 4]).is_err());
        // The zero matrix is singular at the first row.
        match lu.factor(&BandMatrix::new(3, 1, 1)) {
            Err(e @ Error::Singular { .. }) => { let msg = e.to_string(); assert!(msg.contains("row 0"), "{msg}") }
            other => panic!("expected Singular, got {other:?}"),
        }
    }

    #[test]
    fn near_singular_below_relative_threshold() {
        let mut a = BandMatrix::new(2, 1, 1);
        a.set(0, 0, 1e6);
        a.set(1, 1, 1e-10); // 1e-16 of the largest entry: below PIVOT_TOL
        assert!(matches!(BandLu::new().factor(&a), Err(Error::Singular { .. })));
        a.set(1, 1, 1e-8); // 1e-14: ill-conditioned but accepted
        assert!(BandLu::new().factor(&a).is_ok());
    }

    #[test]
    fn non_finite_entries_are_invalid_input() {
        let mut a = BandMatrix::new(3, 1, 1);
        for i in 0..3 {
            a.set(i, i, 1.0);
        }
        a.set(2, 1, f64::NAN);
        match BandLu::new().factor(&a) {
            Err(e @ Error::InvalidInput { .. }) => { let msg = e.to_string(); assert!(msg.contains("(2, 1)"), "{msg}") }
            other => panic!("expected InvalidInput, got {other:?}"),
        }
        a.set(2, 1, f64::INFINITY);
        assert!(matches!(
            BandLu::new().factor(&a),
            Err(Error::InvalidInput { .. })
        ));
        a.set(2, 1, 0.0);
        let mut lu = BandLu::new();
        lu.factor(&a).unwrap();
        assert!(matches!(
            lu.solve_in_place(&mut [1.0, f64::NAN, 0.0]),
            Err(Error::InvalidInput { .. })
        ));
        assert!(matches!(
            lu.solve_in_place(&mut [1.0, 0.0]),
            Err(Error::InvalidInput { .. })
        ));
    }

    #[test]
    fn accessors_matvec_and_band() {
        let mut rng = Lcg(11);
        let d = random_band(&mut rng, 9, 2, 3, 0.0);
        let a = to_band(&d);
        assert_eq!((a.n(), a.kl(), a.ku()), (9, 2, 3));
        assert!(
            a.in_band(5, 3)
                && a.in_band(3, 6)
                && !a.in_band(6, 3)
                && !a.in_band(3, 7)
                && !a.in_band(9, 9)
        );
        assert_eq!(a.get(8, 0), 0.0);
        let x: Vec<f64> = (0..9).map(|_| rng.next()).collect();
        let mut y = vec![0.0; 9];
        a.matvec(&x, &mut y);
        for i in 0..9 {
            let yr: f64 = (0..9).map(|j| d[i][j] * x[j]).sum();
            assert!((y[i] - yr).abs() < 1e-14);
            for j in 0..9 {
                assert_eq!(a.get(i, j), d[i][j]);
            }
        }
        let m = d.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        assert_eq!(a.max_abs(), m);
        let mut b = a.clone();
        b.add(4, 4, 1.5);
        assert_eq!(b.get(4, 4), d[4][4] + 1.5);
        b.fill_zero();
        assert_eq!(b.max_abs(), 0.0);
    }

    #[test]
    fn pivot_ratio_of_diagonal() {
        let mut a = BandMatrix::new(3, 1, 1);
        a.set(0, 0, 2.0);
        a.set(1, 1, -8.0);
        a.set(2, 2, 4.0);
        let mut lu = BandLu::new();
        assert_eq!(lu.pivot_ratio(), 0.0);
        lu.factor(&a).unwrap();
        assert_eq!(lu.pivot_ratio(), 0.25);
    }

    #[test]
    fn reuses_allocations() {
        let mut rng = Lcg(5);
        let d = random_band(&mut rng, 50, 4, 4, 10.0);
        let mut a = to_band(&d);
        let mut lu = BandLu::new();
        lu.factor(&a).unwrap();
        let (pa, pl, pp) = (a.data.as_ptr(), lu.ab.as_ptr(), lu.ipiv.as_ptr());
        a.reshape(40, 3, 4); // smaller: same buffer
        for i in 0..40 {
            a.set(i, i, 1.0);
        }
        lu.factor(&a).unwrap();
        assert_eq!(
            (pa, pl, pp),
            (a.data.as_ptr(), lu.ab.as_ptr(), lu.ipiv.as_ptr())
        );
        assert_eq!(a.get(1, 0), 0.0);
    }

    #[test]
    fn solve_refined_checks_shapes() {
        let mut a = BandMatrix::new(3, 1, 1);
        for i in 0..3 {
            a.set(i, i, 2.0);
        }
        let lu = BandLu::new();
        let mut x = [0.0; 3];
        let mut w = Vec::new();
        assert!(solve_refined(&a, &lu, &[1.0; 3], &mut x, &mut w, 1).is_err());
        let mut lu = BandLu::new();
        lu.factor(&a).unwrap();
        assert!(solve_refined(&a, &lu, &[1.0; 2], &mut x, &mut w, 1).is_err());
        let res = solve_refined(&a, &lu, &[1.0; 3], &mut x, &mut w, 1).unwrap();
        assert_eq!(x, [0.5; 3]);
        assert_eq!(res, 0.0);
    }

    /// Random symmetric band matrix, positive definite by diagonal dominance
    /// when `shift` > 0, plus its dense copy.
    fn random_spd(rng: &mut Lcg, n: usize, k: usize, shift: f64) -> (BandMatrix, Vec<Vec<f64>>) {
        let mut d = vec![vec![0.0; n]; n];
        for i in 0..n {
            for j in i.saturating_sub(k)..i {
                let v = rng.next();
                d[i][j] = v;
                d[j][i] = v;
            }
        }
        for i in 0..n {
            let off: f64 = d[i].iter().map(|v| v.abs()).sum();
            d[i][i] = off + shift * (1.0 + rng.next().abs());
        }
        let mut m = BandMatrix::new(n, k, k);
        for i in 0..n {
            for j in i.saturating_sub(k)..(i + k + 1).min(n) {
                m.set(i, j, d[i][j]);
            }
        }
        (m, d)
    }

    /// The unrolled kernels of half-bandwidths 11–15 do the generic
    /// elimination's arithmetic in the same order: the same matrix stored
    /// with half-bandwidth 16 (the generic path, whose extra diagonals are
    /// zero) gives bit-identical pivots and multipliers. Also with zeros
    /// that stay zero in the factor (each row's entries left of a varying
    /// envelope, as where a KKT band's constraint rows interleave): the
    /// zero multipliers both paths skip.
    #[test]
    fn fixed_width_elimination_is_the_generic_one_bit_for_bit() {
        let mut rng = Lcg(5);
        const WIDE: usize = 16; // no fixed kernel: the generic path
        for (k, envelope) in (11usize..=15).flat_map(|k| [(k, false), (k, true)]) {
            for n in [k + 1, 3 * k, 200] {
                let (mut a, mut d) = random_spd(&mut rng, n, k, 0.5);
                if envelope {
                    // Row i starts at column i − k + i % 4: no fill reaches
                    // left of it (every column m < j < start has L[i][m] = 0).
                    // Still diagonally dominant.
                    for i in 0..n {
                        for j in i.saturating_sub(k)..(i + i % 4).saturating_sub(k).min(i) {
                            d[i][j] = 0.0;
                            d[j][i] = 0.0;
                            a.set(i, j, 0.0);
                            a.set(j, i, 0.0);
                        }
                    }
                }
                let mut wide = BandMatrix::new(n, WIDE, WIDE);
                for i in 0..n {
                    for j in i.saturating_sub(k)..(i + k + 1).min(n) {
                        wide.set(i, j, d[i][j]);
                    }
                }
                let (mut f, mut g) = (BandLdlt::new(), BandLdlt::new());
                f.factor(&a).unwrap();
                g.factor(&wide).unwrap();
                for j in 0..n {
                    for c in 0..=k.min(n - 1 - j) {
                        assert_eq!(f.l[j * (k + 1) + c].to_bits(), g.l[j * (WIDE + 1) + c].to_bits(), "k={k} n={n} envelope {envelope} column {j} entry {c}");
                    }
                }
            }
        }
    }

    /// A random symmetric diagonally dominant band matrix of half-bandwidth
    /// k, built in band storage only, in which every entry coupling columns
    /// below `cut` with columns from `cut` on is zero when `apart`.
    fn random_blocks(rng: &mut Lcg, n: usize, k: usize, cut: usize, apart: bool) -> BandMatrix {
        let mut m = BandMatrix::new(n, k, k);
        let mut off = vec![0.0; n];
        for i in 0..n {
            for j in i.saturating_sub(k)..i {
                let v = if apart && j < cut && i >= cut { 0.0 } else { rng.next() };
                m.set(i, j, v);
                m.set(j, i, v);
                off[i] += v.abs();
                off[j] += v.abs();
            }
        }
        for (i, o) in off.iter().enumerate() {
            m.set(i, i, o + 0.5 * (1.0 + rng.next().abs()));
        }
        m
    }

    /// A matrix that falls apart in two is factored and solved as two
    /// blocks on the pool, with the serial answer bit for bit; a coupled one
    /// is not split (or split where it does fall apart).
    #[test]
    fn split_ldlt_is_the_serial_one_bit_for_bit() {
        let mut rng = Lcg(8);
        let (n, k) = (6000, 11);
        for (cut, apart) in [(3000, true), (2600, true), (3000, false), (500, true)] {
            let a = random_blocks(&mut rng, n, k, cut, apart);
            let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
            let (mut serial, mut pooled) = (BandLdlt::new(), BandLdlt::new());
            pooled.set_parallel(true);
            serial.factor(&a).unwrap();
            pooled.factor(&a).unwrap();
            // Halves under a quarter of the matrix are not worth a thread.
            let expected = if apart && 4 * cut.min(n - cut) >= n { cut } else { 0 };
            assert_eq!(pooled.split(), expected, "cut {cut}, apart {apart}");
            assert_eq!(serial.split(), 0);
            for (x, y) in serial.l.iter().zip(&pooled.l) {
                assert_eq!(x, y, "factor entries (cut {cut})");
            }
            let (mut xs, mut xp) = (b.clone(), b.clone());
            serial.solve_in_place(&mut xs).unwrap();
            pooled.solve_in_place(&mut xp).unwrap();
            assert_eq!(xs, xp, "solutions (cut {cut})");
            // And it is a solution: the residual against A.
            let mut ax = vec![0.0; n];
            a.matvec(&xs, &mut ax);
            let err = ax.iter().zip(&b).fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
            assert!(err < 1e-12, "residual {err:e}");
        }
    }

    #[test]
    fn ldlt_matches_lu_on_random_spd_band() {
        let mut rng = Lcg(21);
        for &(n, k) in &[(1, 0), (2, 1), (10, 0), (17, 3), (60, 7), (200, 15), (40, 45)] {
            let (a, d) = random_spd(&mut rng, n, k, 0.5);
            let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();
            let mut lu = BandLu::new();
            lu.factor(&a).unwrap();
            let mut xlu = b.clone();
            lu.solve_in_place(&mut xlu).unwrap();
            let mut ldlt = BandLdlt::new();
            ldlt.factor(&a).unwrap();
            let mut x = b.clone();
            ldlt.solve_in_place(&mut x).unwrap();
            let scale = inf_norm(&xlu).max(1.0);
            for (xi, ri) in x.iter().zip(&xlu) {
                assert!((xi - ri).abs() <= 1e-12 * scale, "n={n} k={k}: {xi} vs {ri}");
            }
            // ‖A‖_inf from the copy pass equals the full-band one.
            let mut rows = vec![0.0; n];
            assert!((ldlt.anorm - a.norm_inf(&mut rows)).abs() <= 1e-14 * ldlt.anorm);
            let (mut x2, mut w) = (vec![0.0; n], Vec::new());
            let res = solve_refined(&a, &ldlt, &b, &mut x2, &mut w, 1).unwrap();
            assert!(res < 1e-15, "relative residual {res}");
            assert!(ldlt.pivot_ratio() > 0.0 && ldlt.pivot_ratio() <= 1.0);
            let xref = dense_solve(d, b);
            for (xi, ri) in x2.iter().zip(&xref) {
                assert!((xi - ri).abs() <= 1e-12 * scale);
            }
        }
    }

    #[test]
    fn ldlt_declines_small_pivots_and_non_finite() {
        let mut rng = Lcg(4);
        let mut ldlt = BandLdlt::new();
        let mut lu = BandLu::new();
        let (mut x, mut w) = (vec![0.0; 30], Vec::new());
        // Mildly indefinite (one negative diagonal entry deep inside the
        // band): factored, same solution as the LU.
        let (mut a, _) = random_spd(&mut rng, 30, 4, 0.5);
        let v = a.get(17, 17);
        a.set(17, 17, -v);
        ldlt.factor(&a).unwrap();
        let b: Vec<f64> = (0..30).map(|_| rng.next()).collect();
        assert!(solve_refined(&a, &ldlt, &b, &mut x, &mut w, 1).unwrap() < 1e-15);
        lu.factor(&a).unwrap();
        let mut xlu = b.clone();
        lu.solve_in_place(&mut xlu).unwrap();
        for (xi, ri) in x.iter().zip(&xlu) {
            assert!((xi - ri).abs() <= 1e-12 * inf_norm(&xlu).max(1.0));
        }
        // Zero leading pivot (a saddle point ordered with the multiplier
        // first): declined, and the pivoting LU still solves it.
        let mut k = BandMatrix::new(2, 1, 1);
        k.set(0, 1, 1.0);
        k.set(1, 0, 1.0);
        k.set(1, 1, 2.0);
        assert_eq!(ldlt.factor(&k), Err(LdltDecline::Pivot { row: 0, d: 0.0 }));
        assert!(ldlt.solve_in_place(&mut [0.0; 2]).is_err());
        assert_eq!(ldlt.pivot_ratio(), 0.0);
        lu.factor(&k).unwrap();
        // Singular positive semi-definite [[1, 1], [1, 1]], and a tiny
        // negative pivot (indefinite, growth 1e9): declined.
        let mut s = BandMatrix::new(2, 1, 1);
        for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            s.set(i, j, 1.0);
        }
        assert!(matches!(ldlt.factor(&s), Err(LdltDecline::Pivot { row: 1, .. })));
        s.set(1, 1, 1.0 - 1e-9);
        assert!(matches!(ldlt.factor(&s), Err(LdltDecline::Pivot { row: 1, d }) if d < 0.0));
        // A tiny positive pivot on a positive definite matrix is accepted
        // (LDLᵀ of an SPD matrix is backward stable).
        s.set(1, 1, 1.0 + 1e-12);
        ldlt.factor(&s).unwrap();
        // Unsymmetric band shape, non-finite entries.
        assert_eq!(ldlt.factor(&BandMatrix::new(3, 1, 2)), Err(LdltDecline::NotSymmetricBand));
        let (mut a, _) = random_spd(&mut rng, 8, 2, 0.5);
        a.set(5, 4, f64::NAN);
        assert_eq!(ldlt.factor(&a), Err(LdltDecline::NonFinite));
        a.set(5, 4, f64::INFINITY);
        assert_eq!(ldlt.factor(&a), Err(LdltDecline::NonFinite));
        // Empty matrix.
        ldlt.factor(&BandMatrix::new(0, 2, 2)).unwrap();
        ldlt.solve_in_place(&mut []).unwrap();
    }

    /// The growth rule once A showed indefinite: a pivot δ = 1e-9 a_jj
    /// (cancellation: r, then a negative p, then q = 1 + δ coupled by 1 to
    /// r) coupled strongly to what follows (s, by c = 1: growth 1e9) is
    /// declined; coupled weakly (c = 1e-6: growth 1e-3), kept.
    #[test]
    fn ldlt_small_pivot_after_indefinite_declined_only_when_it_grows() {
        let mut a = BandMatrix::new(4, 2, 2);
        a.set(0, 0, 1.0);
        a.set(1, 1, -1.0);
        a.set(2, 2, 1.0 + 1e-9);
        a.set(3, 3, 1.0);
        a.set(0, 2, 1.0);
        a.set(2, 0, 1.0);
        for c in [1.0, 1e-6] {
            a.set(2, 3, c);
            a.set(3, 2, c);
            let r = BandLdlt::new().factor(&a);
            assert_eq!(r.is_ok(), c < 1e-3, "coupling {c}: {r:?}");
        }
    }

    /// A quasi-definite KKT matrix in an interleaved order: y0 pinned by
    /// row 0, then x0 –(spring 1)– x1 held only by a mass ε = 1e-9 until
    /// row 1 pins x1. x1's pivot is 2ε, coupled by 1 to row 1 (growth
    /// 1/(2ε)). `factor` reads row 0's negative pivot as indefiniteness and
    /// declines it; `factor_quasi_definite` knows the rows and solves like
    /// the LU.
    #[test]
    fn quasi_definite_ldlt_accepts_interleaved_rows() {
        let eps = 1e-9;
        // Order: y0, row0, x0, x1, row1.
        let mut a = BandMatrix::new(5, 1, 1);
        let sym = |a: &mut BandMatrix, i: usize, j: usize, v: f64| {
            a.set(i, j, v);
            a.set(j, i, v);
        };
        sym(&mut a, 0, 0, 1.0 + eps);
        sym(&mut a, 0, 1, 1.0);
        sym(&mut a, 2, 2, 1.0 + eps);
        sym(&mut a, 3, 3, 1.0 + eps);
        sym(&mut a, 2, 3, -1.0);
        sym(&mut a, 3, 4, 1.0);
        let negative = [false, true, false, false, true];
        let mut ldlt = BandLdlt::new();
        assert!(matches!(ldlt.factor(&a), Err(LdltDecline::Pivot { row: 3, d }) if d > 0.0));
        ldlt.factor_quasi_definite(&a, &negative).unwrap();
        assert_eq!(ldlt.negative_pivots(), 2);
        let b = [0.3, 0.5, -0.2, 0.1, -0.25];
        let (mut x, mut w) = (vec![0.0; 5], Vec::new());
        let res = solve_refined(&a, &ldlt, &b, &mut x, &mut w, 1).unwrap();
        assert!(res < 1e-15, "relative residual {res}");
        let mut lu = BandLu::new();
        lu.factor(&a).unwrap();
        let mut xlu = b.to_vec();
        lu.solve_in_place(&mut xlu).unwrap();
        let scale = inf_norm(&xlu);
        for (xi, ri) in x.iter().zip(&xlu) {
            assert!((xi - ri).abs() <= 1e-12 * scale, "{xi} vs {ri}");
        }
        // A row whose pivot is not negative (a dependent row: x0 pinned
        // twice) is declined.
        let mut d = BandMatrix::new(3, 2, 2);
        d.set(0, 0, 1.0);
        for (i, j) in [(1, 0), (0, 1), (2, 0), (0, 2)] {
            d.set(i, j, 1.0);
        }
        assert!(matches!(ldlt.factor_quasi_definite(&d, &[false, true, true]), Err(LdltDecline::Pivot { row: 2, .. })));
    }

    /// Blocks added to two column halves land where adding them to the
    /// whole matrix puts them (contiguous indices, indices with gaps, and
    /// in release builds a set spanning past the band, whose out-of-band
    /// entries are dropped); the product of a matrix that falls apart at c,
    /// taken in its two blocks, is the serial one bit for bit; and the
    /// elementwise passes on the pool (zeros, scaling) are the serial ones.
    #[test]
    fn column_halves_and_split_products_are_the_whole_matrix_ones() {
        let mut rng = Lcg(21);
        let (n, kd, c) = (40usize, 4usize, 17usize);
        let mut sets: Vec<Vec<usize>> = vec![vec![0, 1, 2, 3], vec![5, 6, 8, 9], vec![13, 14, 15, 16], vec![17, 18, 19, 20], vec![22, 23, 25, 26], vec![36, 37, 38, 39]];
        if !cfg!(debug_assertions) {
            sets.push(vec![27, 28, 34, 35]); // 35 − 27 > kd: entry by entry
        }
        let (mut whole, mut halves) = (BandMatrix::new(n, kd, kd), BandMatrix::new(n, kd, kd));
        for idx in &sets {
            let m = idx.len();
            let upper: Vec<f64> = (0..m * m).map(|_| rng.next() - 0.5).collect();
            whole.add_sym_block(idx, &upper, m);
            let (mut head, mut tail) = halves.split_columns_mut(c);
            if idx[0] < c {
                head.add_sym_block(idx, &upper, m);
            } else {
                tail.add_sym_block(idx, &upper, m);
            }
        }
        assert_eq!(whole.data, halves.data);
        // No set crosses c: the matrix falls apart there.
        let x: Vec<f64> = (0..n).map(|i| if i % 5 == 2 { 0.0 } else { rng.next() - 0.5 }).collect();
        let (mut y, mut y_split) = (vec![0.0; n], vec![0.0; n]);
        whole.matvec(&x, &mut y);
        whole.matvec_split(&x, &mut y_split, c);
        assert!(y.iter().zip(&y_split).all(|(a, b)| a.to_bits() == b.to_bits()), "{y:?}\n{y_split:?}");
        // Passes on the pool: a band of 9 × 30,000 entries (above the
        // size from which they split).
        let big = 30_000;
        let d: Vec<f64> = (0..big).map(|_| 0.5 + rng.next()).collect();
        let mut a = BandMatrix::new(big, kd, kd);
        for j in 0..big {
            for i in j.saturating_sub(kd)..=(j + kd).min(big - 1) {
                a.set(i, j, rng.next() - 0.5);
            }
        }
        let mut b = a.clone();
        a.scale_symmetric_on(&d, false);
        b.scale_symmetric_on(&d, true);
        assert_eq!(a.data, b.data);
        b.reshape_on(big - 7, kd, kd, true);
        assert!(b.n() == big - 7 && b.data.len() == (2 * kd + 1) * (big - 7) && b.data.iter().all(|&v| v == 0.0));
    }

    #[test]
    fn rows_read_by_stride_are_the_entries() {
        let mut rng = Lcg(21);
        for (n, kl, ku) in [(9, 2, 3), (7, 0, 0), (5, 4, 1), (1, 0, 2), (6, 6, 6)] {
            let mut a = BandMatrix::new(n, kl, ku);
            for i in 0..n {
                for j in 0..n {
                    if a.in_band(i, j) {
                        a.set(i, j, rng.next());
                    }
                }
            }
            for i in 0..n {
                let (j0, row) = a.row(i);
                let got: Vec<(usize, f64)> = row.enumerate().map(|(c, v)| (j0 + c, v)).collect();
                let want: Vec<(usize, f64)> = (0..n).filter(|&j| a.in_band(i, j)).map(|j| (j, a.get(i, j))).collect();
                assert_eq!(got, want, "n {n}, kl {kl}, ku {ku}, row {i}");
            }
        }
    }

    #[test]
    fn add_sym_block_matches_entrywise_adds() {
        let mut rng = Lcg(8);
        let upper: Vec<f64> = (0..36).map(|_| rng.next()).collect();
        // In-band (contiguous, and with a gap) and out-of-band index sets.
        for idx in [vec![3usize, 4, 5, 6, 7, 8], vec![2, 3, 5, 6, 7, 9], vec![0, 1, 2, 3, 4, 9]] {
            if idx[5] - idx[0] > 7 && cfg!(debug_assertions) {
                continue; // out-of-band adds trip BandMatrix::add's debug assertion
            }
            let mut a = BandMatrix::new(12, 7, 7);
            let mut r = BandMatrix::new(12, 7, 7);
            a.add_sym_block(&idx, &upper, 6);
            for p in 0..6 {
                for q in 0..6 {
                    let v = upper[p.min(q) * 6 + p.max(q)];
                    if r.in_band(idx[p], idx[q]) {
                        r.add(idx[p], idx[q], v);
                    }
                }
            }
            // Out-of-band entries are dropped, as by `add` in release builds.
            assert_eq!(a.data, r.data, "{idx:?}");
        }
    }

}

impl BandMatrix {
    /// A ← D A D for the diagonal D = diag(d): symmetric equilibration of a
    /// KKT matrix before factorisation (entries outside the band stay zero).
    pub fn scale_symmetric(&mut self, d: &[f64]) {
        self.scale_symmetric_on(d, false);
    }

    /// [`Self::scale_symmetric`], in column halves on rayon's pool when
    /// `parallel` and the matrix is large.
    pub fn scale_symmetric_on(&mut self, d: &[f64], parallel: bool) {
        self.for_column_halves(parallel, |mut c| c.scale_symmetric(d));
    }

    /// `A[idx[a]][idx[b]] += S[a][b]` for every a, b < m = `idx.len()`, where S
    /// is symmetric and given by its upper half, row-major with stride
    /// `stride` (`S[a][b] = upper[a * stride + b]` for a ≤ b). This is how the
    /// KKT assembly adds a segment's stiffness block (SPEC §4). When all the
    /// indices lie within one band width of each other (always, for a segment
    /// of a rod: its control points are consecutive in the layout) the
    /// entries go straight into their columns; otherwise entry by entry with
    /// the out-of-band policy of [`BandMatrix::add`].
    pub fn add_sym_block(&mut self, idx: &[usize], upper: &[f64], stride: usize) {
        self.columns_mut().add_sym_block(idx, upper, stride);
    }

    /// All the columns, as the view a split assembly's halves use.
    pub fn columns_mut(&mut self) -> BandColumnsMut<'_> {
        let n = self.n;
        self.split_columns_mut(n).0
    }

    /// Columns `..c` and `c..` (`c` ≤ n), mutably and apart: two threads add
    /// blocks to them at once (blocks whose indices all lie on one side).
    pub fn split_columns_mut(&mut self, c: usize) -> (BandColumnsMut<'_>, BandColumnsMut<'_>) {
        let (n, kl, ku, ldab) = (self.n, self.kl, self.ku, self.ldab);
        let c = c.min(n);
        let (head, tail) = self.data.split_at_mut(c * ldab);
        (BandColumnsMut { data: head, first: 0, end: c, n, kl, ku, ldab }, BandColumnsMut { data: tail, first: c, end: n, n, kl, ku, ldab })
    }
}

/// Columns `first..end` of a [`BandMatrix`] ([`BandMatrix::split_columns_mut`]).
#[derive(Debug)]
pub struct BandColumnsMut<'a> {
    /// Column `first`'s storage on.
    data: &'a mut [f64],
    first: usize,
    end: usize,
    n: usize,
    kl: usize,
    ku: usize,
    ldab: usize,
}

impl BandColumnsMut<'_> {
    /// These columns' entries a_ij ← d_i a_ij d_j.
    pub fn scale_symmetric(&mut self, d: &[f64]) {
        let (ku, ldab) = (self.ku, self.ldab);
        for j in self.first..self.end {
            let lo = j.saturating_sub(ku);
            let hi = (j + self.kl).min(self.n - 1);
            let dj = d[j];
            let at = (j - self.first) * ldab + ku;
            let col = &mut self.data[at + lo - j..=at + hi - j];
            for (a, &di) in col.iter_mut().zip(&d[lo..=hi]) {
                *a *= di * dj;
            }
        }
    }

    /// These columns' entries, all zero.
    pub fn fill_zero(&mut self) {
        self.data.fill(0.0);
    }

    /// `(i, j)` is in the matrix, its band and these columns.
    #[inline]
    fn holds(&self, i: usize, j: usize) -> bool {
        i < self.n && (self.first..self.end).contains(&j) && i <= j + self.kl && j <= i + self.ku
    }

    /// `A[i][j] += v`, with the out-of-band policy of [`BandMatrix::add`]
    /// (a column outside the view counts as out of band).
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(self.holds(i, j), "BandColumnsMut::add({i}, {j}) outside columns {}..{} or the band (n={}, kl={}, ku={})", self.first, self.end, self.n, self.kl, self.ku);
        if self.holds(i, j) {
            self.data[(j - self.first) * self.ldab + self.ku + i - j] += v;
        }
    }

    /// [`BandMatrix::add_sym_block`] on these columns.
    pub fn add_sym_block(&mut self, idx: &[usize], upper: &[f64], stride: usize) {
        let m = idx.len();
        let (lo, hi) = idx.iter().fold((usize::MAX, 0), |(l, h), &g| (l.min(g), h.max(g)));
        if m == 0 {
            return;
        }
        if hi >= self.end || lo < self.first || hi - lo > self.kl.min(self.ku) {
            for a in 0..m {
                for b in a..m {
                    let v = upper[a * stride + b];
                    self.add(idx[a], idx[b], v);
                    if a != b {
                        self.add(idx[b], idx[a], v);
                    }
                }
            }
            return;
        }
        let (ku, ldab, first) = (self.ku, self.ldab, self.first);
        if hi - lo + 1 == m && idx.windows(2).all(|w| w[1] == w[0] + 1) {
            // Consecutive indices (a rod's segment): row lo + a of column
            // lo + b sits at ku + a − b, so each column is one contiguous run.
            for b in 0..m {
                let at = (lo + b - first) * ldab + ku - b;
                let col = &mut self.data[at..at + m];
                for (a, x) in col[..=b].iter_mut().enumerate() {
                    *x += upper[a * stride + b];
                }
                for (x, &v) in col[b + 1..].iter_mut().zip(&upper[b * stride + b + 1..b * stride + m]) {
                    *x += v;
                }
            }
            return;
        }
        for (b, &gj) in idx.iter().enumerate() {
            // Row gi of column gj sits at ku + gi - gj >= 0 (gj - gi <= hi - lo <= ku).
            let col = &mut self.data[(gj - first) * ldab..(gj - first + 1) * ldab];
            for (a, &gi) in idx[..=b].iter().enumerate() {
                col[ku + gi - gj] += upper[a * stride + b];
            }
            for (&gi, &v) in idx[b + 1..].iter().zip(&upper[b * stride + b + 1..b * stride + m]) {
                col[ku + gi - gj] += v;
            }
        }
    }
}
