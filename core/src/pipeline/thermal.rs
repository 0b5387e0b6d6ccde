//! The thermal part of a dynamic step (SPEC §3, "Thermal fluctuations"):
//! checks that the world can carry noise, draws the step's standard
//! normals, and keeps the stream's new position only once the step
//! succeeds (a refused step draws the same numbers when retried).
use crate::error::{Error, Result};
use crate::force::thermal::{normals_per_rod, Stream};
use crate::world::{Scheme, World};

/// Before a dynamic step of `h`: with T > 0, the normals of every rod in
/// the workspace (the assembly turns them into forces) and the stream
/// after them; None without noise.
pub(crate) fn begin(world: &mut World, h: f64) -> Result<Option<Stream>> {
    world.ws.thermal_h = 0.0;
    let p = &world.params;
    if (p.temperature > 0.0 || p.overdamped) && p.scheme == Scheme::TrBdf2 {
        return Err(Error::input(
            "thermal noise and overdamped dynamics need scheme 'implicit_euler' or 'trapezoidal' (TR-BDF2's two stages have no matching noise)",
        ));
    }
    let kt = p.kt();
    if kt == 0.0 {
        return Ok(None);
    }
    let (eta, seed) = (p.viscosity, p.seed);
    // A new seed starts its stream from the beginning.
    let mut stream = if world.noise.seed == seed { world.noise } else { Stream { seed, words: 0 } };
    let World { rods, ws, .. } = world;
    ws.thermal_normals.resize_with(rods.len(), Vec::new);
    for (r, (handle, rod)) in rods.iter().enumerate() {
        let drag = rod.drag(eta)?;
        if drag.trans == 0.0 || rod.dofs() == 4 && drag.roll == 0.0 && drag.roll_r2 == 0.0 {
            return Err(Error::input(format!(
                "thermal noise (temperature > 0) on rod {:?} without drag{}: the bath acts through the drag (fluctuation–dissipation); set World(viscosity=…) or the rod's drag/roll_drag",
                crate::handles::RodHandle::from(handle),
                if drag.trans == 0.0 { "" } else { " on its roll" }
            )));
        }
        let v = &mut ws.thermal_normals[r];
        v.clear();
        v.resize(normals_per_rod(rod), 0.0);
        stream = stream.draw(v);
    }
    ws.thermal_h = h;
    ws.thermal_kt = kt;
    Ok(Some(stream))
}
