//! Bead updates around the rod solve (see [`crate::bead`]).
use crate::error::Result;
use crate::handles::Index;
use crate::world::{Event, World};
use nalgebra::Vector3;

/// Weight plus user force of a bead.
pub(crate) fn bead_load(world: &World, b: &crate::bead::Bead) -> Vector3<f64> {
    Vector3::from(world.params.gravity) * b.mass + Vector3::from(b.force)
}

/// Dynamics, before the rod solve. A sliding bead's motion along the rod
/// is its own unknown: its absolute tangential speed w = ṡ + t·v_rod
/// follows (m/h + c) w_{n+1} = m w_n/h + t·F_p + c t·v_rod (implicit in
/// the friction c, the rod's velocity taken at the start of the step),
/// while the rod carries its transverse inertia (its mass matrix gets
/// m (I − t tᵀ) at the bead). The predicted increments are projected so
/// that no two neighbours end the step closer than r_a + r_b (an inelastic
/// impulse shared by mass, which only removes kinetic energy). The force
/// on the rod during the step: the normal part of F_p, the friction
/// c ṡ t, and the bead's own momentum across the rod m (v_b − v_rod)⊥/h
/// (see [`crate::bead`]). A fixed bead rides with the rod: whole load,
/// whole mass.
pub(crate) fn predict(world: &mut World, h: f64) -> Result<()> {
    // The scratch leaves the world for the pass (the world is borrowed).
    let mut s = std::mem::take(&mut world.ws.beads);
    let out = predict_with(world, h, &mut s);
    world.ws.beads = s;
    out
}

/// One bead as the passes see it (per-step scratch).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Row {
    id: Index,
    rod: crate::handles::RodHandle,
    u: f64,
    fixed: bool,
    mass: f64,
    radius: f64,
    /// Position on the rod (length unit), for the chord bound on gaps.
    x: Vector3<f64>,
}

impl Row {
    fn inv_mass(&self) -> f64 {
        if self.fixed {
            0.0
        } else {
            1.0 / self.mass
        }
    }
}

/// Buffers of the bead passes, kept in the workspace so that a step
/// allocates nothing once warmed up.
#[derive(Debug, Default)]
pub(crate) struct Scratch {
    rows: Vec<Row>,
    ds: Vec<f64>,
    /// Rod speed along the tangent, then the bead's absolute speed w.
    w: Vec<f64>,
    jets: Vec<crate::rod::Jet>,
    /// The bead's own velocity at the start of the step.
    v_b: Vec<Vector3<f64>>,
    force: Vec<Vector3<f64>>,
    order: Vec<usize>,
    /// Neighbour pairs (positions in `rows`, period added to the second's u).
    pairs: Vec<(usize, usize, f64)>,
    /// Gap per pair (length unit) and whether it is the exact arc length
    /// or still the chord's lower bound.
    gaps: Vec<(f64, bool)>,
    groups: Vec<Group>,
    /// Per-chain buffers of the projection ([`project`]).
    ds0: Vec<f64>,
    z: Vec<f64>,
    mass: Vec<Option<f64>>,
    pool_of: Vec<usize>,
    pools: Vec<super::bead_chain::Pool>,
    /// Per bead, the Cartesian force of its touching neighbours (force
    /// unit), along the lines of centres ([`pair_forces`]).
    contact: Vec<Vector3<f64>>,
    /// Per chain position, the compression of the pair it opens (force unit).
    push: Vec<f64>,
}

/// The beads of one rod: `len` of them from `order[first]` on, their
/// pairs from `pairs[first_pair]` on (pair j joins the j-th and the next;
/// on a closed rod the last pair closes the ring).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Group {
    first: usize,
    len: usize,
    first_pair: usize,
    closed: bool,
}

impl Scratch {
    /// Fills `rows` from the world's beads (positions not yet set).
    fn load(&mut self, world: &World) {
        self.rows.clear();
        self.rows.extend(world.beads.iter().map(|(id, b)| Row { id, rod: b.rod, u: b.u, fixed: b.fixed, mass: b.mass, radius: b.radius, x: Vector3::zeros() }));
    }
}

fn predict_with(world: &mut World, h: f64, s: &mut Scratch) -> Result<()> {
    s.load(world);
    let n = s.rows.len();
    s.ds.clear();
    s.w.clear();
    s.jets.clear();
    s.v_b.clear();
    for k in 0..n {
        let Some(b) = world.beads.get(s.rows[k].id) else { continue };
        let jet = world.rod(b.rod)?.jet(b.u)?;
        let sigma = jet.d1.norm();
        if !(sigma > 0.0) {
            return Err(crate::error::Error::singular(format!("zero tangent under bead {} at u = {}", s.rows[k].id.0, b.u)));
        }
        let t = jet.d1 / sigma;
        let v_r = t.dot(&jet.velocity);
        s.rows[k].x = jet.position;
        s.jets.push(jet);
        s.w.push(v_r);
        // Its own velocity, read off the jet (no second evaluation).
        let v_b = b.velocity_from(jet.velocity, t);
        s.v_b.push(v_b);
        if b.fixed {
            s.ds.push(0.0);
            continue;
        }
        let w_n = t.dot(&v_b);
        let w = (b.mass * w_n / h + t.dot(&bead_load(world, b)) + b.friction * v_r) / (b.mass / h + b.friction);
        s.ds.push(h * (w - v_r));
    }
    neighbours(world, s)?;
    s.gaps.clear();
    s.gaps.extend(s.pairs.iter().map(|&(a, b, _)| ((s.rows[b].x - s.rows[a].x).norm() - s.rows[a].radius - s.rows[b].radius, false)));
    s.contact.clear();
    s.contact.resize(n, Vector3::zeros());
    let mut s_groups = std::mem::take(&mut s.groups);
    for g in &s_groups {
        project(world, s, g, h)?;
    }
    s_groups.clear();
    s.groups = s_groups;
    // The force on the rod during the step, at the projected sliding speed.
    s.force.clear();
    for k in 0..n {
        let Some(b) = world.beads.get(s.rows[k].id) else { continue };
        let (jet, fp) = (&s.jets[k], bead_load(world, b));
        let f = if b.fixed {
            fp + s.contact[k]
        } else {
            let sigma = jet.d1.norm();
            let t = jet.d1 / sigma;
            let normal = |x: Vector3<f64>| x - t * x.dot(&t);
            let v = s.ds[k] / h;
            s.w[k] += v;
            // The bead's momentum across the rod, m P (v_b − v_rod)/h on
            // top of the transverse inertia the rod carries: what makes the
            // bead follow the rod's bends and turning (the centripetal and
            // Coriolis forces, −m(ṡ²κn + 2ṡ ∂v/∂s⊥) in the limit) as
            // inelastic impulses, which never add energy.
            let across = normal(s.v_b[k] - jet.velocity);
            // The neighbours' push across the rod goes to the rod: with
            // the part along it (in Δs) the pair's forces are equal and
            // opposite along the line of centres, so they do no work.
            normal(fp + s.contact[k]) + t * (b.friction * v) + across * (b.mass / h)
        };
        if !s.ds[k].is_finite() || !f.iter().all(|x| x.is_finite()) {
            return Err(crate::error::Error::NonFinite {
                rod: Some(b.rod),
                detail: format!("bead {}: its sliding step or its force on the rod is not finite (mass {:e}); the world is unchanged", s.rows[k].id.0, b.mass),
            });
        }
        s.force.push(f);
    }
    for k in 0..n {
        if let Some(b) = world.beads.get_mut(s.rows[k].id) {
            b.step_ds = s.ds[k];
            b.step_w = s.w[k];
            b.rod_force = s.force[k].into();
            b.step_t = (s.jets[k].d1 / s.jets[k].d1.norm()).into();
        }
    }
    Ok(())
}

/// Projects the predicted increments of one rod's beads so that no two
/// end the step closer than r_a + r_b ([`super::bead_chain`]). Gaps start
/// as the chord's lower bound of the arc; a pair found touching with a
/// bound gets its exact arc length and the chain is solved again. A closed
/// ring is cut at its slackest pair; a ring too full to cut (every pair
/// pressed) falls back to Gauss–Seidel sweeps.
fn project(world: &World, s: &mut Scratch, g: &Group, h: f64) -> Result<()> {
    let m = g.len;
    if m < 2 {
        return Ok(());
    }
    let n_pairs = if g.closed { m } else { m - 1 };
    let bead = |s: &Scratch, i: usize| s.order[g.first + i % m];
    let slack = |s: &Scratch, j: usize| {
        let (a, b, _) = s.pairs[g.first_pair + j];
        s.gaps[g.first_pair + j].0 + s.ds[b] - s.ds[a]
    };
    s.ds0.clear();
    for i in 0..m {
        let d = s.ds[bead(s, i)];
        s.ds0.push(d);
    }
    for _ in 0..=n_pairs {
        // Restart from the prediction (gaps may have been refined).
        for i in 0..m {
            let k = bead(s, i);
            s.ds[k] = s.ds0[i];
        }
        if (0..n_pairs).all(|j| slack(s, j) >= 0.0) {
            return Ok(());
        }
        // Chain order: from the bead after the cut.
        let cut = if g.closed { (0..m).max_by(|&a, &b| slack(s, a).total_cmp(&slack(s, b))).unwrap_or(0) } else { m - 1 };
        let start = (cut + 1) % m;
        s.z.clear();
        s.mass.clear();
        let mut offset = 0.0;
        for i in 0..m {
            let k = bead(s, start + i);
            s.z.push(s.ds[k] + offset);
            s.mass.push((!s.rows[k].fixed).then_some(s.rows[k].mass));
            if i + 1 < m {
                offset += s.gaps[g.first_pair + (start + i) % m].0;
            }
        }
        s.pool_of.resize(m, 0);
        super::bead_chain::isotonic(&mut s.z, &s.mass, &mut s.pools, &mut s.pool_of);
        let mut offset = 0.0;
        for i in 0..m {
            let k = bead(s, start + i);
            s.ds[k] = s.z[i] - offset;
            if i + 1 < m {
                offset += s.gaps[g.first_pair + (start + i) % m].0;
            }
        }
        // Touching pairs whose gap was only the chord's bound: refine.
        let mut refined = false;
        for i in 0..m {
            let j = (start + i) % m;
            let along_chain = i + 1 < m;
            let touching = if along_chain { s.pool_of[i] == s.pool_of[i + 1] } else { g.closed && slack(s, j) < 0.0 };
            if touching && !s.gaps[g.first_pair + j].1 {
                let (a, b, period) = s.pairs[g.first_pair + j];
                let (ra, rb) = (&s.rows[a], &s.rows[b]);
                s.gaps[g.first_pair + j] = (arc(world.rod(ra.rod)?, ra.u, rb.u + period)? - ra.radius - rb.radius, true);
                refined = true;
            }
        }
        if !refined {
            if g.closed && slack(s, cut) < 0.0 {
                break; // the ring is full: sweeps below
            }
            pair_forces(s, g, start, h);
            return Ok(());
        }
    }
    // Gauss–Seidel sweeps over the ring (every gap exact by now or after
    // the first sweep).
    for _ in 0..50 {
        let mut worst = 0.0f64;
        for j in 0..n_pairs {
            let (a, b, period) = s.pairs[g.first_pair + j];
            if slack(s, j) < 0.0 && !s.gaps[g.first_pair + j].1 {
                let (ra, rb) = (&s.rows[a], &s.rows[b]);
                s.gaps[g.first_pair + j] = (arc(world.rod(ra.rod)?, ra.u, rb.u + period)? - ra.radius - rb.radius, true);
            }
            let c = slack(s, j);
            let (wa, wb) = (s.rows[a].inv_mass(), s.rows[b].inv_mass());
            if c >= 0.0 || wa + wb == 0.0 {
                continue;
            }
            s.ds[a] += c * wa / (wa + wb);
            s.ds[b] -= c * wb / (wa + wb);
            worst = worst.max(-c);
        }
        if worst == 0.0 {
            break;
        }
    }
    Ok(())
}

/// The contact forces of one rod's projected chain, from `start` (after
/// the cut) on. The projection moved bead i by Δs_i − Δs⁰_i, a push
/// m_i (Δs_i − Δs⁰_i)/h² along the string, which is f_(i−1) − f_i with
/// f_i the compression of pair (i, i+1); f is summed from each pool's free
/// end (from both ends, so that a fixed bead, whose push is unknown, takes
/// the rest). Two spheres touch along their line of centres c: the pair
/// gets ∓F c, equal and opposite, with F = f/c̄ (c̄ the mean of c·t over
/// the two beads, within a few percent of 1 for beads that touch), whose
/// parts along the tangents are (to second order in the pair's turn) the
/// ∓f the projection applied; the parts across them are what the string
/// must bear. A ring too full to cut (its Gauss–Seidel sweeps) passes no
/// such forces.
fn pair_forces(s: &mut Scratch, g: &Group, start: usize, h: f64) {
    let m = g.len;
    let chain = |i: usize| (start + i) % m;
    let bead = |s: &Scratch, i: usize| s.order[g.first + chain(i)];
    let pushed = |s: &Scratch, i: usize| {
        let k = bead(s, i);
        s.rows[k].mass * (s.ds[k] - s.ds0[chain(i)]) / (h * h)
    };
    // Forward from the chain's start: f_i = f_(i−1) − push_i, reset at a
    // pool's end (no contact) and unknown past a fixed bead (NaN).
    s.push.clear();
    let mut f = 0.0;
    for i in 0..m - 1 {
        let k = bead(s, i);
        f = if s.rows[k].fixed { f64::NAN } else { f - pushed(s, i) };
        if s.pool_of[i] != s.pool_of[i + 1] {
            f = 0.0;
        }
        s.push.push(f);
    }
    // Backward for the pairs the forward sum could not reach.
    let mut f = 0.0;
    for i in (1..m).rev() {
        let k = bead(s, i);
        f = if s.rows[k].fixed { f64::NAN } else { f + pushed(s, i) };
        if s.pool_of[i] != s.pool_of[i - 1] {
            f = 0.0;
        }
        if s.push[i - 1].is_nan() {
            s.push[i - 1] = f;
        }
    }
    for i in 0..m - 1 {
        let f = s.push[i];
        if !(f > 0.0) {
            continue; // apart, or two fixed beads (no way to share the push)
        }
        let (a, b) = (bead(s, i), bead(s, i + 1));
        let d = s.rows[b].x - s.rows[a].x;
        let len = d.norm();
        if !(len > 0.0) {
            continue;
        }
        let c = d / len;
        let ct = |k: usize| c.dot(&(s.jets[k].d1 / s.jets[k].d1.norm()));
        let ct = 0.5 * (ct(a) + ct(b));
        if ct > 0.1 {
            s.contact[a] -= c * (f / ct);
            s.contact[b] += c * (f / ct);
        }
    }
}

/// Arc length of `rod` from `ua` to `ub` (≥ ua; past the end of a closed
/// rod it wraps), 3-point Gauss on |r'|.
fn arc(rod: &crate::rod::Rod, ua: f64, ub: f64) -> Result<f64> {
    const X: [f64; 3] = [-0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4];
    const W: [f64; 3] = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
    let (lo, hi) = rod.domain();
    let (m, r) = (0.5 * (ua + ub), 0.5 * (ub - ua));
    let mut s = 0.0;
    for (x, w) in X.iter().zip(W) {
        let u = m + r * x;
        let u = if period(rod).is_some() { u } else { u.clamp(lo, hi) };
        let d = rod.eval(u, 1)?;
        s += w * r * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    }
    Ok(s)
}

/// Neighbouring beads on each rod in the order of `u` (positions in
/// `s.rows`, into `s.pairs`; one [`Group`] per rod into `s.groups`), with the period to add to the second's
/// abscissa: on a closed rod the last and first are neighbours across the
/// seam.
fn neighbours(world: &World, s: &mut Scratch) -> Result<()> {
    let Scratch { rows, order, pairs, groups, .. } = s;
    order.clear();
    groups.clear();
    order.extend(0..rows.len());
    order.sort_unstable_by(|&a, &b| rows[a].rod.index.cmp(&rows[b].rod.index).then(rows[a].u.total_cmp(&rows[b].u)).then(a.cmp(&b)));
    pairs.clear();
    let mut k = 0;
    while k < order.len() {
        let mut e = k;
        while e + 1 < order.len() && rows[order[e + 1]].rod.index == rows[order[k]].rod.index {
            pairs.push((order[e], order[e + 1], 0.0));
            e += 1;
        }
        let first_pair = pairs.len() - (e - k);
        let mut closed = false;
        if e > k {
            if let Some(p) = period(world.rod(rows[order[k]].rod)?) {
                pairs.push((order[e], order[k], p));
                closed = true;
            }
        }
        groups.push(Group { first: k, len: e + 1 - k, first_pair, closed });
        k = e + 1;
    }
    Ok(())
}

/// The parameter period of a closed rod (None for an open one).
fn period(rod: &crate::rod::Rod) -> Option<f64> {
    (rod.knots().kind() == crate::spline::KnotKind::Periodic).then(|| rod.knots().n_ctrl() as f64)
}

/// Number of beads whose abscissa is an unknown of the statics.
pub(crate) fn n_sliding(world: &World) -> usize {
    world.beads.iter().filter(|(_, b)| !b.fixed).count()
}

/// Statics: the bead's whole load goes to the rod.
pub(crate) fn static_load(world: &mut World) {
    let g = Vector3::from(world.params.gravity);
    for (_, b) in world.beads.iter_mut() {
        b.rod_force = (g * b.mass + Vector3::from(b.force)).into();
        b.step_ds = 0.0;
        b.velocity = 0.0;
        b.carried = None;
    }
}

/// Dynamics, after the rod solve: advance each bead along the new rod
/// shape, keep beads from passing each other, remove those that left
/// (their events go to `events`).
pub(crate) fn advance(world: &mut World, h: f64, events: &mut Vec<Event>) -> Result<()> {
    let mut s = std::mem::take(&mut world.ws.beads);
    let out = advance_with(world, h, events, &mut s);
    world.ws.beads = s;
    out
}

fn advance_with(world: &mut World, h: f64, events: &mut Vec<Event>, s: &mut Scratch) -> Result<()> {
    // Neighbours are taken in the order before the move.
    s.load(world);
    neighbours(world, s)?;
    for k in 0..s.rows.len() {
        let Some(b) = world.beads.get(s.rows[k].id) else { continue };
        if b.fixed {
            continue;
        }
        // Sliding speed relative to the rod as it now moves.
        let rod = world.rod(b.rod)?;
        let jet = rod.jet(b.u)?;
        let speed = jet.d1.norm();
        let v = b.step_w - (jet.d1 / speed).dot(&jet.velocity);
        let du = h * v / speed;
        // Its own velocity: the rod's across the step's tangent, where it
        // was, and the step's speed along it.
        let t = Vector3::from(b.step_t);
        let carried = jet.velocity - t * t.dot(&jet.velocity) + t * b.step_w;
        // On a closed rod a bead goes round: its abscissa wraps.
        let period = period(rod);
        if let Some(b) = world.beads.get_mut(s.rows[k].id) {
            b.u = period.map_or(b.u + du, |p| (b.u + du).rem_euclid(p));
            b.velocity = v;
            b.carried = Some(carried.into());
        }
    }
    contacts(world, s)?;
    for r in &s.rows {
        let Some(b) = world.beads.get(r.id) else { continue };
        let (a, z) = world.rod(b.rod)?.domain();
        if b.u < a || b.u > z {
            world.beads.remove(r.id);
            events.push(Event::BeadLeft { bead: r.id.into(), time: world.time });
        }
    }
    Ok(())
}

/// After the step, what the predicted increments could not foresee (the
/// rod stretched or bent under them): neighbours closer than r_a + r_b
/// are set r_a + r_b apart about their centre of mass, with a common
/// velocity (inelastic; a fixed bead acts as an infinite mass). A pair
/// whose chord already exceeds r_a + r_b is clear (the arc is longer).
fn contacts(world: &mut World, s: &mut Scratch) -> Result<()> {
    for r in s.rows.iter_mut() {
        if let Some(b) = world.beads.get(r.id) {
            // A bead past an open rod's end (leaving) sits at the end.
            let rod = world.rod(b.rod)?;
            let (lo, hi) = rod.domain();
            r.u = b.u;
            r.x = rod.position(if period(rod).is_some() { b.u } else { b.u.clamp(lo, hi) })?;
        }
    }
    for p in 0..s.pairs.len() {
        let (ka, kb, period) = s.pairs[p];
        let (ia, ib) = (s.rows[ka].id, s.rows[kb].id);
        let (Some(a), Some(b)) = (world.beads.get(ia), world.beads.get(ib)) else { continue };
        let need = a.radius + b.radius;
        // Rows are updated when a pair moves, so the chord is current.
        if (s.rows[kb].x - s.rows[ka].x).norm() >= need {
            continue;
        }
        let rod = world.rod(a.rod)?;
        let bu = b.u + period;
        let gap = arc(rod, a.u, bu)?;
        if gap >= need {
            continue;
        }
        let (ma, mb) = match (a.fixed, b.fixed) {
            (true, true) => continue,
            (true, false) => (1.0, 0.0),
            (false, true) => (0.0, 1.0),
            (false, false) => (a.mass, b.mass),
        };
        let m = ma + mb;
        let (sc, v) = ((ma * a.u + mb * bu) / m, (ma * a.velocity + mb * b.velocity) / m);
        let span = need / (gap / (bu - a.u).max(f64::MIN_POSITIVE));
        let wrap = |u: f64| if period > 0.0 { u.rem_euclid(period) } else { u };
        let (ua, ub) = (wrap(sc - span * mb / m), wrap(sc + span * ma / m - period));
        let (xa, xb) = (rod.position(ua), rod.position(ub));
        for (k, i, u, x) in [(ka, ia, ua, xa), (kb, ib, ub, xb)] {
            if let Some(bead) = world.beads.get_mut(i) {
                bead.u = u;
                // The common speed along the rod replaces the bead's own.
                if let Some(c) = bead.carried {
                    let t = Vector3::from(bead.step_t);
                    bead.carried = Some((Vector3::from(c) + t * (v - bead.velocity)).into());
                }
                bead.velocity = v;
            }
            // A bead pushed past the end has left; its chord is moot.
            s.rows[k].x = x.unwrap_or(s.rows[k].x);
        }
    }
    Ok(())
}

/// Statics: moves the sliding beads (in arena order, fixed ones skipped)
/// by their solved abscissa increments (clamped to an open rod, wrapped
/// round a closed one) and returns the largest |Δu|.
pub(crate) fn apply(world: &mut World, du: &[f64]) -> Result<f64> {
    let mut worst = 0.0f64;
    let ids: Vec<Index> = world.beads.iter().filter(|(_, b)| !b.fixed).map(|(i, _)| i).collect();
    for (i, d) in ids.into_iter().zip(du) {
        let Some(b) = world.beads.get(i) else { continue };
        let rod = world.rod(b.rod)?;
        let (lo, hi) = rod.domain();
        let u = match period(rod) {
            Some(p) => (b.u + d).rem_euclid(p),
            None => (b.u + d).clamp(lo, hi),
        };
        worst = worst.max(d.abs().min((u - b.u).abs()));
        if let Some(b) = world.beads.get_mut(i) {
            b.u = u;
        }
    }
    Ok(worst)
}
