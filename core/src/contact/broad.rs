//! Broad phase of rod–rod detection: which capsules may touch. Capsules
//! are grouped in runs of [`GROUP`] consecutive ones along a rod, each run
//! in the box of its capsules' boxes, and a uniform grid of runs finds the
//! runs whose boxes overlap. A capsule is often about as long as its
//! radius (5 per spline segment), so a grid of single capsules visits tens
//! of neighbours each; a grid of runs visits a few, and only overlapping
//! runs have their capsules paired.
use crate::error::{Error, Result};
use nalgebra::Vector3;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// Capsules per run.
pub(crate) const GROUP: usize = 8;

/// An axis-aligned box (length unit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Bounds {
    pub lo: Vector3<f64>,
    pub hi: Vector3<f64>,
}

impl Bounds {
    /// Closed boxes: touching faces overlap.
    pub fn overlaps(&self, o: &Bounds) -> bool {
        // All six comparisons, without branches (most tests in a dense
        // structure are near misses that short-circuiting mispredicts).
        let (a, b) = (&self, o);
        (a.lo.x <= b.hi.x) & (b.lo.x <= a.hi.x) & (a.lo.y <= b.hi.y) & (b.lo.y <= a.hi.y) & (a.lo.z <= b.hi.z) & (b.lo.z <= a.hi.z)
    }
    fn union(&self, o: &Bounds) -> Bounds {
        Bounds { lo: self.lo.inf(&o.lo), hi: self.hi.sup(&o.hi) }
    }
}

/// A grid cell's indices, hashed as three words (the array's own `Hash`
/// goes through a byte slice, several times slower here).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) struct Cell(pub [i64; 3]);

impl std::hash::Hash for Cell {
    fn hash<H: Hasher>(&self, state: &mut H) {
        for x in self.0 {
            state.write_i64(x);
        }
    }
}

/// A fast hasher for grid cells (three small integers; SipHash's
/// resistance to adversarial keys buys nothing here).
#[derive(Default)]
pub(crate) struct CellHasher(u64);

impl Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }
    fn write_i64(&mut self, x: i64) {
        self.write_u64(x as u64);
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
    fn write_u32(&mut self, x: u32) {
        self.write_u64(x as u64);
    }
}


/// A map keyed by grid cells.
type CellMap<V> = HashMap<Cell, V, BuildHasherDefault<CellHasher>>;

/// The runs of a set of capsules and their grid.
#[derive(Debug, Default)]
pub(crate) struct Runs {
    /// First capsule, one past the last, box.
    runs: Vec<(usize, usize, Bounds)>,
    /// Runs sorted by cell, then by index.
    order: Vec<(Cell, usize)>,
    /// Each run's cell (an index into `around`), and for each occupied
    /// cell the ranges of `order` in it and its 26 neighbours (looked up
    /// once per cell, not once per run).
    cell_of: Vec<usize>,
    around: Vec<std::ops::Range<usize>>,
    ranges: Vec<(usize, usize)>,
    /// Each occupied cell's range of `order`.
    cells: CellMap<(usize, usize)>,
}

impl Runs {
    /// Runs of the capsules with these boxes, each rod's capsules being
    /// the range `ranges[r]` (a run never spans two rods).
    #[cfg(test)]
    pub fn new(boxes: &[Bounds], ranges: &[(usize, usize)]) -> Result<Runs> {
        let mut runs = Runs::default();
        runs.fill(boxes, ranges)?;
        Ok(runs)
    }

    /// [`Runs::new`] in place, keeping the buffers.
    pub fn fill(&mut self, boxes: &[Bounds], ranges: &[(usize, usize)]) -> Result<()> {
        self.runs.clear();
        for &(first, end) in ranges {
            let mut k = first;
            while k < end {
                let e = (k + GROUP).min(end);
                let b = boxes[k + 1..e].iter().fold(boxes[k], |acc, x| acc.union(x));
                self.runs.push((k, e, b));
                k = e;
            }
        }
        // Cells as wide as the widest run: runs whose boxes overlap then
        // have their centres in neighbouring cells.
        let cell = self.runs.iter().map(|r| (r.2.hi - r.2.lo).max()).fold(0.0, f64::max);
        if !(cell > 0.0) || !cell.is_finite() {
            return Err(Error::input("contact detection: the rods have no extent (zero capsule length and radius)"));
        }
        let key = |b: &Bounds| Runs::key_of(b, cell);
        self.order.clear();
        self.order.extend(self.runs.iter().enumerate().map(|(i, r)| (key(&r.2), i)));
        self.order.sort_unstable();
        self.cells.clear();
        let mut first = 0;
        for k in 1..=self.order.len() {
            if k == self.order.len() || self.order[k].0 != self.order[first].0 {
                self.cells.insert(self.order[first].0, (first, k));
                first = k;
            }
        }
        self.cell_of.clear();
        self.cell_of.resize(self.runs.len(), 0);
        self.around.clear();
        self.ranges.clear();
        let mut k = 0;
        while k < self.order.len() {
            let (c, _) = self.order[k];
            let (_, end) = self.cells[&c];
            let start = self.ranges.len();
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        if let Some(&r) = self.cells.get(&Cell([c.0[0] + dx, c.0[1] + dy, c.0[2] + dz])) {
                            self.ranges.push(r);
                        }
                    }
                }
            }
            for m in k..end {
                self.cell_of[self.order[m].1] = self.around.len();
            }
            self.around.push(start..self.ranges.len());
            k = end;
        }
        Ok(())
    }

    fn key_of(b: &Bounds, cell: f64) -> Cell {
        let m = 0.5 * (b.lo + b.hi) / cell;
        Cell([m.x.floor() as i64, m.y.floor() as i64, m.z.floor() as i64])
    }

    pub fn len(&self) -> usize {
        self.runs.len()
    }

    /// Run `a`'s capsules (a range, in the capsules' order).
    pub fn capsules(&self, a: usize) -> std::ops::Range<usize> {
        self.runs[a].0..self.runs[a].1
    }

    /// Run `a`'s box.
    pub fn bounds(&self, a: usize) -> &Bounds {
        &self.runs[a].2
    }

    /// The runs `b ≥ a` whose boxes overlap run `a`'s (`a` itself
    /// included), into `out`: over all `a`, each overlapping pair once.
    pub fn partners(&self, a: usize, out: &mut Vec<usize>) {
        out.clear();
        let ra = &self.runs[a];
        for &(lo, hi) in &self.ranges[self.around[self.cell_of[a]].clone()] {
            // A cell's runs are in index order: skip those before `a`.
            let cell = &self.order[lo..hi];
            let from = cell.partition_point(|&(_, b)| b < a);
            out.extend(cell[from..].iter().map(|&(_, b)| b).filter(|&b| ra.2.overlaps(&self.runs[b].2)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every pair of capsules whose boxes overlap is in a pair of
    /// overlapping runs, exactly once: random boxes along random walks
    /// (three "rods" of 1, 8 and 50 capsules, sizes over two decades).
    #[test]
    fn runs_pair_every_overlapping_capsule_once() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            ((seed >> 11) as f64) / ((1u64 << 53) as f64)
        };
        for trial in 0..20 {
            let mut boxes = Vec::new();
            let mut ranges = Vec::new();
            for n in [1usize, 8, 50, 23] {
                let first = boxes.len();
                let mut p = Vector3::new(rnd(), rnd(), rnd());
                for _ in 0..n {
                    let step = Vector3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 0.2;
                    let q = p + step;
                    let r = 0.01 + 0.1 * rnd() * (trial as f64 / 20.0);
                    boxes.push(Bounds { lo: p.inf(&q) - Vector3::repeat(r), hi: p.sup(&q) + Vector3::repeat(r) });
                    p = q;
                }
                ranges.push((first, boxes.len()));
            }
            let runs = Runs::new(&boxes, &ranges).unwrap();
            let mut seen = vec![0u32; boxes.len() * boxes.len()];
            let mut partners = Vec::new();
            for a in 0..runs.len() {
                runs.partners(a, &mut partners);
                for &b in &partners {
                    for i in runs.capsules(a) {
                        for j in runs.capsules(b) {
                            if (a != b || j > i) && boxes[i].overlaps(&boxes[j]) {
                                seen[i.min(j) * boxes.len() + i.max(j)] += 1;
                            }
                        }
                    }
                }
            }
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    let want = boxes[i].overlaps(&boxes[j]) as u32;
                    assert_eq!(seen[i * boxes.len() + j], want, "trial {trial}: capsules {i}, {j}");
                }
            }
        }
    }

    #[test]
    fn boxes_without_extent_are_refused() {
        let p = Bounds { lo: Vector3::zeros(), hi: Vector3::zeros() };
        assert!(Runs::new(&[p, p], &[(0, 2)]).is_err());
    }
}
