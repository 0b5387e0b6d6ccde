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
//! three); those pairs are moved onto the splines (where strands cross
//! steeply, a pair closest at a capsule's end leaves that to the pair
//! across it: a crossing's ten or so pairs give one projection), and of
//! those landing within half a segment of each other on
//! both rods only the closest: one crossing gives one row (two identical
//! rows would make the system singular), strands lying side by side about
//! two rows per segment (more would outnumber what the control points can
//! meet) — where they stay, rather than all sliding along the strands to
//! the few places the strands sag most. A rod's own capsules closer along it than π (r_a + r_b) (the
//! shortest loop that can touch itself), or than half a circle through the
//! margin's reach (a straight stretch has points at distance d at arc d),
//! are never paired.
//!
//! In the step of a world that uses rayon's pool (`Scratch::parallel`,
//! on one of the pool's threads) the capsules, the pair tests, the nearest
//! partners, the seeds, the projections and the choice among close rows
//! (rod pair by rod pair) run in blocks on the pool (the grid stays on one
//! thread), every block keeping the serial order: the rows are the
//! one-thread rows bit for bit. The buffers live in the world's workspace
//! ([`Scratch`]) from one detection to the next.
use super::capsule::closest_on_axes;
use super::{ContactDetector, ContactPair, ContactSet};
use crate::constraint::kinds::contact::closest_points_and_positions_within;
use crate::constraint::kinds::Contact;
use crate::constraint::ConstraintKind;
use crate::error::Result;
use crate::handles::RodHandle;
use crate::rod::Rod;
use nalgebra::Vector3;
use super::broad::{Bounds, Cell, CellHasher, Runs};
use super::nearest::{Hit, Nearest};
use std::collections::HashMap;
use std::f64::consts::PI;
use std::hash::BuildHasherDefault;

/// Runs whose hits are found, then offered, at a time (a few hundred
/// kilobytes of hits on a dense structure).
const RUNS_PER_CHUNK: usize = 1024;

/// One rod pair's kept rows, keyed by grid cell.
type Kept<V> = HashMap<Cell, V, BuildHasherDefault<CellHasher>>;

/// Rows of one rod pair up to which each is compared with all the kept
/// ones (no grid).
const FEW_ROWS: usize = 32;

/// Which contacts to detect, and how early (`margin`, length unit: pairs
/// closer than their radii plus the margin enter the active-set candidates,
/// so that a step does not tunnel through).
/// `friction`: the Coulomb coefficient between rods (dimensionless, ≥ 0).
/// `no_self_contact`: rods never paired with themselves even with
/// `self_contact` (an image rod that repeats another's self-contacts).
/// `joined`: pairs [a, b] of rods where b continues a (a's end at b's
/// start, tied by the caller): their capsules closer along the joined
/// yarn than the self-contact exclusion are never paired, as on one rod.
/// `pair_friction`: Coulomb coefficients for given rod pairs (either
/// order; [a, a] for a rod against itself) instead of `friction` — a
/// cable against a rope, yarns of two fibres.
/// `line_stiffness`: None, one rigid row where two strands come closest
/// (each place of contact); Some(k), distributed rows (`distributed_rows`):
/// a compliant row at the middle of every capsule within reach of another
/// strand, k the contact's stiffness per unit length (force/length²);
/// their friction a tangential spring per row
/// ([`super::friction::Friction::prepare_spring`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RodContacts {
    pub margin: f64,
    pub self_contact: bool,
    pub between_rods: bool,
    #[serde(default)]
    pub friction: f64,
    #[serde(default)]
    pub no_self_contact: Vec<RodHandle>,
    #[serde(default)]
    pub joined: Vec<[RodHandle; 2]>,
    #[serde(default, deserialize_with = "sorted_pairs")]
    pub pair_friction: Vec<([RodHandle; 2], f64)>,
    #[serde(default)]
    pub line_stiffness: Option<f64>,
}

/// Pair coefficients as read from a snapshot, put in the order the lookup
/// needs (snapshots of 2026-11-30 kept them in the order given); a pair
/// given twice is still refused by `validate`.
fn sorted_pairs<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Vec<([RodHandle; 2], f64)>, D::Error> {
    let mut v: Vec<([RodHandle; 2], f64)> = serde::Deserialize::deserialize(d)?;
    for (k, _) in &mut v {
        *k = pair_key(k[0], k[1]);
    }
    v.sort_by(|a, b| a.0.cmp(&b.0));
    Ok(v)
}

/// A rod pair's key in `pair_friction`: [smaller, larger] handle.
fn pair_key(a: RodHandle, b: RodHandle) -> [RodHandle; 2] {
    [a.min(b), a.max(b)]
}

impl RodContacts {
    pub fn new(margin: f64, self_contact: bool, between_rods: bool) -> Result<RodContacts> {
        let d = RodContacts { margin, self_contact, between_rods, friction: 0.0, no_self_contact: Vec::new(), joined: Vec::new(), pair_friction: Vec::new(), line_stiffness: None };
        d.validate()?;
        Ok(d)
    }
    /// Coulomb coefficient `mu` (≥ 0) between the rods.
    pub fn with_friction(mut self, mu: f64) -> Result<RodContacts> {
        self.friction = mu;
        self.validate()?;
        Ok(self)
    }
    /// These rods are never paired with themselves.
    pub fn without_self_contact(mut self, rods: &[RodHandle]) -> RodContacts {
        self.no_self_contact.extend_from_slice(rods);
        self
    }
    /// Rod `b` continues rod `a` (a's end at b's start): points closer
    /// along the two than the self-contact exclusion are never paired.
    pub fn with_joined(mut self, a: RodHandle, b: RodHandle) -> Result<RodContacts> {
        if a == b {
            return Err(crate::Error::invalid("joined", format!("{a:?}"), "two different rods (a ring is a closed rod)"));
        }
        if self.joined.iter().any(|j| j[0] == a || j[1] == b) {
            return Err(crate::Error::invalid("joined", format!("{a:?} → {b:?}"), "a rod continued by one rod at most and continuing one at most"));
        }
        self.joined.push([a, b]);
        Ok(self)
    }
    /// Coulomb coefficient `mu` (≥ 0) between rods `a` and `b` (either
    /// order; `a` = `b`: the rod against itself), instead of the
    /// detector's; each pair given once.
    pub fn with_pair_friction(mut self, a: RodHandle, b: RodHandle, mu: f64) -> Result<RodContacts> {
        let key = pair_key(a, b);
        // Kept sorted by pair: detection looks a coefficient up per row.
        match self.pair_friction.binary_search_by(|(k, _)| k.cmp(&key)) {
            Ok(_) => return Err(crate::Error::invalid("pair friction", format!("{a:?} and {b:?}"), "each rod pair given once")),
            Err(at) => self.pair_friction.insert(at, (key, mu)),
        }
        self.validate()?;
        Ok(self)
    }
    /// Distributed rows of stiffness `k` per unit length (force/length²,
    /// finite > 0) instead of one rigid row per place of contact. With
    /// friction, each row's is a spring slipping between steps: within a
    /// step a sliding row passes μ N by what it slides over its compliance
    /// (`tests/contact_line.rs`).
    pub fn with_line_stiffness(mut self, k: f64) -> Result<RodContacts> {
        self.line_stiffness = Some(k);
        self.validate()?;
        Ok(self)
    }
    /// Every rod the detector names (its lists of rods and pairs).
    pub fn rods_named(&self) -> impl Iterator<Item = RodHandle> + '_ {
        let pairs = self.joined.iter().chain(self.pair_friction.iter().map(|(k, _)| k));
        self.no_self_contact.iter().copied().chain(pairs.flat_map(|k| k.iter().copied()))
    }
    /// The Coulomb coefficient between rods `a` and `b`.
    pub fn friction_between(&self, a: RodHandle, b: RodHandle) -> f64 {
        let key = pair_key(a, b);
        match self.pair_friction.binary_search_by(|(k, _)| k.cmp(&key)) {
            Ok(i) => self.pair_friction[i].1,
            Err(_) => self.friction,
        }
    }
    pub fn validate(&self) -> Result<()> {
        super::check_margin_and_friction(self.margin, self.friction)?;
        if let Some(k) = self.line_stiffness {
            crate::error::positive("line stiffness", k)?;
        }
        // Sorted, each pair once, each key (min, max): what the lookup
        // needs (a hand-edited snapshot may break it).
        if let Some(w) = self.pair_friction.windows(2).find(|w| w[0].0 >= w[1].0) {
            return Err(crate::Error::invalid("pair friction", format!("{:?} after {:?}", w[1].0, w[0].0), "pairs sorted, each once"));
        }
        if let Some((k, _)) = self.pair_friction.iter().find(|(k, _)| k[0] > k[1]) {
            return Err(crate::Error::invalid("pair friction", format!("{k:?}"), "each pair as [smaller, larger] handle"));
        }
        self.pair_friction.iter().try_for_each(|&(_, mu)| super::friction::check_mu(mu))
    }
}

/// A capsule pair to project onto the splines: capsules and the closest
/// points' parameters on them.
type Seed = (usize, usize, f64, f64);

/// A row found by projection: its points' distance, the rods (indices in
/// the detector's list), the contact and its two points.
type Row = (f64, usize, usize, Contact, Vector3<f64>, Vector3<f64>);

/// Buffers of [`RodContacts`] kept between detections (per block where a
/// phase runs in blocks, [`super::fill_blocks`]).
#[derive(Debug, Default)]
pub(crate) struct Scratch {
    caps: Vec<Capsule>,
    boxes: Vec<Bounds>,
    spheres: Vec<(Vector3<f64>, f64)>,
    /// Per capsule what the nearest partners' strand test reads, apart
    /// from the capsules (a fifth of their bytes: the partners of a hit
    /// lie anywhere in the arrays).
    strands: Vec<Strand>,
    chain: Vec<f64>,
    /// Per rod: closed (a ring)? Read per offer, without a visit to the rod.
    closed: Vec<bool>,
    /// Per rod: a segment's length along its chain.
    segment: Vec<f64>,
    /// Per rod: never paired with itself (`no_self_contact`)?
    no_self: Vec<bool>,
    /// Per rod: the rod continuing it (`joined`), or usize::MAX.
    next: Vec<usize>,
    rod_ranges: Vec<(usize, usize)>,
    runs: Runs,
    hits: Vec<HitBlock>,
    nearest: Nearest,
    /// [`Self::caps`] and the others cut per rod (reused; see [`Parts`]).
    parts: Vec<[usize; 10]>,
    seeds: Vec<Vec<Seed>>,
    seed_list: Vec<Seed>,
    rows: Vec<Vec<Row>>,
    sorted: Vec<Row>,
    /// Each row's rod pair, distance and index in `sorted`.
    by_pair: Vec<((usize, usize), f64, usize)>,
    group_starts: Vec<usize>,
    choice: Vec<Choice>,
    chosen: Vec<([RodHandle; 2], Contact)>,
    /// Distributed rows per block: rods (in the detector's list), the row,
    /// its compliance (length/force).
    lines: Vec<Vec<(usize, usize, Contact, f64)>>,
}

/// One block of the pair tests: its hits, and its own scratch (a run's
/// partners, and the other run's capsules near the first's box).
#[derive(Debug, Default)]
struct HitBlock {
    hits: Vec<Hit>,
    partners: Vec<usize>,
    near: Vec<(usize, (Vector3<f64>, f64))>,
}

impl super::BlockBuffer for HitBlock {
    fn clear(&mut self) {
        self.hits.clear();
    }
}

impl AsRef<[Hit]> for HitBlock {
    fn as_ref(&self) -> &[Hit] {
        &self.hits
    }
}

/// One rod's share of the capsule arrays, filled by one task.
type Parts<'a> = (usize, &'a mut [Capsule], &'a mut [Bounds], &'a mut [(Vector3<f64>, f64)], &'a mut [Strand], &'a mut f64);

// `Scratch::parts` keeps the buffer as words of the same size and
// alignment, or each detection would allocate it again.
const _: () = assert!(std::mem::size_of::<Parts<'static>>() == std::mem::size_of::<[usize; 10]>() && std::mem::align_of::<Parts<'static>>() == std::mem::align_of::<[usize; 10]>());

/// A capsule's rod, arc position and radius ([`Capsule`]'s).
#[derive(Clone, Copy, Debug, Default)]
struct Strand {
    rod: usize,
    sa: f64,
    radius: f64,
}

/// One capsule: its rod (index in the detector's list), its axis from p
/// (abscissa ua, arc position sa) to p + d (abscissa ub), |d|², its
/// radius.
#[derive(Clone, Copy, Debug, Default)]
struct Capsule {
    rod: usize,
    p: Vector3<f64>,
    d: Vector3<f64>,
    dd: f64,
    ua: f64,
    ub: f64,
    sa: f64,
    radius: f64,
}

/// How many capsules [`capsules`] makes of a rod: one per sample and one
/// more on an open rod (its ends are points of the chain too).
fn capsule_count(rod: &Rod) -> usize {
    rod.n_samples() + usize::from(!rod.is_closed())
}

/// The capsules of one rod, into `out` ([`capsule_count`] of them):
/// between the domain ends and the samples (a ring closes its chain, its
/// last capsule running to the first sample one period on). Returns the
/// chain's length.
fn capsules(index: usize, rod: &Rod, out: &mut [Capsule]) -> Result<f64> {
    let (u0, u1) = rod.domain();
    let radius = super::capsule_radius(rod);
    let (mut arc, mut k) = (0.0, 0);
    let mut add = |from: (f64, Vector3<f64>), to: (f64, Vector3<f64>)| {
        let d = to.1 - from.1;
        out[k] = Capsule { rod: index, p: from.1, d, dd: d.norm_squared(), ua: from.0, ub: to.0, sa: arc, radius };
        arc += d.norm();
        k += 1;
    };
    // The samples' points from their cached basis; the ends evaluated.
    let mut samples = rod.samples_at();
    let first = if rod.is_closed() {
        match samples.next() {
            Some(f) => f,
            None => return Ok(0.0),
        }
    } else {
        (u0, rod.position(u0)?)
    };
    let mut from = first;
    for to in samples {
        add(from, to);
        from = to;
    }
    add(from, if rod.is_closed() { (first.0 + (u1 - u0), first.1) } else { (u1, rod.position(u1)?) });
    Ok(arc)
}

impl ContactDetector for RodContacts {
    fn detect_with(&self, rods: &[(RodHandle, &Rod)], out: &mut ContactSet, scratch: &mut super::Scratch) -> Result<()> {
        if !self.self_contact && !self.between_rods {
            return Ok(());
        }
        let exclusion = |reach: f64| self.exclusion(reach);
        // In the step of a world that uses the pool (on one of its
        // threads) the phases below run in blocks on the pool; each keeps
        // the serial order, so the rows are the same bit for bit.
        let parallel = scratch.parallel && rayon::current_thread_index().is_some();
        // Each capsule's box grown by its radius and half the margin: two
        // capsules can be within reach only if their boxes overlap. And the
        // sphere about its middle through its grown ends: a crossing's
        // corner pairs, whose boxes overlap, are out of reach.
        let grow = |c: &Capsule| Vector3::repeat(c.radius + 0.5 * self.margin);
        // Each rod's capsules in its own range of the arrays, filled rod by
        // rod (on the pool when parallel).
        let Scratch { caps, boxes, spheres, strands, chain, closed, segment, no_self, next, rod_ranges, runs, hits, nearest, parts: parts_buf, seeds, seed_list, rows, sorted, by_pair, group_starts, choice, chosen, lines } = &mut scratch.rods;
        rod_ranges.clear();
        closed.clear();
        closed.extend(rods.iter().map(|(_, r)| r.is_closed()));
        no_self.clear();
        no_self.extend(rods.iter().map(|(h, _)| self.no_self_contact.contains(h)));
        next.clear();
        next.resize(rods.len(), usize::MAX);
        // A rod no longer in the world leaves nothing to exclude.
        let index = |h: &RodHandle| rods.iter().position(|(x, _)| x == h);
        for [a, b] in &self.joined {
            if let (Some(a), Some(b)) = (index(a), index(b)) {
                next[a] = b;
            }
        }
        let (no_self, next) = (&no_self[..], &next[..]);
        for (_, rod) in rods {
            let start = rod_ranges.last().map_or(0, |r: &(usize, usize)| r.1);
            rod_ranges.push((start, start + capsule_count(rod)));
        }
        // Every entry is written below: the buffers are only sized, not
        // cleared (17 MB of stores at 100,000 capsules).
        let total = rod_ranges.last().map_or(0, |r| r.1);
        caps.resize(total, Capsule::default());
        boxes.resize(total, Bounds { lo: Vector3::zeros(), hi: Vector3::zeros() });
        spheres.resize(total, (Vector3::zeros(), 0.0));
        strands.resize(total, Strand::default());
        chain.resize(rods.len(), 0.0);
        {
            // The per-rod slices in a buffer kept from the last detection
            // (the same size and alignment: `recycle` keeps its memory).
            let mut parts: Vec<Parts<'_>> = crate::system::workspace::recycle(std::mem::take(parts_buf));
            let (mut c, mut b, mut s, mut t) = (&mut caps[..], &mut boxes[..], &mut spheres[..], &mut strands[..]);
            for ((i, &(first, end)), length) in rod_ranges.iter().enumerate().zip(chain.iter_mut()) {
                let n = end - first;
                let (c0, c1) = std::mem::take(&mut c).split_at_mut(n);
                let (b0, b1) = std::mem::take(&mut b).split_at_mut(n);
                let (s0, s1) = std::mem::take(&mut s).split_at_mut(n);
                let (t0, t1) = std::mem::take(&mut t).split_at_mut(n);
                parts.push((i, c0, b0, s0, t0, length));
                (c, b, s, t) = (c1, b1, s1, t1);
            }
            let fill = |(i, c, b, s, t, length): &mut Parts<'_>| -> Result<()> {
                **length = capsules(*i, rods[*i].1, c)?;
                for (((cap, bx), sp), st) in c.iter().zip(b.iter_mut()).zip(s.iter_mut()).zip(t.iter_mut()) {
                    let q = cap.p + cap.d;
                    *bx = Bounds { lo: cap.p.inf(&q) - grow(cap), hi: cap.p.sup(&q) + grow(cap) };
                    *sp = (0.5 * (cap.p + q), 0.5 * cap.dd.sqrt() + cap.radius + 0.5 * self.margin);
                    *st = Strand { rod: cap.rod, sa: cap.sa, radius: cap.radius };
                }
                Ok(())
            };
            let filled = if parallel {
                use rayon::prelude::*;
                // The first rod's error, as on one thread.
                parts.par_iter_mut().enumerate().map(|(k, p)| fill(p).map_err(|e| (k, e))).reduce(|| Ok(()), super::first_error).map_err(|(_, e)| e)
            } else {
                parts.iter_mut().try_for_each(fill)
            };
            *parts_buf = crate::system::workspace::recycle(parts);
            filled?;
        }
        let (caps, boxes, spheres, strands, chain, closed, rod_ranges) = (&caps[..], &boxes[..], &spheres[..], &strands[..], &chain[..], &closed[..], &rod_ranges[..]);
        if caps.is_empty() {
            return Ok(());
        }
        // Arc length between two capsules of one rod (around a ring).
        let along = |rod: usize, sa: f64, sb: f64| {
            let d = (sb - sa).abs();
            if closed[rod] { d.min(chain[rod] - d) } else { d }
        };
        // Arc length between capsules of two joined rods (b continuing a,
        // or a continuing b), or None.
        let joined_along = |ra: usize, sa: f64, rb: usize, sb: f64| {
            if next[ra] == rb {
                Some(chain[ra] - sa + sb)
            } else if next[rb] == ra {
                Some(chain[rb] - sb + sa)
            } else {
                None
            }
        };
        // Two partners of capsule `i` on one rod closer along it than the
        // shortest loop are on the same pass of that rod. A knot's braid
        // brings three passes: keeping one nearest over all of them left the
        // third without rows, and a tightening overhand knot pulled it
        // through. Equal distances (strands side by side) keep the first
        // pair tested.
        let same_strand = |i: usize, k: usize, j: usize| {
            let (k, j) = (&strands[k], &strands[j]);
            k.rod == j.rod && along(k.rod, k.sa, j.sa) < exclusion(strands[i].radius + j.radius)
        };
        // The exact test of one capsule pair whose boxes and spheres
        // overlap: a rod's own neighbourhood, the closest points; a pair
        // within reach is a hit, offered below to both capsules' nearest
        // partners.
        let test = |i: usize, j: usize| -> Option<(f64, [f64; 2])> {
            // (Which pairs are asked for is checked per pair of runs.)
            let (a, b) = (&caps[i], &caps[j]);
            let same = a.rod == b.rod;
            let reach = a.radius + b.radius;
            // A straight stretch has points at distance d at arc d: the
            // margin's candidates need the rod to have turned back, half a
            // circle at least.
            if same && (along(a.rod, a.sa, b.sa) < exclusion(reach) || j == i + 1) {
                return None;
            }
            // Across a join the capsule's own length is added: the pair
            // next to the join is excluded whatever its lengths.
            if !same && joined_along(a.rod, a.sa, b.rod, b.sa).is_some_and(|s| s < exclusion(reach) + a.dd.sqrt() + b.dd.sqrt()) {
                return None;
            }
            let (s, t, gap2) = closest_on_axes(&a.p, &a.d, a.dd, &b.p, &b.d, b.dd);
            // Most pairs tested are out of reach: their square roots are
            // skipped (the factor covers the rounding of both sides, so
            // the pairs kept are those `dist < reach + margin` keeps).
            let lim = reach + self.margin;
            if gap2 > lim * lim * (1.0 + 1e-12) {
                return None;
            }
            let dist = gap2.sqrt();
            (dist < lim).then_some((dist, [s, t]))
        };
        runs.fill(boxes, rod_ranges)?;
        let runs = &*runs;
        // Run by run in the capsules' order, with itself and the later runs
        // whose boxes overlap it (each pair of runs once). The hits of a
        // chunk of runs are offered before the next chunk's are found: a
        // cache's worth of hits at a time, in order.
        nearest.reset(caps.len(), if parallel { rayon::current_num_threads() } else { 1 });
        for chunk in (0..runs.len()).step_by(RUNS_PER_CHUNK) {
            super::fill_blocks(parallel, RUNS_PER_CHUNK.min(runs.len() - chunk), hits, |range, block| {
                let HitBlock { hits, partners, near: near_b } = block;
                for a in chunk + range.start..chunk + range.end {
                    runs.partners(a, partners);
                    let rod_a = caps[runs.capsules(a).start].rod;
                    for &b in partners.iter() {
                        let same = rod_a == caps[runs.capsules(b).start].rod;
                        if (same && (!self.self_contact || no_self[rod_a])) || (!same && !self.between_rods) {
                            continue;
                        }
                        // Only the capsules of each run within the other's box.
                        let (box_a, box_b) = (runs.bounds(a), runs.bounds(b));
                        near_b.clear();
                        near_b.extend(runs.capsules(b).filter(|&j| boxes[j].overlaps(box_a)).map(|j| (j, spheres[j])));
                        for i in runs.capsules(a).filter(|&i| boxes[i].overlaps(box_b)) {
                            let (ci, ri) = spheres[i];
                            // The spheres only: the capsules' own boxes,
                            // tested after them, never turned a pair away on
                            // a woven mat (992,016 of 992,016 overlapped);
                            // the exact test decides either way.
                            for &(j, (cj, rj)) in near_b.iter().filter(|x| b != a || x.0 > i) {
                                if (ci - cj).norm_squared() <= (ri + rj) * (ri + rj) {
                                    // Runs come in the capsules' order: i < j.
                                    if let Some((d, st)) = test(i, j) {
                                        hits.push((i, j, d, st));
                                    }
                                }
                            }
                        }
                    }
                }
                Ok(())
            })?;
            nearest.take(hits, same_strand);
        }
        // A pair is a candidate when one capsule is the other's nearest on
        // that strand (every pass of a rod by a capsule has its nearest).
        let candidate = |i: usize, j: usize| nearest.get(i, j).or_else(|| nearest.get(j, i));
        // The capsules before and after one along its rod (around a ring).
        let step_along = |k: usize, forward: bool| {
            let (first, end) = rod_ranges[caps[k].rod];
            let closed = closed[caps[k].rod];
            match (forward, k) {
                (true, k) if k + 1 < end => Some(k + 1),
                (true, _) => closed.then_some(first),
                (false, k) if k > first => Some(k - 1),
                (false, _) => closed.then_some(end - 1),
            }
        };
        // Seeds for the projection onto the splines. A candidate whose
        // closest point lies at the end of one of its capsules may leave it
        // to the candidate across that end, which holds that point too and
        // so is at least as close (ties go to the lower pair): a crossing's
        // ten or so candidates then leave one seed, the pair whose closest
        // points lie inside both capsules. It may do so only where the
        // strands cross steeply enough that all the crossing's candidates
        // lie within a segment of it, the reach of a projection's window
        // (sin θ ≥ (r_a + r_b + margin) / segment): every projection would
        // land on the seed's row. Strands at a shallow angle, beside each
        // other or sagging onto each other, keep a seed at every candidate
        // as before: their projections stop at their windows' ends and give
        // rows along the whole stretch in contact.
        segment.clear();
        segment.extend(rods.iter().zip(chain).map(|((_, r), l)| l / r.n_segments().max(1) as f64));
        let segment = &segment[..];
        let steep = |a: &Capsule, b: &Capsule| {
            let (da, db) = (a.d, b.d);
            let l = segment[a.rod].min(segment[b.rod]);
            let reach = a.radius + b.radius + self.margin;
            // |da × db|² ≥ (reach / l)² |da|² |db|², false for a point capsule.
            da.cross(&db).norm_squared() * l * l >= reach * reach * da.norm_squared() * db.norm_squared()
        };
        if let Some(k) = self.line_stiffness {
            return self.distributed_rows(k, parallel, rods, caps, nearest, chain, next, lines, out);
        }
        super::fill_blocks(parallel, caps.len(), seeds, |range, seeds| {
            for i in range {
                for (j, d, [s, t]) in nearest.of(i) {
                    let (lo, hi) = (i.min(j), i.max(j));
                    // Once per pair: from the lower capsule when it names the
                    // higher one, else from the higher.
                    if i == hi && nearest.get(lo, hi).is_some() {
                        continue;
                    }
                    // (s, t): the closest points on caps[lo] and caps[hi], from the hit.
                    let (a, b) = (&caps[lo], &caps[hi]);
                    if !steep(a, b) {
                        seeds.push((lo, hi, s, t));
                        continue;
                    }
                    let across = [
                        (s == 0.0).then(|| (step_along(lo, false), Some(hi))),
                        (s == 1.0).then(|| (step_along(lo, true), Some(hi))),
                        (t == 0.0).then(|| (Some(lo), step_along(hi, false))),
                        (t == 1.0).then(|| (Some(lo), step_along(hi, true))),
                    ];
                    let left = across.iter().flatten().any(|pair| match *pair {
                        (Some(x), Some(y)) if x != y => {
                            let (x, y) = (x.min(y), x.max(y));
                            candidate(x, y).is_some_and(|e| (e, x, y) < (d, lo, hi))
                        }
                        _ => false,
                    });
                    if !left {
                        seeds.push((lo, hi, s, t));
                    }
                }
            }
            Ok(())
        })?;
        seed_list.clear();
        seed_list.extend(seeds.iter().flatten());
        // The cell of the grid on a rod pair's kept rows, four times the
        // largest duplicate distance: the points within it of a row are in
        // at most two cells along each axis, and in one along about half.
        let rmax = caps.iter().map(|c| c.radius).fold(0.0, f64::max);
        let dup_cell = 4.0 * segment.iter().map(|l| 0.5 * l).fold(0.5 * rmax, f64::max);
        // Each kept capsule pair moved to the splines' closest points
        // within those windows.
        super::fill_blocks(parallel, seed_list.len(), rows, |range, rows| {
            for &(i, j, s, t) in &seed_list[range] {
                let (a, b) = (&caps[i], &caps[j]);
                let (ra, rb) = (rods[a.rod].1, rods[b.rod].1);
                // Started unwrapped, inside the windows (a ring's last capsule
                // runs past the period end); the result comes back wrapped.
                let (ua, ub, pa, pb) = closest_points_and_positions_within(ra, rb, a.ua + s * (a.ub - a.ua), b.ua + t * (b.ub - b.ua), window(ra, a), window(rb, b))?;
                let c = Contact { ua, ub, distance: a.radius + b.radius };
                if !self.apart_along(rods, [a.rod, b.rod], &c, (pa - pb).norm(), chain, next) {
                    continue;
                }
                rows.push(((pa - pb).norm(), a.rod, b.rod, c, pa, pb));
            }
            Ok(())
        })?;
        sorted.clear();
        sorted.extend(rows.iter().flatten().cloned());
        // By rod pair, and in each closest first (ties keep the order
        // above), so that of rows landing near each other the one at the
        // touching point is kept — a crossing's row, not a neighbour's off
        // to its side. Only rows of one rod pair can be duplicates, so each
        // pair's rows are chosen on their own: the keys are sorted, not the
        // rows (a sixth of the bytes to move).
        by_pair.clear();
        by_pair.extend(sorted.iter().enumerate().map(|(k, r)| ((r.1.min(r.2), r.1.max(r.2)), r.0, k)));
        let order = |x: &((usize, usize), f64, usize), y: &((usize, usize), f64, usize)| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)).then(x.2.cmp(&y.2));
        if parallel {
            use rayon::prelude::*;
            by_pair.par_sort_unstable_by(order);
        } else {
            by_pair.sort_unstable_by(order);
        }
        // Each rod pair's first row in `by_pair`, and the pairs in blocks
        // (on the pool when parallel): a block's choice touches its pairs'
        // rows only.
        group_starts.clear();
        group_starts.extend((0..by_pair.len()).filter(|&k| k == 0 || by_pair[k].0 != by_pair[k - 1].0));
        let groups = group_starts.len();
        let k = if parallel { (4 * rayon::current_num_threads()).min(groups).max(1) } else { 1 };
        choice.resize_with(k, Choice::default);
        let (by_pair, group_starts, sorted) = (&by_pair[..], &group_starts[..], &sorted[..]);
        let choose = |(b, ch): (usize, &mut Choice)| {
            ch.chosen.clear();
            for g in b * groups / k..(b + 1) * groups / k {
                let end = group_starts.get(g + 1).copied().unwrap_or(by_pair.len());
                choose_among(&by_pair[group_starts[g]..end], sorted, rods, segment, dup_cell, ch);
            }
        };
        if k > 1 {
            use rayon::prelude::*;
            choice.par_iter_mut().enumerate().for_each(choose);
        } else {
            choice.iter_mut().enumerate().for_each(choose);
        }
        chosen.clear();
        chosen.extend(choice.iter().flat_map(|c| c.chosen.iter().cloned()));
        // Back in the order along the rods: the set's order then changes
        // only when rows come or go, not when two trade places in distance
        // (which would rebuild the system's layout). Every field compared:
        // rows that tie are the same row, so an unstable sort (which
        // needs no buffer) gives the order a stable one would.
        let along_rods = |x: &([RodHandle; 2], Contact), y: &([RodHandle; 2], Contact)| {
            x.0.cmp(&y.0).then(x.1.ua.total_cmp(&y.1.ua)).then(x.1.ub.total_cmp(&y.1.ub)).then(x.1.distance.total_cmp(&y.1.distance))
        };
        if parallel {
            use rayon::prelude::*;
            chosen.par_sort_unstable_by(along_rods);
        } else {
            chosen.sort_unstable_by(along_rods);
        }
        for (handles, c) in chosen.iter() {
            out.pairs.push(ContactPair::new(*handles, ConstraintKind::Contact(c.clone()))?.with_friction(self.friction_between(handles[0], handles[1]))?);
        }
        Ok(())
    }
}

/// A capsule's span grown by a segment each way, the window of its
/// projection onto the spline: the chords may pick a capsule next to the
/// one holding a crossing's touching point, and a row held inside the
/// chord's own span then pushes at a slant (a rod pressed across another
/// slid off it).
fn window(rod: &Rod, c: &Capsule) -> (f64, f64) {
    let (u0, u1) = rod.domain();
    let grow = (u1 - u0) / rod.n_segments().max(1) as f64;
    if rod.is_closed() {
        (c.ua - grow, c.ub + grow)
    } else {
        ((c.ua - grow).max(u0), (c.ub + grow).min(u1))
    }
}

impl RodContacts {
    /// Arc length below which a rod's own points are not paired (`reach`:
    /// the two radii): half a turn of the tightest loop that can touch.
    fn exclusion(&self, reach: f64) -> f64 {
        (PI * reach).max(0.5 * PI * (reach + self.margin))
    }

    /// Whether a row projected onto the splines (`c`, its points `dist`
    /// apart, on rods `ends` of the detector's list) still pairs points
    /// apart along the yarn: a projection may slide a self pair along the
    /// rod onto itself, or a pair of joined rods across their join.
    fn apart_along(&self, rods: &[(RodHandle, &Rod)], ends: [usize; 2], c: &Contact, dist: f64, chain: &[f64], next: &[usize]) -> bool {
        let [a, b] = ends;
        let (ra, rb) = (rods[a].1, rods[b].1);
        if a == b {
            let (u0, u1) = ra.domain();
            let du = (c.ua - c.ub).abs();
            let du = if ra.is_closed() { du.min(u1 - u0 - du) } else { du };
            du * chain[a] / (u1 - u0) >= self.exclusion(c.distance) && dist >= 1e-9 * c.distance
        } else if next[a] == b || next[b] == a {
            // Arc to the end of the one and from the start of the other.
            let arc = |rod: &Rod, k: usize, u: f64, to_end: bool| {
                let (u0, u1) = rod.domain();
                chain[k] * if to_end { u1 - u } else { u - u0 } / (u1 - u0)
            };
            let a_first = next[a] == b;
            arc(ra, a, c.ua, a_first) + arc(rb, b, c.ub, !a_first) >= self.exclusion(c.distance)
        } else {
            true
        }
    }

    /// Distributed rows (`line_stiffness` = k): a row at the middle of every
    /// capsule against the closest point of each strand that is its
    /// nearest partner there, the capsule's abscissa held. Where one strand
    /// wraps round another the distance along the wrap is nearly flat, and
    /// one row per place of contact moves to wherever the last step pressed
    /// deepest: a knit cell's steps alternated (README, knitted fabrics).
    /// Rows held at the capsules stay where they are, and along a line of
    /// contact they outnumber what the control points can meet, so each is
    /// compliant: both strands' capsules give rows, each carrying half of
    /// the stiffness k (force/length²) over its capsule's length ℓ, so
    /// compliance 2/(k ℓ), and two strands pressed side by side with q
    /// (force/length) sink by q/k (`tests/contact_line.rs`). Where one
    /// crosses or wraps round the other, the other's rows gather at the
    /// crossing: q/k is the law of strands side by side only. Each row is
    /// a penalty taken where the strands are into each other at the start
    /// of a step, with no active-set rounds (`assemble_with`).
    #[allow(clippy::too_many_arguments)]
    fn distributed_rows(
        &self,
        k: f64,
        parallel: bool,
        rods: &[(RodHandle, &Rod)],
        caps: &[Capsule],
        nearest: &Nearest,
        chain: &[f64],
        next: &[usize],
        lines: &mut Vec<Vec<(usize, usize, Contact, f64)>>,
        out: &mut ContactSet,
    ) -> Result<()> {
        let first = out.pairs.len();
        super::fill_blocks(parallel, caps.len(), lines, |range, lines| {
            for (i, a) in caps[range.clone()].iter().enumerate() {
                let length = a.dd.sqrt();
                if length == 0.0 {
                    continue; // a point capsule (an open rod's end): its neighbour holds it
                }
                for (j, _, _) in nearest.of(range.start + i) {
                    let b = &caps[j];
                    let (ra, rb) = (rods[a.rod].1, rods[b.rod].1);
                    let um = 0.5 * (a.ua + a.ub);
                    let (ua, ub, pa, pb) = closest_points_and_positions_within(ra, rb, um, 0.5 * (b.ua + b.ub), (um, um), window(rb, b))?;
                    let c = Contact { ua, ub, distance: a.radius + b.radius };
                    let dist = (pa - pb).norm();
                    if dist >= c.distance + self.margin || !self.apart_along(rods, [a.rod, b.rod], &c, dist, chain, next) {
                        continue;
                    }
                    lines.push((a.rod, b.rod, c, 2.0 / (k * length)));
                }
            }
            Ok(())
        })?;
        for (a, b, c, compliance) in lines.iter().flatten() {
            let handles = [rods[*a].0, rods[*b].0];
            let pair = ContactPair::new(handles, ConstraintKind::Contact(c.clone()))?.with_friction(self.friction_between(handles[0], handles[1]))?;
            out.pairs.push(pair.with_compliance(*compliance)?);
        }
        // In the order along the rods, as the closest rows are.
        out.pairs[first..].sort_unstable_by(|x, y| {
            let (ConstraintKind::Contact(p), ConstraintKind::Contact(q)) = (&x.kind, &y.kind) else { return std::cmp::Ordering::Equal };
            x.rods.cmp(&y.rods).then(p.ua.total_cmp(&q.ua)).then(p.ub.total_cmp(&q.ub))
        });
        Ok(())
    }
}

/// One block's buffers for the choice among close rows: a rod pair's kept
/// rows (as a chain per grid cell through `kept_rows`, when it has many),
/// and the rows chosen.
#[derive(Debug, Default)]
struct Choice {
    kept: Kept<usize>,
    kept_rows: Vec<(Vector3<f64>, Vector3<f64>, usize)>,
    chosen: Vec<([RodHandle; 2], Contact)>,
}

/// The rows of one rod pair, closest first (`pair`: keys into `sorted`),
/// each kept unless a kept one lies within half a segment of it on both
/// rods (more would outnumber what the control points can meet, strands
/// side by side): into `ch.chosen`. `segment`: a segment's length per rod;
/// `dup_cell`: the grid's cell, at least four times any row's reach.
fn choose_among(pair: &[((usize, usize), f64, usize)], sorted: &[Row], rods: &[(RodHandle, &Rod)], segment: &[f64], dup_cell: f64, ch: &mut Choice) {
    // A pair of rods with a few rows (a crossing, a short stretch side by
    // side) compares each with the kept ones; with many (a yarn against
    // itself), the kept ones are looked up by grid cell.
    let few = pair.len() <= FEW_ROWS;
    let Choice { kept, kept_rows, chosen } = ch;
    kept_rows.clear();
    if !few {
        kept.clear();
    }
    let cell_of = |p: Vector3<f64>| Cell([(p.x / dup_cell).floor() as i64, (p.y / dup_cell).floor() as i64, (p.z / dup_cell).floor() as i64]);
    for &(_, _, k) in pair {
        let (_, ia, ib, ref c, pa, pb) = sorted[k];
        let handles = [rods[ia].0, rods[ib].0];
        let (sa, sb) = ((0.5 * segment[ia]).max(0.25 * c.distance), (0.5 * segment[ib]).max(0.25 * c.distance));
        // One orientation for both (a, b) and (b, a): the lower (rod, u) first.
        let ((p0, s0), (p1, s1)) = if (handles[0], c.ua) <= (handles[1], c.ub) { ((pa, sa), (pb, sb)) } else { ((pb, sb), (pa, sa)) };
        let near = |q0: &Vector3<f64>, q1: &Vector3<f64>| (q0 - p0).norm() < s0 && (q1 - p1).norm() < s1;
        let duplicate = if few {
            kept_rows.iter().any(|(q0, q1, _)| near(q0, q1))
        } else {
            // The cells of the box within s0 of p0 hold every kept row near it.
            let (lo, hi) = (cell_of(p0 - Vector3::repeat(s0)).0, cell_of(p0 + Vector3::repeat(s0)).0);
            let mut found = false;
            'search: for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        let mut next = kept.get(&Cell([x, y, z])).copied().unwrap_or(usize::MAX);
                        while let Some((q0, q1, after)) = kept_rows.get(next) {
                            if near(q0, q1) {
                                found = true;
                                break 'search;
                            }
                            next = *after;
                        }
                    }
                }
            }
            found
        };
        if !duplicate {
            if few {
                kept_rows.push((p0, p1, usize::MAX));
            } else {
                let head = kept.entry(cell_of(p0)).or_insert(usize::MAX);
                kept_rows.push((p0, p1, *head));
                *head = kept_rows.len() - 1;
            }
            chosen.push((handles, c.clone()));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The choice among one rod pair's close rows, by a scan of the kept
    /// rows (≤ FEW_ROWS) or through the grid (more), equals the greedy
    /// choice that compares each row, closest first, with every row kept
    /// before it. Rows at random points of a box a few duplicate distances
    /// wide, fixed seed; the pair seen from either side; every fifth row at
    /// the distance of the one before (ties go to the lower index). One
    /// block's buffers serve pairs of many and few rows in turn, as in a
    /// detection.
    #[test]
    fn close_rows_chosen_through_the_grid_or_by_a_scan_are_the_greedy_choice() {
        let (a, b) = (super::super::test_rod(), super::super::test_rod());
        let rods = [(RodHandle::from(crate::handles::Index(0, 0)), &a), (RodHandle::from(crate::handles::Index(1, 0)), &b)];
        let segment = [0.08, 0.06];
        let spacing = segment.map(|l| 0.5 * l);
        let dup_cell = 4.0 * 0.04;
        let mut lcg = crate::linalg::synthetic::Lcg(5);
        let mut point = |w: f64| Vector3::new(w * lcg.next(), w * lcg.next(), w * lcg.next());
        let mut ch = Choice::default();
        for (n, w) in [(200, 0.2), (12, 0.05), (600, 0.3), (30, 0.1), (200, 0.2)] {
            let mut sorted: Vec<Row> = Vec::new();
            for k in 0..n {
                // A row's two points are about a diameter apart.
                let pa = point(w);
                let pb = pa + point(0.02);
                let (ia, ib) = if k % 3 == 0 { (1, 0) } else { (0, 1) };
                let c = Contact { ua: 2.0 + (pa.x + 1.0), ub: 2.0 + (pb.x + 1.0), distance: 0.02 };
                let d = if k % 5 == 4 { sorted[k - 1].0 } else { (pa - pb).norm() };
                sorted.push((d, ia, ib, c, pa, pb));
            }
            let mut keys: Vec<((usize, usize), f64, usize)> = sorted.iter().enumerate().map(|(k, r)| ((0, 1), r.0, k)).collect();
            keys.sort_unstable_by(|x, y| x.1.total_cmp(&y.1).then(x.2.cmp(&y.2)));
            ch.chosen.clear();
            choose_among(&keys, &sorted, &rods, &segment, dup_cell, &mut ch);
            // The greedy choice, by brute force.
            let mut kept: Vec<(Vector3<f64>, Vector3<f64>)> = Vec::new();
            let mut want = Vec::new();
            for &(_, _, k) in &keys {
                let (_, ia, ib, ref c, pa, pb) = sorted[k];
                let (sa, sb) = (spacing[ia].max(0.25 * c.distance), spacing[ib].max(0.25 * c.distance));
                let ((p0, s0), (p1, s1)) = if (rods[ia].0, c.ua) <= (rods[ib].0, c.ub) { ((pa, sa), (pb, sb)) } else { ((pb, sb), (pa, sa)) };
                if !kept.iter().any(|(q0, q1)| (q0 - p0).norm() < s0 && (q1 - p1).norm() < s1) {
                    kept.push((p0, p1));
                    want.push(([rods[ia].0, rods[ib].0], c.clone()));
                }
            }
            assert_eq!(ch.chosen, want, "{n} rows");
            assert!(want.len() > 1 && want.len() < n, "{n} rows: {} kept, the test should drop some and keep some", want.len());
        }
    }
}
