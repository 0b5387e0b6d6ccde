//! Ordering of the unknowns (thesis IV.3–IV.4, algorithms 9–10): control
//! points in a global order (each rod in turn, or the rods of an interleaved
//! group merged by relative position, so that linked control points are
//! close); the rows of a constraint are inserted right after the control
//! point at the floor of the mean global rank of the extreme control points
//! it touches. One linear pass places everything and a second gives the
//! half-bandwidth, which therefore does not grow with the number of
//! constraints spread along a rod.
use serde::{Deserialize, Serialize};

/// What the layout needs to know of a constraint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstraintSlot {
    /// Positions of its rods in the layout's rod order (twice the same for one rod).
    pub rods: [usize; 2],
    pub n_rows: usize,
    /// Abscissa unknowns (sliders), placed just after the rows: a
    /// frictionless slider's abscissa has no stiffness of its own, and
    /// pivoted after its rows it takes the positive pivot they give it
    /// (before them, the symmetric factorisation met a zero pivot and
    /// fell back to the LU every step).
    pub n_extra: usize,
    /// (which rod: 0/1, control point), `len` of them.
    pub touched: [(u8, usize); crate::constraint::MAX_TOUCHED],
    /// Whether the curve passes through each with weight (see
    /// `constraint::Touched`): the rows are placed among these.
    pub held: [bool; crate::constraint::MAX_TOUCHED],
    pub len: usize,
    /// Slots whose rows or abscissa unknowns these rows also act on (a
    /// bead gap's neighbouring gaps, coupled through the bead they share),
    /// `NO_LINK` for none: they count in the bandwidth.
    pub links: [usize; 2],
}

/// No linked slot ([`ConstraintSlot::links`]).
pub const NO_LINK: usize = usize::MAX;

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Layout {
    /// Global index of the first coordinate of each control point, per rod.
    pub cp_index: Vec<Vec<usize>>,
    pub dofs: Vec<usize>,
    /// Global index of the first row of each constraint.
    pub row_index: Vec<usize>,
    /// Global index of each constraint's first abscissa unknown (= row_index
    /// + row_count) and their number.
    pub extra_index: Vec<usize>,
    #[serde(default)]
    pub extra_count: Vec<usize>,
    pub row_count: Vec<usize>,
    /// Number of unknowns (coordinates + multipliers).
    pub n: usize,
    pub n_rows: usize,
    /// Half-bandwidth (kl = ku).
    pub bandwidth: usize,
}

/// Buffers of [`Layout::rebuild`], kept so that a rebuild allocates
/// nothing once the sizes have been seen.
#[derive(Clone, Debug, Default)]
pub struct LayoutScratch {
    /// Global rank of each control point, rods one after another from
    /// `first[r]`.
    first: Vec<usize>,
    rank: Vec<usize>,
    /// (rank of the control point the rows follow, constraint), sorted.
    anchors: Vec<(usize, usize)>,
}

impl Layout {
    /// `rods[r] = (n_ctrl, dofs, segment control points)`; `order` lists every
    /// (rod, control point) once, in the global order.
    pub fn build(rods: &[(usize, usize, &[[usize; 4]])], order: &[(usize, usize)], cons: &[ConstraintSlot]) -> Layout {
        let mut l = Layout::default();
        l.rebuild(rods.iter().copied(), order, cons, &mut LayoutScratch::default());
        l
    }

    /// [`Layout::build`] into `self`, reusing its buffers and `scratch`'s:
    /// what a slider that changes segment needs every few steps (its rows
    /// move; the order of the control points does not).
    pub fn rebuild<'a, I>(&mut self, rods: I, order: &[(usize, usize)], cons: &[ConstraintSlot], scratch: &mut LayoutScratch)
    where
        I: Iterator<Item = (usize, usize, &'a [[usize; 4]])> + Clone,
    {
        let LayoutScratch { first, rank, anchors } = scratch;
        first.clear();
        let mut total = 0;
        for (n, _, _) in rods.clone() {
            first.push(total);
            total += n;
        }
        rank.clear();
        rank.resize(total, 0);
        for (k, &(r, i)) in order.iter().enumerate() {
            rank[first[r] + i] = k;
        }
        // Constraints whose rows follow each control point.
        anchors.clear();
        for (c, s) in cons.iter().enumerate() {
            let mid = |held_only: bool| {
                let ranks = s.touched[..s.len].iter().zip(&s.held).filter(|(_, &h)| h || !held_only).map(|(&(w, i), _)| rank[first[s.rods[w as usize]] + i]);
                let (lo, hi) = ranks.fold((usize::MAX, 0), |(lo, hi), k| (lo.min(k), hi.max(k)));
                (lo != usize::MAX).then_some((lo + hi) / 2)
            };
            // Not before the middle of the points the curve passes through
            // with weight: a position held at a rod's far end touches its
            // last four points but only the last with weight, and a row
            // placed before it meets a zero pivot in the symmetric
            // factorisation (which then falls back to the LU every step).
            let all = mid(false).unwrap_or(0);
            anchors.push((mid(true).map_or(all, |h| h.max(all)), c));
        }
        // Stable in c within one control point, as the rows were inserted.
        anchors.sort_unstable();
        self.row_index.clear();
        self.row_index.resize(cons.len(), 0);
        self.extra_index.clear();
        self.extra_index.resize(cons.len(), 0);
        self.row_count.clear();
        self.row_count.extend(cons.iter().map(|c| c.n_rows));
        self.extra_count.clear();
        self.extra_count.extend(cons.iter().map(|c| c.n_extra));
        self.cp_index.resize_with(first.len(), Vec::new);
        for (v, (n, _, _)) in self.cp_index.iter_mut().zip(rods.clone()) {
            v.clear();
            v.resize(n, 0);
        }
        self.dofs.clear();
        self.dofs.extend(rods.clone().map(|(_, d, _)| d));
        self.n_rows = 0;
        let mut cursor = 0;
        let mut next = 0;
        for (k, &(r, i)) in order.iter().enumerate() {
            self.cp_index[r][i] = cursor;
            cursor += self.dofs[r];
            while next < anchors.len() && anchors[next].0 == k {
                let c = anchors[next].1;
                self.row_index[c] = cursor;
                cursor += cons[c].n_rows;
                self.n_rows += cons[c].n_rows;
                self.extra_index[c] = cursor;
                cursor += cons[c].n_extra;
                next += 1;
            }
        }
        self.n = cursor;
        let mut bw = 0;
        for (r, (_, dofs, segs)) in rods.enumerate() {
            for ctrl in segs.iter() {
                let lo = ctrl.iter().map(|&i| self.cp_index[r][i]).min().unwrap_or(0);
                let hi = ctrl.iter().map(|&i| self.cp_index[r][i] + dofs - 1).max().unwrap_or(0);
                bw = bw.max(hi - lo);
            }
        }
        for (c, s) in cons.iter().enumerate() {
            let (r0, r1) = (self.row_index[c], (self.extra_index[c] + s.n_extra).saturating_sub(1));
            for &(w, i) in &s.touched[..s.len] {
                let r = s.rods[w as usize];
                let (lo, hi) = (self.cp_index[r][i], self.cp_index[r][i] + self.dofs[r] - 1);
                bw = bw.max(r1.saturating_sub(lo)).max(hi.saturating_sub(r0));
            }
            for &e in s.links.iter().filter(|&&e| e != NO_LINK) {
                // The linked slot's rows and abscissae.
                let (x0, x1) = (self.row_index[e], (self.extra_index[e] + cons[e].n_extra).saturating_sub(1).max(self.row_index[e]));
                bw = bw.max(r1.saturating_sub(x0)).max(x1.saturating_sub(r0));
            }
        }
        self.bandwidth = bw;
    }

    /// Global index of coordinate `local` (= cp * dofs + axis) of rod `r`.
    #[inline]
    pub fn dof(&self, r: usize, local: usize) -> usize {
        let d = self.dofs[r];
        self.cp_index[r][local / d] + local % d
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::ordering::{control_point_order, RodGraph};
    fn chain(n: usize) -> Vec<[usize; 4]> {
        (0..n - 3).map(|s| [s, s + 1, s + 2, s + 3]).collect()
    }
    fn slot(rods: [usize; 2], n_rows: usize, a: [usize; 4], b: Option<[usize; 4]>) -> ConstraintSlot {
        let mut touched = [(0u8, 0usize); crate::constraint::MAX_TOUCHED];
        let mut len = 0;
        for i in a {
            touched[len] = (0, i);
            len += 1;
        }
        if let Some(b) = b {
            for i in b {
                touched[len] = (1, i);
                len += 1;
            }
        }
        ConstraintSlot { rods, n_rows, n_extra: 0, touched, held: [true; crate::constraint::MAX_TOUCHED], len, links: [NO_LINK; 2] }
    }
    /// The bandwidth of a rod with constraints spread along it does not grow
    /// with the number of constraints (IV.A).
    #[test]
    fn bandwidth_independent_of_constraint_count() {
        let segs = chain(400);
        let rods = [(400usize, 4usize, segs.as_slice())];
        let order: Vec<(usize, usize)> = (0..400).map(|i| (0, i)).collect();
        let bw0 = Layout::build(&rods, &order, &[]).bandwidth;
        assert_eq!(bw0, 15);
        for every in [100, 20, 5, 1] {
            let cons: Vec<_> = (0..397).step_by(every).map(|s| slot([0, 0], 3, [s, s + 1, s + 2, s + 3], None)).collect();
            let l = Layout::build(&rods, &order, &cons);
            assert_eq!(l.n, 1600 + 3 * cons.len());
            assert!(l.bandwidth <= bw0 + 2 * 3 + 3, "bandwidth {} with {} constraints", l.bandwidth, cons.len());
        }
    }
    /// Two parallel rods linked by rungs: interleaving keeps the band narrow
    /// and independent of the rod length; sequential ordering makes it span a rod.
    #[test]
    fn interleaving_linked_rods_keeps_the_band_narrow() {
        for n in [50usize, 200] {
            let segs = chain(n);
            let rods = [(n, 4usize, segs.as_slice()), (n, 4usize, segs.as_slice())];
            let cons: Vec<_> =
                (0..n - 3).map(|s| slot([0, 1], 1, [s, s + 1, s + 2, s + 3], Some([s, s + 1, s + 2, s + 3]))).collect();
            let g = [RodGraph { n_ctrl: n, segments: &segs }, RodGraph { n_ctrl: n, segments: &segs }];
            let seq_order: Vec<(usize, usize)> = (0..2).flat_map(|r| (0..n).map(move |i| (r, i))).collect();
            let seq = Layout::build(&rods, &seq_order, &cons);
            let inter = Layout::build(&rods, &control_point_order(&g, &[], &[vec![0, 1]]), &cons);
            // rows sit midway between the linked control points: half the span
            assert!(seq.bandwidth >= 2 * n, "sequential {}", seq.bandwidth);
            assert!(inter.bandwidth <= 45, "interleaved {}", inter.bandwidth);
        }
    }
}
