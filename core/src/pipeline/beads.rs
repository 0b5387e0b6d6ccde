//! Bead updates around the rod solve (see [`crate::bead`]).
//!
//! Dynamics: a sliding bead's abscissa u is an unknown of the step beside
//! its rod's coordinates q. Its position x = r(q, u) = Σ_k N_k(u) P_k moves
//! by J [Δq; Δu] with J = [N_k I₃ …, r′], so its linearised implicit Euler
//! step m (J Δ − h v_b)/h² = F + (the string's reaction and the
//! neighbours' pushes), written in (q, u), has m JᵀJ/h² on the left and
//! Jᵀ (F + m v_b/h) on the right. The Hessian of −F·r adds −F·r″ on (u, u)
//! and −F N′_k on (q_k, u), as in statics; the derivative of J in the
//! inertia term, −(m v_b/h)·∂J, is left out (it is indefinite: with it two
//! beads swinging on the thesis' string gained 8e-6 J in a step). Viscous
//! friction c on the sliding speed |r′| u̇ acts on u alone (the bead's and
//! the string's shares cancel on q): c |r′|²/h on (u, u). The bead's new
//! velocity is J Δ/h, the step's own (the displacement r(q + Δq, u + Δu)
//! − r(q, u) over h, which adds the rod's motion times the slide and the
//! bend's chord, made the swinging necklace gain up to 2e-4 J above an
//! earlier low).
//! Neighbours on one rod are spheres that touch when their centres are
//! r_a + r_b apart: a unilateral row on the chord |x_b − x_a| − r_a − r_b ≥
//! 0, linear in both beads' q and u, whose multiplier pushes them apart
//! along the line of centres (the string bears the part across it, in the
//! same solve). The rows enter and leave with the contacts' active-set
//! rounds ([`update_gaps`]); like a contact row, one holds a penetration of
//! up to [`crate::pipeline::assemble::CONTACT_SLACK`] of the radii instead
//! of pushing it out. Each abscissa is eliminated from the system before
//! the factorisation ([`assemble`]) and Δu solved back from the solution.
use crate::error::{Error, Result};
use crate::handles::{Index, RodHandle};
use crate::system::layout::{ConstraintSlot, NO_LINK};
use crate::system::{Coefficients, KktSystem, Layout};
use crate::world::{Event, World};
use nalgebra::Vector3;

/// Weight plus user force of a bead.
pub(crate) fn bead_load(world: &World, b: &crate::bead::Bead) -> Vector3<f64> {
    Vector3::from(world.params.gravity) * b.mass + Vector3::from(b.force)
}

/// One bead at the start of the step (per-step scratch).
#[derive(Clone, Copy, Debug)]
struct Row {
    id: Index,
    rod: RodHandle,
    /// Its rod's position in the layout (set when the slots are placed).
    rod_pos: usize,
    u: f64,
    n_ctrl: usize,
    fixed: bool,
    mass: f64,
    friction: f64,
    radius: f64,
    ctrl: [usize; 4],
    basis: [[f64; 4]; 4],
    /// Position (length), r′ and r″ at u (length per unit u, and per unit u²).
    x: Vector3<f64>,
    d1: Vector3<f64>,
    d2: Vector3<f64>,
    /// The bead's own velocity (length/time).
    v: Vector3<f64>,
    /// The load F (weight and user force) and F + m v_b/h, the step's
    /// drive (force unit; the load alone for a fixed bead and in Brownian
    /// dynamics).
    load: Vector3<f64>,
    drive: Vector3<f64>,
    /// Its force on the rod besides the point mass's (force unit).
    rod_force: Vector3<f64>,
    /// The abscissa's equation, a Δu + c·Δq + Σ e y = b (the assembly's;
    /// eliminated from the system, solved from it afterwards): diagonal,
    /// coupling to its control points' 12 coordinates, to the rows of its
    /// active gaps (their slots, `NO_LINK` for none; with ±ĉ, the row's
    /// own entries on its coordinates being ±ĉ N_k), right-hand side.
    a: f64,
    c: [f64; 12],
    e: [(usize, f64, Vector3<f64>); 2],
    bu: f64,
}

impl Row {
    /// Unit tangent.
    fn t(&self) -> Vector3<f64> {
        self.d1 / self.d1.norm()
    }
    /// J [Δq; Δu] from a solution and its Δu ([`Self::du`]): the bead's
    /// linearised displacement.
    fn displacement(&self, layout: &Layout, sol: &[f64], du: f64) -> Vector3<f64> {
        let mut d = Vector3::zeros();
        for (k, &c) in self.ctrl.iter().enumerate() {
            let g = layout.cp_index[self.rod_pos][c];
            d += Vector3::new(sol[g], sol[g + 1], sol[g + 2]) * self.basis[0][k];
        }
        d + self.d1 * du
    }
    /// Δu from a solution of the system it was eliminated from (0 for a
    /// fixed bead).
    fn du(&self, layout: &Layout, sol: &[f64]) -> f64 {
        if self.fixed {
            return 0.0;
        }
        let mut r = self.bu;
        for (k, &c) in self.ctrl.iter().enumerate() {
            let g = layout.cp_index[self.rod_pos][c];
            r -= (0..3).map(|a| self.c[3 * k + a] * sol[g + a]).sum::<f64>();
        }
        for &(slot, e, _) in self.e.iter().filter(|x| x.0 != NO_LINK) {
            r -= e * sol[layout.row_index[slot]];
        }
        r / self.a
    }
}

/// Two neighbours on a rod (positions in the scratch's rows, `b` after `a`
/// along u) and their gap beyond r_a + r_b (length unit).
#[derive(Clone, Copy, Debug)]
struct Pair {
    a: usize,
    b: usize,
    /// The period added to `b`'s abscissa (across a closed rod's seam).
    period: f64,
    gap: f64,
    /// The penetration a row may hold (length unit).
    slack: f64,
    /// Unit line of centres, a → b; None where the chord does not run
    /// along the string between them (beads far apart along a string that
    /// comes back on itself): the gap is then the arc's, ∂/∂u = ±|r′|.
    dir: Option<Vector3<f64>>,
    /// Its slot (set when the slots are placed).
    slot: usize,
    /// Its row is in the system; it pulled and left for this step.
    active: bool,
    pulled: bool,
}

impl Pair {
    /// The gap the pair's row keeps at the end of the step: closed, or a
    /// penetration held (at most `slack`): −clamp(−g, 0, slack).
    fn target(&self) -> f64 {
        -(-self.gap).clamp(0.0, self.slack)
    }
    /// The gap's increment for the beads' displacements (linearised).
    fn change(&self, a: &Row, b: &Row, da: Vector3<f64>, db: Vector3<f64>, dua: f64, dub: f64) -> f64 {
        match self.dir {
            Some(c) => c.dot(&(db - da)),
            None => dub * b.d1.norm() - dua * a.d1.norm(),
        }
    }
}

/// Buffers of the bead passes, kept in the workspace so that a step
/// allocates nothing once warmed up.
#[derive(Debug, Default)]
pub(crate) struct Scratch {
    rows: Vec<Row>,
    /// Each row's linearised displacement J [Δq; Δu] over the step.
    disp: Vec<Vector3<f64>>,
    order: Vec<usize>,
    pairs: Vec<Pair>,
    /// The rows describe this step (from [`prepare`] to [`advance`]).
    valid: bool,
}

/// The basis of bead `k` (arena order) at `u` on `rod`: the one this
/// step's [`prepare`] evaluated, if it is still that bead at that abscissa
/// on a rod of as many control points; else evaluated.
pub(crate) fn bead_basis(s: &Scratch, k: usize, id: Index, u: f64, rod: &crate::rod::Rod) -> Result<([usize; 4], [[f64; 4]; 4])> {
    match s.rows.get(k).filter(|r| s.valid && r.id == id && r.u.to_bits() == u.to_bits() && r.n_ctrl == rod.n_ctrl()) {
        Some(r) => Ok((r.ctrl, r.basis)),
        None => rod.basis_at(u),
    }
}

/// Bead `id`'s force on its rod (force unit) for this assembly: the
/// step's, from its row, while the dynamic step's rows are valid (the
/// world's copy is written only once the step has succeeded); else the
/// world's `fallback`.
pub(crate) fn bead_rod_force(s: &Scratch, k: usize, id: Index, fallback: [f64; 3]) -> [f64; 3] {
    s.rows.get(k).filter(|r| s.valid && r.id == id).map_or(fallback, |r| r.rod_force.into())
}

/// Dynamics, before the rod solve: each bead's state at the start of the
/// step, its force on the rod (the load, and the momentum it brings,
/// m (v_b − v_rod)/h, beside the c_v m v_rod the rod's point mass adds),
/// its neighbours and the gap rows that start the active set (pairs that
/// pressed at the end of the last step, or that their velocities close
/// within the step).
pub(crate) fn prepare(world: &mut World, h: f64) -> Result<()> {
    // The scratch leaves the world for the pass (the world is borrowed).
    let mut s = std::mem::take(&mut world.ws.beads);
    s.valid = false;
    let out = prepare_with(world, h, &mut s);
    s.valid = out.is_ok();
    world.ws.beads = s;
    out
}

fn prepare_with(world: &mut World, h: f64, s: &mut Scratch) -> Result<()> {
    // Brownian dynamics refuses sliding beads (`pipeline/thermal.rs`): a
    // sliding bead always has its momentum.
    let momentum = 1.0 / h;
    s.rows.clear();
    for (id, b) in world.beads.iter() {
        let rod = world.rod(b.rod)?;
        let (ctrl, basis) = rod.basis_at(b.u)?;
        let (x, d1, v_rod) = rod.motion_from(&ctrl, &basis);
        let d2 = second_derivative(rod, &ctrl, &basis);
        if !(d1.norm() > 0.0) {
            return Err(Error::singular(format!("zero tangent under bead {} at u = {}", id.0, b.u)));
        }
        let f = bead_load(world, b);
        let v = b.velocity_from(v_rod, d1 / d1.norm());
        let (drive, rod_force) = if b.fixed { (f, f) } else { (f + v * (momentum * b.mass), f + (v - v_rod) * (momentum * b.mass)) };
        if !rod_force.iter().chain(drive.iter()).all(|x| x.is_finite()) {
            return Err(Error::NonFinite { rod: Some(b.rod), detail: format!("bead {}: its force on the rod is not finite (mass {:e}); the world is unchanged", id.0, b.mass) });
        }
        #[rustfmt::skip]
        s.rows.push(Row { id, rod: b.rod, rod_pos: 0, u: b.u, n_ctrl: rod.n_ctrl(), fixed: b.fixed, mass: b.mass, friction: b.friction, radius: b.radius, ctrl, basis, x, d1, d2, v, load: f, drive, rod_force, a: 0.0, c: [0.0; 12], e: [(NO_LINK, 0.0, Vector3::zeros()); 2], bu: 0.0 });
    }
    neighbours(world, s)?;
    for i in 0..s.pairs.len() {
        let Pair { a, b, .. } = s.pairs[i];
        let (ra, rb) = (&s.rows[a], &s.rows[b]);
        let (gap, dir) = gap(world.rod(ra.rod)?, ra, rb, s.pairs[i].period)?;
        let p = &mut s.pairs[i];
        p.gap = gap;
        p.dir = dir;
        p.slack = crate::pipeline::assemble::CONTACT_SLACK * 0.5 * (ra.radius + rb.radius);
        // Closing speed at the start of the step.
        let closing = match dir {
            Some(c) => c.dot(&(rb.v - ra.v)),
            None => rb.t().dot(&rb.v) - ra.t().dot(&ra.v),
        };
        let pressed = world.beads.get(ra.id).is_some_and(|x| x.pressed);
        p.active = pressed || p.gap + h * closing < p.target();
        p.pulled = false;
    }
    // The world's beads are not written here: a step refused later leaves
    // them as they were (their force on the rod is read from the rows).
    Ok(())
}

/// r″ at a bead: Σ N″_k P_k (length per unit u²).
fn second_derivative(rod: &crate::rod::Rod, ctrl: &[usize; 4], basis: &[[f64; 4]; 4]) -> Vector3<f64> {
    let (q, d) = (rod.coords(), rod.dofs());
    ctrl.iter().zip(&basis[2]).fold(Vector3::zeros(), |acc, (&i, &w)| acc + Vector3::new(q[i * d], q[i * d + 1], q[i * d + 2]) * w)
}

/// The slots of the step's bead rows (after `slots`' constraints, contacts
/// and friction rows): one per neighbour pair, with a row while the pair
/// is active, linked to the active gaps beside it that share a sliding
/// bead. `rod_pos` gives a rod's position in the layout.
pub(crate) fn place(s: &mut Scratch, slots: &mut Vec<ConstraintSlot>, rod_pos: impl Fn(RodHandle) -> Result<usize>) -> Result<()> {
    use crate::constraint::MAX_TOUCHED;
    if !s.valid {
        return Ok(());
    }
    for r in s.rows.iter_mut() {
        r.rod_pos = rod_pos(r.rod)?;
    }
    let touched_of = |ctrl: &[usize; 4], touched: &mut [(u8, usize); MAX_TOUCHED], from: usize| {
        for (t, &c) in touched[from..from + 4].iter_mut().zip(ctrl) {
            *t = (0, c);
        }
    };
    // One slot per pair, along each rod, with a row while the pair is
    // active: the slots' count stays put as pairs come and go (the
    // layout's buffers with it). A row also acts on the rows of the
    // active gaps beside it that share a sliding bead (its abscissa,
    // eliminated, couples them).
    for p in s.pairs.iter_mut() {
        p.slot = slots.len();
        slots.push(ConstraintSlot { rods: [s.rows[p.a].rod_pos; 2], n_rows: 0, n_extra: 0, touched: [(0, 0); MAX_TOUCHED], held: [true; MAX_TOUCHED], len: 0, links: [NO_LINK; 2] });
    }
    // Each sliding bead's active gaps (their values come with the assembly).
    for r in s.rows.iter_mut() {
        r.e = [(NO_LINK, 0.0, Vector3::zeros()); 2];
    }
    for p in s.pairs.iter().filter(|p| p.active) {
        for bead in [p.a, p.b] {
            let r = &mut s.rows[bead];
            if !r.fixed {
                let free = if r.e[0].0 == NO_LINK { 0 } else { 1 };
                r.e[free].0 = p.slot;
            }
        }
    }
    for p in s.pairs.iter().filter(|p| p.active) {
        let (a, b) = (&s.rows[p.a], &s.rows[p.b]);
        // The bead's other active gap, if it slides.
        let beside = |r: &Row| r.e.iter().map(|x| x.0).find(|&q| q != NO_LINK && q != p.slot).unwrap_or(NO_LINK);
        let links = [beside(a), beside(b)];
        let slot = &mut slots[p.slot];
        touched_of(&a.ctrl, &mut slot.touched, 0);
        touched_of(&b.ctrl, &mut slot.touched, 4);
        (slot.n_rows, slot.len, slot.links) = (1, 8, links);
    }
    Ok(())
}

/// Adds the beads' blocks to the assembled system `sys` (see the module's
/// comment): each active gap's row, then each sliding bead's abscissa
/// equation a Δu + c·Δq + Σ e y = b eliminated (a Schur complement: −c cᵀ/a
/// on its control points, −c e/a and −e e/a on its gaps' rows, −c b/a and
/// −e b/a on their right-hand sides). Kept in the system, a train of beads
/// pressed together put its abscissae beside its rows on the same few
/// control points and widened the band by as many (34 against 16 for the
/// thesis' necklace). An abscissa whose diagonal is not positive has no
/// motion of its own to solve: with mass or friction the step is too long
/// for the bend (`Diverged`, which `adaptive_dt` retries in sub-steps);
/// without either, a load that pulls it off a bend (`Singular`).
pub(crate) fn assemble(sys: &mut KktSystem, layout: &Layout, s: &mut Scratch, k: Coefficients, step: u64) -> Result<()> {
    if !s.valid {
        return Ok(());
    }
    for p in s.pairs.iter().filter(|p| p.active) {
        let ri = layout.row_index[p.slot];
        // ∂gap/∂(q, u): ∓ĉ N_k on each bead's points (a sliding bead's go
        // with its block below), ∓ĉ·r′ on its abscissa.
        for (bead, sign) in [(p.a, -1.0), (p.b, 1.0)] {
            let r = &mut s.rows[bead];
            if let (Some(c), true) = (p.dir, r.fixed) {
                for (kk, &cp) in r.ctrl.iter().enumerate() {
                    for a in 0..3 {
                        let gj = layout.cp_index[r.rod_pos][cp] + a;
                        let v = sign * c[a] * r.basis[0][kk];
                        sys.matrix.add(ri, gj, v);
                        sys.matrix.add(gj, ri, v);
                    }
                }
            }
            if !r.fixed {
                let v = sign * p.dir.map_or(r.d1.norm(), |c| c.dot(&r.d1));
                // Its entry for this gap, placed by `place`.
                if let Some(x) = r.e.iter_mut().find(|x| x.0 == p.slot) {
                    (x.1, x.2) = (v, p.dir.map_or(Vector3::zeros(), |c| c * sign));
                }
            }
        }
        sys.rhs[ri] = p.target() - p.gap;
    }
    // The eliminated abscissae: one symmetric block each over its 12
    // coordinates and its (at most two) rows.
    let mut idx = [0usize; 14];
    let mut blk = [0.0f64; 14 * 14];
    for r in s.rows.iter_mut() {
        if r.fixed {
            continue;
        }
        // Inertia m |r′|²/h² and drag c |r′|²/h along the rod, less the
        // load's pull off the bend, F·r″.
        let hold = (k.mass * r.mass + k.drag * r.friction) * r.d1.norm_squared();
        r.a = hold - r.load.dot(&r.d2);
        if !(r.a > 0.0) {
            // With mass or friction the step is too long for the bend; a
            // shorter step restores the diagonal (and `adaptive_dt` retries
            // a diverged step in sub-steps).
            if hold > 0.0 {
                return Err(Error::Diverged {
                    step,
                    rod: Some(r.rod),
                    factor: r.load.dot(&r.d2) / hold,
                    detail: format!(
                        "bead {} at u = {}: the time step is too long for its load on the bend of its rod (the load's pull off the bend, F·r″ = {:.3e}, exceeds its inertia and drag along the rod, {hold:.3e}); the world is unchanged (reduce dt, or World(adaptive_dt=True))",
                        r.id.0,
                        r.u,
                        r.load.dot(&r.d2)
                    ),
                });
            }
            return Err(Error::singular(format!(
                "bead {} at u = {}: its motion along the rod has no mass, no friction and a load that pulls it off the bend (diagonal {:e}); give it mass or friction",
                r.id.0, r.u, r.a
            )));
        }
        r.bu = k.force * r.drive.dot(&r.d1);
        if !(r.a.is_finite() && r.bu.is_finite()) {
            return Err(Error::NonFinite { rod: Some(r.rod), detail: format!("bead {} (mass {:e}): its equation along the rod is not finite; the world is unchanged", r.id.0, r.mass) });
        }
        let mut v = [0.0f64; 14];
        let mut m = 0;
        for (kk, &c) in r.ctrl.iter().enumerate() {
            for a in 0..3 {
                r.c[3 * kk + a] = k.mass * r.mass * r.basis[0][kk] * r.d1[a] - r.load[a] * r.basis[1][kk];
                idx[m] = layout.cp_index[r.rod_pos][c] + a;
                v[m] = r.c[3 * kk + a];
                m += 1;
            }
        }
        for &(slot, e, _) in r.e.iter().filter(|x| x.0 != NO_LINK) {
            idx[m] = layout.row_index[slot];
            v[m] = e;
            m += 1;
        }
        // v v/a as v (v/a): the product first overflows for huge masses.
        for i in 0..m {
            sys.rhs[idx[i]] -= v[i] * (r.bu / r.a);
            for j in i..m {
                blk[i * 14 + j] = -v[i] * (v[j] / r.a);
            }
        }
        // Its gap rows' own entries on its coordinates, ±ĉ N_k.
        for (t, &(_, _, c)) in r.e.iter().filter(|x| x.0 != NO_LINK).enumerate() {
            for kk in 0..4 {
                for a in 0..3 {
                    blk[(3 * kk + a) * 14 + 12 + t] += c[a] * r.basis[0][kk];
                }
            }
        }
        sys.matrix.add_sym_block(&idx[..m], &blk, 14);
    }
    Ok(())
}

/// One round of the gaps' active set after a solve: a row whose multiplier
/// pulls leaves, a pair the solution closes past its target enters — again
/// after it left, unless `lock` (the late rounds, as for contacts: rows
/// that pull together all leave, and one of them may still be needed; kept
/// out for the rest of the step, trains of beads pushed by changing forces
/// ended steps overlapping by up to 3e-4 m beyond the slack of 1e-4 m).
/// Returns whether the set changed.
pub(crate) fn update_gaps(world: &mut World, lock: bool) -> bool {
    let ws = &mut world.ws;
    let (s, layout, sol) = (&mut ws.beads, &ws.layout, &ws.sys.sol);
    if !s.valid {
        return false;
    }
    let mut changed = false;
    for p in s.pairs.iter_mut() {
        let (a, b) = (&s.rows[p.a], &s.rows[p.b]);
        if p.active {
            let force = -sol[layout.row_index[p.slot]];
            if force < 0.0 {
                (p.active, p.pulled, changed) = (false, true, true);
            }
        } else if !(lock && p.pulled) {
            let (dua, dub) = (a.du(layout, sol), b.du(layout, sol));
            let (da, db) = (a.displacement(layout, sol, dua), b.displacement(layout, sol, dub));
            let end = p.gap + p.change(a, b, da, db, dua, dub);
            if end < p.target() - 1e-9 * (a.radius + b.radius) {
                (p.active, changed) = (true, true);
            }
        }
    }
    changed
}

/// The gap (length unit) between neighbours `a` and `b` beyond r_a + r_b
/// and their unit line of centres. Beads are spheres threaded on the
/// string: they touch when their centres are r_a + r_b apart, along the
/// chord c = x_b − x_a. That holds while the chord runs along the string
/// between them (ĉ·t, averaged over the pair, above ½ and the arc, from
/// their abscissae and |r′|, under twice the chord); otherwise (beads far
/// apart along a string that comes back on itself) the gap is the arc
/// length less r_a + r_b (3-point Gauss) and the direction None.
fn gap(rod: &crate::rod::Rod, a: &Row, b: &Row, period: f64) -> Result<(f64, Option<Vector3<f64>>)> {
    let need = a.radius + b.radius;
    let d = b.x - a.x;
    let len = d.norm();
    if len > 0.0 {
        let c = d / len;
        let cbar = 0.5 * (c.dot(&a.t()) + c.dot(&b.t()));
        let along = (b.u + period - a.u) * 0.5 * (a.d1.norm() + b.d1.norm());
        if cbar > 0.5 && along < 2.0 * len {
            return Ok((len - need, Some(c)));
        }
    }
    Ok((arc(rod, a.u, b.u + period)? - need, None))
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
    let Scratch { rows, order, pairs, .. } = s;
    order.clear();
    order.extend(0..rows.len());
    order.sort_unstable_by(|&a, &b| rows[a].rod.index.cmp(&rows[b].rod.index).then(rows[a].u.total_cmp(&rows[b].u)).then(a.cmp(&b)));
    pairs.clear();
    let pair = |a: usize, b: usize, period: f64| Pair { a, b, period, gap: 0.0, slack: 0.0, dir: None, slot: 0, active: false, pulled: false };
    let mut k = 0;
    while k < order.len() {
        let mut e = k;
        while e + 1 < order.len() && rows[order[e + 1]].rod.index == rows[order[k]].rod.index {
            pairs.push(pair(order[e], order[e + 1], 0.0));
            e += 1;
        }
        if e > k {
            if let Some(p) = period(world.rod(rows[order[k]].rod)?) {
                pairs.push(pair(order[e], order[k], p));
            }
        }
        k = e + 1;
    }
    // Two knotted beads: nothing moves between them.
    pairs.retain(|p| !(rows[p.a].fixed && rows[p.b].fixed));
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
        b.step_du = 0.0;
        b.velocity = 0.0;
        b.carried = None;
    }
    // A dynamic step's rows (one that failed) do not describe this solve.
    world.ws.beads.valid = false;
}

/// Dynamics, after the rod solve: each sliding bead moves by its solved
/// Δu (round a closed rod it wraps) and takes the velocity J [Δq; Δu]/h
/// (see the module's comment); the pairs that pressed are remembered for
/// the next step's active set; beads that left an open rod are removed
/// (their events go to `events`).
pub(crate) fn advance(world: &mut World, h: f64, events: &mut Vec<Event>) -> Result<()> {
    let mut s = std::mem::take(&mut world.ws.beads);
    let out = advance_with(world, h, events, &mut s);
    s.valid = false;
    world.ws.beads = s;
    out
}

fn advance_with(world: &mut World, h: f64, events: &mut Vec<Event>, s: &mut Scratch) -> Result<()> {
    if !s.valid {
        return Ok(());
    }
    // The step succeeded: its forces on the rods become the world's.
    for r in &s.rows {
        if let Some(b) = world.beads.get_mut(r.id) {
            b.rod_force = r.rod_force.into();
            if b.fixed {
                b.step_du = 0.0;
            }
        }
    }
    for (k, r) in s.rows.iter().enumerate() {
        let Some(b) = world.beads.get(r.id) else { continue };
        if b.fixed {
            continue;
        }
        let rod = world.rod(b.rod)?;
        let period = period(rod);
        let u = period.map_or(b.u + b.step_du, |p| (b.u + b.step_du).rem_euclid(p));
        // Where it is now (an open rod's end for a bead that left it).
        let (lo, hi) = rod.domain();
        let (ctrl, basis) = rod.basis_at(if period.is_some() { u } else { u.clamp(lo, hi) })?;
        let (_, d1, v_rod) = rod.motion_from(&ctrl, &basis);
        let v = s.disp[k] / h;
        let t = if d1.norm() > 0.0 { d1 / d1.norm() } else { r.t() };
        if let Some(b) = world.beads.get_mut(r.id) {
            b.u = u;
            b.velocity = t.dot(&(v - v_rod));
            b.carried = Some(v.into());
        }
    }
    for (_, b) in world.beads.iter_mut() {
        b.pressed = false;
    }
    for p in s.pairs.iter().filter(|p| p.active) {
        if let Some(b) = world.beads.get_mut(s.rows[p.a].id) {
            b.pressed = true;
        }
    }
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

/// Records each sliding bead's abscissa increment Δu (`scale` × the
/// solution's) for [`advance`].
pub(crate) fn record_increments(world: &mut World, scale: f64) {
    let World { beads, ws, .. } = world;
    let s = &mut ws.beads;
    if !s.valid {
        return;
    }
    s.disp.clear();
    for r in &s.rows {
        let du = r.du(&ws.layout, &ws.sys.sol);
        s.disp.push(r.displacement(&ws.layout, &ws.sys.sol, du) * scale);
        if let (false, Some(b)) = (r.fixed, beads.get_mut(r.id)) {
            b.step_du = scale * du;
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipeline::assemble::{assemble, Regime};
    use crate::{IntegrationParameters, Material, RodBuilder, Section};

    /// Two beads pressed together on a helix (a curved string in 3-D), at
    /// rest, one with friction: what the step writes for them against
    /// central differences. With v_b = 0 a bead's part of the step is the
    /// minimum of Φ(q, u) = m |r(q, u) − x₀|²/(2h²) − F·r(q, u) + c |r′₀|²
    /// (u − u₀)²/(2h): its abscissa's equation a Δu + c·Δq + e y = b has
    /// a = ∂²Φ/∂u², c = ∂²Φ/∂u∂q, b = −∂Φ/∂u, e = ∂g/∂u, with g = |r(q, u_b)
    /// − r(q, u_a)| − r_a − r_b the gap. The abscissae eliminated, the gap
    /// row holds ∂g/∂q − Σ e c/a on the coordinates, −Σ e²/a on its
    /// diagonal and the gap to close (0: touching within its slack) less
    /// Σ e b/a on the right. Measured: 1.3e-8 at most (relative); leaving
    /// out −F·r″ fails it (4.9e-2 against 4.6e-2 for a).
    #[test]
    fn bead_blocks_and_gap_rows_match_finite_differences() {
        let rod = RodBuilder::helix(0.1, 0.05, 1.0)
            .control_points(12)
            .with_roll(false)
            .section(Section::circle(0.002).unwrap())
            .material(Material::new("nylon", 3e9, 0.4, 1150.0).unwrap())
            .build()
            .unwrap();
        // A long step, so that the load's curvature terms weigh against the inertia's.
        let h = 0.05;
        let mut w = World::new(IntegrationParameters { dt: h, gravity: [0.0, -9.81, -3.0], ..Default::default() });
        let r = w.add_rod(rod);
        let (u0, u1) = w.rod(r).unwrap().domain();
        let ua = u0 + 0.4 * (u1 - u0);
        // Bead b's centre 2.5 cm further along (the chord): radii summing to that.
        let ub = ua + 0.025 / w.rod(r).unwrap().eval(ua, 1).unwrap()[..3].iter().map(|x| x * x).sum::<f64>().sqrt();
        let chord = (w.rod(r).unwrap().position(ub).unwrap() - w.rod(r).unwrap().position(ua).unwrap()).norm();
        let a = w.add_bead(r, ua, 0.01, 0.3, 0.5 * chord).unwrap();
        let b = w.add_bead(r, ub, 0.02, 0.0, 0.5 * chord + 1e-9).unwrap();
        w.set_bead_force(b, [0.1, 0.2, -0.05]).unwrap();
        w.beads.get_mut(a.into()).unwrap().pressed = true;
        prepare(&mut w, h).unwrap();
        assemble(&mut w, Regime::Dynamic { h }).unwrap();
        let (s, layout, sys) = (&w.ws.beads, &w.ws.layout, &w.ws.sys);
        assert!(s.pairs.len() == 1 && s.pairs[0].active && s.pairs[0].dir.is_some(), "one pressed pair on the chord");
        let base = w.rod(r).unwrap().clone();
        let dofs = base.dofs();
        let x_of = |rod: &crate::rod::Rod, u: f64| rod.position(u).unwrap();
        let d1_of = |rod: &crate::rod::Rod, u: f64| Vector3::from_column_slice(&rod.eval(u, 1).unwrap()[..3]);
        let perturbed = |j: usize, e: f64| {
            let mut rod = base.clone();
            rod.state_mut().0[j] += e;
            rod
        };
        let n_cp = base.n_ctrl();
        let (eu, eq) = (1e-5, 1e-7);
        let mut worst = 0.0f64;
        let mut check = |got: f64, want: f64, what: &str| {
            let err = (got - want).abs() / want.abs().max(1e-3);
            worst = worst.max(err);
            assert!(err < 1e-5, "{what}: assembled {got:.9e}, finite differences {want:.9e}");
        };
        let (ba, bb) = (w.bead(a).unwrap().clone(), w.bead(b).unwrap().clone());
        let gap = |rod: &crate::rod::Rod, ua: f64, ub: f64| (x_of(rod, ub) - x_of(rod, ua)).norm() - ba.radius - bb.radius;
        assert!(gap(&base, ba.u, bb.u).abs() < 1e-8);
        // Per bead, from differences: a, c (all coordinates, zero off its
        // points), b, e.
        let mut fd = Vec::new();
        for (bead, row) in [(&ba, &s.rows[0]), (&bb, &s.rows[1])] {
            let f = bead_load(&w, bead);
            let (x0, d10) = (x_of(&base, bead.u), d1_of(&base, bead.u));
            let grad_u = |rod: &crate::rod::Rod, u: f64| d1_of(rod, u).dot(&((x_of(rod, u) - x0) * (bead.mass / (h * h)) - f)) + bead.friction / h * d10.norm_squared() * (u - bead.u);
            let a_fd = (grad_u(&base, bead.u + eu) - grad_u(&base, bead.u - eu)) / (2.0 * eu);
            let c_fd: Vec<f64> = (0..n_cp * dofs).map(|j| (grad_u(&perturbed(j, eq), bead.u) - grad_u(&perturbed(j, -eq), bead.u)) / (2.0 * eq)).collect();
            let b_fd = -grad_u(&base, bead.u);
            let shift = |d: f64| if std::ptr::eq(bead, &ba) { gap(&base, ba.u + d, bb.u) } else { gap(&base, ba.u, bb.u + d) };
            let e_fd = (shift(eu) - shift(-eu)) / (2.0 * eu);
            check(row.a, a_fd, "a");
            check(row.bu, b_fd, "b");
            check(row.e[0].1, e_fd, "e");
            for (kk, &cp) in row.ctrl.iter().enumerate() {
                for ax in 0..3 {
                    check(row.c[3 * kk + ax], c_fd[cp * dofs + ax], "c");
                }
            }
            fd.push((a_fd, c_fd, b_fd, e_fd));
        }
        let ri = layout.row_index[s.pairs[0].slot];
        check(sys.rhs[ri], -fd.iter().map(|(a, _, b, e)| e * b / a).sum::<f64>(), "gap rhs");
        check(sys.matrix.get(ri, ri), -fd.iter().map(|(a, _, _, e)| e * e / a).sum::<f64>(), "gap row diagonal");
        for cp in 0..n_cp {
            for ax in 0..3 {
                let j = cp * dofs + ax;
                let dg = (gap(&perturbed(j, eq), ba.u, bb.u) - gap(&perturbed(j, -eq), ba.u, bb.u)) / (2.0 * eq);
                let want = dg - fd.iter().map(|(a, c, _, e)| e * c[j] / a).sum::<f64>();
                let gj = layout.cp_index[0][cp] + ax;
                check(sys.matrix.get(ri, gj), want, "gap row on the coordinates");
                check(sys.matrix.get(gj, ri), want, "gap row on the coordinates (transpose)");
            }
        }
        println!("largest relative difference {worst:.2e}");
    }
}
