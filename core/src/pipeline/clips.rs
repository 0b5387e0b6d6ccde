//! Clips after a solve (thesis algorithms 4–5): release held rods pulled
//! out harder than the clip's resistance, capture rods that entered an
//! armed clip.
use crate::constraint::kinds::Position;
use crate::error::Result;
use crate::handles::RodHandle;
use crate::world::{Event, World};
use nalgebra::Vector3;

/// Appends what happened to `events`.
pub(crate) fn update(world: &mut World, events: &mut Vec<Event>) -> Result<()> {
    // The clip list is walked from a recycled buffer (clips change as
    // they go); the buffer returns to the workspace whatever happens.
    let mut ids = std::mem::take(&mut world.ws.clip_ids);
    ids.clear();
    ids.extend(world.clips.iter().map(|(i, _)| i));
    let out = update_listed(world, &ids, events);
    world.ws.clip_ids = ids;
    out
}

fn update_listed(world: &mut World, ids: &[crate::handles::Index], events: &mut Vec<Event>) -> Result<()> {
    for &i in ids {
        let Some(clip) = world.clips.get(i).cloned() else { continue };
        let axis = Vector3::from(clip.axis);
        if let Some((rod, con)) = clip.held {
            // Force of the clip on the rod along −axis = pull-out force.
            let pull = match world.reaction(con) {
                Ok(r) => -Vector3::from(r.force).dot(&axis),
                Err(_) => 0.0, // the constraint was removed (rod removed, broken)
            };
            if world.constraint(con).is_err() || pull > clip.resistance {
                let _ = world.remove_constraint(con);
                if let Some(c) = world.clips.get_mut(i) {
                    c.held = None;
                    c.disarmed = true;
                }
                events.push(Event::ClipReleased { clip: i.into(), rod, force: pull, time: world.time });
            }
            continue;
        }
        // Closest point of every rod to the centre.
        let centre = Vector3::from(clip.center);
        let mut best: Option<(RodHandle, f64, f64)> = None;
        for (h, rod) in world.rods() {
            let (u, d) = rod.closest_point(&centre)?;
            if d <= clip.radius && best.is_none_or(|b| d < b.2) {
                best = Some((h, u, d));
            }
        }
        match best {
            None => {
                if let Some(c) = world.clips.get_mut(i) {
                    c.disarmed = false;
                }
            }
            Some((rod, u, _)) if !clip.disarmed => {
                let kind = Position { u, axes: [true, true, true, false], target: [clip.center[0], clip.center[1], clip.center[2], 0.0] };
                if let Ok(con) = world.add_constraint(rod, kind, 0.0) {
                    if let Some(c) = world.clips.get_mut(i) {
                        c.held = Some((rod, con));
                    }
                    events.push(Event::ClipCaptured { clip: i.into(), rod, constraint: con, u, time: world.time });
                }
            }
            _ => {}
        }
    }
    Ok(())
}
