//! Solve and apply: factorise along the chain of [`crate::system::Factorisation`],
//! with the contact active set settled around it, then move the rods, store
//! the multipliers and advance the sliders.
use super::assemble::{assemble_with, Regime};
use crate::constraint::{Row, MAX_ROWS};
use crate::error::{Error, Result, Unknown};
use crate::handles::Index;
use crate::system::{Layout, Solved};
use crate::world::World;

/// Most re-solves one solve (a step, a Newton iterate) spends settling
/// the contact active set. After [`crate::contact::friction::FREE_ROUNDS`]
/// of them friction is held, and the rest go to the normal set alone, in
/// which a pair that pulls leaves for good (see `Workspace::pulled`).
const MAX_ACTIVE_SET_ROUNDS: usize = 15;

/// Names unknown `g` of the system for error messages.
fn describe(layout: &Layout, rod_ids: &[Index], con_ids: &[Index], contact_ids: &[usize], stick_ids: &[usize], g: usize) -> Unknown {
    for (r, cps) in layout.cp_index.iter().enumerate() {
        for (i, &start) in cps.iter().enumerate() {
            if g >= start && g < start + layout.dofs[r] {
                return Unknown::Coordinate { rod: rod_ids[r].into(), ctrl: i, axis: g - start };
            }
        }
    }
    let (nc, np, ns) = (con_ids.len(), contact_ids.len(), stick_ids.len());
    for (c, &start) in layout.extra_index.iter().enumerate() {
        if g >= start && g < start + layout.extra_count.get(c).copied().unwrap_or(0) {
            return match con_ids.get(c) {
                Some(&h) => Unknown::Abscissa { constraint: h.into() },
                None => Unknown::BeadAbscissa { bead: c - nc - np - ns },
            };
        }
    }
    for (c, &start) in layout.row_index.iter().enumerate() {
        if g >= start && g < start + layout.row_count[c] {
            if let Some(&h) = con_ids.get(c) {
                return Unknown::Multiplier { constraint: h.into(), row: g - start };
            }
            if let Some(&p) = contact_ids.iter().chain(stick_ids).nth(c - nc) {
                return Unknown::Contact { pair: p };
            }
        }
    }
    Unknown::Index { index: g }
}

/// Solves the assembled system.
pub(crate) fn solve(world: &mut World) -> Result<Solved> {
    let ws = &mut world.ws;
    let (layout, rod_ids, con_ids, contact_ids, stick_ids) = (&ws.layout, &ws.rod_ids, &ws.con_ids, &ws.contact_ids, &ws.stick_ids);
    let out = ws.sys.solve(layout, world.params.linear_solver, |g| describe(layout, rod_ids, con_ids, contact_ids, stick_ids, g));
    match out {
        Err(Error::Singular { unknown, mut constraints, detail }) => {
            if let Some(u) = &unknown {
                involved(world, u, &mut constraints);
            }
            Err(Error::Singular { unknown, constraints, detail })
        }
        other => other,
    }
}

/// The constraints involved in a singular system at `unknown`: those whose
/// rows act on the coordinates it touches (a multiplier: its constraint's
/// coordinates; a coordinate: itself). Dependent or contradictory rows
/// share coordinates, so the culprits are among them.
fn involved(world: &World, unknown: &Unknown, out: &mut Vec<crate::handles::ConstraintHandle>) {
    let ws = &world.ws;
    let (layout, a) = (&ws.layout, &ws.sys.matrix);
    let is_coord = |g: usize| layout.cp_index.iter().zip(&layout.dofs).any(|(cps, &d)| cps.iter().any(|&s| g >= s && g < s + d));
    let rows_of = |c: usize| layout.row_index[c]..layout.row_index[c] + layout.row_count[c];
    let columns = |i: usize| {
        let mut js = Vec::new();
        a.for_row(i, |j, v| {
            if v != 0.0 {
                js.push(j)
            }
        });
        js.into_iter()
    };
    let mut cols: Vec<usize> = match unknown {
        Unknown::Multiplier { constraint, .. } => match ws.con_ids.iter().position(|&h| crate::handles::ConstraintHandle::from(h) == *constraint) {
            Some(c) => rows_of(c).flat_map(columns).filter(|&j| is_coord(j)).collect(),
            None => return,
        },
        Unknown::Coordinate { rod, ctrl, axis } => match ws.rod_ids.iter().position(|&h| crate::handles::RodHandle::from(h) == *rod) {
            Some(r) => vec![layout.cp_index[r][*ctrl] + axis],
            None => return,
        },
        _ => return,
    };
    cols.sort_unstable();
    cols.dedup();
    for (c, &h) in ws.con_ids.iter().enumerate() {
        let h = crate::handles::ConstraintHandle::from(h);
        if !out.contains(&h) && rows_of(c).any(|i| columns(i).any(|j| cols.binary_search(&j).is_ok())) {
            out.push(h);
        }
    }
}

/// Assembles and solves for `regime`, settling the contact active set: a
/// pair whose multiplier would pull leaves it, a pair the solution would
/// push through its gap enters it, and the system is solved again. Returns
/// the elastic energy and the solve.
pub(crate) fn assemble_and_solve(world: &mut World, regime: Regime) -> Result<(f64, Solved)> {
    let out = settle_and_solve(world, regime);
    // What the rounds kept holds for them only.
    world.ws.pulled.clear();
    world.ws.detected.valid = false;
    out
}

fn settle_and_solve(world: &mut World, regime: Regime) -> Result<(f64, Solved)> {
    world.ws.blocked.clear();
    world.ws.pulled.clear();
    if !world.contacts.is_empty() {
        activate_touching(world)?;
    }
    let mut rounds = 0;
    // The rods stay where they are through the rounds: one detection.
    let mut reuse = false;
    loop {
        let energy = assemble_with(world, regime, reuse)?;
        reuse = true;
        let solved = match solve(world) {
            Err(e) if block_dependent_contact(world, &e) => continue,
            other => other?,
        };
        let contacts_moved = !world.contacts.is_empty() && rounds < MAX_ACTIVE_SET_ROUNDS && update_active_set(world, rounds >= crate::contact::friction::FREE_ROUNDS)?;
        // The beads' gap rows settle in the same rounds (dynamics only).
        let beads_moved = rounds < MAX_ACTIVE_SET_ROUNDS && super::beads::update_gaps(world, rounds >= crate::contact::friction::FREE_ROUNDS);
        if !(contacts_moved || beads_moved) {
            check_blocked(world)?;
            return Ok((energy, solved));
        }
        rounds += 1;
    }
}

/// A rod's largest bounding radius as the last assembly measured it.
fn radius(ws: &crate::system::Workspace, r: usize) -> f64 {
    ws.radii.get(r).copied().unwrap_or(0.0)
}

/// Position of rod `h` in the layout of the last assembly (None: not in it).
fn layout_position(ws: &crate::system::Workspace, h: crate::handles::RodHandle) -> Option<usize> {
    crate::world::position_of(&ws.rod_pos, h).ok()
}

/// The change of a linearised row's measure under the last solution ΔX
/// (its two sides at layout positions `sides`).
fn row_change(ws: &crate::system::Workspace, row: &Row, sides: [usize; 2]) -> f64 {
    row.entries().iter().filter(|e| e.0 < 2).map(|&(w, l, v)| v * ws.sys.sol[ws.layout.dof(sides[w as usize], l)]).sum()
}

/// A pair taken out as dependent must have been redundant (its point
/// held by the other rows): if the solution drives it deeper, the rows
/// contradict each other (a rod squeezed between obstacles closer than its
/// diameter) — a `Singular` error naming the pairs, before anything moves.
fn check_blocked(world: &World) -> Result<()> {
    if world.ws.blocked.is_empty() {
        return Ok(());
    }
    let mut rows = [Row::default(); MAX_ROWS];
    let ws = &world.ws;
    let pos = |h| layout_position(ws, h);
    let mut bad = Vec::new();
    for (i, p) in world.contacts.pairs.iter().enumerate() {
        if !is_blocked(&world.rods, &ws.blocked, p) {
            continue;
        }
        let (Some(a), Some(b)) = (world.rods.get(p.rods[0].into()), world.rods.get(p.rods[1].into())) else { continue };
        let (Some(ra), Some(rb)) = (pos(p.rods[0]), pos(p.rods[1])) else { continue };
        p.kind.linearize(&[a, b], &mut rows[..1])?;
        let moved = row_change(ws, &rows[0], [ra, rb]);
        // Deeper by more than a millionth of the rods' reach.
        let reach = radius(ws, ra).max(radius(ws, rb));
        if moved < -1e-6 * reach.max(f64::MIN_POSITIVE) {
            bad.push(i);
        }
    }
    match bad.first() {
        None => Ok(()),
        Some(&first) => Err(Error::Singular {
            unknown: Some(Unknown::Contact { pair: first }),
            constraints: Vec::new(),
            detail: format!("contacts that cannot all be met (pairs {bad:?} of the contact set are pushed through by the others): obstacles or rods closer than the rods' diameters"),
        }),
    }
}

/// After a failed factorisation: when the row found dependent is a contact
/// pair's (its point already held — an anchor on an obstacle's surface),
/// takes the pair out of the active set for the rest of the solve and
/// returns true (assemble and solve again). Bounded: each pair once.
pub(crate) fn block_dependent_contact(world: &mut World, e: &Error) -> bool {
    let Error::Singular { unknown: Some(Unknown::Contact { pair }), .. } = e else { return false };
    let n = world.contacts.pairs.len();
    let Some(p) = world.contacts.pairs.get_mut(*pair) else { return false };
    if !p.active || world.ws.blocked.len() > n {
        return false;
    }
    p.active = false;
    let p = p.clone();
    world.ws.blocked.push(p);
    true
}

/// Whether `p` is a pair [`block_dependent_contact`] took out.
pub(crate) fn is_blocked(rods: &crate::handles::Arena<crate::rod::Rod>, blocked: &[crate::contact::ContactPair], p: &crate::contact::ContactPair) -> bool {
    blocked.iter().any(|b| b.rods == p.rods && super::assemble::same_place(rods, b, p))
}

/// Takes into the active set every pair at or past contact now.
fn activate_touching(world: &mut World) -> Result<()> {
    let mut rows = [Row::default(); MAX_ROWS];
    let World { rods, contacts, ws, .. } = world;
    for p in contacts.pairs.iter_mut() {
        if is_blocked(rods, &ws.blocked, p) {
            continue;
        }
        let pair = [rods.get(p.rods[0].into()), rods.get(p.rods[1].into())];
        if let [Some(a), Some(b)] = pair {
            p.kind.linearize(&[a, b], &mut rows[..1])?;
            // rhs = target − g: the gap g − target = −rhs.
            if -rows[0].rhs <= 0.0 {
                p.active = true;
            }
        }
    }
    Ok(())
}

/// After a solve (for callers that assemble and solve themselves, round
/// `round` of the active set for this iterate, from 0): settles the contact
/// active set as the step's rounds do (friction held after
/// [`crate::contact::friction::FREE_ROUNDS`], then a pulling pair leaves
/// for the rest of the iterate); true when it changed and the system must
/// be assembled and solved again, false also once the rounds ran out.
pub(crate) fn settle_contacts(world: &mut World, round: usize) -> Result<bool> {
    if world.contacts.is_empty() || round >= MAX_ACTIVE_SET_ROUNDS {
        return Ok(false);
    }
    update_active_set(world, round >= crate::contact::friction::FREE_ROUNDS)
}

/// After a solve: drop pulling pairs, add pairs the step would penetrate,
/// move the friction of active pairs between stick and slip
/// ([`crate::contact::friction`]; held as it is when `freeze_friction`).
/// Returns whether anything changed.
fn update_active_set(world: &mut World, freeze_friction: bool) -> Result<bool> {
    // The per-pair row buffers leave the workspace for the pass.
    let (mut row_of, mut stick_of) = (std::mem::take(&mut world.ws.row_of), std::mem::take(&mut world.ws.stick_of));
    let out = update_active_set_with(world, freeze_friction, &mut row_of, &mut stick_of);
    (world.ws.row_of, world.ws.stick_of) = (row_of, stick_of);
    out
}

fn update_active_set_with(world: &mut World, freeze_friction: bool, row_of: &mut Vec<usize>, stick_of: &mut Vec<usize>) -> Result<bool> {
    let mut changed = false;
    let mut rows = [Row::default(); MAX_ROWS];
    let World { rods, contacts, ws, .. } = world;
    let layout = &ws.layout;
    let nc = ws.con_ids.len();
    let np = ws.contact_ids.len();
    row_of.clear();
    row_of.resize(contacts.pairs.len(), usize::MAX);
    for (k, &i) in ws.contact_ids.iter().enumerate() {
        row_of[i] = layout.row_index[nc + k];
    }
    stick_of.clear();
    stick_of.resize(contacts.pairs.len(), usize::MAX);
    for (k, &i) in ws.stick_ids.iter().enumerate() {
        stick_of[i] = layout.row_index[nc + np + k];
    }
    let pos = |h| layout_position(ws, h);
    // This solve's displacement of rod `h`'s point at `u`.
    let step_of = |h: crate::handles::RodHandle, rod: &crate::rod::Rod, u: f64| -> Result<nalgebra::Vector3<f64>> {
        let Some(r) = pos(h) else { return Ok(nalgebra::Vector3::zeros()) };
        let (ctrl, b) = rod.basis_at(u)?;
        let mut d = nalgebra::Vector3::zeros();
        for k in 0..4 {
            for a in 0..3 {
                d[a] += b[0][k] * ws.sys.sol[layout.dof(r, ctrl[k] * rod.dofs() + a)];
            }
        }
        Ok(d)
    };
    let mut newly_pulled = Vec::new();
    for (i, p) in contacts.pairs.iter_mut().enumerate() {
        let (Some(a), Some(b)) = (rods.get(p.rods[0].into()), rods.get(p.rods[1].into())) else { continue };
        // A compliant row is a penalty set at the start of the step
        // (`assemble_with`): kept or left as it is, its force as solved
        // but never pulling (the linear penalty's, where the step parts
        // the strands).
        let penalty = p.is_penalty();
        if p.active {
            let mut force = -ws.sys.sol[row_of[i]];
            if penalty {
                force = force.max(0.0);
            } else if force < 0.0 {
                p.active = false;
                // Held rounds settle the normal set alone; a pair pulling
                // when in and pressed a little past its slack when out
                // would go in and out until the rounds ran out.
                if freeze_friction {
                    newly_pulled.push(p.clone());
                }
                changed = true;
                continue;
            }
            p.force = force;
            if let Some(f) = &mut p.friction {
                let g = crate::contact::friction::geometry(&p.kind, [a, b])?;
                let stick = match (stick_of[i], &f.rows) {
                    (k, Some(kind)) if k != usize::MAX => Some(friction_reaction(&ws.sys.sol, k, kind, [a, b])?),
                    _ => None,
                };
                // A penalty row's spring slips between steps
                // (`Friction::prepare_spring`); held, a pair only records
                // its force, and its motion is not needed.
                let frozen = freeze_friction || penalty;
                let mut moved = nalgebra::Vector3::zeros();
                if !frozen {
                    moved = step_of(p.rods[0], a, g.ua)?;
                    if let Some(ub) = g.ub {
                        moved -= step_of(p.rods[1], b, ub)?;
                    }
                    if let Some((start, _, _)) = f.start {
                        moved += g.relative - nalgebra::Vector3::from(start);
                    }
                }
                changed |= f.update(&g, stick, moved, force, frozen);
            }
            continue;
        }
        if penalty || is_blocked(rods, &ws.blocked, p) || is_blocked(rods, &ws.pulled, p) {
            continue;
        }
        p.kind.linearize(&[a, b], &mut rows[..1])?;
        let (Some(ra), Some(rb)) = (pos(p.rods[0]), pos(p.rods[1])) else { continue };
        // Deeper than the penetration a row may hold (see `assemble::CONTACT_SLACK`).
        let held = rows[0].rhs.clamp(0.0, super::assemble::contact_slack(ws.contact_slack, p, [radius(ws, ra), radius(ws, rb)]));
        if -rows[0].rhs + row_change(ws, &rows[0], [ra, rb]) < -held {
            p.active = true;
            changed = true;
        }
    }
    ws.pulled.extend(newly_pulled);
    Ok(changed)
}

/// The force on rod a of a pair's friction rows (`kind`, from row `r0` of
/// the solution `sol`): a sticking pair's two rows, a slipping pair's one.
fn friction_reaction(sol: &[f64], r0: usize, kind: &crate::constraint::ConstraintKind, rods: [&crate::rod::Rod; 2]) -> Result<nalgebra::Vector3<f64>> {
    let mut lambda = [0.0; 2];
    for (l, s) in lambda.iter_mut().zip(&sol[r0..r0 + kind.n_rows()]) {
        *l = -s;
    }
    Ok(nalgebra::Vector3::from(kind.reaction(&rods, &lambda[..kind.n_rows()])?.force))
}

/// Applies the solution as [`apply`] does, but only if the new state is
/// acceptable: every coordinate and velocity finite (else `NonFinite`
/// naming the rod, before anything moves) and every rod's Poisson update
/// possible (else its error, with the move undone). On error the world is
/// as it was before the call.
///
/// `elastic_before` (a dynamic step: the elastic energy at its start) turns
/// on the divergence guard: see `IntegrationParameters::divergence_factor`.
pub(crate) fn commit(world: &mut World, scale: f64, set_velocity: Option<f64>, elastic_before: Option<f64>) -> Result<(f64, f64)> {
    check_finite(world, scale, set_velocity)?;
    let budget = begin(world, scale, elastic_before);
    let moved = apply(world, scale, set_velocity);
    finish(world, budget)?;
    Ok(moved)
}

/// The first half of [`commit`] for a step applied in several parts: the
/// divergence guard's budget (when `elastic_before` is given, with the
/// work of the solution in the system now) and the undo buffer.
pub(crate) fn begin(world: &mut World, scale: f64, elastic_before: Option<f64>) -> Option<f64> {
    let guard = elastic_before.filter(|_| world.params.divergence_factor.is_finite());
    let budget = guard.map(|u| u + energy_in(world, scale));
    save_undo(world);
    budget
}

/// For a step applied in several parts: keeps each rod's kinetic energy
/// now (for naming the rod whose energy grew) and returns their sum.
pub(crate) fn kinetic_before(world: &mut World) -> f64 {
    let parallel = super::uses_pool(world);
    let World { rods, ws, .. } = world;
    per_rod(rods, parallel, &mut ws.energy_before, |r| r.kinetic_energy());
    ws.energy_before.iter().sum()
}

/// `f` of each rod in world order into `out` (on rayon's pool when
/// `parallel`; the values are the same either way).
fn per_rod(rods: &crate::handles::Arena<crate::rod::Rod>, parallel: bool, out: &mut Vec<f64>, f: impl Fn(&crate::rod::Rod) -> f64 + Sync + Send) {
    if parallel {
        rods.par_map_into(out, f);
    } else {
        out.clear();
        out.extend(rods.iter().map(|(_, r)| f(r)));
    }
}

/// Σ |Λ E| over the multiplier rows of the last solve: what the
/// constraints may have put in.
pub(crate) fn constraint_work(world: &World) -> f64 {
    let ws = &world.ws;
    let mut total = 0.0;
    for (c, &r0) in ws.layout.row_index.iter().enumerate() {
        for i in r0..r0 + ws.layout.row_count[c] {
            total += (ws.sys.sol[i] * ws.sys.rhs[i]).abs();
        }
    }
    total
}

/// The second half of [`commit`]: every Poisson update possible and the
/// divergence guard satisfied, or everything since [`begin`] undone.
pub(crate) fn finish(world: &mut World, budget: Option<f64>) -> Result<()> {
    let refused = world.rods.iter().find_map(|(h, r)| {
        r.check_poisson().err().or_else(|| {
            r.transport_obstacle().map(|why| Error::NonFinite {
                rod: Some(h.into()),
                detail: format!("{why} in one step: the reference directors cannot follow (reduce dt, or World(adaptive_dt=True)); the world is unchanged"),
            })
        })
    });
    let mut growth = world.growth;
    if refused.is_none() && budget.is_some() {
        let parallel = super::uses_pool(world);
        let World { rods, ws, .. } = world;
        per_rod(rods, parallel, &mut ws.energy_after, |r| r.elastic_energy() + r.kinetic_energy());
    }
    let refused = refused.or_else(|| budget.and_then(|b| divergence(world, b, &mut growth)));
    if let Some(e) = refused {
        undo(world);
        return Err(e);
    }
    world.growth = growth;
    Ok(())
}

/// Stores each rod's kinetic energy now and returns what the step may
/// bring in on top of the elastic energy: the kinetic energy plus the work
/// of the external forces and the constraints, Σ ½VᵀMV + Σ |F·ΔX| + Σ |Λ E|.
/// (The per-rod figure, for naming the rod, leaves the elastic part out:
/// the assembly gave it only in total.)
fn energy_in(world: &mut World, scale: f64) -> f64 {
    let parallel = super::uses_pool(world);
    let World { rods, ws, .. } = world;
    per_rod(rods, parallel, &mut ws.energy_before, |r| r.kinetic_energy());
    let mut total = 0.0;
    for (r, (_, rod)) in rods.iter().enumerate() {
        let k = ws.energy_before[r];
        total += k;
        let d = rod.dofs();
        if let Some(f) = ws.ext.get(r) {
            for i in 0..rod.n_ctrl() {
                for a in 0..d {
                    total += (f[i * d + a] * scale * ws.sys.sol[ws.layout.cp_index[r][i] + a]).abs();
                }
            }
        }
    }
    total + constraint_work(world)
}

/// The guard's verdict after `apply`. Implicit Euler never creates energy:
/// the elastic + kinetic energy after a step stays below the energy before
/// it plus the work done during it, but for round-off and the transient
/// error of a linearised step (a pendulum released with dt of seconds
/// overshoots once, then settles). A step that creates energy extends the
/// current run of such steps; when a run of two or more brings the
/// accumulated growth beyond `divergence_factor` the step is refused as
/// Diverged, naming the rod whose energy grew the most. (Both energy parts
/// are needed: a Frenet frame flip raises the elastic energy with little
/// motion.)
fn divergence(world: &World, budget: f64, growth: &mut crate::world::Growth) -> Option<Error> {
    let factor = world.params.divergence_factor;
    let (mut after, mut floor) = (0.0, 0.0);
    let mut worst: Option<(crate::handles::RodHandle, f64)> = None;
    for (((h, rod), k0), &e1) in world.rods.iter().zip(&world.ws.energy_before).zip(&world.ws.energy_after) {
        // Energy of a 1e-6 strain: below it, nothing counts as growth.
        let f = 1e-12 * rod.cache().ea_ref() * rod.rest_length();
        after += e1;
        floor += f;
        let ratio = e1 / (k0 + f);
        if worst.is_none_or(|(_, r)| ratio > r) {
            worst = Some((h.into(), ratio));
        }
    }
    // A world with nothing in it has nothing to grow (0/0).
    let ratio = if after == 0.0 && budget + floor == 0.0 { 1.0 } else { after / (budget + floor) };
    // The growth is a leaky product: a dissipating step takes back what it
    // dissipates, never below 1, and the run ends only when the factor is
    // back to 1 — so a blow-up that alternates growth and partial
    // dissipation still adds up. One overshoot (a run of one step) may pass
    // up to factor², a longer run up to factor.
    if ratio.is_finite() && ratio <= 1.0 + 1e-9 {
        let f = (growth.factor * ratio).max(1.0);
        *growth = crate::world::Growth { steps: if f > 1.0 { growth.steps } else { 0 }, factor: f };
        return None;
    }
    let run = crate::world::Growth { steps: growth.steps + 1, factor: growth.factor.max(1.0) * ratio };
    let limit = if run.steps < 2 { factor * factor } else { factor };
    if ratio.is_finite() && run.factor <= limit {
        *growth = run;
        return None;
    }
    Some(Error::Diverged {
        step: world.steps + 1,
        rod: worst.map(|w| w.0),
        factor: run.factor,
        detail: format!(
            "{} steps have created energy (with partial dissipation between), {:.3e} times what the loads and constraints put in (divergence_factor = {factor}); this one would bring the elastic + kinetic energy to {after:.3e}; the world is unchanged (reduce dt, or World(adaptive_dt=True))",
            run.steps, run.factor
        ),
    })
}

/// The state `apply` would produce is finite (coordinates, velocities,
/// multipliers, slider increments).
pub(crate) fn check_finite(world: &World, scale: f64, set_velocity: Option<f64>) -> Result<()> {
    let ws = &world.ws;
    for (r, (h, rod)) in world.rods.iter().enumerate() {
        let d = rod.dofs();
        let q = rod.coords();
        for i in 0..q.len() / d {
            for a in 0..d {
                let dx = scale * ws.sys.sol[ws.layout.cp_index[r][i] + a];
                let v = set_velocity.map_or(0.0, |inv_h| dx * inv_h);
                if !(q[i * d + a] + dx).is_finite() || !v.is_finite() {
                    return Err(Error::NonFinite {
                        rod: Some(h.into()),
                        detail: format!(
                            "the step would move control point {i} (coordinate {a}) by {dx:e} to a non-finite state; the world is unchanged (reduce dt or the loads)"
                        ),
                    });
                }
            }
        }
    }
    if let Some(x) = ws.sys.sol.iter().find(|x| !x.is_finite()) {
        return Err(Error::NonFinite { rod: None, detail: format!("the solution holds {x}; the world is unchanged") });
    }
    Ok(())
}

/// The reach guard (`IntegrationParameters::max_move`): Diverged, before
/// anything is applied, when the solution would move a control point
/// (its position, not its roll) farther than `max_move`.
pub(crate) fn check_reach(world: &World, scale: f64) -> Result<()> {
    let Some(limit) = world.params.max_move else { return Ok(()) };
    let ws = &world.ws;
    // The farthest move over every rod, so that the refusal's factor is
    // the step's reach (callers size a retry from it), not the first
    // control point past the limit.
    let mut far = None;
    for (r, (h, rod)) in world.rods.iter().enumerate() {
        for i in 0..rod.n_ctrl() {
            let k = ws.layout.cp_index[r][i];
            let d = scale * (ws.sys.sol[k].powi(2) + ws.sys.sol[k + 1].powi(2) + ws.sys.sol[k + 2].powi(2)).sqrt();
            if d > limit && far.is_none_or(|(_, _, m): (_, usize, f64)| d > m) {
                far = Some((h, i, d));
            }
        }
    }
    match far {
        None => Ok(()),
        Some((h, i, d)) => Err(Error::Diverged {
            step: world.steps + 1,
            rod: Some(h.into()),
            factor: d / limit,
            detail: format!(
                "the step would move control point {i} by {d:.3e} (its farthest move), more than max_move = {limit:.3e}; the world is unchanged (reduce dt, or World(adaptive_dt=True))"
            ),
        }),
    }
}

/// Saves what [`apply`] overwrites.
fn save_undo(world: &mut World) {
    let World { rods, constraints, ws, .. } = world;
    let u = &mut ws.undo;
    u.clear();
    for (_, rod) in rods.iter() {
        u.extend_from_slice(rod.coords());
        u.extend_from_slice(rod.velocities());
    }
    for (_, c) in constraints.iter() {
        u.extend_from_slice(&c.multipliers);
        c.kind.visit_abscissae(&mut |_, x| u.push(x));
    }
}

/// Puts back what [`save_undo`] saved (same rods and constraints).
pub(crate) fn undo(world: &mut World) {
    let World { rods, constraints, ws, .. } = world;
    let mut it = ws.undo.iter().copied();
    for (_, rod) in rods.iter_mut() {
        let (q, v) = rod.state_mut();
        q.iter_mut().chain(v.iter_mut()).zip(&mut it).for_each(|(x, y)| *x = y);
    }
    for (_, c) in constraints.iter_mut() {
        c.multipliers.iter_mut().zip(&mut it).for_each(|(x, y)| *x = y);
        c.kind.visit_abscissae_mut(&mut |_, x| {
            if let Some(y) = it.next() {
                *x = y;
            }
        });
    }
    ws.left.clear();
}

/// Applies the solution: q += scale ΔX (and V = ΔX / h when given), stores
/// the multipliers Λ = −y, moves the sliders. Returns max |ΔX| over
/// positions and over roll.
pub(crate) fn apply(world: &mut World, scale: f64, set_velocity: Option<f64>) -> (f64, f64) {
    let World { rods, constraints, contacts, ws, .. } = world;
    let (mut dx_max, mut dth_max) = (0.0f64, 0.0f64);
    for (r, (_, rod)) in rods.iter_mut().enumerate() {
        let d = rod.dofs();
        let (q, v) = rod.state_mut();
        for i in 0..q.len() / d {
            for a in 0..d {
                let dx = scale * ws.sys.sol[ws.layout.cp_index[r][i] + a];
                q[i * d + a] += dx;
                if let Some(inv_h) = set_velocity {
                    v[i * d + a] = dx * inv_h;
                }
                if a < 3 {
                    dx_max = dx_max.max(dx.abs());
                } else {
                    dth_max = dth_max.max(dx.abs());
                }
            }
        }
    }
    for (c, (h, con)) in constraints.iter_mut().enumerate() {
        let r0 = ws.layout.row_index[c];
        // An elastic constraint's unknown is c_k × its multiplier (`ConstraintRef::elastic`).
        let share = if con.is_elastic() && ws.sys.elastic_share > 0.0 { ws.sys.elastic_share } else { 1.0 };
        for (i, m) in con.multipliers.iter_mut().enumerate() {
            *m = -ws.sys.sol[r0 + i] / share;
        }
        let ne = con.kind.n_extra();
        if ne > 0 {
            let mut du = [0.0; 2];
            for (k, x) in du.iter_mut().enumerate().take(ne) {
                *x = scale * ws.sys.sol[ws.layout.extra_index[c] + k];
            }
            let (Some(a), Some(b)) = (rods.get(con.rod.into()), rods.get(con.other.unwrap_or(con.rod).into())) else {
                continue;
            };
            if !con.kind.advance(&[a, b], &du[..ne]) {
                ws.left.push(h);
            }
        }
    }
    let nc = ws.con_ids.len();
    for p in contacts.pairs.iter_mut() {
        p.force = 0.0;
    }
    for (k, &i) in ws.contact_ids.iter().enumerate() {
        let (p, f) = (&mut contacts.pairs[i], -ws.sys.sol[ws.layout.row_index[nc + k]]);
        // A penalty row never pulls (see `update_active_set_with`).
        p.force = if p.is_penalty() { f.max(0.0) } else { f };
    }
    // Sticking pairs: their rows' multipliers are the friction force;
    // slipping ones: μ N along −μ N ŝ plus their row's reaction across ŝ.
    let np = ws.contact_ids.len();
    for (k, &i) in ws.stick_ids.iter().enumerate() {
        let p = &mut contacts.pairs[i];
        let r0 = ws.layout.row_index[nc + np + k];
        if let (Some(f), Some(a), Some(b)) = (&mut p.friction, rods.get(p.rods[0].into()), rods.get(p.rods[1].into())) {
            if let Some(Ok(force)) = f.rows.as_ref().map(|kind| friction_reaction(&ws.sys.sol, r0, kind, [a, b])) {
                f.force = match f.slip {
                    None => force.into(),
                    // The applied slip force turned by its row's reaction
                    // (the linearisation's correction of ŝ), on the cone.
                    Some(_) => {
                        let total = nalgebra::Vector3::from(f.slip_applied) + force;
                        let limit = f.mu * f.normal;
                        (if total.norm() > 0.0 { total * (limit / total.norm()) } else { total }).into()
                    }
                };
            }
        }
    }
    super::beads::record_increments(world, scale);
    (dx_max, dth_max)
}

/// Rate of change of the potential along the last solution, −(F + P)·ΔX
/// over the coordinates and abscissae (the static right-hand side is the
/// generalised force; multiplier rows left out): negative for a descent
/// direction.
pub(crate) fn directional_derivative(world: &World) -> f64 {
    let sys = &world.ws.sys;
    let rows = sys.multiplier_rows();
    (0..rows.len()).filter(|&i| !rows[i]).map(|i| -sys.rhs[i] * sys.sol[i]).sum()
}

/// Largest constraint residual |E − CΛ| of the assembled system (a
/// compliant row is at rest when its violation equals C Λ).
pub(crate) fn violation(world: &World) -> f64 {
    let mut v = 0.0f64;
    for (c, (_, con)) in world.constraints.iter().enumerate() {
        for i in 0..con.kind.n_rows() {
            let e = world.ws.sys.rhs[world.ws.layout.row_index[c] + i];
            v = v.max((e - con.compliance * con.multipliers[i]).abs());
        }
    }
    // Active contacts' normal rows are met as equalities too (a
    // penetration the step must undo is a violation like any other).
    let nc = world.ws.con_ids.len();
    for k in 0..world.ws.contact_ids.len() {
        v = v.max(world.ws.sys.rhs[world.ws.layout.row_index[nc + k]].abs());
    }
    v
}

/// Largest constraint violation |target − g(q)| at the current coordinates.
pub(crate) fn constraint_violation(world: &World) -> Result<f64> {
    let mut rows = [Row::default(); MAX_ROWS];
    let mut v = 0.0f64;
    for (_, c) in world.constraints.iter() {
        let nr = c.kind.n_rows();
        let pair = world.rods_of(c)?;
        let mut kind = c.kind.clone();
        kind.project(&pair)?; // contacts: at the current closest points
        kind.linearize(&pair, &mut rows[..nr])?;
        v = rows[..nr].iter().zip(&c.multipliers).fold(v, |m, (r, l)| m.max((r.rhs - c.compliance * l).abs()));
    }
    Ok(v)
}

/// Total potential energy: elastic energy plus the potentials of gravity,
/// the loads and the beads' loads on their rods (−F_b · r(u_b)).
pub(crate) fn potential(world: &World) -> Result<f64> {
    use crate::force::ForceField;
    let t = world.time;
    let gravity = crate::force::gravity::Gravity(world.params.gravity);
    let mut p = 0.0;
    for (_, rod) in world.rods.iter() {
        p += rod.elastic_energy() + gravity.potential(rod, t)?;
    }
    for (_, l) in world.loads.iter() {
        p += l.potential(world.rod(l.rod())?, t)?;
    }
    for (_, b) in world.beads.iter() {
        p -= nalgebra::Vector3::from(b.rod_force).dot(&world.rod(b.rod)?.position(b.u)?);
    }
    Ok(p)
}
