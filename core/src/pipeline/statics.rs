//! Quasi-static equilibrium (II.83): K ΔX = F + P iterated to equilibrium.
//! K is indefinite under compression and large rotations defeat plain
//! Newton, so each iterate solves the damped system (K + λ D) ΔX = F + P
//! with D = |diag K| (Levenberg–Marquardt; the thesis' "incomplete Newton"
//! is a fixed damping), accepted when the potential energy U − Fᵀq does not
//! rise (or while constraints are still being reached); λ ÷4 after an
//! accepted step and ×4 after a rejected one. Once λ is negligible the
//! iteration is Newton's method, and convergence is declared on the Newton
//! increment. A mass-based damping (pseudo-transient continuation, M/h²)
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
    world.params.validate()?;
    if world.rods.is_empty() {
        return Ok(RelaxReport::default()); // nothing to move
    }
    // A refused or unconverged relax leaves the world as it was (positions,
    // velocities, constraint kinds, beads, plastic state). The copy costs
    // less than one iteration's factorisation.
    let before = world.clone();
    let out = relax_from(world);
    if out.is_err() {
        *world = before;
    }
    out
}

fn relax_from(world: &mut World) -> Result<RelaxReport> {
    let tol = world.params.relax_tolerance;
    let length = world.rods.iter().map(|(_, r)| r.rest_length()).fold(0.0, f64::max);
    beads::static_load(world);
    // Statically defined? (rigid-body modes not held by constraints nor by
    // stiffness.) Checked before anything changes, so a refusal leaves the
    // world as it was.
    assemble(world, Regime::Statics { bead_unknowns: false })?;
    definedness::check_statically_defined(world, false)?;
    for (_, r) in world.rods.iter_mut() {
        r.state_mut().1.iter_mut().for_each(|v| *v = 0.0);
    }
    let mut lambda: f64 = 1.0;
    let mut report = RelaxReport::default();
    let mut potential = solve::potential(world)?;
    let statics = Regime::Statics { bead_unknowns: true };
    for _ in 0..world.params.relax_max_iterations {
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
            Err(e) => {
                // A singular Newton system once the constraints are met and
                // the iterate stands still: a free rigid mode that the
                // start's violation hid from the first check (a clamped ring
                // spinning about its clamp tangent). Name it.
                if newton && violation <= tol * length && report.increment <= tol * length && report.iterations > 1 {
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
        if solve::settle_contacts(world)? {
            continue; // the contact active set changed: solve again
        }
        report.factorisation = solved.factorisation;
        let (dx, dth) = solve::apply(world, 1.0, None);
        let n_sliding = beads::n_sliding(world);
        let n_cons = world.ws.layout.row_index.len() - n_sliding;
        let du: Vec<f64> = (0..n_sliding).map(|j| world.ws.sys.sol[world.ws.layout.extra_index[n_cons + j]]).collect();
        let dbead = beads::apply(world, &du)?;
        if !world.ws.left.is_empty() {
            // A slider left its rod: the configuration changed, start anew.
            post_solve::drop_departed_sliders(world, &mut report.events);
            potential = solve::potential(world)?;
            continue;
        }
        let trial = solve::potential(world)?;
        let vtrial = solve::constraint_violation(world)?;
        if std::env::var_os("STRANDKIT_DEBUG").is_some() {
            eprintln!("relax it {} λ {lambda:.3e} newton {newton} dx {dx:.3e} dth {dth:.3e} viol {violation:.3e} vtrial {vtrial:.3e} pot {potential:.9e} -> {trial:.9e}", report.iterations);
        }
        // Energy comparisons are meaningless at round-off level: a step
        // below the tolerance is accepted as is.
        // Otherwise a step must halve the constraint violation, or lower
        // the potential without increasing the violation.
        let tiny = dx <= tol * length && dth <= tol && dbead <= tol * 1e3;
        let accept = trial.is_finite()
            && (tiny
                || (violation > 1e-5 * tol * length && vtrial <= 0.5 * violation)
                || (trial <= potential + 1e-11 * potential.abs() && vtrial <= violation.max(tol.sqrt() * length)));
        if !accept {
            for ((_, r), q) in world.rods.iter_mut().zip(saved) {
                r.state_mut().0.copy_from_slice(&q);
            }
            for ((_, c), k) in world.constraints.iter_mut().zip(saved_kinds) {
                c.kind = k;
            }
            for ((_, b), u) in world.beads.iter_mut().zip(saved_beads) {
                b.u = u;
            }
            world.ws.left.clear();
            report.rejected += 1;
            lambda = (lambda * 4.0).max(1e-6);
            if lambda > 1e8 {
                return Err(Error::not_converged(
                    report.iterations,
                    report.violation.max(report.increment),
                    format!("relax: no descent step found (potential {potential:.6e})"),
                ));
            }
            continue;
        }
        potential = trial;
        report.increment = dx;
        report.violation = violation;
        if newton && dx <= tol * length && dth <= tol && violation <= tol * length && dbead <= tol * 1e3 {
            // The same rigid-mode check as at the start, now that the
            // constraints are met: a mode the start's violation made look
            // weakly held is named instead of returned as an equilibrium
            // that any spin of it also is.
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
                potential = solve::potential(world)?;
                lambda = 1e-6;
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
        lambda /= 4.0;
    }
    Err(Error::not_converged(
        report.iterations,
        report.violation.max(report.increment),
        format!("relax: last increment {:.3e}, violation {:.3e}", report.increment, report.violation),
    ))
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
    let (a, layout) = (&world.ws.sys.band, &world.ws.layout);
    let (n, bw) = (a.n(), a.kl().max(a.ku()));
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
    let cols = |g: usize| (g.saturating_sub(bw)..(g + bw + 1).min(n)).filter(move |&j| j != g && !is_row[j] && a.get(g, j) != 0.0);
    let diag_max = (0..n).filter(|&g| !is_row[g]).map(|g| a.get(g, g).abs()).fold(0.0f64, f64::max);
    // Width: the coordinate block's, and each row's span of coordinates.
    let mut width = 0;
    for g in 0..n {
        let span: Vec<usize> = cols(g).map(|j| pos[j]).collect();
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
        p.set(pos[g], pos[g], a.get(g, g));
        for j in cols(g) {
            p.set(pos[g], pos[j], a.get(g, j));
        }
    }
    for g in (0..n).filter(|&g| is_row[g]) {
        let l: Vec<(usize, f64)> = cols(g).map(|j| (pos[j], a.get(g, j))).collect();
        let norm2: f64 = l.iter().map(|e| e.1 * e.1).sum();
        if norm2 == 0.0 {
            continue;
        }
        let c = -a.get(g, g); // the row's compliance (scaled), ≥ 0
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
