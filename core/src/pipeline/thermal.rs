//! The thermal part of a dynamic step (SPEC §3, "Thermal fluctuations"):
//! checks that the world can carry noise (or Brownian dynamics), draws the
//! step's standard normals, and keeps the stream's new position only once
//! the step succeeds (a step refused with an error leaves it as it was).
//!
//! A step refused and retried as n sub-steps (`adaptive_dt`) keeps the
//! refused step's Brownian path: the sub-steps' normals η_1…η_n are drawn
//! from a discrete Brownian bridge pinned to Σ η_j = √n ξ (ξ the refused
//! step's normals), η_j ~ N(S/m, 1 − 1/m) given the sum S still to come
//! over the m sub-steps left. Fresh noise would bias the retried intervals
//! (large kicks are what make a step fail), reusing ξ in each sub-step
//! would heat them.
use crate::error::{Error, Result};
use crate::force::thermal::{normals_per_rod, Stream};
use crate::world::{Scheme, World};

/// The Brownian bridge of a retried step: per rod, the sum of the normals
/// still to come, and the number of sub-steps left.
#[derive(Clone, Debug, Default)]
pub(crate) struct Bridge {
    pub remaining: Vec<Vec<f64>>,
    pub left: usize,
}

/// The normals of a step's first try (None if it drew none), taken from
/// the workspace after it was refused, for [`bridge`].
pub(crate) fn take_first(world: &mut World) -> Option<Vec<Vec<f64>>> {
    let ws = &mut world.ws;
    ws.thermal_drawn.then(|| std::mem::take(&mut ws.thermal_first))
}

/// Before a retry as `n` sub-steps of the refused step whose normals are
/// `first`.
pub(crate) fn bridge(world: &mut World, n: usize, first: Option<&Vec<Vec<f64>>>) {
    let scale = (n as f64).sqrt();
    world.ws.bridge = first.filter(|_| n > 1).map(|f| Bridge { remaining: f.iter().map(|v| v.iter().map(|x| x * scale).collect()).collect(), left: n });
}

/// Checks that `world` can take a thermal or Brownian step of `h`; with
/// T > 0, draws every rod's normals into the workspace (the assembly turns
/// them into forces) and returns the stream after them; None without noise.
pub(crate) fn begin(world: &mut World, h: f64) -> Result<Option<Stream>> {
    world.ws.thermal_h = 0.0;
    world.ws.thermal_drawn = false;
    let p = &world.params;
    let kt = p.kt();
    if kt == 0.0 && !p.overdamped {
        return Ok(None);
    }
    let what = if kt > 0.0 { "thermal noise (temperature > 0)" } else { "Brownian dynamics (overdamped)" };
    if p.scheme == Scheme::TrBdf2 {
        return Err(Error::input(format!(
            "{what} needs scheme 'implicit_euler' or 'trapezoidal' (TR-BDF2's two stages have no matching noise)"
        )));
    }
    if world.beads.iter().any(|(_, b)| !b.fixed) {
        return Err(Error::input(format!(
            "{what} with sliding beads is not implemented (their motion along the rod has friction but no noise); fix the beads or remove them"
        )));
    }
    for (handle, rod) in world.rods.iter() {
        let drag = p.drag_of(rod)?;
        let handle = crate::handles::RodHandle::from(handle);
        // At T = 0 Brownian dynamics is a deterministic gradient flow: a
        // configuration-dependent drag needs no drift there.
        if p.overdamped && kt > 0.0 && drag.axial != 0.0 {
            return Err(Error::input(format!(
                "{what} on rod {handle:?} with anisotropic drag is not implemented (a configuration-dependent drag needs the kT ∇·D⁻¹ drift); set World(isotropic_drag=True)"
            )));
        }
        if drag.trans == 0.0 || rod.dofs() == 4 && drag.roll == 0.0 && drag.roll_r2 == 0.0 {
            return Err(Error::input(format!(
                "{what} on rod {handle:?} without drag{}: the bath acts through the drag (fluctuation–dissipation); set World(viscosity=…) or the rod's drag/roll_drag",
                if drag.trans == 0.0 { "" } else { " on its roll" }
            )));
        }
        if kt > 0.0 && rod.dofs() == 4 && rod.frame_model() == crate::energy::FrameModel::Frenet {
            return Err(Error::input(format!(
                "{what} on rod {handle:?}: its roll is measured from the Frenet frame, undefined where the fluctuating rod is straight; build it with model='reference' (or without roll)"
            )));
        }
    }
    if kt == 0.0 {
        return Ok(None);
    }
    let seed = p.seed;
    // A new seed starts its stream from the beginning (so seeds A, B, A
    // replay A's numbers).
    let mut stream = if world.noise.seed == seed { world.noise } else { Stream { seed, words: 0 } };
    let World { rods, ws, params, .. } = world;
    ws.thermal_normals.resize_with(rods.len(), Vec::new);
    for (r, (_, rod)) in rods.iter().enumerate() {
        let v = &mut ws.thermal_normals[r];
        v.clear();
        v.resize(normals_per_rod(rod, &params.drag_of(rod)?), 0.0);
        stream = stream.draw(v);
    }
    if let Some(b) = ws.bridge.as_mut().filter(|b| b.left > 0 && b.remaining.len() == rods.len()) {
        // η = S/m + √(1 − 1/m) ζ, then S −= η.
        let m = b.left as f64;
        let spread = (1.0 - 1.0 / m).sqrt();
        for (z, s) in ws.thermal_normals.iter_mut().zip(b.remaining.iter_mut()) {
            for (z, s) in z.iter_mut().zip(s.iter_mut()) {
                *z = *s / m + spread * *z;
                *s -= *z;
            }
        }
        b.left -= 1;
    } else {
        // The first try of a step: its normals, should it be retried.
        ws.thermal_first.clone_from(&ws.thermal_normals);
    }
    ws.thermal_h = h;
    ws.thermal_kt = kt;
    ws.thermal_drawn = true;
    Ok(Some(stream))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::{IntegrationParameters, Units};
    use crate::{Material, RodBuilder, Section};
    use nalgebra::Vector3;

    /// The sub-steps of a retried step sum to the refused step's normals
    /// (× √n, the same Brownian path) and are themselves standard normals.
    #[test]
    fn retried_sub_steps_follow_the_refused_steps_path() {
        let mut w = World::new(IntegrationParameters {
            temperature: 298.15,
            units: Units::Molecular,
            viscosity: 1.0,
            scheme: Scheme::Trapezoidal,
            seed: 5,
            ..Default::default()
        });
        for _ in 0..4 {
            let rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(50.0, 0.0, 0.0))
                .control_points(40)
                .with_roll(false)
                .section(Section::circle(1.0).unwrap())
                .material(Material::new("dna", 262.0, -0.5, 1.7e-3).unwrap())
                .build()
                .unwrap();
            w.add_rod(rod);
        }
        begin(&mut w, 1e-3).unwrap();
        let first = take_first(&mut w).unwrap();
        let count: usize = first.iter().map(Vec::len).sum();
        for n in [2usize, 4, 8] {
            bridge(&mut w, n, Some(&first));
            let mut sum: Vec<Vec<f64>> = first.iter().map(|v| vec![0.0; v.len()]).collect();
            let mut squares = 0.0;
            for _ in 0..n {
                w.noise = begin(&mut w, 1e-3 / n as f64).unwrap().unwrap();
                for (s, z) in sum.iter_mut().zip(&w.ws.thermal_normals) {
                    s.iter_mut().zip(z).for_each(|(s, z)| *s += z);
                    squares += z.iter().map(|z| z * z).sum::<f64>();
                }
            }
            let scale = (n as f64).sqrt();
            let worst = sum.iter().flatten().zip(first.iter().flatten()).map(|(s, x)| (s - scale * x).abs()).fold(0.0, f64::max);
            assert!(worst < 1e-12, "n = {n}: the sub-steps' normals miss the path by {worst}");
            // Mean square 1 within 4 standard errors √(2/N).
            let ms = squares / (n * count) as f64;
            assert!((ms - 1.0).abs() < 4.0 * (2.0 / (n * count) as f64).sqrt(), "n = {n}: mean square {ms}");
            w.ws.bridge = None;
        }
    }
}
