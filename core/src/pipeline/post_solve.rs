//! What happens after every accepted solve, defined once and run in one
//! order by step, relax and the quasi-dynamic frames:
//!
//! 1. departed sliders are removed (`SliderLeft`);
//! 2. beads advance along their rods (dynamics only; `BeadLeft`);
//! 3. the frame model's per-sample state is transported to the new shape;
//! 4. constraints whose measure exceeds their break force are removed
//!    (`ConstraintBroken`, algorithm 5);
//! 5. clips release and capture (`ClipReleased`, `ClipCaptured`, algorithms 4–5);
//! 6. plasticity, Poisson contraction and material rupture (`RodRuptured`,
//!    algorithms 1–3).
use super::rupture::{inelastic_update, Inelastic};
use crate::constraint::BreakPolicy;
use crate::error::Result;
use crate::world::{Event, World};

/// One post-solve stage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    Sliders,
    Beads,
    Frames,
    Breaking,
    Clips,
    Inelastic,
}

/// The stages, in the order they run.
pub const STAGES: [Stage; 6] = [Stage::Sliders, Stage::Beads, Stage::Frames, Stage::Breaking, Stage::Clips, Stage::Inelastic];

/// Runs every stage after a solve; `h` is the time step of a dynamic solve
/// (None: a static one, whose beads were unknowns of the solve). Events are
/// appended in the order they happen.
pub(crate) fn run(world: &mut World, h: Option<f64>, events: &mut Vec<Event>) -> Result<Inelastic> {
    let mut inelastic = Inelastic::default();
    for stage in STAGES {
        match stage {
            Stage::Sliders => drop_departed_sliders(world, events),
            Stage::Beads => {
                if let Some(h) = h {
                    super::beads::advance(world, h, events)?;
                }
            }
            Stage::Frames => world.rods.iter_mut().for_each(|(_, r)| r.transport_frames()),
            Stage::Breaking => break_constraints(world, h, events)?,
            Stage::Clips => super::clips::update(world, events)?,
            Stage::Inelastic => inelastic = inelastic_update(world, events)?,
        }
    }
    Ok(inelastic)
}

/// Removes the sliders that left their rod during the last solve.
pub(crate) fn drop_departed_sliders(world: &mut World, events: &mut Vec<Event>) {
    for h in std::mem::take(&mut world.ws.left) {
        if let Some(c) = world.constraints.remove(h) {
            events.push(Event::SliderLeft { constraint: h.into(), label: c.label, time: world.time, kind: c.kind });
        }
    }
}

/// Removes the constraints whose last reaction exceeds their break force
/// (algorithm 5), measured by their policy — averaged over their
/// `averaging_time` after a dynamic step of length `h` — and reports them.
fn break_constraints(world: &mut World, h: Option<f64>, events: &mut Vec<Event>) -> Result<()> {
    let mut broken = Vec::new();
    let mut averaged = std::mem::take(&mut world.ws.break_measures);
    averaged.clear();
    for (handle, c) in world.constraints.iter() {
        let Some(b) = c.breaking else { continue };
        let rods = world.rods_of(c)?;
        let measure = match b.policy {
            BreakPolicy::Magnitude => Some(c.kind.reaction(&rods, &c.multipliers)?.magnitude()),
            BreakPolicy::Tension => c.kind.tension(&rods, &c.multipliers)?,
            BreakPolicy::Compression => c.kind.tension(&rods, &c.multipliers)?.map(|t| -t),
        };
        let measure = match (measure, h) {
            (Some(f), Some(h)) if b.averaging_time > 0.0 => {
                let m = c.break_measure.unwrap_or(0.0);
                let m = m + (1.0 - (-h / b.averaging_time).exp()) * (f - m);
                averaged.push((handle, m));
                Some(m)
            }
            _ => measure,
        };
        if let Some(f) = measure.filter(|f| *f > b.force) {
            broken.push((handle, f, b.policy));
        }
    }
    for &(handle, m) in &averaged {
        if let Some(c) = world.constraints.get_mut(handle) {
            c.break_measure = Some(m);
        }
    }
    world.ws.break_measures = averaged;
    let mut gone = Vec::new();
    for (h, force, policy) in broken {
        if let Some(c) = world.constraints.remove(h) {
            if let Some(l) = &c.label {
                world.groups.mark_broken(h.into(), world.time, force);
                gone.push(l.clone());
            }
            events.push(Event::ConstraintBroken { constraint: h.into(), label: c.label, time: world.time, force, policy, kind: c.kind });
        }
    }
    // Those that fail with a constraint broken under its load go first;
    // then, transitively, whatever goes with any of them.
    let failing: Vec<_> = world.constraints.iter().filter(|(_, c)| c.fails_with.iter().any(|l| gone.contains(l))).map(|(h, _)| h).collect();
    for h in failing {
        gone.extend(drop_unheld(world, h, events));
    }
    remove_dependents(world, gone, events);
    Ok(())
}

/// Removes, transitively, the constraints that `breaks_with` one of the
/// labels in `gone` (reported as broken with force 0).
pub(crate) fn remove_dependents(world: &mut World, mut gone: Vec<String>, events: &mut Vec<Event>) {
    while !gone.is_empty() {
        let deps: Vec<_> = world
            .constraints
            .iter()
            .filter(|(_, c)| c.breaks_with.iter().any(|l| gone.contains(l)))
            .map(|(h, _)| h)
            .collect();
        gone.clear();
        for h in deps {
            gone.extend(drop_unheld(world, h, events));
        }
    }
}

/// Removes constraint `h`, which can no longer hold (its partner broke, or
/// a rupture cut its rod between its points): reported as broken at force
/// 0; returns its label.
pub(crate) fn drop_unheld(world: &mut World, h: crate::handles::Index, events: &mut Vec<Event>) -> Option<String> {
    let c = world.constraints.remove(h)?;
    let policy = c.breaking.map(|b| b.policy).unwrap_or_default();
    if c.label.is_some() {
        world.groups.mark_broken(h.into(), world.time, 0.0);
    }
    let label = c.label.clone();
    events.push(Event::ConstraintBroken { constraint: h.into(), label: c.label, time: world.time, force: 0.0, policy, kind: c.kind });
    label
}
