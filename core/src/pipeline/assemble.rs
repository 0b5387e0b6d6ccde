//! The first stages of every solve: gather the external forces (force
//! fields, beads), place the unknowns (ordering and layout, rebuilt only
//! when the topology changes) and assemble the KKT system.
use crate::bead::Bead;
use crate::constraint::MAX_TOUCHED;
use crate::contact::{ContactDetector, ContactSet};
use crate::error::Result;
use crate::force::{gravity::Gravity, thermal::Thermal, ForceField, Load};
use crate::handles::{Arena, RodHandle};
use crate::rod::Rod;
use crate::system::kkt::{BeadRef, Coefficients, ConstraintRef, PointMass};
use crate::system::layout::{ConstraintSlot, NO_LINK};
use crate::system::ordering::{control_point_order_with, RodGraph, Strategy};
use crate::system::workspace::recycle;
use crate::system::{Layout, Workspace};
use crate::world::{position_of, Constraint, IntegrationParameters, World};

/// What kind of solve the system is assembled for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Regime {
    /// A linearised implicit Euler step of h (II.77–II.82).
    Dynamic { h: f64 },
    /// A Newton iteration of a trapezoidal step of h (SPEC §3): the first
    /// at the start of the step (forces at t, whole), the next ones at the
    /// iterate (forces at t + h, halved, the other half in the workspace's
    /// `trapezoidal` state).
    Trapezoidal { h: f64, first: bool },
    /// The BDF2 stage of a TR-BDF2 step: an implicit Euler solve of step
    /// `h2` (forces at t + `h`, plus the workspace's `extra`).
    Bdf2 { h2: f64, h: f64 },
    /// Newton statics (II.83); `bead_unknowns`: beads' abscissae are
    /// unknowns, placed like sliders next to the control points they touch.
    Statics { bead_unknowns: bool },
}

impl Regime {
    pub fn coefficients(self) -> Coefficients {
        match self {
            // Implicit Euler is one linear solve per step: compression's
            // negative transverse stiffness is left out of its matrix
            // (`step_stiffness`). Statics and the trapezoidal rule's Newton
            // iterations keep the exact Hessian (the same solution either
            // way; quadratic convergence and the stability test need it);
            // TR-BDF2's BDF2 stage is one solve too, but with M/h₂² twelve
            // times larger, and keeps it so that the scheme's measured
            // behaviour (README table) stands.
            Regime::Dynamic { h } => Coefficients { mass: 1.0 / (h * h), drag: 1.0 / h, momentum: 1.0 / h, stiffness: 1.0, force: 1.0, step_stiffness: true },
            Regime::Bdf2 { h2: h, .. } => Coefficients { mass: 1.0 / (h * h), drag: 1.0 / h, momentum: 1.0 / h, stiffness: 1.0, force: 1.0, step_stiffness: false },
            // 2M (ΔX − hV)/h² + D ΔX/h = ½ (f_n + f(q_n + ΔX)), the drag
            // on the mean velocity ΔX/h; ∂/∂ΔX of the right side is −K/2.
            Regime::Trapezoidal { h, first } => Coefficients {
                mass: 2.0 / (h * h),
                drag: 1.0 / h,
                momentum: 2.0 / h,
                stiffness: 0.5,
                force: if first { 1.0 } else { 0.5 },
                step_stiffness: false,
            },
            Regime::Statics { .. } => Coefficients { mass: 0.0, drag: 0.0, momentum: 0.0, stiffness: 1.0, force: 1.0, step_stiffness: false },
        }
    }
    /// Time the forces are evaluated at: the end of an implicit Euler
    /// step; the start, then the end, of a trapezoidal one.
    fn force_time(self, now: f64) -> f64 {
        match self {
            Regime::Dynamic { h } => now + h,
            Regime::Trapezoidal { h, first } => now + if first { 0.0 } else { h },
            Regime::Bdf2 { h, .. } => now + h,
            Regime::Statics { .. } => now,
        }
    }
    /// A time step: the beads' unknowns and gap rows are this step's
    /// ([`crate::pipeline::beads::prepare`]).
    fn dynamic(self) -> bool {
        !matches!(self, Regime::Statics { .. })
    }
    fn bead_unknowns(self) -> bool {
        matches!(self, Regime::Statics { bead_unknowns: true })
    }
}

/// Which control points each segment uses, folded into one number (a rod
/// replaced by one of the same size but other knot multiplicities changes it).
fn segment_fingerprint(r: &Rod) -> usize {
    r.cache().seg_ctrl.iter().enumerate().fold(r.n_segments(), |h, (s, c)| h.wrapping_mul(31).wrapping_add(c[0] ^ (c[3] << 20) ^ s))
}

/// Fills the constraint slots (constraints, active contacts, beads when they
/// are unknowns) and rebuilds the layout if the topology changed.
fn place(
    ws: &mut Workspace,
    rods: &[&Rod],
    constraints: &Arena<Constraint>,
    beads: &Arena<Bead>,
    contacts: &ContactSet,
    interleave: &[Vec<RodHandle>],
    regime: Regime,
) -> Result<()> {
    ws.slots.clear();
    ws.contact_ids.clear();
    let pos = &ws.rod_pos;
    for (_, c) in constraints.iter() {
        let (a, b) = (position_of(pos, c.rod)?, position_of(pos, c.other.unwrap_or(c.rod))?);
        let t = c.kind.touched(&[rods[a], rods[b]])?;
        ws.slots.push(ConstraintSlot { rods: [a, b], n_rows: c.kind.n_rows(), n_extra: c.kind.n_extra(), touched: t.items, held: t.held, len: t.len, links: [NO_LINK; 2] });
    }
    ws.stick_ids.clear();
    for (i, p) in contacts.active() {
        let (a, b) = (position_of(pos, p.rods[0])?, position_of(pos, p.rods[1])?);
        let t = p.kind.touched(&[rods[a], rods[b]])?;
        ws.slots.push(ConstraintSlot { rods: [a, b], n_rows: 1, n_extra: 0, touched: t.items, held: t.held, len: t.len, links: [NO_LINK; 2] });
        ws.contact_ids.push(i);
    }
    for (i, p) in contacts.active() {
        if let Some(k) = p.friction.as_ref().and_then(|f| f.rows.as_ref()) {
            let (a, b) = (position_of(pos, p.rods[0])?, position_of(pos, p.rods[1])?);
            let t = k.touched(&[rods[a], rods[b]])?;
            ws.slots.push(ConstraintSlot { rods: [a, b], n_rows: k.n_rows(), n_extra: 0, touched: t.items, held: t.held, len: t.len, links: [NO_LINK; 2] });
            ws.stick_ids.push(i);
        }
    }
    if regime.dynamic() {
        let pos = &ws.rod_pos;
        crate::pipeline::beads::place(&mut ws.beads, &mut ws.slots, |h| position_of(pos, h))?;
    } else if regime.bead_unknowns() {
        for (_, b) in beads.iter().filter(|(_, b)| !b.fixed) {
            let r = position_of(pos, b.rod)?;
            let ctrl = rods[r].basis_at(b.u)?.0;
            let mut touched = [(0u8, 0usize); MAX_TOUCHED];
            for (t, c) in touched.iter_mut().zip(ctrl) {
                *t = (0, c);
            }
            ws.slots.push(ConstraintSlot { rods: [r, r], n_rows: 0, n_extra: 1, touched, held: [true; MAX_TOUCHED], len: 4, links: [NO_LINK; 2] });
        }
    }
    // The layout (algorithms 9–10) changes only with the topology: rods
    // (identity, size), constraint slots (touched control points move
    // when a slider changes segment) and interleaving. Rebuilt then only,
    // so a step allocates nothing.
    let shape_now = rods.iter().zip(&ws.rod_ids).map(|(r, i)| (*i, r.n_ctrl(), r.dofs(), segment_fingerprint(r)));
    let same_rods = ws.layout_rods.len() == rods.len() && ws.layout_rods.iter().copied().eq(shape_now) && ws.layout_groups.as_slice() == interleave;
    if same_rods && ws.layout_slots == ws.slots {
        return Ok(());
    }
    // The middle control points of each side of a two-rod slot, linked
    // crosswise, so that rods running either way are ordered alike.
    ws.links.clear();
    for s in ws.slots.iter().filter(|s| s.rods[0] != s.rods[1]) {
        let t = &s.touched[..s.len];
        let mid = |side: u8| -> [Option<usize>; 2] {
            let mut c = t.iter().filter(|e| e.0 == side).map(|e| e.1);
            let (first, second, third) = (c.next(), c.next(), c.next());
            [second.or(first), third.or(second).or(first)]
        };
        let (a, b) = (mid(0), mid(1));
        for x in a.into_iter().flatten() {
            for y in b.into_iter().flatten() {
                ws.links.push((s.rods[0], x, s.rods[1], y));
            }
        }
    }
    let shapes = rods.iter().map(|r| (r.n_ctrl(), r.dofs(), r.cache().seg_ctrl.as_slice()));
    if same_rods && ws.links == ws.layout_links {
        // Only one-rod slots moved (a slider changed segment): the same
        // order, the rows placed again, nothing allocated.
        ws.layout.rebuild(shapes, &ws.layout_order, &ws.slots, &mut ws.layout_scratch);
        ws.layout_slots.clone_from(&ws.slots);
        return Ok(());
    }
    let graphs: Vec<RodGraph<'_>> = rods.iter().map(|r| RodGraph { n_ctrl: r.n_ctrl(), segments: &r.cache().seg_ctrl }).collect();
    let groups: Vec<Vec<usize>> =
        interleave.iter().map(|g| g.iter().map(|h| position_of(pos, *h)).collect::<Result<Vec<_>>>()).collect::<Result<_>>()?;
    // Two bandwidth-reducing orderings of linked rods; the narrower band wins.
    let segs: Vec<_> = shapes.collect();
    let order = control_point_order_with(&graphs, &ws.links, &groups, Strategy::Rcm);
    let rcm = Layout::build(&segs, &order, &ws.slots);
    (ws.layout, ws.layout_order) = if ws.links.is_empty() {
        (rcm, order)
    } else {
        let merged_order = control_point_order_with(&graphs, &ws.links, &groups, Strategy::Parameter);
        let merged = Layout::build(&segs, &merged_order, &ws.slots);
        if merged.bandwidth < rcm.bandwidth {
            (merged, merged_order)
        } else {
            (rcm, order)
        }
    };
    ws.layout_links.clone_from(&ws.links);
    ws.layout_rods = rods.iter().zip(&ws.rod_ids).map(|(r, i)| (*i, r.n_ctrl(), r.dofs(), segment_fingerprint(r))).collect();
    ws.layout_slots.clone_from(&ws.slots);
    ws.layout_groups = interleave.to_vec();
    Ok(())
}

/// Rod `h`'s stick compliance ([`crate::contact::friction::stick_compliance`],
/// which scans its sections), once per assembly: `memo` by arena slot, NaN
/// until computed.
fn stick_compliance(memo: &mut Vec<f64>, h: crate::handles::RodHandle, rod: &Rod) -> Result<f64> {
    let k = h.index as usize;
    if memo.len() <= k {
        memo.resize(k + 1, f64::NAN);
    }
    if memo[k].is_nan() {
        memo[k] = crate::contact::friction::stick_compliance(rod)?;
    }
    Ok(memo[k])
}

/// Refreshes the rod and constraint ids and the handle → position map.
fn index(ws: &mut Workspace, rods: &Arena<Rod>, constraints: &Arena<Constraint>) {
    ws.rod_ids.clear();
    ws.rod_ids.extend(rods.iter().map(|(i, _)| i));
    ws.con_ids.clear();
    ws.con_ids.extend(constraints.iter().map(|(i, _)| i));
    ws.rod_pos.clear();
    ws.rod_pos.resize(rods.capacity(), None);
    for (k, i) in ws.rod_ids.iter().enumerate() {
        ws.rod_pos[i.0 as usize] = Some((i.1, k));
    }
}

/// Builds the layout only (for reporting the bandwidth).
pub(crate) fn layout(world: &mut World, bead_unknowns: bool) -> Result<()> {
    let World { rods: rod_arena, constraints, beads, contacts, interleave, ws, .. } = world;
    index(ws, rod_arena, constraints);
    let rods: Vec<&Rod> = rod_arena.iter().map(|(_, r)| r).collect();
    place(ws, &rods, constraints, beads, contacts, interleave, Regime::Statics { bead_unknowns })
}

/// Assembles the system for `regime`: contacts detected, forces gathered,
/// layout placed. Returns the elastic energy.
pub(crate) fn assemble(world: &mut World, regime: Regime) -> Result<f64> {
    assemble_with(world, regime, false)
}

/// [`assemble`]; `reuse`: the rods have not moved since the last
/// assembly with `reuse` (a round of the same active set), whose detected
/// pairs serve again (`Workspace::detected`).
pub(crate) fn assemble_with(world: &mut World, regime: Regime, reuse: bool) -> Result<f64> {
    world.params.validate()?;
    // Detection takes the pool where the rest of the step does.
    world.ws.detect.parallel = super::uses_pool(world);
    let World { rods: rod_arena, constraints, loads, beads, contacts, detectors, interleave, params, ws, time, steps, .. } = world;
    // Contacts follow the closest points of their rods.
    for (_, c) in constraints.iter_mut() {
        if let (Some(a), Some(b)) = (rod_arena.get(c.rod.into()), rod_arena.get(c.other.unwrap_or(c.rod).into())) {
            c.kind.project(&[a, b])?;
        }
    }
    // The last assembly's pairs move to the kept buffer (the carry-over
    // reads them); the detectors fill the one they leave.
    let mut previous = std::mem::take(&mut ws.previous_pairs);
    previous.clear();
    if !detectors.is_empty() {
        std::mem::swap(&mut previous, &mut contacts.pairs);
        if reuse && ws.detected.valid {
            contacts.pairs.extend(ws.detected.pairs.iter().cloned());
        } else {
            ws.detected.valid = false;
            detect_all(rod_arena, detectors, ws, contacts)?;
            // Pairs a first solve of this step went through (recheck.rs).
            contacts.pairs.extend(ws.recheck_pairs.iter().cloned());
            // Before the pairs are kept for the rounds: they do not move
            // the rods, so the decision stands through them.
            decide_penalties(rod_arena, &ws.blocked, &mut contacts.pairs)?;
            if reuse {
                ws.detected.pairs.clear();
                ws.detected.pairs.extend(contacts.pairs.iter().cloned());
                ws.detected.valid = true;
            }
        }
    } else {
        // Pairs added by hand (or restored) with no detector to refresh
        // them follow their rods' closest points like contact constraints;
        // detected ones were just placed near the capsules that found them.
        for p in contacts.pairs.iter_mut() {
            if let (Some(a), Some(b)) = (rod_arena.get(p.rods[0].into()), rod_arena.get(p.rods[1].into())) {
                p.kind.project(&[a, b])?;
            }
        }
        decide_penalties(rod_arena, &ws.blocked, &mut contacts.pairs)?;
    }
    // A pair detected again keeps its place in the active set (and its
    // force): the active-set rounds re-assemble (on the pairs of the first
    // round's detection, `Workspace::detected`). A penalty row's place
    // was decided above; an active one takes its force (the friction's
    // normal) and friction state from the pair found there.
    // A pair taken out as dependent (see `solve::block_dependent_contact`) stays out.
    let carry = Carry::new(&previous, std::mem::take(&mut ws.carry));
    for p in contacts.pairs.iter_mut().filter(|p| !super::solve::is_blocked(rod_arena, &ws.blocked, p)) {
        if p.is_penalty() && !p.active {
            continue; // left out by `decide_penalties`, its force 0
        }
        if let Some(old) = carry.find(rod_arena, &previous, p) {
            p.active = true;
            if !p.is_penalty() {
                p.force = old.force;
            }
            if let (Some(f), Some(of)) = (&mut p.friction, &old.friction) {
                f.carry(of);
            }
        }
    }
    ws.carry = carry.order;
    ws.previous_pairs = previous;
    // Friction: the anchor of the step and the friction rows of active
    // pairs (stick rows, or the row across a slip between rods).
    ws.stick.clear();
    for p in contacts.pairs.iter_mut() {
        let penalty = p.is_penalty();
        if let (Some(f), Some(a), Some(b)) = (&mut p.friction, rod_arena.get(p.rods[0].into()), rod_arena.get(p.rods[1].into())) {
            if p.active {
                let g = crate::contact::friction::geometry(&p.kind, [a, b])?;
                if penalty {
                    f.prepare_spring(&g, [a, b], *steps, p.force, p.compliance)?;
                } else {
                    let c = stick_compliance(&mut ws.stick, p.rods[0], a)? + if g.ub.is_some() { stick_compliance(&mut ws.stick, p.rods[1], b)? } else { 0.0 };
                    f.prepare(&g, [a, b], *steps, p.force, c)?;
                }
            } else {
                f.reset();
            }
        }
    }
    index(ws, rod_arena, constraints);
    let mut rods: Vec<&Rod> = recycle(std::mem::take(&mut ws.rod_refs));
    rods.extend(rod_arena.iter().map(|(_, r)| r));
    let placed = place(ws, &rods, constraints, beads, contacts, interleave, regime);
    let energy = placed.and_then(|_| gather_and_assemble(ws, &rods, constraints, loads, beads, contacts, params, *time, *steps + 1, regime));
    ws.rod_refs = recycle(rods);
    let energy = energy?;
    for (_, b) in beads.iter_mut() {
        b.u_assembled = b.u;
    }
    Ok(energy)
}

/// Penalty rows (`ContactPair::is_penalty`) act where the strands are into
/// each other when the pairs are found (their force −g/C) and wait for the
/// next step where they are not: they take no part in the active-set
/// rounds. Left to the rounds, the rows of a knit cell (thousands, along
/// lines of contact) were still pulling, four in ten, when the rounds ran
/// out. Blocked pairs (`solve::block_dependent_contact`) stay out.
fn decide_penalties(rods: &Arena<Rod>, blocked: &[crate::contact::ContactPair], pairs: &mut [crate::contact::ContactPair]) -> Result<()> {
    let mut row = [crate::constraint::Row::default(); 1];
    for p in pairs.iter_mut().filter(|p| p.is_penalty()) {
        p.active = false;
        if super::solve::is_blocked(rods, blocked, p) {
            continue;
        }
        if let (Some(a), Some(b)) = (rods.get(p.rods[0].into()), rods.get(p.rods[1].into())) {
            p.kind.linearize(&[a, b], &mut row)?;
            p.active = row[0].rhs > 0.0; // rhs = target − g
            // Its force at the start of the step, −g/C: the normal force
            // its friction is bounded by through the step.
            p.force = if p.active { row[0].rhs / p.compliance } else { 0.0 };
        }
    }
    Ok(())
}

/// Penetration a frictionless contact row holds instead of pushing out, in
/// an implicit Euler step: half a percent of the rods' radii. A row
/// re-seated where the spline already sags through (rows sit about one per
/// segment) would otherwise push it out within one step and add energy;
/// deeper than this it is pushed back to it; a rod at rest sinks to it.
/// A sticking row holds it too (pushing out, a rod dropped on a plane with
/// μ = 0.3 gained up to 1.2e-4 of its energy in a step; the falling rope
/// bridge, which had diverged with it before the active-set fixes, now
/// runs); a slipping row keeps none (held, the capstan's slipping rope
/// diverged at step 1917).
pub(crate) const CONTACT_SLACK: f64 = 5e-3;

/// The penetration pair `p` (on rods `a`, `b`) may hold: [`CONTACT_SLACK`]
/// of both rods' radii for a rod–rod (or self) row, of the rod's own
/// against an obstacle's tangent plane; none while it slips, for a
/// compliant row (it sinks by its force's share anyway) or outside an
/// implicit Euler step (`on`).
/// `radii`: the two rods' largest bounding radii ([`largest_radius`]).
pub(crate) fn contact_slack(on: bool, p: &crate::contact::ContactPair, radii: [f64; 2]) -> f64 {
    if !on || p.is_penalty() || p.friction.as_ref().is_some_and(|f| f.slip.is_some()) {
        return 0.0;
    }
    let reach = match p.kind {
        crate::constraint::ConstraintKind::Contact(_) => radii[0] + radii[1],
        _ => radii[0],
    };
    CONTACT_SLACK * reach
}

/// A rod's largest bounding radius (kept per assembly in
/// `Workspace::radii`: a yarn has thousands of sections and a fabric
/// thousands of contacts).
pub(crate) fn largest_radius(r: &Rod) -> f64 {
    r.sections().iter().map(|s| s.bounding_radius()).fold(0.0, f64::max)
}

/// Every detector over every rod, its pairs appended to `out` (the list
/// of rods kept in the workspace's buffer between calls).
pub(crate) fn detect_all(rods: &Arena<Rod>, detectors: &[crate::contact::Detector], ws: &mut Workspace, out: &mut ContactSet) -> Result<()> {
    let mut list: Vec<(RodHandle, &Rod)> = recycle(std::mem::take(&mut ws.rod_list));
    list.extend(rods.iter().map(|(i, r)| (i.into(), r)));
    let found = detectors.iter().try_for_each(|d| d.detect_with(&list, out, &mut ws.detect));
    ws.rod_list = recycle(list);
    found
}

/// Two contact rows at the same place (abscissae within half a parameter
/// unit, a fraction of a knot span).
/// An obstacle row's tangent plane turns with the rod: the same place if
/// its normal turned less than 60°.
/// A ring's abscissae are compared around its period (a row on its seam
/// may come back as u ≈ 0 or u ≈ period).
pub(crate) fn same_place(rods: &Arena<Rod>, a: &crate::contact::ContactPair, b: &crate::contact::ContactPair) -> bool {
    use crate::constraint::ConstraintKind::{Contact, Plane};
    let apart = |side: usize, x: f64, y: f64| abscissae_apart(rods, a.rods[side], x, y);
    match (&a.kind, &b.kind) {
        (Contact(x), Contact(y)) => apart(0, x.ua, y.ua) + apart(1, x.ub, y.ub) < 0.5,
        (Plane(x), Plane(y)) => apart(0, x.u, y.u) < 0.5 && nalgebra::Vector3::from(x.normal).dot(&nalgebra::Vector3::from(y.normal)) > 0.5,
        (x, y) => x == y,
    }
}

/// |x − y| on rod `rod` (parameter units), around a ring's period.
fn abscissae_apart(rods: &Arena<Rod>, rod: crate::handles::RodHandle, x: f64, y: f64) -> f64 {
    let d = (x - y).abs();
    match rods.get(rod.into()) {
        Some(r) if r.is_closed() => d.min(r.n_ctrl() as f64 - d),
        _ => d,
    }
}

/// The previous assembly's active pairs sorted by rods and abscissa on the
/// first rod: a new pair's match (the first in the previous order at the
/// same place) is sought among those within `same_place`'s half unit, not
/// among all (a fabric has thousands of pairs, all on one yarn).
pub(crate) struct Carry {
    order: Vec<CarryEntry>,
}

/// (rods, abscissa on the first rod, index in the previous pairs).
pub(crate) type CarryEntry = (crate::handles::RodHandle, crate::handles::RodHandle, f64, usize);

/// A pair's abscissa on its first rod.
fn first_u(p: &crate::contact::ContactPair) -> f64 {
    match &p.kind {
        crate::constraint::ConstraintKind::Contact(x) => x.ua,
        crate::constraint::ConstraintKind::Plane(x) => x.u,
        _ => 0.0,
    }
}

impl Carry {
    /// `order`: a buffer to reuse (the workspace's).
    fn new(previous: &[crate::contact::ContactPair], mut order: Vec<CarryEntry>) -> Carry {
        order.clear();
        // A non-finite abscissa would break the sorted search: such a pair
        // matches nothing (same_place cannot hold for it either).
        order.extend(previous.iter().enumerate().filter(|(_, p)| p.active && first_u(p).is_finite()).map(|(i, p)| (p.rods[0], p.rods[1], first_u(p), i)));
        // Ties by index, as a stable sort would leave them: a total order,
        // so the unstable sort (no buffer) gives the same.
        order.sort_unstable_by(|a, b| (a.0, a.1).cmp(&(b.0, b.1)).then(a.2.total_cmp(&b.2)).then(a.3.cmp(&b.3)));
        Carry { order }
    }

    fn find<'a>(&self, rods: &Arena<Rod>, previous: &'a [crate::contact::ContactPair], p: &crate::contact::ContactPair) -> Option<&'a crate::contact::ContactPair> {
        let u = first_u(p);
        // same_place decides; the window only has to contain its matches
        // (a hair wider than its half unit, for rounding at the edge).
        let half = 0.5 + 1e-9;
        // A ring's abscissae are compared around its period.
        let period = rods.get(p.rods[0].into()).filter(|r| r.is_closed()).map(|r| r.n_ctrl() as f64);
        // A penalty row (held at its capsule's middle, several within
        // the half unit) takes its own: the nearest, not the first.
        let nearest = p.is_penalty();
        let apart = |q: &crate::contact::ContactPair| match (&q.kind, &p.kind) {
            (crate::constraint::ConstraintKind::Contact(x), crate::constraint::ConstraintKind::Contact(y)) => {
                abscissae_apart(rods, p.rods[0], x.ua, y.ua) + abscissae_apart(rods, p.rods[1], x.ub, y.ub)
            }
            _ => 0.0,
        };
        let mut best: Option<usize> = None;
        for shift in [0.0, 1.0, -1.0] {
            let Some(t) = period.map(|t| t * shift).or((shift == 0.0).then_some(0.0)) else { continue };
            let lo = self.order.partition_point(|e| (e.0, e.1) < (p.rods[0], p.rods[1]) || (e.0, e.1) == (p.rods[0], p.rods[1]) && e.2 < u + t - half);
            for e in self.order[lo..].iter().take_while(|e| (e.0, e.1) == (p.rods[0], p.rods[1]) && e.2 <= u + t + half) {
                let better = |b: usize| if nearest { apart(&previous[e.3]) < apart(&previous[b]) } else { e.3 < b };
                if best.is_none_or(better) && same_place(rods, &previous[e.3], p) {
                    best = Some(e.3);
                }
            }
        }
        best.map(|i| &previous[i])
    }
}

/// External generalised forces (III.1–III.10: gravity and the loads, the
/// beads' forces on their rods) and the assembly proper.
#[allow(clippy::too_many_arguments)]
fn gather_and_assemble(
    ws: &mut Workspace,
    rods: &[&Rod],
    constraints: &Arena<Constraint>,
    loads: &Arena<Load>,
    beads: &Arena<Bead>,
    contacts: &ContactSet,
    params: &IntegrationParameters,
    time: f64,
    step: u64,
    regime: Regime,
) -> Result<f64> {
    let t = regime.force_time(time);
    let pos = &ws.rod_pos;
    ws.ext.resize_with(rods.len(), Vec::new);
    let gravity = Gravity(params.gravity);
    for (r, rod) in rods.iter().enumerate() {
        let f = &mut ws.ext[r];
        f.clear();
        f.resize(rod.coords().len(), 0.0);
        gravity.add_force(rod, t, f)?;
    }
    ws.field_k.clear();
    for (_, l) in loads.iter() {
        let r = position_of(pos, l.rod())?;
        l.add_force(rods[r], t, &mut ws.ext[r])?;
        let fk = &mut ws.field_k;
        l.add_stiffness(rods[r], t, &mut |i, j, v| fk.push((r, i, j, v)))?;
    }
    // Each rod's drag, once per assembly: the D/h blocks, the trapezoidal
    // rule's D ΔX/h and the thermal force all use these (statics: none).
    ws.drags.clear();
    for rod in rods {
        ws.drags.push(if matches!(regime, Regime::Statics { .. }) { Default::default() } else { params.drag_of(rod)? });
    }
    if ws.thermal_h > 0.0 {
        for (r, rod) in rods.iter().enumerate() {
            let field = Thermal { kt: ws.thermal_kt, h: ws.thermal_h, drag: ws.drags[r], normals: &ws.thermal_normals[r] };
            field.add_force(rod, t, &mut ws.ext[r])?;
        }
    }
    ws.masses.clear();
    for (k, (id, b)) in beads.iter().enumerate() {
        let r = position_of(pos, b.rod)?;
        let (ctrl, bs) = crate::pipeline::beads::bead_basis(&ws.beads, k, id, b.u, rods[r])?;
        let force = crate::pipeline::beads::bead_rod_force(&ws.beads, k, id, b.rod_force);
        crate::force::spread(&mut ws.ext[r], rods[r].dofs(), &ctrl, &bs[0], &force);
        let seg = rods[r].knots().locate(b.u)?;
        ws.masses.push(PointMass { rod: r, seg, ctrl, b: bs[0], mass: b.mass });
    }
    // ½ f(t + h) here, the other half of the trapezoid (and the drag of
    // the iterate) from the state of the step; the BDF2 stage's drag term.
    let scale = match regime {
        Regime::Trapezoidal { first: false, .. } => Some(0.5),
        Regime::Bdf2 { .. } => Some(1.0),
        _ => None,
    };
    if let Some(s) = scale {
        for (f, extra) in ws.ext.iter_mut().zip(&ws.trapezoidal.extra) {
            f.iter_mut().zip(extra).for_each(|(x, e)| *x = s * *x + e);
        }
    }
    // Slipping contacts: −μ N ŝ on rod a, its opposite on rod b (weighted
    // like the other forces of a trapezoidal iterate: its other half is in
    // the recorded forces of the step's start).
    let weight = scale.unwrap_or(1.0);
    for (_, p) in contacts.active() {
        let Some(f) = p.friction.as_ref().and_then(|f| f.slip_force()) else { continue };
        let f = f.map(|x| weight * x);
        let g = crate::contact::friction::geometry(&p.kind, [rods[position_of(pos, p.rods[0])?], rods[position_of(pos, p.rods[1])?]])?;
        let r = position_of(pos, p.rods[0])?;
        let (ctrl, bs) = rods[r].basis_at(g.ua)?;
        crate::force::spread(&mut ws.ext[r], rods[r].dofs(), &ctrl, &bs[0], &f);
        if let Some(ub) = g.ub {
            let r = position_of(pos, p.rods[1])?;
            let (ctrl, bs) = rods[r].basis_at(ub)?;
            crate::force::spread(&mut ws.ext[r], rods[r].dofs(), &ctrl, &bs[0], &[-f[0], -f[1], -f[2]]);
        }
    }
    ws.contact_slack = matches!(regime, Regime::Dynamic { .. });
    ws.radii.clear();
    ws.radii.extend(rods.iter().map(|r| largest_radius(r)));
    let mut crefs: Vec<ConstraintRef<'_>> = recycle(std::mem::take(&mut ws.con_refs));
    for (_, c) in constraints.iter() {
        let (a, b) = (position_of(pos, c.rod)?, position_of(pos, c.other.unwrap_or(c.rod))?);
        crefs.push(ConstraintRef { rods: [a, b], kind: &c.kind, compliance: c.compliance, lambda: &c.multipliers, slack: 0.0, elastic: c.is_elastic() });
    }
    for &i in &ws.contact_ids {
        let p = &contacts.pairs[i];
        let (a, b) = (position_of(pos, p.rods[0])?, position_of(pos, p.rods[1])?);
        let slack = contact_slack(ws.contact_slack, p, [ws.radii[a], ws.radii[b]]);
        crefs.push(ConstraintRef { rods: [a, b], kind: &p.kind, compliance: p.compliance, lambda: std::slice::from_ref(&p.force), slack, elastic: false });
    }
    for &i in &ws.stick_ids {
        let p = &contacts.pairs[i];
        let (a, b) = (position_of(pos, p.rods[0])?, position_of(pos, p.rods[1])?);
        // Placed only for pairs with friction rows (see `place`).
        let kind = p.friction.as_ref().and_then(|f| f.rows.as_ref()).expect("a placed pair has its friction rows");
        let compliance = p.friction.as_ref().map_or(0.0, |f| f.compliance);
        crefs.push(ConstraintRef { rods: [a, b], kind, compliance, lambda: &[0.0, 0.0][..kind.n_rows()], slack: 0.0, elastic: false });
    }
    let mut k = regime.coefficients();
    if params.overdamped && matches!(regime, Regime::Dynamic { .. } | Regime::Trapezoidal { .. }) {
        k.mass = 0.0;
        k.momentum = 0.0;
    }
    // The step matrix's extra stiffness (K' − K ≥ 0) damps the sideways
    // motion of compressed samples, with no noise to match it: a thermal
    // step keeps the exact Hessian (its calibrated fluctuations stand).
    if ws.thermal_h > 0.0 {
        k.step_stiffness = false;
    }
    ws.sys.record_forces = matches!(regime, Regime::Trapezoidal { first: true, .. });
    ws.sys.linear_solver = params.linear_solver;
    let mut energy = ws.sys.assemble(&ws.layout, rods, &ws.drags, &ws.ext, &crefs, &ws.masses, &ws.field_k, k, params.parallel);
    if energy.is_ok() && regime.dynamic() {
        energy = energy.and_then(|e| crate::pipeline::beads::assemble(&mut ws.sys, &ws.layout, &mut ws.beads, k, step).map(|_| e));
    } else if energy.is_ok() && regime.bead_unknowns() {
        let static_beads: Vec<BeadRef> = beads
            .iter()
            .filter(|(_, b)| !b.fixed)
            .map(|(_, b)| Ok(BeadRef { rod: position_of(pos, b.rod)?, u: b.u, load: b.rod_force, mass: b.mass }))
            .collect::<Result<_>>()?;
        energy = energy.and_then(|e| ws.sys.assemble_beads(&ws.layout, rods, crefs.len(), &static_beads, k).map(|_| e));
    }
    ws.con_refs = recycle(crefs);
    ws.sys.matrix.finish();
    energy
}

#[cfg(test)]
mod storage_tests {
    use super::*;
    use crate::constraint::kinds::{Position, RelativeDistance};
    use crate::{ConstraintKind, RodContacts, IntegrationParameters, LinearSolver, Material, RodBuilder, Section, World};
    use nalgebra::Vector3;

    /// Two rods pressed across each other with friction, tied by distance
    /// links, one carrying a sliding bead: every kind of entry the assembly
    /// writes (segment blocks, bead masses and abscissae, constraint,
    /// contact and stick rows). Assembled in band and in sparse storage
    /// from the same state, the matrices agree entry by entry, exactly
    /// (the same sums in the same order), as do the right-hand sides.
    #[test]
    fn band_and_sparse_storage_assemble_the_same_matrix() {
        let rod = |a: Vector3<f64>, b: Vector3<f64>| {
            RodBuilder::straight(a, b)
                .control_points(12)
                .with_roll(true)
                .section(Section::circle(0.01).unwrap())
                .material(Material::new("nylon", 3e9, 0.4, 1150.0).unwrap())
                .build()
                .unwrap()
        };
        let mut w = World::new(IntegrationParameters { dt: 2e-3, gravity: [0.0, 0.0, -9.81], ..Default::default() });
        let a = w.add_rod(rod(Vector3::new(-0.5, 0.0, 0.0), Vector3::new(0.5, 0.0, 0.0)));
        let b = w.add_rod(rod(Vector3::new(0.0, -0.5, 0.021), Vector3::new(0.0, 0.5, 0.021)));
        for h in [a, b] {
            let (u0, u1) = w.rod(h).unwrap().domain();
            for u in [u0, u1] {
                let p = w.rod(h).unwrap().position(u).unwrap();
                w.add_constraint(h, ConstraintKind::Position(Position { u, axes: [true; 4], target: [p.x, p.y, p.z, 0.0] }), 0.0).unwrap();
            }
        }
        let (u0, u1) = w.rod(a).unwrap().domain();
        let (ua, ub) = (u0 + 0.2 * (u1 - u0), u0 + 0.3 * (u1 - u0));
        let distance = (w.rod(a).unwrap().position(ua).unwrap() - w.rod(b).unwrap().position(ub).unwrap()).norm();
        w.add_link(a, b, ConstraintKind::RelativeDistance(RelativeDistance { ua, ub, distance }), 0.0).unwrap();
        w.add_bead(a, u0 + 0.7 * (u1 - u0), 0.01, 0.0, 0.0).unwrap();
        w.add_load(crate::Load::PointForce(crate::force::PointForce { rod: b, u: 0.5 * (u0 + u1), force: [0.0, 0.0, -20.0] })).unwrap();
        w.add_contact_detector(RodContacts::new(0.005, false, true).unwrap().with_friction(0.3).unwrap()).unwrap();
        for _ in 0..20 {
            w.step().unwrap();
        }
        let mid = |h| w.rod(h).unwrap().position(0.5 * (u0 + u1)).unwrap();
        assert!(w.contacts().active().count() > 0, "the rods touch: {} pairs, mid z {} {}", w.contacts().pairs.len(), mid(a).z, mid(b).z);
        let snapshot = w.to_json().unwrap();
        for regime in [Regime::Dynamic { h: 2e-3 }, Regime::Statics { bead_unknowns: true }] {
            let mut got = Vec::new();
            for solver in [LinearSolver::Band, LinearSolver::Sparse] {
                let mut w = World::from_json(&snapshot).unwrap();
                w.params.linear_solver = solver;
                assemble(&mut w, regime).unwrap();
                let m = &w.ws.sys.matrix;
                let n = m.n();
                let dense: Vec<f64> = (0..n * n).map(|k| m.get(k / n, k % n)).collect();
                got.push((m.storage(), dense, w.ws.sys.rhs.clone(), w.ws.layout.n_rows));
            }
            let (band, sparse) = (&got[0], &got[1]);
            assert_eq!((band.0, sparse.0), (crate::system::matrix::Storage::Band, crate::system::matrix::Storage::Sparse));
            assert!(band.3 > 4, "constraint and contact rows assembled ({})", band.3);
            assert_eq!(band.1, sparse.1, "{regime:?}: matrices differ");
            assert_eq!(band.2, sparse.2, "{regime:?}: right-hand sides differ");
        }
    }
}
