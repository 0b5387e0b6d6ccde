//! Ordering of the unknowns (thesis IV.3–IV.4, algorithms 9–10): the control
//! points of each rod in order; the rows of a constraint are inserted right
//! after the control point at the floor of the mean of the extreme control
//! points it touches. One linear pass places everything and a second gives
//! the half-bandwidth, which therefore does not grow with the number of
//! constraints spread along a rod.
use serde::{Deserialize, Serialize};

/// What the layout needs to know of a constraint.
#[derive(Clone, Copy, Debug)]
pub struct ConstraintSlot {
    /// Position of its rod in the layout's rod order.
    pub rod: usize,
    pub n_rows: usize,
    pub touched: [usize; 4],
}

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Layout {
    /// Global index of the first coordinate of each control point, per rod.
    pub cp_index: Vec<Vec<usize>>,
    pub dofs: Vec<usize>,
    /// Global index of the first row of each constraint.
    pub row_index: Vec<usize>,
    pub row_count: Vec<usize>,
    /// Number of unknowns (coordinates + multipliers).
    pub n: usize,
    pub n_rows: usize,
    /// Half-bandwidth (kl = ku).
    pub bandwidth: usize,
}

impl Layout {
    /// `rods[r] = (n_ctrl, dofs, segment control points)`.
    pub fn build(rods: &[(usize, usize, &[[usize; 4]])], cons: &[ConstraintSlot]) -> Layout {
        // anchors[r][i]: constraints whose rows follow control point i of rod r.
        let mut anchors: Vec<Vec<Vec<usize>>> = rods.iter().map(|(n, _, _)| vec![Vec::new(); *n]).collect();
        for (c, s) in cons.iter().enumerate() {
            let lo = *s.touched.iter().min().unwrap_or(&0); // touched has 4 entries
            let hi = *s.touched.iter().max().unwrap_or(&0);
            anchors[s.rod][(lo + hi) / 2].push(c);
        }
        let mut l = Layout {
            row_index: vec![0; cons.len()],
            row_count: cons.iter().map(|c| c.n_rows).collect(),
            ..Default::default()
        };
        let mut cursor = 0;
        for (r, (n, dofs, _)) in rods.iter().enumerate() {
            let mut idx = Vec::with_capacity(*n);
            for anchored in anchors[r].iter().take(*n) {
                idx.push(cursor);
                cursor += dofs;
                for &c in anchored {
                    l.row_index[c] = cursor;
                    cursor += cons[c].n_rows;
                    l.n_rows += cons[c].n_rows;
                }
            }
            l.cp_index.push(idx);
            l.dofs.push(*dofs);
        }
        l.n = cursor;
        // Half-bandwidth: segment blocks and constraint rows.
        let mut bw = 0;
        for (r, (_, dofs, segs)) in rods.iter().enumerate() {
            for ctrl in segs.iter() {
                let lo = ctrl.iter().map(|&i| l.cp_index[r][i]).min().unwrap_or(0);
                let hi = ctrl.iter().map(|&i| l.cp_index[r][i] + dofs - 1).max().unwrap_or(0);
                bw = bw.max(hi - lo);
            }
        }
        for (c, s) in cons.iter().enumerate() {
            let (r0, r1) = (l.row_index[c], l.row_index[c] + s.n_rows - 1);
            for &i in &s.touched {
                let (lo, hi) = (l.cp_index[s.rod][i], l.cp_index[s.rod][i] + l.dofs[s.rod] - 1);
                bw = bw.max(r1.saturating_sub(lo)).max(hi.saturating_sub(r0));
            }
        }
        l.bandwidth = bw;
        l
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
    fn chain(n: usize) -> Vec<[usize; 4]> {
        (0..n - 3).map(|s| [s, s + 1, s + 2, s + 3]).collect()
    }
    /// The bandwidth of a rod with constraints spread along it does not grow
    /// with the number of constraints (IV.A).
    #[test]
    fn bandwidth_independent_of_constraint_count() {
        let segs = chain(400);
        let rods = [(400usize, 4usize, segs.as_slice())];
        let bw0 = Layout::build(&rods, &[]).bandwidth;
        assert_eq!(bw0, 15);
        let mut last = 0;
        for every in [100, 20, 5, 1] {
            let cons: Vec<_> = (0..397)
                .step_by(every)
                .map(|s| ConstraintSlot { rod: 0, n_rows: 3, touched: [s, s + 1, s + 2, s + 3] })
                .collect();
            let l = Layout::build(&rods, &cons);
            assert_eq!(l.n, 1600 + 3 * cons.len());
            assert!(l.bandwidth <= bw0 + 2 * 3 + 3, "bandwidth {} with {} constraints", l.bandwidth, cons.len());
            last = last.max(l.bandwidth);
        }
        assert!(last < 30);
    }
}
