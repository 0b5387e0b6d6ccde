//! A square matrix assembled entry by entry straight into a compressed
//! sparse column (CSC) pattern, for KKT systems whose band is wide but
//! sparse (a fabric, a mat, a duplex: SPEC §5). Band storage costs
//! n × (2 bw + 1) entries to zero, fill and read per assembly — quadratic
//! in a fabric's width — where this costs the entries actually added.
//!
//! The pattern is structural: every position added (even with a zero
//! value), its transpose and the diagonal, kept as the union over the
//! assemblies since the size last changed. An assembly that adds the same
//! positions in the same order as the previous one (a time loop without
//! topology change) writes each value to the slot that position had (the
//! slot map of the previous assembly); positions past the first difference
//! are looked up in the pattern, which is rebuilt only when one is not in
//! it.

/// Entries added to a [`CscAssembly`], then read as a CSC matrix.
#[derive(Clone, Debug, Default)]
pub struct CscAssembly {
    n: usize,
    /// Positions (column, row) of this assembly's additions in order; the
    /// first `count` of them, when `same`, are also the previous assembly's.
    pos: Vec<(u32, u32)>,
    /// Their values.
    add_val: Vec<f64>,
    /// `slot[k]`: where position k lands in the pattern (valid for the
    /// positions the last `finish` saw).
    slot: Vec<u32>,
    /// Additions so far in this assembly.
    count: usize,
    /// This assembly has matched the previous one's positions so far.
    same: bool,
    /// The first position that differed from the previous assembly's.
    diverged_at: usize,
    /// The positions the slot map was built for.
    mapped: usize,
    finished: bool,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    val: Vec<f64>,
    /// `mirror[p]`: the slot of the transpose of slot p.
    mirror: Vec<usize>,
    /// The diagonal's slot per column.
    diag: Vec<usize>,
    /// A new number (unique in the process) whenever the pattern changes:
    /// factorisations key their symbolic analysis on it.
    generation: u64,
    // Scratch of the pattern build (the previous pattern kept for the
    // comparison: a rebuild allocates nothing once warmed up).
    spare_ptr: Vec<usize>,
    spare_idx: Vec<usize>,
    bucket_ptr: Vec<usize>,
    bucket: Vec<u32>,
    stamp: Vec<u32>,
}

/// Positions are stored as u32 pairs (half the traffic of usize pairs).
pub const MAX_ORDER: usize = u32::MAX as usize;

impl CscAssembly {
    /// Starts an assembly of an `n × n` matrix (the additions are summed
    /// from zero at `finish`), `n ≤
    /// MAX_ORDER` (`system::kkt::storage_for` keeps larger systems in band
    /// storage).
    pub fn begin(&mut self, n: usize) {
        debug_assert!(n <= MAX_ORDER);
        self.same = self.n == n && self.col_ptr.len() == n + 1;
        if !self.same {
            self.pos.clear();
            self.mapped = 0;
        }
        self.n = n;
        self.count = 0;
        self.diverged_at = 0;
        self.finished = false;
        self.add_val.resize(self.pos.len(), 0.0);
    }

    pub fn n(&self) -> usize {
        self.n
    }

    /// `A[i][j] += v` (summed with earlier additions at the same place).
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(i < self.n && j < self.n && !self.finished);
        let k = self.count;
        self.count += 1;
        let p = (j as u32, i as u32);
        if self.same {
            if self.pos.get(k) == Some(&p) {
                self.add_val[k] = v;
                return;
            }
            self.same = false;
            self.diverged_at = k;
            // Slots past k are stale from here on, even if this assembly
            // is never finished.
            self.mapped = self.mapped.min(k);
            self.pos.truncate(k);
            self.add_val.truncate(k);
        }
        self.pos.push(p);
        self.add_val.push(v);
    }

    /// `A[idx[a]][idx[b]] += S[a][b]` for a symmetric S given by its upper
    /// half, row-major with stride `stride` (as `BandMatrix::add_sym_block`).
    pub fn add_sym_block(&mut self, idx: &[usize], upper: &[f64], stride: usize) {
        let m = idx.len();
        for b in 0..m {
            for a in 0..m {
                let v = if a <= b { upper[a * stride + b] } else { upper[b * stride + a] };
                self.add(idx[a], idx[b], v);
            }
        }
    }

    /// Ends the assembly: the values are summed into the pattern (rebuilt
    /// when a position is not in it). Additions after it are not counted.
    pub fn finish(&mut self) {
        if self.finished {
            return;
        }
        self.finished = true;
        let k = self.count;
        if !(self.same && k == self.pos.len() && self.mapped == k) {
            let from = if self.same { k.min(self.mapped) } else { self.diverged_at.min(self.mapped) };
            self.pos.truncate(k);
            self.add_val.truncate(k);
            // Positions past the first difference (a value-dependent entry,
            // a contact row more or less) are looked up in the pattern; only
            // a position outside it makes a new pattern.
            if !(self.col_ptr.len() == self.n + 1 && self.map_from(from)) {
                self.rebuild();
            }
        }
        self.val.clear();
        self.val.resize(self.row_idx.len(), 0.0);
        for (&s, &v) in self.slot[..k].iter().zip(&self.add_val[..k]) {
            self.val[s as usize] += v;
        }
    }

    /// Slots of the positions from `from` on, looked up in the pattern held
    /// (its columns are sorted); false when one is not in it.
    fn map_from(&mut self, from: usize) -> bool {
        self.slot.truncate(from);
        for &(j, i) in &self.pos[from..] {
            let (a, b) = (self.col_ptr[j as usize], self.col_ptr[j as usize + 1]);
            match self.row_idx[a..b].binary_search(&(i as usize)) {
                Ok(p) => self.slot.push((a + p) as u32),
                Err(_) => return false,
            }
        }
        self.mapped = self.pos.len();
        true
    }

    /// The pattern of the positions added (with transposes and the
    /// diagonal), and each position's slot.
    fn rebuild(&mut self) {
        let n = self.n;
        // Bucket the rows of each column (every position twice: as added
        // and transposed, plus the diagonal), a counting sort by column.
        self.bucket_ptr.clear();
        self.bucket_ptr.resize(n + 2, 0);
        for &(j, i) in &self.pos {
            self.bucket_ptr[j as usize + 2] += 1;
            self.bucket_ptr[i as usize + 2] += 1;
        }
        for j in 0..n {
            self.bucket_ptr[j + 2] += 1;
        }
        for j in 2..n + 2 {
            self.bucket_ptr[j] += self.bucket_ptr[j - 1];
        }
        self.bucket.clear();
        self.bucket.resize(self.bucket_ptr[n + 1], 0);
        for j in 0..n {
            let at = &mut self.bucket_ptr[j + 1];
            self.bucket[*at] = j as u32;
            *at += 1;
        }
        for &(j, i) in &self.pos {
            let at = &mut self.bucket_ptr[j as usize + 1];
            self.bucket[*at] = i;
            *at += 1;
            let at = &mut self.bucket_ptr[i as usize + 1];
            self.bucket[*at] = j;
            *at += 1;
        }
        // Unique sorted rows per column (a stamp per row marks the column
        // that last took it).
        std::mem::swap(&mut self.col_ptr, &mut self.spare_ptr);
        std::mem::swap(&mut self.row_idx, &mut self.spare_idx);
        self.col_ptr.clear();
        self.row_idx.clear();
        self.stamp.clear();
        self.stamp.resize(n, u32::MAX);
        self.col_ptr.push(0);
        // The previous pattern of this size stays in: positions that come
        // and go (a value-dependent entry, contact rows) would otherwise
        // make a new pattern, and a new symbolic factorisation, each time.
        let keep = self.spare_ptr.len() == n + 1;
        for j in 0..n {
            let start = self.row_idx.len();
            let old = if keep { &self.spare_idx[self.spare_ptr[j]..self.spare_ptr[j + 1]] } else { &[][..] };
            for i in self.bucket[self.bucket_ptr[j]..self.bucket_ptr[j + 1]].iter().map(|&i| i as usize).chain(old.iter().copied()) {
                if self.stamp[i] != j as u32 {
                    self.stamp[i] = j as u32;
                    self.row_idx.push(i);
                }
            }
            self.row_idx[start..].sort_unstable();
            self.col_ptr.push(self.row_idx.len());
        }
        if self.spare_ptr != self.col_ptr || self.spare_idx != self.row_idx {
            // Unique across instances: a factorisation fed by several
            // assemblies tells their patterns apart.
            static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
            self.generation = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        }
        // Slots of the positions, the diagonal and the transposes.
        let find = |col_ptr: &[usize], row_idx: &[usize], i: usize, j: usize| -> usize {
            let (a, b) = (col_ptr[j], col_ptr[j + 1]);
            // Every position added is in its column (just built).
            a + row_idx[a..b].binary_search(&i).unwrap_or_else(|e| e)
        };
        self.slot.clear();
        self.slot.extend(self.pos.iter().map(|&(j, i)| find(&self.col_ptr, &self.row_idx, i as usize, j as usize) as u32));
        self.diag.clear();
        self.diag.extend((0..n).map(|j| find(&self.col_ptr, &self.row_idx, j, j)));
        // Slots are u32 (a pattern of 4e9 entries would not fit in memory).
        debug_assert!(self.row_idx.len() <= u32::MAX as usize);
        mirror_slots(&self.col_ptr, &self.row_idx, &mut self.bucket_ptr, &mut self.mirror);
        self.mapped = self.pos.len();
    }

    /// Column pointers, row indices (sorted) and values of the pattern.
    pub fn csc(&self) -> (&[usize], &[usize], &[f64]) {
        debug_assert!(self.finished);
        (&self.col_ptr, &self.row_idx, &self.val)
    }
    /// The slot of each slot's transpose.
    pub fn mirror(&self) -> &[usize] {
        &self.mirror
    }
    /// Changes whenever the pattern does.
    pub fn generation(&self) -> u64 {
        self.generation
    }
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Entry (i, j) (zero outside the pattern).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        debug_assert!(self.finished);
        let (a, b) = (self.col_ptr[j], self.col_ptr[j + 1]);
        self.row_idx[a..b].binary_search(&i).map_or(0.0, |p| self.val[a + p])
    }
    #[inline]
    pub fn diag(&self, i: usize) -> f64 {
        debug_assert!(self.finished);
        self.val[self.diag[i]]
    }
    /// `A[i][i] += v` after the assembly (damping).
    #[inline]
    pub fn add_diag(&mut self, i: usize, v: f64) {
        debug_assert!(self.finished);
        self.val[self.diag[i]] += v;
    }
    /// Column j's rows and values.
    #[inline]
    pub fn column(&self, j: usize) -> (&[usize], &[f64]) {
        debug_assert!(self.finished);
        let (a, b) = (self.col_ptr[j], self.col_ptr[j + 1]);
        (&self.row_idx[a..b], &self.val[a..b])
    }
    /// Row i's entries (j, A[i][j]), through the transposes of column i.
    pub fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        debug_assert!(self.finished);
        (self.col_ptr[i]..self.col_ptr[i + 1]).map(move |p| (self.row_idx[p], self.val[self.mirror[p]]))
    }

    /// A ← D A D.
    pub fn scale_symmetric(&mut self, d: &[f64]) {
        debug_assert!(self.finished);
        for j in 0..self.n {
            let dj = d[j];
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                self.val[p] *= d[self.row_idx[p]] * dj;
            }
        }
    }

    /// y = A x.
    pub fn matvec(&self, x: &[f64], y: &mut [f64]) {
        assert!(x.len() == self.n && y.len() == self.n, "CscAssembly::matvec: length mismatch");
        debug_assert!(self.finished);
        y.fill(0.0);
        for (j, &xj) in x.iter().enumerate() {
            if xj != 0.0 {
                for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                    y[self.row_idx[p]] += self.val[p] * xj;
                }
            }
        }
    }

    /// Largest |a_ij| (NaN ignored, as `BandMatrix::max_abs`).
    pub fn max_abs(&self) -> f64 {
        self.val.iter().fold(0.0, |m, v| m.max(v.abs()))
    }
}

/// `mirror[p]`: the slot of the transpose of slot p, for a CSC pattern
/// with a symmetric structure and sorted columns (`next`: scratch). Walking
/// the columns in order, row i's entries come in increasing column order:
/// each is the next unmatched slot of column i.
pub(crate) fn mirror_slots(col_ptr: &[usize], row_idx: &[usize], next: &mut Vec<usize>, mirror: &mut Vec<usize>) {
    let n = col_ptr.len() - 1;
    mirror.clear();
    mirror.resize(row_idx.len(), 0);
    next.clear();
    next.extend_from_slice(&col_ptr[..n]);
    for j in 0..n {
        for p in col_ptr[j]..col_ptr[j + 1] {
            let i = row_idx[p];
            mirror[p] = next[i];
            next[i] += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::synthetic::Lcg;

    /// Dense reference of a sequence of additions.
    fn dense(n: usize, adds: &[(usize, usize, f64)]) -> Vec<Vec<f64>> {
        let mut a = vec![vec![0.0; n]; n];
        for &(i, j, v) in adds {
            a[i][j] += v;
        }
        a
    }

    fn check(m: &CscAssembly, a: &[Vec<f64>]) {
        let n = a.len();
        for i in 0..n {
            for j in 0..n {
                assert_eq!(m.get(i, j), a[i][j], "({i}, {j})");
            }
            assert_eq!(m.diag(i), a[i][i]);
            let row: Vec<(usize, f64)> = m.row(i).collect();
            for (j, v) in row {
                assert_eq!(v, a[i][j]);
            }
        }
        let (ptr, idx, _) = m.csc();
        for j in 0..n {
            let rows = &idx[ptr[j]..ptr[j + 1]];
            assert!(rows.windows(2).all(|w| w[0] < w[1]), "column {j} sorted and unique");
            assert!(rows.contains(&j), "diagonal of {j} stored");
            for &i in rows {
                assert!(idx[ptr[i]..ptr[i + 1]].contains(&j), "pattern symmetric at ({i}, {j})");
            }
        }
        for (p, &q) in m.mirror().iter().enumerate() {
            assert_eq!(m.mirror()[q], p);
        }
    }

    /// Random additions (repeats, one-sided entries), re-assembled with the
    /// same positions (slot map reused: same generation), with a changed
    /// tail and a different size: every entry equals the dense sum.
    #[test]
    fn assembly_matches_dense_sums_through_reuse_and_changes() {
        let mut rng = Lcg(7);
        let n = 23;
        let mut adds: Vec<(usize, usize, f64)> = (0..300)
            .map(|_| ((rng.next().abs() * 20.0) as usize % 20, (rng.next().abs() * 20.0) as usize % 20, rng.next()))
            .collect();
        let mut m = CscAssembly::default();
        let assemble = |m: &mut CscAssembly, adds: &[(usize, usize, f64)], n: usize| {
            m.begin(n);
            for &(i, j, v) in adds {
                m.add(i, j, v);
            }
            m.finish();
        };
        assemble(&mut m, &adds, n);
        check(&m, &dense(n, &adds));
        let g = m.generation();
        for a in adds.iter_mut() {
            a.2 = rng.next();
        }
        assemble(&mut m, &adds, n);
        check(&m, &dense(n, &adds));
        assert_eq!(m.generation(), g, "same positions: same pattern");
        // A shorter sequence whose tail differs but stays in the pattern:
        // looked up, the pattern kept.
        let tail: Vec<_> = adds[..40].to_vec();
        adds.truncate(250);
        adds.extend(tail);
        assemble(&mut m, &adds, n);
        check(&m, &dense(n, &adds));
        assert_eq!(m.generation(), g, "positions already in the pattern: same pattern");
        // Rows 20–22 hold only their diagonal so far.
        adds.push((0, n - 1, 2.5));
        assemble(&mut m, &adds, n);
        check(&m, &dense(n, &adds));
        assert_ne!(m.generation(), g, "a new entry: a new pattern");
        adds.retain(|&(i, j, _)| i < 11 && j < 11);
        assemble(&mut m, &adds, 11);
        check(&m, &dense(11, &adds));
        // Fewer additions with the same prefix.
        adds.truncate(adds.len() / 2);
        assemble(&mut m, &adds, 11);
        check(&m, &dense(11, &adds));
    }

    /// An assembly abandoned after a change of positions (an error before
    /// `finish`) leaves no stale slot for the next one.
    #[test]
    fn an_unfinished_assembly_leaves_no_stale_slots() {
        let mut m = CscAssembly::default();
        let first = [(0, 0, 1.0), (1, 2, 2.0), (3, 1, 3.0), (2, 2, 4.0)];
        let run = |m: &mut CscAssembly, adds: &[(usize, usize, f64)], finish: bool| {
            m.begin(4);
            for &(i, j, v) in adds {
                m.add(i, j, v);
            }
            if finish {
                m.finish();
            }
        };
        run(&mut m, &first, true);
        // Differs at the second addition, then stops (no finish).
        run(&mut m, &[(0, 0, 1.0), (3, 3, 5.0), (0, 3, 6.0), (1, 1, 7.0)], false);
        // The first positions again: every value where it belongs.
        run(&mut m, &first, true);
        check(&m, &dense(4, &first));
    }

    #[test]
    fn symmetric_block_scaling_and_matvec() {
        let mut m = CscAssembly::default();
        m.begin(6);
        let upper = [1.0, 2.0, 3.0, 0.0, 4.0, 5.0, 0.0, 0.0, 6.0];
        m.add_sym_block(&[1, 4, 2], &upper, 3);
        m.add(5, 0, 7.0);
        m.finish();
        let mut a = vec![vec![0.0; 6]; 6];
        let idx = [1, 4, 2];
        for x in 0..3 {
            for y in 0..3 {
                a[idx[x]][idx[y]] += if x <= y { upper[x * 3 + y] } else { upper[y * 3 + x] };
            }
        }
        a[5][0] += 7.0;
        check(&m, &a);
        let x = [1.0, -2.0, 0.5, 3.0, 0.0, 1.5];
        let mut y = [0.0; 6];
        m.matvec(&x, &mut y);
        for i in 0..6 {
            let e: f64 = (0..6).map(|j| a[i][j] * x[j]).sum();
            assert!((y[i] - e).abs() < 1e-15);
        }
        let d = [1.0, 2.0, 0.5, 1.0, 3.0, 1.0];
        m.scale_symmetric(&d);
        assert_eq!(m.get(4, 2), 5.0 * 3.0 * 0.5);
        assert_eq!(m.get(5, 0), 7.0);
        m.add_diag(3, 2.0);
        assert_eq!(m.diag(3), 2.0);
    }
}
