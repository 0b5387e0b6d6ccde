//! Synthetic KKT systems with the structure of SPEC §5, for the linear
//! algebra tests and the band-vs-sparse benchmark
//! (`core/examples/band_vs_sparse.rs`): a deterministic generator, a
//! symmetric entry builder whose coordinate block is made diagonally
//! dominant (SPD), interleaved rods linked by constraint rows (1-D
//! ordering) and a woven fabric (2-D, wide but sparse band).
use super::band::BandMatrix;

/// Small deterministic generator in [−1, 1) (no `rand` dependency).
pub struct Lcg(pub u64);

impl Lcg {
    #[allow(clippy::should_implement_trait)] // not an Iterator: an infinite f64 stream
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// Symmetric entries `(i, j, v)` (added both ways unless `i == j`), summed
/// into a band matrix by [`Self::band`].
pub struct KktBuilder {
    pub n: usize,
    pub e: Vec<(usize, usize, f64)>,
}

impl KktBuilder {
    pub fn new(n: usize) -> Self {
        Self { n, e: Vec::new() }
    }
    pub fn sym(&mut self, i: usize, j: usize, v: f64) {
        self.e.push((i, j, v));
        if i != j {
            self.e.push((j, i, v));
        }
    }
    pub fn band(&self) -> BandMatrix {
        let bw = self.e.iter().map(|&(i, j, _)| i.abs_diff(j)).max().unwrap_or(0);
        let mut a = BandMatrix::new(self.n, bw, bw);
        for &(i, j, v) in &self.e {
            a.add(i, j, v);
        }
        a
    }
    /// Makes the coordinate block diagonally dominant (SPD) given its off-diagonal entries.
    fn finish_spd(&mut self, is_coord: &[bool], rng: &mut Lcg) {
        let mut rowsum = vec![0.0; self.n];
        for &(i, j, v) in &self.e {
            if is_coord[i] && is_coord[j] && i != j {
                rowsum[i] += f64::abs(v);
            }
        }
        for (i, rs) in rowsum.into_iter().enumerate() {
            if is_coord[i] {
                self.sym(i, i, rs + 0.5 + rng.next().abs());
            }
        }
    }
}

/// SPEC §5 1-D ordering: `m` interleaved cubic rods (3 coordinates per
/// control point, coupling ±3 control points), linked at every control
/// point by a one-row constraint between neighbouring rods, plus a
/// constraint on rod 0 every third point. Rows follow their group.
/// Returns the entries and which unknowns are coordinates.
pub fn chain_kkt(rng: &mut Lcg, k_pts: usize, m: usize) -> (KktBuilder, Vec<bool>) {
    let mut is_coord = Vec::new();
    let mut cp = vec![vec![0usize; k_pts]; m];
    let mut rows = Vec::new(); // (row, touched coordinate indices)
    for k in 0..k_pts {
        for c in cp.iter_mut() {
            c[k] = is_coord.len();
            is_coord.extend([true; 3]);
        }
        for r in 0..m.saturating_sub(1) {
            let touched: Vec<usize> = (0..3).flat_map(|a| [cp[r][k] + a, cp[r + 1][k] + a]).collect();
            rows.push((is_coord.len(), touched));
            is_coord.push(false);
        }
        if k >= 1 && k % 3 == 0 {
            let touched: Vec<usize> = (0..3).flat_map(|a| [cp[0][k - 1] + a, cp[0][k] + a]).collect();
            rows.push((is_coord.len(), touched));
            is_coord.push(false);
        }
    }
    let mut b = KktBuilder::new(is_coord.len());
    for c in &cp {
        for k in 0..k_pts {
            for l in k..(k + 4).min(k_pts) {
                for a in 0..3 {
                    for bb in 0..3 {
                        if l > k || bb > a {
                            b.sym(c[k] + a, c[l] + bb, 0.5 * rng.next());
                        }
                    }
                }
            }
        }
    }
    for (row, touched) in rows {
        for t in touched {
            b.sym(row, t, rng.next());
        }
    }
    b.finish_spd(&is_coord, rng);
    (b, is_coord)
}

/// A woven "2-D" fabric: at each crossing (x, y) a weft point and a warp
/// point (3 coordinates each) and a 3-row pin constraint between them
/// (compliance on its diagonal); weft rods couple ±3 crossings along x,
/// warp rods ±3 along y. Ordered row by row, so the half-bandwidth is
/// ~27 nx but the band is sparse.
pub fn grid_kkt(rng: &mut Lcg, nx: usize, ny: usize, compliance: f64) -> (KktBuilder, Vec<bool>) {
    let node = |x: usize, y: usize| 9 * (y * nx + x);
    let n = 9 * nx * ny;
    let mut is_coord = vec![true; n];
    let mut b = KktBuilder::new(n);
    for y in 0..ny {
        for x in 0..nx {
            let p = node(x, y);
            for a in 0..3 {
                is_coord[p + 6 + a] = false;
                b.sym(p + 6 + a, p + a, 1.0 + 0.1 * rng.next());
                b.sym(p + 6 + a, p + 3 + a, -1.0 + 0.1 * rng.next());
                b.sym(p + 6 + a, p + 6 + a, -compliance);
            }
            // weft (offset 0) along x, warp (offset 3) along y
            for s in 0..=3 {
                let nbrs = [(x + s < nx).then(|| (node(x + s, y), 0)), (y + s < ny).then(|| (node(x, y + s), 3))];
                for (q, off) in nbrs.into_iter().flatten() {
                    for a in 0..3 {
                        for c in 0..3 {
                            if s > 0 || c > a {
                                b.sym(p + off + a, q + off + c, 0.5 * rng.next());
                            }
                        }
                    }
                }
            }
        }
    }
    b.finish_spd(&is_coord, rng);
    (b, is_coord)
}
