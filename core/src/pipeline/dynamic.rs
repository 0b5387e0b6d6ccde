//! Linearised implicit Euler (II.77–II.82; V^n is the velocity):
//!   (M/h² + D/h + K^n) ΔX = M V^n / h + F + P^n,   V^{n+1} = ΔX / h,
//! with the constraint rows of SPEC §4 in the same solve.
use super::assemble::Regime;
use super::{post_solve, solve, StepReport};
use crate::error::Result;
use crate::world::World;

/// Advances the world by one time step `params.dt`.
pub fn step(world: &mut World) -> Result<StepReport> {
    world.params.validate()?;
    let h = world.params.dt;
    super::beads::predict(world, h)?;
    let (energy, solved) = solve::assemble_and_solve(world, Regime::Dynamic { h })?;
    solve::commit(world, 1.0, Some(1.0 / h))?;
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
        events,
    })
}
