//! Bead updates around the rod solve (see [`crate::bead`]).
use crate::error::Result;
use crate::handles::Index;
use crate::world::{Event, World};
use nalgebra::Vector3;

/// Weight plus user force of a bead.
pub(crate) fn bead_load(world: &World, b: &crate::bead::Bead) -> Vector3<f64> {
    Vector3::from(world.params.gravity) * b.mass + Vector3::from(b.force)
}

/// Dynamics, before the rod solve. A sliding bead's motion along the rod
/// is its own unknown: its absolute tangential speed w = ṡ + t·v_rod
/// follows (m/h + c) w_{n+1} = m w_n/h + t·F_p + c t·v_rod (implicit in
/// the friction c, the rod's velocity taken at the start of the step),
/// while the rod carries its transverse inertia (its mass matrix gets
/// m (I − t tᵀ) at the bead). The predicted increments are projected so
/// that no two neighbours end the step closer than r_a + r_b (an inelastic
/// impulse shared by mass, which only removes kinetic energy). The force
/// on the rod during the step: the normal part of F_p, the friction
/// c ṡ t, and −m (ṡ² κn + 2ṡ (∂v_rod/∂s)⊥) of the bead following the
/// rod's curvature and turning (x = r(s(t), t)). A fixed bead rides with
/// the rod: whole load, whole mass.
pub(crate) fn predict(world: &mut World, h: f64) -> Result<()> {
    let ids: Vec<Index> = world.beads.iter().map(|(i, _)| i).collect();
    let beads: Vec<&crate::bead::Bead> = world.beads.iter().map(|(_, b)| b).collect();
    let mut ds = Vec::with_capacity(ids.len());
    let mut rod_speed = Vec::with_capacity(ids.len());
    for &b in &beads {
        let rod = world.rod(b.rod)?;
        let t = rod.tangent(b.u)?;
        let v_r = t.dot(&rod.eval_velocity(b.u)?);
        rod_speed.push(v_r);
        if b.fixed {
            ds.push(0.0);
            continue;
        }
        let w_n = b.velocity + v_r;
        let w = (b.mass * w_n / h + t.dot(&bead_load(world, b)) + b.friction * v_r) / (b.mass / h + b.friction);
        ds.push(h * (w - v_r));
    }
    let u_now: Vec<f64> = beads.iter().map(|b| b.u).collect();
    let pairs = neighbours(world, &ids, &u_now)?;
    let mut gaps = Vec::with_capacity(pairs.len());
    for &(a, b, period) in &pairs {
        let (ba, bb) = (beads[a], beads[b]);
        gaps.push(arc(world.rod(ba.rod)?, ba.u, bb.u + period)? - ba.radius - bb.radius);
    }
    // Gauss–Seidel on the increments (a chain of touching beads needs a
    // few passes); fixed beads do not move.
    for _ in 0..50 {
        let mut worst = 0.0f64;
        for (&(a, b, _), &gap) in pairs.iter().zip(&gaps) {
            let c = gap + ds[b] - ds[a];
            if c >= 0.0 {
                continue;
            }
            let inv = |k: usize| if beads[k].fixed { 0.0 } else { 1.0 / beads[k].mass };
            let (wa, wb) = (inv(a), inv(b));
            if wa + wb == 0.0 {
                continue;
            }
            ds[a] += c * wa / (wa + wb);
            ds[b] -= c * wb / (wa + wb);
            worst = worst.max(-c);
        }
        if worst <= 1e-12 * h {
            break;
        }
    }
    let mut out = Vec::with_capacity(ids.len());
    for (k, (&b, i)) in beads.iter().zip(&ids).enumerate() {
        let fp = bead_load(world, b);
        let f = if b.fixed {
            fp
        } else {
            let rod = world.rod(b.rod)?;
            let (d1, d2) = (rod.eval(b.u, 1)?, rod.eval(b.u, 2)?);
            let (d1, d2) = (Vector3::new(d1[0], d1[1], d1[2]), Vector3::new(d2[0], d2[1], d2[2]));
            let sigma = d1.norm();
            let t = d1 / sigma;
            let normal = |x: Vector3<f64>| x - t * x.dot(&t);
            let v = ds[k] / h;
            let kappa_n = normal(d2) / (sigma * sigma);
            let turn = normal(rod.velocity_derivative(b.u, 1)? / sigma);
            normal(fp) + t * (b.friction * v) - (kappa_n * (v * v) + turn * (2.0 * v)) * b.mass
        };
        if !ds[k].is_finite() || !f.iter().all(|x| x.is_finite()) {
            return Err(crate::error::Error::NonFinite {
                rod: Some(b.rod),
                detail: format!("bead {}: its sliding step or its force on the rod is not finite (mass {:e}); the world is unchanged", i.0, b.mass),
            });
        }
        out.push(f);
    }
    for (k, (&i, f)) in ids.iter().zip(out).enumerate() {
        if let Some(b) = world.beads.get_mut(i) {
            b.step_ds = ds[k];
            b.step_w = ds[k] / h + rod_speed[k];
            b.rod_force = f.into();
        }
    }
    Ok(())
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
/// `ids`), with the period to add to the second's abscissa: on a closed
/// rod the last and first are neighbours across the seam.
fn neighbours(world: &World, ids: &[Index], u: &[f64]) -> Result<Vec<(usize, usize, f64)>> {
    let rod_of = |k: usize| world.beads.get(ids[k]).map(|x| x.rod.index).unwrap_or(0);
    let mut order: Vec<usize> = (0..ids.len()).collect();
    order.sort_by(|&a, &b| rod_of(a).cmp(&rod_of(b)).then(u[a].total_cmp(&u[b])));
    let mut pairs = Vec::new();
    let mut k = 0;
    while k < order.len() {
        let mut e = k;
        while e + 1 < order.len() && rod_of(order[e + 1]) == rod_of(order[k]) {
            pairs.push((order[e], order[e + 1], 0.0));
            e += 1;
        }
        if e > k {
            if let Some(b) = world.beads.get(ids[order[k]]) {
                if let Some(p) = period(world.rod(b.rod)?) {
                    pairs.push((order[e], order[k], p));
                }
            }
        }
        k = e + 1;
    }
    Ok(pairs)
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
        if b.fixed {
            continue;
        }
        // Sliding speed relative to the rod as it now moves.
        let rod = world.rod(b.rod)?;
        let d = rod.eval(b.u, 1)?;
        let d1 = Vector3::new(d[0], d[1], d[2]);
        let speed = d1.norm();
        let v = b.step_w - (d1 / speed).dot(&rod.eval_velocity(b.u)?);
        let du = h * v / speed;
        // On a closed rod a bead goes round: its abscissa wraps.
        let period = period(rod);
        if let Some(b) = world.beads.get_mut(i) {
            b.u = period.map_or(b.u + du, |p| (b.u + du).rem_euclid(p));
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

/// After the step, what the predicted increments could not foresee (the
/// rod stretched or bent under them): neighbours closer than r_a + r_b
/// are set r_a + r_b apart about their centre of mass, with a common
/// velocity (inelastic; a fixed bead acts as an infinite mass).
pub(crate) fn contacts(world: &mut World, ids: &[Index], old_u: &[f64]) -> Result<()> {
    for (ka, kb, period) in neighbours(world, ids, old_u)? {
        let (Some(a), Some(b)) = (world.beads.get(ids[ka]).cloned(), world.beads.get(ids[kb]).cloned()) else {
            continue;
        };
        let rod = world.rod(a.rod)?;
        let bu = b.u + period;
        let gap = arc(rod, a.u, bu)?;
        let need = a.radius + b.radius;
        if gap >= need {
            continue;
        }
        let (ma, mb) = match (a.fixed, b.fixed) {
            (true, true) => continue,
            (true, false) => (1.0, 0.0),
            (false, true) => (0.0, 1.0),
            (false, false) => (a.mass, b.mass),
        };
        let m = ma + mb;
        let (sc, v) = ((ma * a.u + mb * bu) / m, (ma * a.velocity + mb * b.velocity) / m);
        let span = need / (gap / (bu - a.u).max(f64::MIN_POSITIVE));
        let wrap = |u: f64| if period > 0.0 { u.rem_euclid(period) } else { u };
        if let Some(x) = world.beads.get_mut(ids[ka]) {
            x.u = wrap(sc - span * mb / m);
            x.velocity = v;
        }
        if let Some(x) = world.beads.get_mut(ids[kb]) {
            x.u = wrap(sc + span * ma / m - period);
            x.velocity = v;
        }
    }
    Ok(())
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
