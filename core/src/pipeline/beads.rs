//! Bead updates around the rod solve (see [`crate::bead`]).
use crate::error::Result;
use crate::handles::Index;
use crate::world::{Event, World};
use nalgebra::Vector3;

/// Weight plus user force of a bead.
pub(crate) fn bead_load(world: &World, b: &crate::bead::Bead) -> Vector3<f64> {
    Vector3::from(world.params.gravity) * b.mass + Vector3::from(b.force)
}

/// Dynamics, before the rod solve: the bead's arc-length increment from
/// (c/h + m/h²) Δs_{n+1} = t·F_p + m Δs_n/h², and the force
/// F_p − m a_t t it applies to the rod during the step.
pub(crate) fn predict(world: &mut World, h: f64) -> Result<()> {
    let ids: Vec<Index> = world.beads.iter().map(|(i, _)| i).collect();
    for i in ids {
        let Some(b) = world.beads.get(i) else { continue };
        let t = world.rod(b.rod)?.tangent(b.u)?;
        let fp = bead_load(world, b);
        let ds_n = b.velocity * h;
        let ds = (t.dot(&fp) + b.mass * ds_n / (h * h)) / (b.friction / h + b.mass / (h * h));
        let a_t = (ds - ds_n) / (h * h);
        let f = fp - t * (b.mass * a_t);
        if !ds.is_finite() || !f.iter().all(|x| x.is_finite()) {
            return Err(crate::error::Error::NonFinite {
                rod: Some(b.rod),
                detail: format!("bead {}: its sliding step or its force on the rod is not finite (mass {:e}); the world is unchanged", i.0, b.mass),
            });
        }
        if let Some(b) = world.beads.get_mut(i) {
            b.step_ds = ds;
            b.rod_force = f.into();
        }
    }
    Ok(())
}

/// Statics: the bead's whole load goes to the rod.
pub(crate) fn static_load(world: &mut World) {
    let g = Vector3::from(world.params.gravity);
    for (_, b) in world.beads.iter_mut() {
        b.rod_force = (g * b.mass + Vector3::from(b.force)).into();
        b.step_ds = 0.0;
        b.velocity = 0.0;
    }
}

/// Dynamics, after the rod solve: advance each bead along the new rod
/// shape, keep beads from passing each other, remove those that left.
pub(crate) fn advance(world: &mut World, h: f64) -> Result<Vec<Event>> {
    let ids: Vec<Index> = world.beads.iter().map(|(i, _)| i).collect();
    let old_u: Vec<f64> = ids.iter().filter_map(|i| world.beads.get(*i).map(|b| b.u)).collect();
    for &i in &ids {
        let Some(b) = world.beads.get(i) else { continue };
        let rod = world.rod(b.rod)?;
        let speed = rod.eval(b.u, 1).map(|d| Vector3::new(d[0], d[1], d[2]).norm())?;
        let (du, v) = (b.step_ds / speed, b.step_ds / h);
        if let Some(b) = world.beads.get_mut(i) {
            b.u += du;
            b.velocity = v;
        }
    }
    contacts(world, &ids, &old_u)?;
    let mut events = Vec::new();
    for &i in &ids {
        let Some(b) = world.beads.get(i) else { continue };
        let (a, z) = world.rod(b.rod)?.domain();
        if b.u < a || b.u > z {
            world.beads.remove(i);
            events.push(Event::BeadLeft { bead: i.into(), time: world.time });
        }
    }
    Ok(events)
}

/// Inelastic contact between neighbouring beads of a rod (order of the
/// previous step): centre of mass and momentum kept, gap r_a + r_b.
pub(crate) fn contacts(world: &mut World, ids: &[Index], old_u: &[f64]) -> Result<()> {
    let mut order: Vec<usize> = (0..ids.len()).collect();
    order.sort_by(|&a, &b| {
        let (ba, bb) = (world.beads.get(ids[a]), world.beads.get(ids[b]));
        let ra = ba.map(|x| x.rod.index).unwrap_or(0);
        let rb = bb.map(|x| x.rod.index).unwrap_or(0);
        ra.cmp(&rb).then(old_u[a].total_cmp(&old_u[b]))
    });
    for w in order.windows(2) {
        let (Some(a), Some(b)) = (world.beads.get(ids[w[0]]).cloned(), world.beads.get(ids[w[1]]).cloned()) else {
            continue;
        };
        if a.rod != b.rod {
            continue;
        }
        let rod = world.rod(a.rod)?;
        let mid = 0.5 * (a.u + b.u);
        let (lo, hi) = rod.domain();
        let d = rod.eval(mid.clamp(lo, hi), 1)?;
        let speed = Vector3::new(d[0], d[1], d[2]).norm();
        let gap = (b.u - a.u) * speed;
        let need = a.radius + b.radius;
        if gap >= need {
            continue;
        }
        let m = a.mass + b.mass;
        let (sc, v) = ((a.mass * a.u + b.mass * b.u) / m, (a.mass * a.velocity + b.mass * b.velocity) / m);
        let span = need / speed;
        if let Some(x) = world.beads.get_mut(ids[w[0]]) {
            x.u = sc - span * b.mass / m;
            x.velocity = v;
        }
        if let Some(x) = world.beads.get_mut(ids[w[1]]) {
            x.u = sc + span * a.mass / m;
            x.velocity = v;
        }
    }
    Ok(())
}

/// Statics: moves the beads by their solved abscissa increments
/// (clamped to the rod) and returns the largest |Δu|.
pub(crate) fn apply(world: &mut World, du: &[f64]) -> Result<f64> {
    let mut worst = 0.0f64;
    let ids: Vec<Index> = world.beads.iter().map(|(i, _)| i).collect();
    for (i, d) in ids.into_iter().zip(du) {
        let Some(b) = world.beads.get(i) else { continue };
        let (lo, hi) = world.rod(b.rod)?.domain();
        let u = (b.u + d).clamp(lo, hi);
        worst = worst.max((u - b.u).abs());
        if let Some(b) = world.beads.get_mut(i) {
            b.u = u;
        }
    }
    Ok(worst)
}
