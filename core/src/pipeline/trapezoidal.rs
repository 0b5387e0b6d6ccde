//! The trapezoidal rule (SPEC §3; Newmark γ = ½, β = ¼): with f = F + P
//! the external and elastic forces and V' = 2ΔX/h − V,
//!   R(ΔX) = 2M (ΔX − hV)/h² + D ΔX/h − ½ (f(t, q) + f(t + h, q + ΔX)) + Lᵀλ = 0,
//! the rigid constraints held at q + ΔX as in implicit Euler (and the end
//! velocity projected onto them, [`project_velocities`]), a compliant one
//! averaged as a part of f (`ConstraintRef::elastic`; held at q + ΔX when
//! `held_at_end`). Newton on R with
//! the same banded system, (2M/h² + D/h + K/2) δ + Lᵀλ = −R, the rods
//! moved to each iterate (so constraints, sliders and contacts linearise
//! there as in statics). The first iteration, from ΔX = 0, is the
//! linearised implicit midpoint rule; alone it injects energy into a fast
//! spinning rod (its stiffness points the old way), so the step iterates
//! until the increment is negligible.
//!
//! On linear problems the rule keeps ½VᵀMV + ½XᵀKX exactly and lengthens
//! each period by a factor ωh / (2 atan(ωh/2)) ≈ 1 + (ωh)²/12.
use super::assemble::Regime;
use super::solve;
use crate::error::{Error, Result};
use crate::system::Solved;
use crate::world::World;

/// Newton iterations of one step at most (a step that needs more, or
/// whose iterations diverge, is refused as NotConverged, the world
/// unchanged; `adaptive_dt` retries it).
const MAX_ITERATIONS: usize = 20;
/// Converged when the last increment is below this fraction of the step's
/// motion (positions and roll separately), or below round-off.
const TOLERANCE: f64 = 1e-4;
/// Round-off floors: positions (× the longest rod), roll (radians).
const FLOOR: f64 = 1e-12;
const ROLL_FLOOR: f64 = 1e-10;
/// An iteration moving the rods this many times farther than the first
/// (the linearised step) is divergence. Under thermal kicks on a rod
/// resolved below its thermal stretch scale (A = 50 nm, S = 1100 pN on
/// 0.16 nm segments, 5 ps) increments went 0.19, 0.45, 0.28, 3.3 nm, …
/// before the clamp's rows degenerated.
const DIVERGED: f64 = 10.0;

/// Per-rod vectors of the step (rod-local coordinates), kept between
/// steps so that a step allocates nothing.
#[derive(Debug, Default)]
pub(crate) struct State {
    /// Velocities at the start of the step.
    v_n: Vec<Vec<f64>>,
    /// f(t, q) = F + P at the start of the step.
    f_n: Vec<Vec<f64>>,
    /// ΔX so far.
    dx: Vec<Vec<f64>>,
    /// What the assembly adds to ½ f(t + h, q + ΔX): ½ f_n − D ΔX / h
    /// (the BDF2 stage: its drag term).
    pub(crate) extra: Vec<Vec<f64>>,
    /// External forces F at the start of the step (the guard's work).
    ext_n: Vec<Vec<f64>>,
}

/// One trapezoidal step of `h`: returns the elastic energy at its start,
/// the last solve and the number of solves. On error the world is as it
/// was before (but for the beads' prediction, as with implicit Euler).
pub(crate) fn step(world: &mut World, h: f64) -> Result<(f64, Solved, usize)> {
    guarded(world, h, |world, solved| {
        let out = iterate(world, h, solved)?;
        finish_velocities(world, h)?;
        Ok(out)
    })
}

/// The frame of a multi-solve step: the first trapezoidal solve of step
/// `h1` (nothing moved if it fails), the per-step state and undo buffer,
/// then `rest` (which applies that solve and whatever follows); undone on
/// error, guarded over the whole step on success. Returns the elastic
/// energy at the start, the last solve and the number of solves.
fn guarded(world: &mut World, h1: f64, rest: impl FnOnce(&mut World, Solved) -> Result<(Solved, usize)>) -> Result<(f64, Solved, usize)> {
    let (energy, solved) = solve::assemble_and_solve(world, Regime::Trapezoidal { h: h1, first: true })?;
    solve::check_finite(world, 1.0, None)?;
    solve::check_reach(world, 1.0)?;
    let kinetic = start(world);
    solve::begin(world, 1.0, None);
    match rest(world, solved) {
        Ok((solved, solves)) => {
            solve::finish(world, budget(world, energy, kinetic))?;
            Ok((energy, solved, solves))
        }
        Err(e) => {
            solve::undo(world);
            Err(e)
        }
    }
}

/// γ of TR-BDF2: the BDF2 stage then uses the same c_m/c_k ratio as the
/// trapezoidal one, ((1 − γ)/(2 − γ) h)² = (γh/2)².
const GAMMA: f64 = 2.0 - std::f64::consts::SQRT_2;

/// One TR-BDF2 step of `h` (SPEC §3; Bank et al. 1985): a trapezoidal
/// stage to t + γh (its Newton iterations run to convergence, as in
/// `step`), then the BDF2 stage through q_n, q_γ, q_{n+1}:
///   q' − a q_γ + b q_n = c h V',   M (V' − a V_γ + b V_n) = c h (f(t + h, q') − Lᵀλ),
/// a = 1/(γ(2 − γ)), b = (1 − γ)²/(γ(2 − γ)), c = (1 − γ)/(2 − γ).
/// With ΔX = q' − q_γ and Δ₁ = q_γ − q_n this is an implicit Euler solve
/// of step h₂ = c h with velocity V* = a V_γ − b V_n + b Δ₁/h₂ (and drag
/// D b Δ₁/h₂ on the right), after which V' = (ΔX − b Δ₁)/h₂. Returns the
/// elastic energy at the start, the last solve and the number of solves.
pub(crate) fn tr_bdf2(world: &mut World, h: f64) -> Result<(f64, Solved, usize)> {
    let h1 = GAMMA * h;
    guarded(world, h1, |world, solved| {
        let (_, solves) = iterate(world, h1, solved)?;
        finish_velocities(world, h1)?;
        let h2 = (1.0 - GAMMA) / (2.0 - GAMMA) * h;
        bdf2_velocity(world, h2);
        let (_, solved) = solve::assemble_and_solve(world, Regime::Bdf2 { h2, h })?;
        solve::check_finite(world, 1.0, Some(1.0 / h2))?;
        solve::check_reach(world, 1.0)?;
        solve::apply(world, 1.0, Some(1.0 / h2));
        bdf2_finish(world, h2);
        accumulate(world);
        Ok((solved, solves + 1))
    })
}

/// Before the BDF2 stage (rods at q_γ with V_γ, Δ₁ in `dx`): V = V*,
/// extra = b D Δ₁ / h₂.
fn bdf2_velocity(world: &mut World, h2: f64) {
    let (a, b) = (1.0 / (GAMMA * (2.0 - GAMMA)), (1.0 - GAMMA).powi(2) / (GAMMA * (2.0 - GAMMA)));
    let World { rods, ws, .. } = world;
    let st = &mut ws.trapezoidal;
    for (r, (_, rod)) in rods.iter_mut().enumerate() {
        rod.drag_times(&ws.drags[r], &st.dx[r], &mut st.extra[r]);
        st.extra[r].iter_mut().for_each(|e| *e *= b / h2);
        let (_, v) = rod.state_mut();
        for ((v, v0), x) in v.iter_mut().zip(&st.v_n[r]).zip(&st.dx[r]) {
            *v = a * *v - b * v0 + b * x / h2;
        }
    }
}

/// After the BDF2 stage's apply (V = ΔX/h₂): V' = (ΔX − b Δ₁)/h₂.
fn bdf2_finish(world: &mut World, h2: f64) {
    let b = (1.0 - GAMMA).powi(2) / (GAMMA * (2.0 - GAMMA));
    let World { rods, ws, .. } = world;
    for (r, (_, rod)) in rods.iter_mut().enumerate() {
        let (_, v) = rod.state_mut();
        for (v, x) in v.iter_mut().zip(&ws.trapezoidal.dx[r]) {
            *v -= b * x / h2;
        }
    }
}

/// The divergence guard's budget of the whole step (SPEC §3 of
/// `solve::commit`): elastic + kinetic energy at the start, the work of the
/// external forces at the start over ΔX, the constraints' of the last solve;
/// None when the guard is off.
fn budget(world: &World, elastic: f64, kinetic: f64) -> Option<f64> {
    if !world.params.divergence_factor.is_finite() {
        return None;
    }
    let st = &world.ws.trapezoidal;
    let work: f64 = st.ext_n.iter().zip(&st.dx).map(|(f, x)| f.iter().zip(x).map(|(f, x)| (f * x).abs()).sum::<f64>()).sum();
    Some(elastic + kinetic + work + solve::constraint_work(world))
}

/// Keeps V_n, F_n and f_n = F + P (the first assembly's), zeroes ΔX;
/// returns the kinetic energy now.
fn start(world: &mut World) -> f64 {
    let kinetic = solve::kinetic_before(world);
    let World { rods, ws, .. } = world;
    let n = rods.len();
    let st = &mut ws.trapezoidal;
    for v in [&mut st.v_n, &mut st.f_n, &mut st.dx, &mut st.extra, &mut st.ext_n] {
        v.resize_with(n, Vec::new);
    }
    for (r, (_, rod)) in rods.iter().enumerate() {
        let m = rod.velocities().len();
        st.v_n[r].clear();
        st.v_n[r].extend_from_slice(rod.velocities());
        st.f_n[r].clear();
        st.f_n[r].extend(ws.ext[r].iter().zip(&ws.sys.elastic_forces[r]).map(|(f, p)| f + p));
        st.ext_n[r].clone_from(&ws.ext[r]);
        st.dx[r].clear();
        st.dx[r].resize(m, 0.0);
        st.extra[r].clear();
        st.extra[r].resize(m, 0.0);
    }
    kinetic
}

/// Applies the solve in the system, then Newton iterations until the
/// increment is negligible. Returns the last solve and the number of solves.
fn iterate(world: &mut World, h: f64, mut solved: Solved) -> Result<(Solved, usize)> {
    let longest = world.rods.iter().fold(0.0f64, |m, (_, r)| m.max(r.rest_length()));
    let mut first = 0.0;
    for solves in 1..=MAX_ITERATIONS {
        solve::check_finite(world, 1.0, None)?;
        solve::check_reach(world, 1.0)?;
        let [step_x, step_th, total_x, total_th] = accumulate(world);
        solve::apply(world, 1.0, None);
        let converged = step_x <= TOLERANCE * total_x + FLOOR * longest && step_th <= TOLERANCE * total_th + ROLL_FLOOR;
        // A slider that left its rod ends the iterations (it is removed after the step).
        if solves > 1 && converged || !world.ws.left.is_empty() {
            return Ok((solved, solves));
        }
        if solves == 1 {
            first = step_x;
        }
        // An iterate far beyond the linearised step's estimate is Newton
        // diverging: refused now, before its iterates reach a shape where
        // the constraints' rows degenerate (that ended as Singular, which
        // `adaptive_dt` does not retry).
        let diverging = solves > 1 && step_x > DIVERGED * first.max(FLOOR * longest);
        if solves == MAX_ITERATIONS || diverging {
            let why = if diverging { "diverge, moving" } else { "still move" };
            return Err(refused(solves, step_x, format!("iterations {why} the rods by {step_x:.3e} (of {total_x:.3e}) after {solves} solves")));
        }
        prepare(world, h);
        solved = match solve::assemble_and_solve(world, Regime::Trapezoidal { h, first: false }) {
            Ok((_, s)) => s,
            // The first solve had these rows regular: singular at an
            // iterate is the iterate's (Newton gone astray), a retry's case.
            Err(Error::Singular { detail, .. }) => return Err(refused(solves, step_x, format!("iterate {solves} made the system singular ({detail})"))),
            Err(e) => return Err(e),
        };
    }
    unreachable!("the loop returns at its last iteration")
}

/// A step refused after `solves` Newton solves: NotConverged, which
/// `adaptive_dt` retries.
fn refused(solves: usize, step_x: f64, what: String) -> Error {
    Error::NotConverged { iterations: solves, residual: step_x, detail: format!("the trapezoidal step's Newton {what}; the world is unchanged (reduce dt, or World(adaptive_dt=True))") }
}

/// Adds the solution in the system to ΔX; returns max |δ| and max |ΔX|
/// over positions, then over roll.
fn accumulate(world: &mut World) -> [f64; 4] {
    let World { rods, ws, .. } = world;
    let mut out = [0.0f64; 4];
    for (r, (_, rod)) in rods.iter().enumerate() {
        let d = rod.dofs();
        let dx = &mut ws.trapezoidal.dx[r];
        for i in 0..rod.n_ctrl() {
            for a in 0..d {
                let s = ws.sys.sol[ws.layout.cp_index[r][i] + a];
                let x = &mut dx[i * d + a];
                *x += s;
                let k = usize::from(a == 3);
                out[k] = out[k].max(s.abs());
                out[2 + k] = out[2 + k].max(x.abs());
            }
        }
    }
    out
}

/// Before an assembly at the iterate: V = V_n − ΔX/h (so that the
/// momentum term 2MV/h carries −2MΔX/h²) and extra = ½ f_n − D ΔX/h.
fn prepare(world: &mut World, h: f64) {
    let World { rods, ws, .. } = world;
    let st = &mut ws.trapezoidal;
    for (r, (_, rod)) in rods.iter_mut().enumerate() {
        rod.drag_times(&ws.drags[r], &st.dx[r], &mut st.extra[r]);
        for (e, f) in st.extra[r].iter_mut().zip(&st.f_n[r]) {
            *e = 0.5 * f - *e / h;
        }
        let (_, v) = rod.state_mut();
        for ((v, v0), x) in v.iter_mut().zip(&st.v_n[r]).zip(&st.dx[r]) {
            *v = v0 - x / h;
        }
    }
}

/// V' = 2ΔX/h − V_n; NonFinite (nothing changed by it) if not finite.
fn finish_velocities(world: &mut World, h: f64) -> Result<()> {
    let World { rods, ws, .. } = world;
    let st = &ws.trapezoidal;
    for (r, (handle, _)) in rods.iter().enumerate() {
        if let Some(i) = st.dx[r].iter().zip(&st.v_n[r]).position(|(x, v0)| !(2.0 * x / h - v0).is_finite()) {
            return Err(Error::NonFinite {
                rod: Some(handle.into()),
                detail: format!("the step would give coordinate {i} a non-finite velocity; the world is unchanged (reduce dt or the loads)"),
            });
        }
    }
    // Brownian dynamics has no velocity: it stays as it was.
    let keep = world.params.overdamped;
    for (r, (_, rod)) in rods.iter_mut().enumerate() {
        let (_, v) = rod.state_mut();
        for ((v, v0), x) in v.iter_mut().zip(&st.v_n[r]).zip(&st.dx[r]) {
            *v = if keep { *v0 } else { 2.0 * x / h - v0 };
        }
    }
    if !keep {
        project_velocities(world)?;
    }
    Ok(())
}

/// Removes from V' = 2ΔX/h − V_n what the rigid constraints forbid. The
/// rule holds them on the positions only: V' keeps V_n's component along
/// each constraint's normal (flipped), which the normals' turning feeds
/// and nothing damps (drag acts on ΔX). Under thermal noise that velocity
/// grew without bound (a free 30 bp duplex's kinetic energy 0.8 → 2.3 of
/// equipartition in 1 ns, then non-finite). The correction δ solves the
/// last Newton matrix with right-hand side 0 but −L V' on the rigid world
/// constraints' rows (linearised at the end): L (V' + δ) = 0, δ the
/// smallest in that matrix's metric (2M/h² + D/h + K/2, compliant rows
/// included). One re-solve with the last factors; nothing to do without
/// rigid world constraints.
fn project_velocities(world: &mut World) -> Result<()> {
    let World { rods, constraints, ws, .. } = world;
    if !constraints.iter().any(|(_, c)| c.compliance == 0.0) {
        return Ok(());
    }
    ws.sys.rhs.iter_mut().for_each(|x| *x = 0.0);
    for (c, (_, con)) in constraints.iter().enumerate() {
        if con.compliance != 0.0 {
            continue;
        }
        let (Some(a), Some(b)) = (rods.get(con.rod.into()), rods.get(con.other.unwrap_or(con.rod).into())) else {
            continue;
        };
        let nr = con.kind.n_rows();
        ws.rows.resize(nr.max(ws.rows.len()), Default::default());
        con.kind.linearize(&[a, b], &mut ws.rows[..nr])?;
        for (i, row) in ws.rows[..nr].iter().enumerate() {
            // Slider entries (side 2) move abscissae, not velocities.
            let lv: f64 = row.entries().iter().filter(|e| e.0 < 2).map(|&(w, local, v)| v * [a, b][w as usize].velocities()[local]).sum();
            ws.sys.rhs[ws.layout.row_index[c] + i] = -lv;
        }
    }
    ws.sys.resolve()?;
    for (r, (_, rod)) in rods.iter_mut().enumerate() {
        let d = rod.dofs();
        let (_, v) = rod.state_mut();
        for (i, v) in v.iter_mut().enumerate() {
            *v += ws.sys.sol[ws.layout.cp_index[r][i / d] + i % d];
        }
    }
    Ok(())
}
