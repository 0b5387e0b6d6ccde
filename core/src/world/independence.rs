//! Redundant and contradictory constraints (SPEC §5): a batch of new
//! constraints is rejected when one of its rows is linearly dependent (at
//! the current configuration) on the rows already imposed on the rods it
//! touches or on earlier rows of the batch — redundant rows leave the
//! multipliers undefined, contradictory ones have no solution.
//!
//! Compliant constraints are left out, as batch and as existing rows: their
//! −C/h² block keeps the KKT matrix regular whatever their rows (a stacking
//! spring may well repeat a rigid rung's direction).
//!
//! Checked once per batch on the sparse structure: the rows are reduced by
//! Givens rotations into an upper-triangular R stored row by row, each row
//! as a dense window from its pivot column (George–Heath). With the columns
//! in the band-reducing order of the layout, a row meets O(bandwidth) pivots
//! of O(bandwidth) width, so a batch of k constraints costs O(k bw²) instead
//! of the O(k² n) of a dense re-check per add.
use crate::constraint::{Row, MAX_ROWS};
use crate::error::{Error, Result};
use crate::handles::RodHandle;
use crate::system::ordering::{control_point_order, Link, RodGraph};
use crate::world::{Constraint, World};

use std::collections::HashMap;

/// Relative size under which a reduced row counts as dependent (as the
/// dense Gram–Schmidt check it replaces).
const DEPENDENT: f64 = 1e-9;

/// A row of R: dense values from its pivot column on.
struct RRow {
    start: usize,
    v: Vec<f64>,
}

/// Incremental sparse QR (rows only; Q is not kept).
struct Reducer {
    rows: HashMap<usize, RRow>,
    work: Vec<f64>,
}

impl Reducer {
    /// Reduces the sparse row `entries` (column, value) against R; keeps it
    /// and returns true when it is independent.
    fn add(&mut self, entries: &[(usize, f64)]) -> bool {
        let Some(lo) = entries.iter().map(|e| e.0).min() else { return true };
        let mut hi = entries.iter().map(|e| e.0).max().unwrap_or(lo) + 1;
        self.work.clear();
        self.work.resize(hi - lo, 0.0);
        for &(c, x) in entries {
            self.work[c - lo] += x;
        }
        let norm0 = self.work.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm0 == 0.0 {
            return false;
        }
        let mut c = lo;
        while c < hi {
            let x = self.work[c - lo];
            if x == 0.0 {
                c += 1;
                continue;
            }
            match self.rows.get_mut(&c) {
                Some(r) => {
                    // Widen whichever window is shorter, then rotate so that
                    // work[c] becomes 0.
                    let r_end = r.start + r.v.len();
                    if r_end > hi {
                        self.work.resize(r_end - lo, 0.0);
                        hi = r_end;
                    } else if hi > r_end {
                        r.v.resize(hi - r.start, 0.0);
                    }
                    let p = r.v[0];
                    let h = p.hypot(x);
                    let (cs, sn) = (p / h, x / h);
                    for j in c..hi {
                        let (a, b) = (r.v[j - c], self.work[j - lo]);
                        r.v[j - c] = cs * a + sn * b;
                        self.work[j - lo] = -sn * a + cs * b;
                    }
                    self.work[c - lo] = 0.0;
                    c += 1;
                }
                None => {
                    let rest = self.work[c - lo..].iter().map(|x| x * x).sum::<f64>().sqrt();
                    if rest <= DEPENDENT * norm0 {
                        return false;
                    }
                    self.rows.insert(c, RRow { start: c, v: self.work[c - lo..].to_vec() });
                    return true;
                }
            }
        }
        false
    }
}

/// Checks that `batch` adds no row dependent on the constraints already on
/// the rods it touches (nor on each other).
pub(crate) fn check(world: &World, batch: &[Constraint]) -> Result<()> {
    check_with(&|h| world.rod(h), world.constraints.iter().map(|(i, c)| (i.0 as usize, c)), batch)
}

/// The same with the rods given by a lookup and the existing constraints by
/// an iterator (index, constraint): an assembly checks its batch against
/// its own rods before anything is added to the world.
pub(crate) fn check_with<'a>(
    rod_of: &dyn Fn(RodHandle) -> Result<&'a crate::rod::Rod>,
    existing: impl Iterator<Item = (usize, &'a Constraint)>,
    batch: &[Constraint],
) -> Result<()> {
    let hard: Vec<&Constraint> = batch.iter().filter(|c| c.compliance == 0.0).collect();
    if hard.is_empty() {
        return Ok(());
    }
    // Rods of the batch, and every existing constraint touching one of them.
    let mut rods: Vec<RodHandle> = Vec::new();
    let mut index: HashMap<RodHandle, usize> = HashMap::new();
    let mut add_rod = |h: RodHandle, rods: &mut Vec<RodHandle>| {
        index.entry(h).or_insert_with(|| {
            rods.push(h);
            rods.len() - 1
        });
    };
    for c in &hard {
        add_rod(c.rod, &mut rods);
        add_rod(c.other.unwrap_or(c.rod), &mut rods);
    }
    let mine: std::collections::HashSet<RodHandle> = rods.iter().copied().collect();
    let related: Vec<(usize, &Constraint)> =
        existing.filter(|(_, c)| c.compliance == 0.0).filter(|(_, c)| mine.contains(&c.rod) || c.other.is_some_and(|o| mine.contains(&o))).collect();
    for (_, c) in &related {
        add_rod(c.rod, &mut rods);
        add_rod(c.other.unwrap_or(c.rod), &mut rods);
    }
    let rod_refs: Vec<&crate::rod::Rod> = rods.iter().map(|h| rod_of(*h)).collect::<Result<_>>()?;
    // Column order: the layout's control-point order over these rods.
    let mut links: Vec<Link> = Vec::new();
    for c in related.iter().map(|(_, c)| *c).chain(hard.iter().copied()) {
        if let Some(o) = c.other {
            let (a, b) = (index[&c.rod], index[&o]);
            let t = c.kind.touched(&[rod_refs[a], rod_refs[b]])?;
            let s = t.as_slice();
            if let (Some(x), Some(y)) = (s.iter().find(|e| e.0 == 0), s.iter().find(|e| e.0 == 1)) {
                links.push((a, x.1, b, y.1));
            }
        }
    }
    let graphs: Vec<RodGraph<'_>> = rod_refs.iter().map(|r| RodGraph { n_ctrl: r.n_ctrl(), segments: &r.cache().seg_ctrl }).collect();
    let order = control_point_order(&graphs, &links, &[]);
    let mut rank: Vec<Vec<usize>> = rod_refs.iter().map(|r| vec![0; r.n_ctrl()]).collect();
    for (k, &(r, i)) in order.iter().enumerate() {
        rank[r][i] = k;
    }
    let mut red = Reducer { rows: HashMap::new(), work: Vec::new() };
    let mut buf = [Row::default(); MAX_ROWS];
    let mut entries: Vec<(usize, f64)> = Vec::with_capacity(64);
    let mut rows_of = |c: &Constraint, buf: &mut [Row; MAX_ROWS]| -> Result<Vec<Vec<(usize, f64)>>> {
        let sides = [index[&c.rod], index[&c.other.unwrap_or(c.rod)]];
        let nr = c.kind.n_rows();
        c.kind.linearize(&[rod_refs[sides[0]], rod_refs[sides[1]]], &mut buf[..nr])?;
        Ok(buf[..nr]
            .iter()
            .map(|row| {
                entries.clear();
                // (entries on a slider's own abscissa unknown, side 2, are private to it)
                for &(w, i, x) in row.entries().iter().filter(|e| e.0 < 2) {
                    let r = sides[w as usize];
                    let d = rod_refs[r].dofs();
                    entries.push((rank[r][i / d] * 4 + i % d, x));
                }
                entries.clone()
            })
            .collect())
    };
    // Existing rows first (they are independent), each ordered by its first column.
    let mut existing: Vec<Vec<(usize, f64)>> = Vec::new();
    for (_, c) in &related {
        existing.extend(rows_of(c, &mut buf)?);
    }
    existing.sort_by_key(|r| r.iter().map(|e| e.0).min().unwrap_or(0));
    for r in &existing {
        red.add(r);
    }
    for (k, c) in batch.iter().enumerate().filter(|(_, c)| c.compliance == 0.0) {
        for row in rows_of(c, &mut buf)? {
            if !red.add(&row) {
                let on: Vec<usize> = related.iter().map(|(i, _)| *i).take(12).collect();
                let who = if batch.len() > 1 { format!("{} (constraint {k} of the batch)", c.kind.name()) } else { c.kind.name().to_string() };
                return Err(Error::input(format!(
                    "linearly dependent constraint: {who} repeats what constraints {on:?}{} on the same rods already impose (redundant rows leave the forces undefined; contradictory ones have no solution)",
                    if batch.len() > 1 { " and the batch's earlier ones" } else { "" }
                )));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn reducer_finds_dependence() {
        let mut r = Reducer { rows: HashMap::new(), work: Vec::new() };
        assert!(r.add(&[(0, 1.0), (1, 2.0)]));
        assert!(r.add(&[(1, 1.0), (2, 1.0)]));
        assert!(!r.add(&[(0, 2.0), (1, 5.0), (2, 1.0)]), "row0 * 2 + row1");
        assert!(r.add(&[(0, 2.0), (1, 5.0), (2, 1.0 + 1e-6)]));
        assert!(!r.add(&[(5, 0.0)]), "zero row");
    }
}
