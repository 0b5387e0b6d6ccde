//! Quasi-static equilibrium (II.83): K ΔX = F + P iterated to equilibrium.
//! When the constraints hold at the start, Newton's method with a line
//! search on the potential energy U − Fᵀq, along the Newton step or a path
//! corrected to second order (large rotations defeat the straight line).
//! Otherwise, and after a step no line search could use (K indefinite
//! under compression, a line search cut short), each iterate solves the
//! damped system (K + λ D) ΔX = F + P with D = |diag K| (Levenberg–
//! Marquardt; the thesis' "incomplete Newton" is a fixed damping),
//! accepted when the potential does not rise (or while constraints are
//! still being reached); λ ÷4 after an accepted step and ×4 after a
//! rejected one, Newton again once λ is negligible. Convergence is declared
//! on a full Newton increment. Membrane locking of the iteration (a Newton
//! step that turns a stiff rod stretches it by θ²/2, so the potential
//! refuses it and the line search crawls) is met at mixed integration
//! points (Magisano, Leonetti & Garcea, CMAME 313 (2017)): such a step is
//! taken when the potential less that stretch of turning accepts it, the
//! next stiffness predicts the stretch from the tangents it started from,
//! and a watchdog returns to plain descent when the potential does not
//! follow (`IntegrationParameters::relax_mixed`). A mass-based damping (pseudo-transient continuation, M/h²)
//! was tried first: it stalls when the mass is very unevenly distributed,
//! e.g. a bead on a light string.
use super::assemble::{assemble, Regime};
use super::{beads, definedness, post_solve, solve, RelaxReport};
use crate::error::{Error, Result};
use crate::world::{Event, World};

/// Moves the world to static equilibrium under its loads and constraints
/// (velocities are zeroed). Errors when a rod is not statically defined or
/// when the iteration does not converge. An equilibrium reached is followed
/// by the post-solve stages; plastic flow there moves the equilibrium, so
/// the iteration continues until the offsets stop moving, while a break, a
/// clip event or a rupture ends the solve with its events.
pub fn relax(world: &mut World) -> Result<RelaxReport> {
    super::on_pool(world, relax_here)
}

fn relax_here(world: &mut World) -> Result<RelaxReport> {
    world.params.validate()?;
    if world.rods.is_empty() {
        return Ok(RelaxReport::default()); // nothing to move
    }
    // A refused or unconverged relax leaves the world as it was (positions,
    // velocities, constraint kinds, beads, plastic state). The copy costs
    // less than one iteration's factorisation.
    let before = world.clone();
    let mut out = relax_from(world, 0.0, world.params.relax_mixed);
    // Newton's method goes to the nearest stationary point, stable or not
    // (a column past its buckling load, started slightly bent, back to
    // straight); the damped iteration descends. An unstable equilibrium
    // found by Newton is checked by a damped solve from the same start,
    // whose answer is kept (the same point again when the start is on it).
    if let Some(newton) = out.as_ref().ok().filter(|r| r.stable == Some(false)).cloned() {
        let newton_world = std::mem::replace(world, before.clone());
        // Plain energy descent there: the mixed merit is not the energy.
        match relax_from(world, 1.0, false) {
            Ok(mut damped) => {
                damped.iterations += newton.iterations;
                out = Ok(damped);
            }
            Err(_) => *world = newton_world, // Newton's answer stands
        }
    }
    if out.is_err() {
        *world = before;
    }
    out
}

/// The smallest positive margin of the world's contact detectors.
pub(crate) fn contact_reach(world: &World) -> Option<f64> {
    world
        .detectors
        .iter()
        .map(|d| match d {
            crate::contact::Detector::Rods(r) => r.margin,
            crate::contact::Detector::Obstacle(o) => o.margin,
        })
        .filter(|m| *m > 0.0)
        .reduce(f64::min)
}

/// The relax iteration from `lambda` (0: Newton with a line search first;
/// 1: the damped iteration, Newton once λ has fallen below 1e-9); `mixed`:
/// Newton steps may be taken on the mixed merit (not with contact
/// detectors, whose active set and anchors a watchdog return would not
/// restore).
fn relax_from(world: &mut World, lambda: f64, mixed: bool) -> Result<RelaxReport> {
    let out = relax_iterate(world, lambda, mixed);
    for (_, r) in world.rods.iter_mut() {
        r.end_mixed();
    }
    out
}

fn relax_iterate(world: &mut World, lambda: f64, mixed: bool) -> Result<RelaxReport> {
    let tol = world.params.relax_tolerance;
    let length = world.rods.iter().map(|(_, r)| r.rest_length()).fold(0.0, f64::max);
    world.ws.blocked.clear();
    world.ws.pulled.clear();
    beads::static_load(world);
    // Statically defined? (rigid-body modes not held by constraints nor by
    // stiffness.) Checked before anything changes, so a refusal leaves the
    // world as it was.
    assemble(world, Regime::Statics { bead_unknowns: false })?;
    definedness::check_statically_defined(world, false)?;
    for (_, r) in world.rods.iter_mut() {
        r.state_mut().1.iter_mut().for_each(|v| *v = 0.0);
    }
    // Newton first (λ = 0), damping only after a step that no line search
    // could use — when the constraints hold at the start. A start that
    // violates them takes the damped iteration: a full Newton step that
    // meets the constraints may cost any amount of potential energy (a
    // rope bridge's assembled ropes: 5e9 J), and the potential alone is no
    // merit function for reaching them.
    let start_violation = solve::constraint_violation(world)?;
    let mut lambda = if start_violation > tol * length { lambda.max(1.0) } else { lambda };
    let mut report = RelaxReport::default();
    let statics = Regime::Statics { bead_unknowns: true };
    let mut watchdog: Option<Watchdog> = None;
    let mut mixed = mixed && contact_reach(world).is_none();
    let mut forgiven = false;
    // Active-set rounds of this iterate: without a bound a free fabric's
    // pairs went in and out on every solve, and relax never moved.
    let mut rounds = 0;
    for _ in 0..world.params.relax_max_iterations {
        // The mixed iteration moves on to this iterate (its merit is the
        // potential here); after a step only the merit accepted, the
        // stiffness predicts the stretch from the iterate before.
        let predicting = mixed && forgiven;
        if mixed {
            for (_, r) in world.rods.iter_mut() {
                r.advance_mixed(forgiven);
            }
        }
        forgiven = false;
        let mut potential = solve::potential(world)?;
        // The watchdog, armed by a step taken on the merit alone: disarmed
        // once the potential is below where that step started.
        if mixed {
            match watchdog.as_mut() {
                Some(w) if potential <= w.potential + 1e-11 * w.potential.abs() => watchdog = None,
                Some(w) => {
                    if w.since > WATCHDOG_STEPS {
                        // No lower potential in that many iterates: back to
                        // where the merit took over, on with the plain
                        // iteration.
                        w.restore(world);
                        (potential, lambda) = (w.potential, w.lambda);
                        watchdog = None;
                        mixed = false;
                        for (_, r) in world.rods.iter_mut() {
                            r.end_mixed();
                        }
                        if std::env::var_os("STRANDKIT_DEBUG").is_some() {
                            eprintln!("relax: watchdog went back at iteration {}", report.iterations);
                        }
                    }
                }
                None => {}
            }
        }
        let newton = lambda < 1e-9;
        assemble(world, statics)?;
        if !newton {
            let ws = &mut world.ws;
            ws.sys.damp(&ws.layout, lambda);
        }
        let violation = solve::violation(world);
        let saved: Vec<Vec<f64>> = world.rods.iter().map(|(_, r)| r.coords().to_vec()).collect();
        let saved_beads: Vec<f64> = world.beads.iter().map(|(_, b)| b.u).collect();
        let saved_kinds: Vec<_> = world.constraints.iter().map(|(_, c)| c.kind.clone()).collect();
        let solved = solve::solve(world);
        report.iterations += 1;
        let solved = match solved {
            Ok(s) => s,
            Err(e) if solve::block_dependent_contact(world, &e) => continue,
            Err(e) => {
                // A singular Newton system once the constraints are met and
                // the iterate stands still: a free rigid mode that the
                // start's violation hid from the first check (a clamped ring
                // spinning about its clamp tangent). Name it.
                if newton && violation <= tol * length && report.increment <= tol * length && report.iterations > 1 {
                    for (_, r) in world.rods.iter_mut() {
                        r.end_mixed();
                    }
                    free_mode_check(world)?;
                }
                if lambda < 1e6 {
                    lambda = (lambda * 4.0).max(1e-6); // singular K: damp more
                    report.rejected += 1;
                    continue;
                }
                return Err(e);
            }
        };
        if solve::settle_contacts(world, rounds)? {
            rounds += 1;
            continue; // the contact active set changed: solve again
        }
        // The next iterate settles its own set (a pair that pulled here
        // may press there).
        rounds = 0;
        world.ws.pulled.clear();
        report.factorisation = solved.factorisation;
        let slope = solve::directional_derivative(world);
        // The Newton solution z = (p, y): steps on the coordinates and
        // abscissae, multipliers on the rows.
        let z = world.ws.sys.sol.clone();
        let is_row = world.ws.sys.multiplier_rows().to_vec();
        // With contact detection, no iterate moves a point farther than
        // the detectors' margin: a longer Newton step could carry a rod
        // through an obstacle or another rod unseen (pairs are found only
        // within the margin). A trust region on the step length α.
        let alpha_max = match contact_reach(world) {
            Some(m) => {
                // Positions only (not roll angles nor abscissae).
                let ws = &world.ws;
                let dx = ws.layout.cp_index.iter().zip(world.rods.iter()).fold(0.0f64, |acc, (cps, (_, rod))| {
                    cps.iter().fold(acc, |acc, &g| (0..3.min(rod.dofs())).fold(acc, |acc, a| acc.max(z[g + a].abs())))
                });
                if dx > m {
                    m / dx
                } else {
                    1.0
                }
            }
            None => 1.0,
        };
        let beads_at: Vec<usize> = {
            let (n_sliding, layout) = (beads::n_sliding(world), &world.ws.layout);
            let n_cons = layout.row_index.len() - n_sliding;
            (0..n_sliding).map(|j| layout.extra_index[n_cons + j]).collect()
        };
        let saved_state = (&saved[..], &saved_kinds[..], &saved_beads[..]);
        let mut path = Path { z: &z, is_row: &is_row, beads_at: &beads_at, saved: saved_state, last_alpha: f64::NAN };
        // Energy comparisons are meaningless at round-off level: a step
        // below the tolerance is accepted as is. Otherwise a step must cut
        // the constraint violation (by half for the full step), or lower
        // the potential (by Armijo's sufficient decrease along a shortened
        // or curved step) without increasing the violation.
        // With the mixed iteration, a step the potential refuses is still
        // taken when the mixed merit (the potential less the stretch of
        // turning, `mixed_merit_shift`) accepts it and no stretch sample
        // turned past `MAX_TURN`.
        let accept_with = |t: &Trial, plain: bool, energy: f64| {
            let tiny = plain && t.dx <= tol * length && t.dth <= tol && t.dbead <= tol * 1e3;
            let lowered = if plain { potential + 1e-11 * potential.abs() } else { potential + 1e-4 * t.alpha * slope };
            energy.is_finite()
                && (tiny
                    || (violation > 1e-2 * tol * length && t.violation <= (1.0 - 0.5 * t.alpha) * violation)
                    || (energy <= lowered && t.violation <= violation.max(tol.sqrt() * length)))
        };
        let by_merit = |t: &Trial, plain: bool| mixed && newton && t.turn <= MAX_TURN && accept_with(t, plain, t.merit);
        let accept = |t: &Trial, plain: bool| accept_with(t, plain, t.energy) || by_merit(t, plain);
        // What the line search lowers: the merit where it may decide.
        let value = |t: &Trial| if mixed { t.merit } else { t.energy };
        let debug = std::env::var_os("STRANDKIT_DEBUG").is_some();
        let log = |t: &Trial, curved: bool| {
            if debug {
                eprintln!(
                    "relax it {} λ {lambda:.3e} α {:.3e} turn {:.2e} curved {curved} dx {:.3e} dth {:.3e} viol {violation:.3e} vtrial {:.3e} pot {potential:.9e} -> {:.9e} slope {slope:.3e}",
                    report.iterations, t.alpha, t.turn, t.dx, t.dth, t.violation, t.energy
                );
            }
        };
        // The full step; then (Newton only, along a descent direction) the
        // curved path x + α p + ½ α² a with Newton's second-order
        // correction a (`curvature_correction`), searched for the lowest
        // potential. From a straight rod the linear step of a large
        // deflection over-stretches the rod (transverse motion lengthens
        // it to second order), a stretch energy ∝ α⁴ that the straight line
        // pays and the curved path, which moves the points back along the
        // rod, much less.
        let full = path.evaluate(world, alpha_max, None)?;
        log(&full, false);
        let outcome = if full.left || accept(&full, true) {
            Some(full)
        } else if !(newton && slope < 0.0) {
            None
        } else {
            // (Not after a step on the merit: the finite difference takes
            // the factorised matrix for −∂R/∂q, which the predicting
            // stiffness is not.)
            let correction = if predicting { None } else { curvature_correction(world, &mut path, statics, length)? };
            report.corrections += correction.is_some() as usize;
            let a = correction.as_deref();
            let mut rejected = full;
            let mut best = None;
            if a.is_some() {
                let t = path.evaluate(world, alpha_max, a)?;
                log(&t, true);
                if t.left || accept(&t, false) {
                    best = Some(t);
                } else {
                    rejected = t;
                }
            }
            // Backtracking to the first point of sufficient decrease (the
            // minimiser of the quadratic through E(0), E′(0) and the last
            // rejected point, kept within [α/10, α/2]) ...
            let mut trials = 0;
            while best.is_none() && trials < MAX_BACKTRACKS {
                let alpha = rejected.alpha;
                let curvature = value(&rejected) - potential - slope * alpha;
                let next = if mixed && rejected.turn > MAX_TURN {
                    0.9 * alpha * MAX_TURN / rejected.turn
                } else if curvature > 0.0 {
                    -slope * alpha * alpha / (2.0 * curvature)
                } else {
                    0.1 * alpha
                };
                let t = path.evaluate(world, next.clamp(0.1 * alpha, 0.5 * alpha), a)?;
                log(&t, a.is_some());
                trials += 1;
                if t.left || accept(&t, false) {
                    best = Some(t);
                } else {
                    rejected = t;
                }
            }
            // ... then towards the minimum along the path: the parabola
            // through E(0), the best point and the rejected one, while it
            // keeps lowering the potential (the stretch energy makes the
            // first acceptable point far short of it).
            if let Some(mut b) = best.take().filter(|b| !b.left) {
                for _ in 0..MAX_EXPANSIONS {
                    let Some(next) = parabola_minimum((0.0, potential), (b.alpha, value(&b)), (rejected.alpha, value(&rejected))) else { break };
                    if !(next > 1.2 * b.alpha && next < 0.95 * rejected.alpha) {
                        break;
                    }
                    let t = path.evaluate(world, next, a)?;
                    log(&t, a.is_some());
                    if !t.left && accept(&t, false) && value(&t) < value(&b) {
                        b = t;
                    } else {
                        break;
                    }
                }
                if path.last_alpha != b.alpha {
                    b = path.evaluate(world, b.alpha, a)?; // back to the best point
                }
                best = Some(b);
            }
            best
        };
        forgiven = mixed && outcome.is_some_and(|t| !t.left && !accept_with(&t, t.alpha == alpha_max && !t.curved, t.energy));
        if forgiven && watchdog.is_none() {
            // Where this step started: the saved state, and the frames,
            // which are transported only below.
            watchdog = Some(Watchdog {
                potential,
                lambda,
                since: 0,
                rods: saved.iter().zip(world.rods.iter()).map(|(q, (_, r))| (q.clone(), r.frames.clone())).collect(),
                kinds: saved_kinds.clone(),
                beads: saved_beads.clone(),
            });
        } else if let Some(w) = watchdog.as_mut().filter(|_| outcome.is_some()) {
            w.since += 1; // an accepted step that has not yet brought the potential down
        }
        let (dx, dth, dbead, trial, newton_step, short) = match outcome {
            Some(t) => (t.dx, t.dth, t.dbead, if t.left { f64::NAN } else { t.energy }, t.alpha == 1.0 && !t.curved, t.alpha < SHORT_STEP * alpha_max),
            None => {
                restore(world, &saved, &saved_kinds, &saved_beads);
                (0.0, 0.0, 0.0, f64::NAN, false, false)
            }
        };
        if !world.ws.left.is_empty() {
            // A slider left its rod: the configuration changed, start anew.
            post_solve::drop_departed_sliders(world, &mut report.events);
            watchdog = None;
            continue;
        }
        if trial.is_nan() {
            report.rejected += 1;
            lambda = (lambda * 4.0).max(DAMPING_RESTART);
            if lambda > 1e8 {
                return Err(Error::not_converged(
                    report.iterations,
                    report.violation.max(report.increment),
                    format!("relax: no descent step found (potential {potential:.6e})"),
                ));
            }
            continue;
        }
        // Reference directors follow every accepted iterate (the energy is
        // continuous across a transport), keeping
        // the smallest rotations short however far the rod turns overall.
        // An iterate that turned a tangent past 150° keeps the old ones.
        for (_, r) in world.rods.iter_mut() {
            if r.transport_obstacle().is_none() {
                r.transport_frames();
            }
        }
        report.increment = dx;
        report.violation = violation;
        if newton && newton_step && dx <= tol * length && dth <= tol && violation <= tol * length && dbead <= tol * 1e3 {
            // The same rigid-mode check as at the start, now that the
            // constraints are met: a mode the start's violation made look
            // weakly held is named instead of returned as an equilibrium
            // that any spin of it also is.
            for (_, r) in world.rods.iter_mut() {
                r.end_mixed();
            }
            let potential = solve::potential(world)?;
            free_mode_check(world)?;
            assemble(world, statics)?;
            let mut events: Vec<Event> = Vec::new();
            let inelastic = post_solve::run(world, None, &mut events)?;
            let topology_changed = !events.is_empty();
            report.events.extend(events);
            report.plastic_samples += inelastic.yielded;
            if std::env::var_os("STRANDKIT_DEBUG").is_some() {
                eprintln!("relax plastic: {} samples, max increment {:.3e}", inelastic.yielded, inelastic.max_increment);
            }
            // Stop when the flow has converged, or when it stagnates: a
            // rod at yield all along (uniform moment) has an indeterminate
            // plastic distribution, and the rounds then trade a constant
            // small increment between samples (reported, not an error).
            let stagnant = inelastic.max_increment > 0.99 * report.plastic_increment && report.plastic_increment > 0.0;
            report.plastic_increment = inelastic.max_increment;
            if inelastic.max_increment > world.params.plastic_tolerance && !topology_changed && !stagnant {
                lambda = 0.0;
                watchdog = None;
                continue;
            }
            report.potential = potential;
            report.bandwidth = world.ws.layout.bandwidth;
            report.n_unknowns = world.ws.layout.n;
            if !topology_changed {
                report.unstable_directions = unstable_directions(world);
                report.stable = report.unstable_directions.map(|k| k == 0);
            }
            return Ok(report);
        }
        // A Newton direction the line search had to cut below SHORT_STEP
        // is a poor model of the potential here: the damped iteration
        // takes over (and hands back to Newton as λ falls).
        lambda = if short && newton { DAMPING_RESTART } else if lambda < 1e-9 { 0.0 } else { lambda / 4.0 };
    }
    Err(Error::not_converged(
        report.iterations,
        report.violation.max(report.increment),
        format!("relax: last increment {:.3e}, violation {:.3e}", report.increment, report.violation),
    ))
}

/// Most shortenings of one Newton step before the damping takes over.
const MAX_BACKTRACKS: usize = 10;

/// Shortest line-search step after which Newton keeps going undamped.
const SHORT_STEP: f64 = 0.05;

/// The damping λ after a Newton step that no line search could use.
const DAMPING_RESTART: f64 = 1e-4;

/// Largest turn (rad) of a stretch sample's tangent in one iterate taken
/// on the mixed merit: the merit measures stretch along the iterate's
/// tangents (t·r′), a prediction that loses its meaning towards a right
/// angle. Measured on the SPEC §10 cantilever at 7–1000 control points with
/// the merit deciding every Newton step (an earlier variant): 0.75 and 1.0
/// gave the same solve counts up to 2e5 N, 1.0 took 42 solves at 5e5 N and
/// 1000 points (0.75: 22), 0.5 and 0.3 took more solves at every load.
const MAX_TURN: f64 = 0.75;

/// Accepted steps the mixed iteration may take, after one taken on the
/// merit alone, without lowering the potential below where that one
/// started, before the watchdog takes it back there and the plain
/// iteration goes on (the merit forgives stretch, so the potential is not
/// monotone: on the cantilever it rises once, after the first step). Total
/// solves of the test files' relaxes with 1 / 2 / 4: necklace 1575 / 1578
/// / 2279 (plain 1563), a bead on a string 152 / 77 / 77 (plain 63), the
/// hanging chain 26 / 36 / 38 (plain 23); the cantilever's the same.
const WATCHDOG_STEPS: usize = 2;

/// Where a mixed iteration left monotone descent (Chamberlain, Powell,
/// Lemaréchal & Pedersen, Math. Prog. Study 16 (1982): the watchdog
/// technique).
struct Watchdog {
    potential: f64,
    lambda: f64,
    since: usize,
    rods: Vec<(Vec<f64>, Vec<crate::energy::FrameState>)>,
    kinds: Vec<crate::constraint::ConstraintKind>,
    beads: Vec<f64>,
}

impl Watchdog {
    fn restore(&self, world: &mut World) {
        let q: Vec<Vec<f64>> = self.rods.iter().map(|(q, _)| q.clone()).collect();
        restore(world, &q, &self.kinds, &self.beads);
        for ((_, r), (_, frames)) in world.rods.iter_mut().zip(&self.rods) {
            r.frames.clone_from(frames);
        }
    }
}

/// Most points tried beyond the first acceptable one of a line search.
const MAX_EXPANSIONS: usize = 3;

/// One point of a line search.
#[derive(Clone, Copy, Debug)]
struct Trial {
    alpha: f64,
    dx: f64,
    dth: f64,
    dbead: f64,
    energy: f64,
    violation: f64,
    /// A slider left its rod on the way (energy not evaluated).
    left: bool,
    /// On the curved path (α = 1 is then not the Newton step).
    curved: bool,
    /// Largest turn of a stretch sample's tangent (rad; mixed iteration).
    turn: f64,
    /// The mixed merit (the energy without a mixed iteration).
    merit: f64,
}

type Saved<'a> = (&'a [Vec<f64>], &'a [crate::constraint::ConstraintKind], &'a [f64]);

/// The path of a line search: from the saved state, q + α p + ½ α² a
/// (coordinates and abscissae), with the multipliers y of the solve.
struct Path<'a> {
    z: &'a [f64],
    is_row: &'a [bool],
    beads_at: &'a [usize],
    saved: Saved<'a>,
    last_alpha: f64,
}

impl Path<'_> {
    /// Moves the world to the path's point α (from the saved state) and
    /// measures it.
    fn evaluate(&mut self, world: &mut World, alpha: f64, a: Option<&[f64]>) -> Result<Trial> {
        let (dx, dth, dbead) = self.move_to(world, alpha, a)?;
        let turn = world.rods.iter().fold(0.0f64, |m, (_, r)| m.max(r.mixed_turn()));
        let mut t = Trial { alpha, dx, dth, dbead, energy: f64::NAN, violation: f64::NAN, left: !world.ws.left.is_empty(), curved: a.is_some(), turn, merit: f64::NAN };
        if !t.left {
            t.energy = solve::potential(world)?;
            t.merit = t.energy + world.rods.iter().map(|(_, r)| r.mixed_merit_shift()).sum::<f64>();
            t.violation = solve::constraint_violation(world)?;
        }
        Ok(t)
    }
}

impl Path<'_> {
    /// Moves the world from the saved state to the path's point α (the
    /// multipliers set to y); returns the largest moves (positions, roll,
    /// bead abscissae).
    fn move_to(&mut self, world: &mut World, alpha: f64, a: Option<&[f64]>) -> Result<(f64, f64, f64)> {
        restore(world, self.saved.0, self.saved.1, self.saved.2);
        for (i, x) in world.ws.sys.sol.iter_mut().enumerate() {
            let c = a.map_or(0.0, |a| a[i]);
            *x = if self.is_row[i] { self.z[i] } else { alpha * self.z[i] + 0.5 * alpha * alpha * c };
        }
        self.last_alpha = alpha;
        let (dx, dth) = solve::apply(world, 1.0, None);
        let du: Vec<f64> = self.beads_at.iter().map(|&g| world.ws.sys.sol[g]).collect();
        Ok((dx, dth, beads::apply(world, &du)?))
    }
}

/// The abscissa of the minimum of the parabola through three points, if
/// it opens upwards.
fn parabola_minimum(p0: (f64, f64), p1: (f64, f64), p2: (f64, f64)) -> Option<f64> {
    let (a, b) = ((p1.1 - p0.1) / (p1.0 - p0.0), (p2.1 - p1.1) / (p2.0 - p1.0));
    let c = (b - a) / (p2.0 - p0.0);
    (c > 0.0 && c.is_finite()).then(|| 0.5 * (p0.0 + p1.0) - a / (2.0 * c))
}

/// Largest move of the finite difference of `curvature_correction`, as a
/// fraction of the longest rod: small enough that the third-order terms
/// of a large step (they dominate from 1e-3 of a 2 m step of a 4 m
/// cantilever) stay out of the difference, large enough for the round-off
/// of the forces (ε |R| / h²).
const CORRECTION_PROBE: f64 = 5e-6;

/// Newton's second-order correction (the "geodesic acceleration" of
/// Transtrum & Sethna 2012): with R(q) = b(q) − A(q) ŷ the residual of
/// the Newton system at the multipliers y found, the path q + α p + ½ α² a
/// with A a = −R''[p, p] cancels R to second order in α. R'' is a finite
/// difference along p, (2/h²)(R(q + h p) − (1 − h) R(q)) (R(q) = A p̂ by
/// Newton's equation), at the cost of one assembly and one solve with the
/// factors already computed. A rotation's linearisation (points moving
/// along the tangent of their circle) is corrected to the circle to second
/// order. None when the probe point cannot be assembled.
fn curvature_correction(world: &mut World, path: &mut Path<'_>, regime: Regime, length: f64) -> Result<Option<Vec<f64>>> {
    let (z, is_row) = (path.z, path.is_row);
    let peak = z.iter().zip(is_row).filter(|(_, &r)| !r).fold(0.0f64, |m, (x, _)| m.max(x.abs()));
    let h = (CORRECTION_PROBE * length / peak).clamp(1e-7, 1e-2);
    restore(world, path.saved.0, path.saved.1, path.saved.2);
    let r0 = world.ws.sys.residual_less_rows(&world.ws.layout, z, true);
    let moved = path.move_to(world, h, None).is_ok() && world.ws.left.is_empty();
    let assembled = moved && assemble(world, regime).is_ok();
    let rh = assembled.then(|| world.ws.sys.residual_less_rows(&world.ws.layout, z, false));
    restore(world, path.saved.0, path.saved.1, path.saved.2);
    let Some(rh) = rh else { return Ok(None) };
    let k = 2.0 / (h * h);
    let sys = &mut world.ws.sys;
    for ((b, r1), r0) in sys.rhs.iter_mut().zip(&rh).zip(&r0) {
        *b = k * (r1 - (1.0 - h) * r0);
    }
    if sys.resolve().is_err() {
        return Ok(None);
    }
    // A correction larger than the step is no second-order term (Transtrum
    // & Sethna keep |a| ≤ 2 × 0.75 |p|): the expansion does not hold that far.
    let norm = |v: &[f64]| v.iter().zip(is_row).filter(|(_, &r)| !r).fold(0.0f64, |m, (x, _)| m.max(x.abs()));
    if !(0.5 * norm(&sys.sol) <= 0.75 * norm(z)) {
        return Ok(None);
    }
    Ok(Some(sys.sol.clone()))
}

/// Puts back the coordinates, constraint kinds and bead abscissae saved
/// before a trial step.
fn restore(world: &mut World, q: &[Vec<f64>], kinds: &[crate::constraint::ConstraintKind], u: &[f64]) {
    for ((_, r), q) in world.rods.iter_mut().zip(q) {
        r.state_mut().0.copy_from_slice(q);
    }
    for ((_, c), k) in world.constraints.iter_mut().zip(kinds) {
        c.kind = k.clone();
    }
    for ((_, b), u) in world.beads.iter_mut().zip(u) {
        b.u = *u;
    }
    world.ws.left.clear();
}

/// The start's statically-defined check at the current iterate.
fn free_mode_check(world: &mut World) -> Result<()> {
    assemble(world, Regime::Statics { bead_unknowns: false })?;
    definedness::check_statically_defined(world, true)
}

/// Unstable directions of the last assembled static system (the undamped
/// Newton matrix at the converged iterate). By Sylvester's law of inertia
/// the constrained equilibrium is stable when the stiffness restricted to
/// the constraints' null space is positive definite. That restriction has
/// the inertia of A + Σ ρ_r l_r l_rᵀ (A the coordinate block, l_r the
/// constraint rows) minus the rows' positive directions: a compliant row is
/// its own spring (ρ = 1/C), a hard row gets ρ = 1e4 × the stiffest diagonal
/// — far above any negative stiffness, far below round-off trouble. The
/// negative pivots of that matrix's LDLᵀ are the unstable directions.
/// (Factoring the KKT matrix itself meets zero pivots where the layout puts
/// a row before the last control point it touches.)
fn unstable_directions(world: &World) -> Option<usize> {
    stability(world).map(|(k, _)| k)
}

/// The number of unstable directions and, if there are any, one of them
/// as a change of the coordinates (flat over the system's unknowns, zero on
/// the multiplier rows).
fn stability(world: &World) -> Option<(usize, Option<Vec<f64>>)> {
    use crate::linalg::band::{BandLdlt, BandMatrix};
    let (a, layout) = (&world.ws.sys.matrix, &world.ws.layout);
    let n = a.n();
    let mut is_row = vec![false; n];
    for (c, &r0) in layout.row_index.iter().enumerate() {
        is_row[r0..r0 + layout.row_count[c]].iter_mut().for_each(|x| *x = true);
    }
    let mut pos = vec![usize::MAX; n];
    let mut m = 0;
    for g in 0..n {
        if !is_row[g] {
            pos[g] = m;
            m += 1;
        }
    }
    let is_row = &is_row;
    // Row g's nonzero entries on other coordinates.
    let cols = |g: usize| {
        let mut e = Vec::new();
        a.for_row(g, |j, v| {
            if j != g && !is_row[j] && v != 0.0 {
                e.push((j, v));
            }
        });
        e
    };
    let diag_max = (0..n).filter(|&g| !is_row[g]).map(|g| a.diag(g).abs()).fold(0.0f64, f64::max);
    // Width: the coordinate block's, and each row's span of coordinates.
    let mut width = 0;
    for g in 0..n {
        let span: Vec<usize> = cols(g).iter().map(|&(j, _)| pos[j]).collect();
        if is_row[g] {
            if let (Some(lo), Some(hi)) = (span.iter().min(), span.iter().max()) {
                width = width.max(hi - lo);
            }
        } else {
            width = span.iter().fold(width, |w, &p| w.max(p.abs_diff(pos[g])));
        }
    }
    let mut p = BandMatrix::new(m, width, width);
    for g in (0..n).filter(|&g| !is_row[g]) {
        p.set(pos[g], pos[g], a.diag(g));
        for (j, v) in cols(g) {
            p.set(pos[g], pos[j], v);
        }
    }
    for g in (0..n).filter(|&g| is_row[g]) {
        let l: Vec<(usize, f64)> = cols(g).into_iter().map(|(j, v)| (pos[j], v)).collect();
        let norm2: f64 = l.iter().map(|e| e.1 * e.1).sum();
        if norm2 == 0.0 {
            continue;
        }
        let c = -a.diag(g); // the row's compliance (scaled), ≥ 0
        let rho = if c > 0.0 { 1.0 / c } else { 1e4 * diag_max / norm2 };
        for &(i, x) in &l {
            for &(j, y) in &l {
                p.add(i, j, rho * x * y);
            }
        }
    }
    let mut f = BandLdlt::new();
    if let Err(e) = f.factor_for_inertia(&p) {
        if std::env::var_os("STRANDKIT_DEBUG").is_some() {
            eprintln!("relax stability: LDLᵀ declined: {e:?}");
        }
        return None;
    }
    let k = f.negative_pivots();
    let direction = (k > 0).then(|| f.negative_direction()).flatten().map(|x| {
        let mut full = vec![0.0; n];
        // The band is equilibrated (D A D): the physical direction is D x.
        (0..n).filter(|&g| !is_row[g]).for_each(|g| full[g] = x[pos[g]] * world.ws.sys.scale.get(g).copied().unwrap_or(1.0));
        full
    });
    Some((k, direction))
}

/// `relax`, then, while the equilibrium found is unstable, a push of
/// `amplitude` (length unit: the largest control-point move) along a
/// direction in which the potential energy decreases and `relax` again (at
/// most 5 times): a column straight above its buckling load ends buckled.
/// The returned report is the last relax's.
pub fn relax_perturbed(world: &mut World, amplitude: f64) -> Result<RelaxReport> {
    crate::error::positive("perturb amplitude", amplitude)?;
    let mut report = relax(world)?;
    for _ in 0..5 {
        if report.stable != Some(false) {
            break;
        }
        let Some((_, Some(dir))) = stability(world) else { break };
        let peak = world.ws.layout.cp_index.iter().flatten().flat_map(|&g| (0..3).map(move |a| g + a)).fold(0.0f64, |m, g| m.max(dir[g].abs()));
        if !(peak > 0.0) {
            break;
        }
        let layout = &world.ws.layout;
        for (r, (_, rod)) in world.rods.iter_mut().enumerate() {
            let d = rod.dofs();
            let (q, _) = rod.state_mut();
            for (i, &g) in layout.cp_index[r].iter().enumerate() {
                for a in 0..d {
                    q[i * d + a] += amplitude * dir[g + a] / peak;
                }
            }
        }
        report = relax(world)?;
    }
    Ok(report)
}
