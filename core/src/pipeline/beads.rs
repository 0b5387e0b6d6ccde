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
    /// Position on the rod (length unit), unit tangent and |r′| there
    /// (length per unit u): what the gap of a pair is measured from.
    x: Vector3<f64>,
    t: Vector3<f64>,
    speed: f64,
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
    /// The rod's velocity under each bead at the start of the step.
    v_rod: Vec<Vector3<f64>>,
    /// The bead's own velocity at the start of the step.
    v_b: Vec<Vector3<f64>>,
    force: Vec<Vector3<f64>>,
    order: Vec<usize>,
    /// Neighbour pairs (positions in `rows`, period added to the second's u).
    pairs: Vec<(usize, usize, f64)>,
    /// Gap per pair beyond r_a + r_b, as an arc length along the string,
    /// and the pair's c̄ (0 where the gap is the arc's) ([`gap`]).
    gaps: Vec<(f64, f64)>,
    /// Each bead's basis at its abscissa this step, from the prediction on
    /// (the assembly and the advance read it instead of evaluating it
    /// again): bead, abscissa, rod's control point count, control points
    /// and basis. Emptied when the step's bead passes end.
    basis: Vec<(Index, f64, usize, [usize; 4], [[f64; 4]; 4])>,
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
        self.rows.extend(world.beads.iter().map(|(id, b)| Row { id, rod: b.rod, u: b.u, fixed: b.fixed, mass: b.mass, radius: b.radius, x: Vector3::zeros(), t: Vector3::zeros(), speed: 0.0 }));
    }
}

/// The basis of bead `k` (arena order) at `u` on `rod`: the one this step's
/// prediction cached, if it is still that bead at that abscissa on a rod
/// of as many control points; else evaluated.
pub(crate) fn bead_basis(s: &Scratch, k: usize, id: Index, u: f64, rod: &crate::rod::Rod) -> Result<([usize; 4], [[f64; 4]; 4])> {
    match s.basis.get(k).filter(|e| e.0 == id && e.1.to_bits() == u.to_bits() && e.2 == rod.n_ctrl()) {
        Some(e) => Ok((e.3, e.4)),
        None => rod.basis_at(u),
    }
}

fn predict_with(world: &mut World, h: f64, s: &mut Scratch) -> Result<()> {
    s.load(world);
    let n = s.rows.len();
    s.ds.clear();
    s.w.clear();
    s.v_rod.clear();
    s.v_b.clear();
    s.basis.clear();
    for k in 0..n {
        let Some(b) = world.beads.get(s.rows[k].id) else { continue };
        let rod = world.rod(b.rod)?;
        let (ctrl, basis) = rod.basis_at(b.u)?;
        s.basis.push((s.rows[k].id, b.u, rod.n_ctrl(), ctrl, basis));
        let (x, d1, velocity) = rod.motion_from(&ctrl, &basis);
        let sigma = d1.norm();
        if !(sigma > 0.0) {
            return Err(crate::error::Error::singular(format!("zero tangent under bead {} at u = {}", s.rows[k].id.0, b.u)));
        }
        let t = d1 / sigma;
        let v_r = t.dot(&velocity);
        (s.rows[k].x, s.rows[k].t, s.rows[k].speed) = (x, t, sigma);
        s.v_rod.push(velocity);
        s.w.push(v_r);
        // Its own velocity, from the same evaluation.
        let v_b = b.velocity_from(velocity, t);
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
    for &(a, b, period) in &s.pairs {
        let g = gap(world.rod(s.rows[a].rod)?, &s.rows[a], &s.rows[b], period)?;
        s.gaps.push(g);
    }
    s.contact.clear();
    s.contact.resize(n, Vector3::zeros());
    let mut s_groups = std::mem::take(&mut s.groups);
    for g in &s_groups {
        project(s, g, h);
    }
    s_groups.clear();
    s.groups = s_groups;
    // The force on the rod during the step, at the projected sliding speed.
    s.force.clear();
    for k in 0..n {
        let Some(b) = world.beads.get(s.rows[k].id) else { continue };
        let fp = bead_load(world, b);
        let f = if b.fixed {
            fp + s.contact[k]
        } else {
            let t = s.rows[k].t;
            let normal = |x: Vector3<f64>| x - t * x.dot(&t);
            let v = s.ds[k] / h;
            s.w[k] += v;
            // The bead's momentum across the rod, m P (v_b − v_rod)/h on
            // top of the transverse inertia the rod carries: what makes the
            // bead follow the rod's bends and turning (the centripetal and
            // Coriolis forces, −m(ṡ²κn + 2ṡ ∂v/∂s⊥) in the limit) as
            // inelastic impulses, which never add energy.
            let across = normal(s.v_b[k] - s.v_rod[k]);
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
            b.step_t = s.rows[k].t.into();
        }
    }
    Ok(())
}

/// Projects the predicted increments of one rod's beads so that no two
/// end the step closer than r_a + r_b ([`super::bead_chain`], with the
/// gaps of [`gap`]). A closed ring is cut at its slackest pair; a ring too
/// full to cut (every pair pressed) falls back to Gauss–Seidel sweeps.
fn project(s: &mut Scratch, g: &Group, h: f64) {
    let m = g.len;
    if m < 2 {
        return;
    }
    let n_pairs = if g.closed { m } else { m - 1 };
    let bead = |s: &Scratch, i: usize| s.order[g.first + i % m];
    let slack = |s: &Scratch, j: usize| {
        let (a, b, _) = s.pairs[g.first_pair + j];
        s.gaps[g.first_pair + j].0 + s.ds[b] - s.ds[a]
    };
    if (0..n_pairs).all(|j| slack(s, j) >= 0.0) {
        return;
    }
    s.ds0.clear();
    for i in 0..m {
        let d = s.ds[bead(s, i)];
        s.ds0.push(d);
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
    if !(g.closed && slack(s, cut) < 0.0) {
        pair_forces(s, g, start, h);
        return;
    }
    // The ring is full: Gauss–Seidel sweeps over it, from the prediction.
    for i in 0..m {
        let k = bead(s, i);
        s.ds[k] = s.ds0[i];
    }
    for _ in 0..50 {
        let mut worst = 0.0f64;
        for j in 0..n_pairs {
            let (a, b, _) = s.pairs[g.first_pair + j];
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
}

/// The gap (length unit) between neighbours `a` and `b` beyond r_a + r_b,
/// as the arc length along the string that closes it. Beads are spheres
/// threaded on the string: they touch when their centres are r_a + r_b
/// apart, along the chord c = x_b − x_a. Sliding by Δs moves a centre by
/// Δs t, so the chord shortens by c·t_a Δs_a − c·t_b Δs_b: the gap in arc
/// length is (|c| − r_a − r_b)/c̄ with c̄ the mean of ĉ·t over the pair
/// (1 on a straight string, cos(θ/2) on a bend that turns by θ between
/// them). That holds while the chord runs along the string between them
/// (c̄ > ½ and the arc, from their abscissae and |r′|, under twice the
/// chord); otherwise (beads far apart along a string that comes back on
/// itself) the gap is the arc length less r_a + r_b (3-point Gauss).
fn gap(rod: &crate::rod::Rod, a: &Row, b: &Row, period: f64) -> Result<(f64, f64)> {
    let need = a.radius + b.radius;
    let d = b.x - a.x;
    let len = d.norm();
    if len > 0.0 {
        let c = d / len;
        let cbar = 0.5 * (c.dot(&a.t) + c.dot(&b.t));
        let along = (b.u + period - a.u) * 0.5 * (a.speed + b.speed);
        if cbar > 0.5 && along < 2.0 * len {
            return Ok(((len - need) / cbar, cbar));
        }
    }
    Ok((arc(rod, a.u, b.u + period)? - need, 0.0))
}

/// The contact forces of one rod's projected chain, from `start` (after
/// the cut) on. The projection moved bead i by Δs_i − Δs⁰_i, a push
/// m_i (Δs_i − Δs⁰_i)/h² along the string, which is f_(i−1) − f_i with
/// f_i the compression of pair (i, i+1); f is summed from each pool's free
/// end (from both ends, so that a fixed bead, whose push is unknown, takes
/// the rest). Two spheres touch along their line of centres ĉ: the pair
/// gets ∓F ĉ, equal and opposite, with F = f/c̄ ([`gap`]: the multiplier
/// of the chord's constraint), whose parts along the tangents are (to
/// second order in the pair's turn) the ∓f the projection applied; the
/// parts across them are what the string must bear. A ring too full to
/// cut (its Gauss–Seidel sweeps) passes no such forces.
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
        // The pair's c̄ (0: far apart along a string that comes back, no
        // line of centres to push along).
        let cbar = s.gaps[g.first_pair + chain(i)].1;
        let d = s.rows[b].x - s.rows[a].x;
        let len = d.norm();
        if cbar > 0.0 && len > 0.0 {
            let c = d / len;
            s.contact[a] -= c * (f / cbar);
            s.contact[b] += c * (f / cbar);
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
        // Sliding speed relative to the rod as it now moves (the basis at
        // the bead is the prediction's: it has not moved yet).
        let rod = world.rod(b.rod)?;
        let (ctrl, basis) = bead_basis(s, k, s.rows[k].id, b.u, rod)?;
        let (_, d1, velocity) = rod.motion_from(&ctrl, &basis);
        let speed = d1.norm();
        let v = b.step_w - (d1 / speed).dot(&velocity);
        let du = h * v / speed;
        // Its own velocity: the rod's across the step's tangent, where it
        // was, and the step's speed along it.
        let t = Vector3::from(b.step_t);
        let carried = velocity - t * t.dot(&velocity) + t * b.step_w;
        // On a closed rod a bead goes round: its abscissa wraps.
        let period = period(rod);
        if let Some(b) = world.beads.get_mut(s.rows[k].id) {
            b.u = period.map_or(b.u + du, |p| (b.u + du).rem_euclid(p));
            b.velocity = v;
            b.carried = Some(carried.into());
        }
    }
    s.basis.clear();
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

/// Sets `row` to the point of `rod` at its abscissa (an open rod's end
/// for a bead past it, which is leaving): position, unit tangent, |r′|.
fn place(rod: &crate::rod::Rod, row: &mut Row) -> Result<()> {
    let (lo, hi) = rod.domain();
    let u = if period(rod).is_some() { row.u } else { row.u.clamp(lo, hi) };
    let (ctrl, b) = rod.basis_at(u)?;
    let (x, d1, _) = rod.motion_from(&ctrl, &b);
    row.speed = d1.norm();
    row.x = x;
    row.t = if row.speed > 0.0 { d1 / row.speed } else { Vector3::zeros() };
    Ok(())
}

/// After the step, what the predicted increments could not foresee (the
/// rod stretched or bent under them): neighbours whose gap ([`gap`], at
/// the new shape) is negative are moved apart along the string by it,
/// about their centre of mass, with a common velocity (inelastic; a fixed
/// bead acts as an infinite mass).
fn contacts(world: &mut World, s: &mut Scratch) -> Result<()> {
    for r in s.rows.iter_mut() {
        if let Some(b) = world.beads.get(r.id) {
            r.u = b.u;
            place(world.rod(b.rod)?, r)?;
        }
    }
    for p in 0..s.pairs.len() {
        let (ka, kb, period) = s.pairs[p];
        let (ia, ib) = (s.rows[ka].id, s.rows[kb].id);
        let (Some(a), Some(b)) = (world.beads.get(ia), world.beads.get(ib)) else { continue };
        let (ma, mb) = match (a.fixed, b.fixed) {
            (true, true) => continue,
            (true, false) => (1.0, 0.0),
            (false, true) => (0.0, 1.0),
            (false, false) => (a.mass, b.mass),
        };
        let handle = a.rod;
        let rod = world.rod(handle)?;
        // A bead past an open rod's end has left: it pushes no one.
        let (lo, hi) = rod.domain();
        let off = |u: f64| self::period(rod).is_none() && !(lo..=hi).contains(&u);
        if off(a.u) || off(b.u) {
            continue;
        }
        let (g, _) = gap(rod, &s.rows[ka], &s.rows[kb], period)?;
        if g >= 0.0 {
            continue;
        }
        let m = ma + mb;
        let v = (ma * a.velocity + mb * b.velocity) / m;
        let ring = self::period(rod);
        let wrap = |u: f64| ring.map_or(u, |q| u.rem_euclid(q));
        // Arc length to abscissa with each bead's |r′|.
        let ua = wrap(a.u + g * mb / m / s.rows[ka].speed.max(f64::MIN_POSITIVE));
        let ub = wrap(b.u - g * ma / m / s.rows[kb].speed.max(f64::MIN_POSITIVE));
        for (k, i, u) in [(ka, ia, ua), (kb, ib, ub)] {
            if let Some(bead) = world.beads.get_mut(i) {
                bead.u = u;
                // The common speed along the rod replaces the bead's own.
                if let Some(c) = bead.carried {
                    let t = Vector3::from(bead.step_t);
                    bead.carried = Some((Vector3::from(c) + t * (v - bead.velocity)).into());
                }
                bead.velocity = v;
            }
            s.rows[k].u = u;
            place(world.rod(handle)?, &mut s.rows[k])?;
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
