//! A dynamic step: linearised implicit Euler (II.77–II.82; V^n is the velocity)
//!   (M/h² + D/h + K^n) ΔX = M V^n / h + F + P^n,   V^{n+1} = ΔX / h,
//! with the constraint rows of SPEC §4 in the same solve, or the
//! trapezoidal rule (`Scheme::Trapezoidal`, SPEC §3; `trapezoidal.rs`).
//!
//! With `IntegrationParameters::adaptive_dt`, a step refused as diverged or
//! non-finite is retried as 2, 4, … sub-steps (up to `2^max_halvings`)
//! from the state before it; the report counts the sub-steps.
use super::assemble::Regime;
use super::{post_solve, solve, StepReport};
use crate::error::{Error, Result};
use crate::world::{Scheme, World};

/// Advances the world by one time step `params.dt`.
pub fn step(world: &mut World) -> Result<StepReport> {
    super::on_pool(world, step_here)
}

fn step_here(world: &mut World) -> Result<StepReport> {
    world.params.validate()?;
    check_scheme(world)?;
    let h = world.params.dt;
    // The contact set changes during the solve (detection, active set,
    // friction state): a refused step puts it back.
    // (Copied into a kept buffer: no allocation once it has grown.)
    let saved = !world.contacts.is_empty() || !world.detectors.is_empty();
    if saved {
        world.ws.contacts_before.pairs.clone_from(&world.contacts.pairs);
    }
    world.ws.bridge = None;
    let first = step_by(world, h);
    if first.is_err() && saved {
        std::mem::swap(&mut world.contacts, &mut world.ws.contacts_before);
    }
    if !world.params.adaptive_dt || !matches!(first, Err(Error::Diverged { .. } | Error::NonFinite { .. } | Error::NotConverged { .. })) {
        return first; // a refused step left the world unchanged
    }
    // The sub-steps follow the refused step's Brownian path (thermal.rs).
    let normals = super::thermal::take_first(world);
    let before = world.clone();
    let mut last = first;
    for j in 1..=world.params.max_halvings {
        let n = 1u32 << j;
        super::thermal::bridge(world, n as usize, normals.as_ref());
        let tried = substeps(world, h / n as f64, n);
        world.ws.bridge = None;
        match tried {
            Ok(report) => return Ok(report),
            Err(e) => {
                *world = before.clone();
                let retry = matches!(e, Error::Diverged { .. } | Error::NonFinite { .. } | Error::NotConverged { .. });
                last = Err(e);
                if !retry {
                    break;
                }
            }
        }
    }
    last
}

/// The second-order schemes do not take sliding beads: a bead's abscissa
/// is an unknown of the implicit Euler step only (their Newton iterations
/// do not carry it; when the bead's motion along the rod was a first-order
/// update beside their step it pumped energy in — TR-BDF2: one 2 g bead
/// on the necklace's string from −3.6e-3 J to 67 J in 200 steps of
/// 0.8 ms). Refused up front, the world unchanged; knotted (fixed) beads
/// ride with the rod and are fine.
fn check_scheme(world: &World) -> Result<()> {
    let scheme = world.params.scheme;
    if scheme != Scheme::ImplicitEuler && world.beads.iter().any(|(_, b)| !b.fixed) {
        let name = if scheme == Scheme::TrBdf2 { "tr_bdf2" } else { "trapezoidal" };
        return Err(Error::input(format!(
            "scheme '{name}' with sliding beads is not supported (a bead's abscissa is an unknown of implicit Euler steps only); use scheme 'implicit_euler', or fix the beads"
        )));
    }
    Ok(())
}

/// `n` steps of `h`, reported as one (events in order, energy before the first).
fn substeps(world: &mut World, h: f64, n: u32) -> Result<StepReport> {
    let mut report = step_by(world, h)?;
    for _ in 1..n {
        let next = step_by(world, h)?;
        let events = std::mem::take(&mut report.events);
        let solves = report.solves + next.solves;
        report = StepReport { elastic_energy: report.elastic_energy, events: [events, next.events.clone()].concat(), solves, ..next };
    }
    report.substeps = n;
    Ok(report)
}

/// One step of `h`.
fn step_by(world: &mut World, h: f64) -> Result<StepReport> {
    if world.params.viscosity > 0.0 && !world.params.isotropic_drag {
        // The anisotropic drag's directions, constant over the step.
        for (_, rod) in world.rods.iter_mut() {
            rod.freeze_drag_frame();
        }
    }
    let noise = super::thermal::begin(world, h)?;
    // thermal_h marks the assembly of a thermal step, and the frozen drag
    // tangents belong to it: both off again whatever happens, a panic
    // included (Python catches it and the world lives on), so that outside
    // a step the drag is that of the current shape.
    struct Off<'a>(&'a mut World);
    impl Drop for Off<'_> {
        fn drop(&mut self) {
            self.0.ws.thermal_h = 0.0;
            for (_, rod) in self.0.rods.iter_mut() {
                rod.drag_frame.clear();
            }
        }
    }
    let (energy, solved, solves) = {
        let guard = Off(world);
        advance(guard.0, h)?
    };
    if let Some(n) = noise {
        world.noise = n;
    }
    if world.params.overdamped {
        // Brownian dynamics has no velocity.
        for (_, rod) in world.rods.iter_mut() {
            rod.state_mut().1.iter_mut().for_each(|v| *v = 0.0);
        }
    }
    world.time += h;
    world.steps += 1;
    let mut events = Vec::new();
    let inelastic = post_solve::run(world, Some(h), &mut events)?;
    let ws = &world.ws;
    Ok(StepReport {
        time: world.time,
        n_unknowns: ws.layout.n,
        n_multipliers: ws.layout.n_rows,
        bandwidth: ws.layout.bandwidth,
        residual: solved.residual,
        factorisation: solved.factorisation,
        fallbacks: solved.fallbacks,
        factor_entries: ws.sys.factor_entries(),
        elastic_energy: energy,
        plastic_samples: inelastic.yielded,
        active_contacts: world.contacts.active().count(),
        substeps: 1,
        solves: solves as u32,
        events,
    })
}

/// The scheme's solves of one step of `h` (the beads' start of step first).
fn advance(world: &mut World, h: f64) -> Result<(f64, crate::system::Solved, usize)> {
    super::beads::prepare(world, h)?;
    Ok(match world.params.scheme {
        Scheme::ImplicitEuler => implicit_euler(world, h)?,
        Scheme::Trapezoidal => super::trapezoidal::step(world, h)?,
        Scheme::TrBdf2 => super::trapezoidal::tr_bdf2(world, h)?,
    })
}

/// The implicit Euler step: one solve, or with `contact_recheck` one more
/// for each detection at its end that finds pairs it went through
/// (`recheck.rs`), each from the start of the step.
fn implicit_euler(world: &mut World, h: f64) -> Result<(f64, crate::system::Solved, usize)> {
    let out = implicit_euler_solves(world, h);
    // The pairs a step went through are that step's only (cleared however
    // it ends, so every step starts without any).
    world.ws.recheck_pairs.clear();
    out
}

fn implicit_euler_solves(world: &mut World, h: f64) -> Result<(f64, crate::system::Solved, usize)> {
    let growth = world.growth;
    let mut solves = 1;
    loop {
        let (energy, solved) = solve::assemble_and_solve(world, Regime::Dynamic { h })?;
        solve::check_reach(world, 1.0)?;
        // Brownian dynamics has no velocity to update (zeroed after the step).
        let velocity = (!world.params.overdamped).then_some(1.0 / h);
        solve::commit(world, 1.0, velocity, Some(energy))?;
        let again = if world.params.contact_recheck && solves <= super::recheck::MAX_AGAIN { super::recheck::missed(world) } else { Ok(false) };
        if let Ok(false) = again {
            return Ok((energy, solved, solves));
        }
        // From the start of the step again (or refused as it was): its rods,
        // its contact set as it was, and the pairs it went through.
        solve::undo(world);
        world.growth = growth;
        again?;
        world.contacts.pairs.clone_from(&world.ws.contacts_before.pairs);
        solves += 1;
    }
}
