//! Rod–rod and self-contact detection (SPEC §7, thesis III.75–81): each
//! rod is a chain of capsules between consecutive samples (its ends
//! included), of the rod's largest section radius. A uniform grid finds
//! the capsules that may touch (O(n) for a bounded density); the closed
//! form of [`super::capsule`] gives their closest points; a pair closer
//! than the radii plus `margin` becomes a unilateral
//! [`ConstraintKind::Contact`] (|r_a − r_b| ≥ r_a + r_b) at the splines'
//! closest points within a segment of the two capsules. A pair is kept
//! when one of its capsules is the other's nearest on that strand (every
//! pass of a rod by a capsule has its nearest: a knot's braid brings
//! three), and of those landing within half a segment of each other on
//! both rods only the closest: one crossing gives one row (two identical
//! rows would make the system singular), strands lying side by side about
//! two rows per segment (more would outnumber what the control points can
//! meet) — where they stay, rather than all sliding along the strands to
//! the few places the strands sag most. A rod's own capsules closer along it than π (r_a + r_b) (the
//! shortest loop that can touch itself), or than half a circle through the
//! margin's reach (a straight stretch has points at distance d at arc d),
//! are never paired.
use super::capsule::closest_on_segments;
use super::{ContactDetector, ContactPair, ContactSet};
use crate::constraint::kinds::contact::closest_points_within;
use crate::constraint::kinds::Contact;
use crate::constraint::ConstraintKind;
use crate::error::{Error, Result};
use crate::handles::RodHandle;
use crate::rod::Rod;
use nalgebra::Vector3;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::f64::consts::PI;

/// Which contacts to detect, and how early (`margin`, length unit: pairs
/// closer than their radii plus the margin enter the active-set candidates,
/// so that a step does not tunnel through).
/// `friction`: the Coulomb coefficient between rods (dimensionless, ≥ 0).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RodContacts {
    pub margin: f64,
    pub self_contact: bool,
    pub between_rods: bool,
    #[serde(default)]
    pub friction: f64,
}

impl RodContacts {
    pub fn new(margin: f64, self_contact: bool, between_rods: bool) -> Result<RodContacts> {
        let d = RodContacts { margin, self_contact, between_rods, friction: 0.0 };
        d.validate()?;
        Ok(d)
    }
    /// Coulomb coefficient `mu` (≥ 0) between the rods.
    pub fn with_friction(mut self, mu: f64) -> Result<RodContacts> {
        self.friction = mu;
        self.validate()?;
        Ok(self)
    }
    pub fn validate(&self) -> Result<()> {
        super::check_margin_and_friction(self.margin, self.friction)
    }
}

/// One capsule: its rod (index in the detector's list), its axis from p
/// (abscissa ua, arc position sa) to q (ub, sb), its radius.
struct Capsule {
    rod: usize,
    p: Vector3<f64>,
    q: Vector3<f64>,
    ua: f64,
    ub: f64,
    sa: f64,
    radius: f64,
}

/// The capsules of one rod: between the domain ends and the samples (a
/// ring closes its chain). Returns them and the chain's length.
fn capsules(index: usize, rod: &Rod, out: &mut Vec<Capsule>) -> Result<f64> {
    let (u0, u1) = rod.domain();
    let (us, radius) = super::probe_points(rod);
    // The samples' points from their cached basis; the ends evaluated.
    let mut pts: Vec<Vector3<f64>> = Vec::with_capacity(us.len());
    if !rod.is_closed() {
        pts.push(rod.position(u0)?);
    }
    pts.extend(rod.sample_points());
    if !rod.is_closed() {
        pts.push(rod.position(u1)?);
    }
    debug_assert_eq!(pts.len(), us.len());
    let n = if rod.is_closed() { pts.len() } else { pts.len() - 1 };
    let mut arc = 0.0;
    for k in 0..n {
        let j = (k + 1) % pts.len();
        // A ring's last capsule runs to the first sample, one period on.
        let ub = if j == 0 { us[0] + (u1 - u0) } else { us[j] };
        out.push(Capsule { rod: index, p: pts[k], q: pts[j], ua: us[k], ub, sa: arc, radius });
        arc += (pts[j] - pts[k]).norm();
    }
    Ok(arc)
}

/// A grid cell's indices, hashed as three words (the array's own `Hash`
/// goes through a byte slice, several times slower here).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Cell([i64; 3]);

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
struct CellHasher(u64);

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

impl ContactDetector for RodContacts {
    fn detect(&self, rods: &[(RodHandle, &Rod)], out: &mut ContactSet) -> Result<()> {
        if !self.self_contact && !self.between_rods {
            return Ok(());
        }
        // Arc length below which a rod's own points are not paired.
        let exclusion = |reach: f64| (PI * reach).max(0.5 * PI * (reach + self.margin));
        let mut caps = Vec::new();
        let mut chain = Vec::with_capacity(rods.len());
        for (i, (_, rod)) in rods.iter().enumerate() {
            chain.push(capsules(i, rod, &mut caps)?);
        }
        if caps.is_empty() {
            return Ok(());
        }
        // Grid cells larger than any capsule plus the reach: a touching
        // pair's midpoints are then in neighbouring cells.
        let rmax = caps.iter().map(|c| c.radius).fold(0.0, f64::max);
        let lmax = caps.iter().map(|c| (c.q - c.p).norm()).fold(0.0, f64::max);
        let cell = lmax + 2.0 * rmax + self.margin;
        if !(cell > 0.0) || !cell.is_finite() {
            return Err(Error::input("contact detection: the rods have no extent (zero capsule length and radius)"));
        }
        let key = |c: &Capsule| {
            let m = 0.5 * (c.p + c.q) / cell;
            [m.x.floor() as i64, m.y.floor() as i64, m.z.floor() as i64]
        };
        // Capsules sorted by cell; each occupied cell a range of them.
        let keys: Vec<Cell> = caps.iter().map(|c| Cell(key(c))).collect();
        let mut order: Vec<(Cell, usize)> = keys.iter().enumerate().map(|(i, k)| (*k, i)).collect();
        order.sort_unstable();
        let mut cells: HashMap<Cell, (usize, usize), BuildHasherDefault<CellHasher>> = HashMap::default();
        let mut first = 0;
        for k in 1..=order.len() {
            if k == order.len() || order[k].0 != order[first].0 {
                cells.insert(order[first].0, (first, k));
                first = k;
            }
        }
        // Each capsule's box grown by its radius and half the margin: two
        // capsules can be within reach only if their boxes overlap.
        let grow = |c: &Capsule| Vector3::repeat(c.radius + 0.5 * self.margin);
        let boxes: Vec<(Vector3<f64>, Vector3<f64>)> = caps.iter().map(|c| (c.p.inf(&c.q) - grow(c), c.p.sup(&c.q) + grow(c))).collect();
        // Arc length between two capsules of one rod (around a ring).
        let along = |a: &Capsule, b: &Capsule| {
            let d = (b.sa - a.sa).abs();
            if rods[a.rod].1.is_closed() { d.min(chain[a.rod] - d) } else { d }
        };
        // Candidates (every pair of neighbouring cells visited once: a cell
        // with itself and with the 13 cells after it).
        let mut found: Vec<(usize, usize, f64, f64, f64)> = Vec::new();
        const FORWARD: [[i64; 3]; 14] = [
            [0, 0, 0], [1, 0, 0], [-1, 1, 0], [0, 1, 0], [1, 1, 0], [-1, -1, 1], [0, -1, 1],
            [1, -1, 1], [-1, 0, 1], [0, 0, 1], [1, 0, 1], [-1, 1, 1], [0, 1, 1], [1, 1, 1],
        ];
        for &(lo, hi) in cells.values() {
            let k = keys[order[lo].1].0;
            for d in FORWARD {
                let Some(&(lo2, hi2)) = cells.get(&Cell([k[0] + d[0], k[1] + d[1], k[2] + d[2]])) else { continue };
                let same_cell = d == [0, 0, 0];
                for x in lo..hi {
                    let start = if same_cell { x + 1 } else { lo2 };
                    for y in start..hi2 {
                        let (i, j) = (order[x].1.min(order[y].1), order[x].1.max(order[y].1));
                        let (a, b) = (&caps[i], &caps[j]);
                        let (ba, bb) = (&boxes[i], &boxes[j]);
                        if (0..3).any(|t| ba.0[t] > bb.1[t] || bb.0[t] > ba.1[t]) {
                            continue;
                        }
                        let same = a.rod == b.rod;
                        if (same && !self.self_contact) || (!same && !self.between_rods) {
                            continue;
                        }
                        let reach = a.radius + b.radius;
                        // A straight stretch has points at distance d at arc
                        // d: the margin's candidates need the rod to have
                        // turned back, half a circle at least.
                        if same && (along(a, b) < exclusion(reach) || j == i + 1) {
                            continue;
                        }
                        let (s, t, dist) = closest_on_segments(&a.p, &a.q, &b.p, &b.q);
                        if dist < reach + self.margin {
                            found.push((i, j, s, t, dist));
                        }
                    }
                }
            }
        }
        // A deterministic order whatever the hash map's iteration order:
        // along the first capsule's rod, then by the direction of the
        // partner's cell, then along the partner's rod (the order of a scan
        // capsule by capsule; it decides ties below, and the plectoneme's
        // closest approach moves from 0.94 to 0.80 diameters with them).
        let direction = |i: usize, j: usize| {
            let (a, b) = (keys[i].0, keys[j].0);
            (b[0] - a[0] + 1) * 9 + (b[1] - a[1] + 1) * 3 + (b[2] - a[2] + 1)
        };
        let mut sorted: Vec<(usize, i64, usize, usize)> = found.iter().enumerate().map(|(n, f)| (f.0, direction(f.0, f.1), f.1, n)).collect();
        sorted.sort_unstable();
        let found: Vec<(usize, usize, f64, f64, f64)> = sorted.iter().map(|x| found[x.3]).collect();
        // Each capsule's nearest partner on every strand passing by, ties to
        // the first in that order (parallel strands give equal distances).
        // Partners on one rod farther apart along it than the shortest loop
        // are different passes (a knot's braid brings three): keeping one
        // nearest over all of them left the third strand without rows, and
        // a tightening overhand knot pulled it through.
        let mut best: Vec<Vec<(usize, f64)>> = (0..caps.len()).map(|_| Vec::new()).collect();
        let mut offer = |i: usize, j: usize, dist: f64| {
            let strand = best[i].iter_mut().find(|(k, _)| caps[*k].rod == caps[j].rod && along(&caps[*k], &caps[j]) < exclusion(caps[i].radius + caps[j].radius));
            match strand {
                Some(e) if dist < e.1 => *e = (j, dist),
                Some(_) => {}
                None => best[i].push((j, dist)),
            }
        };
        for &(i, j, _, _, dist) in &found {
            offer(i, j, dist);
            offer(j, i, dist);
        }
        let nearest = |i: usize, j: usize| best[i].iter().any(|(k, _)| *k == j);
        // Half a segment's length along each rod (its chain over its segments).
        let spacing: Vec<f64> = rods.iter().zip(&chain).map(|((_, r), l)| 0.5 * l / r.n_segments().max(1) as f64).collect();
        // Rows kept, by rod pair and grid cell (as large as the largest
        // duplicate distance, so a duplicate is in a neighbouring cell).
        let dup_cell = spacing.iter().copied().fold(0.5 * rmax, f64::max);
        type Kept = HashMap<(RodHandle, RodHandle, Cell), Vec<(Vector3<f64>, Vector3<f64>)>, BuildHasherDefault<CellHasher>>;
        let mut kept: Kept = HashMap::default();
        // A capsule's span grown by a segment each way: the chords may pick
        // a capsule next to the one holding a crossing's touching point, and
        // a row held inside the chord's own span then pushes at a slant (a
        // rod pressed across another slid off it).
        let window = |rod: &Rod, c: &Capsule| {
            let (u0, u1) = rod.domain();
            let grow = (u1 - u0) / rod.n_segments().max(1) as f64;
            if rod.is_closed() {
                (c.ua - grow, c.ub + grow)
            } else {
                ((c.ua - grow).max(u0), (c.ub + grow).min(u1))
            }
        };
        // Each kept capsule pair moved to the splines' closest points
        // within those windows.
        let mut rows: Vec<(f64, usize, usize, Contact, Vector3<f64>, Vector3<f64>)> = Vec::new();
        for (i, j, s, t, _) in found {
            if !nearest(i, j) && !nearest(j, i) {
                continue;
            }
            let (a, b) = (&caps[i], &caps[j]);
            let (ra, rb) = (rods[a.rod].1, rods[b.rod].1);
            // Started unwrapped, inside the windows (a ring's last capsule
            // runs past the period end); the result comes back wrapped.
            let (ua, ub) = closest_points_within(ra, rb, a.ua + s * (a.ub - a.ua), b.ua + t * (b.ub - b.ua), window(ra, a), window(rb, b))?;
            let c = Contact { ua, ub, distance: a.radius + b.radius };
            let (pa, pb) = (ra.position(c.ua)?, rb.position(c.ub)?);
            if a.rod == b.rod {
                // The projection may slide a self pair along the rod onto
                // itself: keep it only if it still closes a loop.
                let (u0, u1) = ra.domain();
                let du = (c.ua - c.ub).abs();
                let du = if ra.is_closed() { du.min(u1 - u0 - du) } else { du };
                let along = du * chain[a.rod] / (u1 - u0);
                if along < exclusion(c.distance) || (pa - pb).norm() < 1e-9 * c.distance {
                    continue;
                }
            }
            rows.push(((pa - pb).norm(), a.rod, b.rod, c, pa, pb));
        }
        // Closest first (a stable sort: ties keep the order above), so that
        // of rows landing near each other the one at the touching point is
        // kept — a crossing's row, not a neighbour's off to its side.
        rows.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut chosen: Vec<([RodHandle; 2], Contact)> = Vec::with_capacity(rows.len());
        for (_, ia, ib, c, pa, pb) in rows {
            let handles = [rods[ia].0, rods[ib].0];
            // Rows closer than half a segment on both rods would outnumber
            // what the control points can meet (strands side by side).
            let (sa, sb) = (spacing[ia].max(0.25 * c.distance), spacing[ib].max(0.25 * c.distance));
            // One orientation for both (a, b) and (b, a): the lower (rod, u) first.
            let ((h0, p0, s0), (h1, p1, s1)) =
                if (handles[0], c.ua) <= (handles[1], c.ub) { ((handles[0], pa, sa), (handles[1], pb, sb)) } else { ((handles[1], pb, sb), (handles[0], pa, sa)) };
            let cell_of = |p: &Vector3<f64>| [(p.x / dup_cell).floor() as i64, (p.y / dup_cell).floor() as i64, (p.z / dup_cell).floor() as i64];
            let k = cell_of(&p0);
            let mut duplicate = false;
            'search: for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let Some(list) = kept.get(&(h0, h1, Cell([k[0] + dx, k[1] + dy, k[2] + dz]))) else { continue };
                        if list.iter().any(|(q0, q1): &(Vector3<f64>, Vector3<f64>)| (q0 - p0).norm() < s0 && (q1 - p1).norm() < s1) {
                            duplicate = true;
                            break 'search;
                        }
                    }
                }
            }
            if !duplicate {
                kept.entry((h0, h1, Cell(k))).or_default().push((p0, p1));
                chosen.push((handles, c));
            }
        }
        // Back in the order along the rods: the set's order then changes
        // only when rows come or go, not when two trade places in distance
        // (which would rebuild the system's layout).
        chosen.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.ua.total_cmp(&y.1.ua)).then(x.1.ub.total_cmp(&y.1.ub)));
        for (handles, c) in chosen {
            out.pairs.push(ContactPair::new(handles, ConstraintKind::Contact(c))?.with_friction(self.friction)?);
        }
        Ok(())
    }
}
