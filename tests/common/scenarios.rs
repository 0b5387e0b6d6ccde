//! Reference scenarios of SPEC §10, shared by the showcase, the tests and
//! the benchmarks (SI units).
use strandkit::prelude::*;
use nalgebra::Vector3;
use strandkit::{
    ConstraintHandle, ConstraintKind, IntegrationParameters, Load, LoadHandle, Material, RodBuilder, RodHandle,
    RodOptions, Result, Section, World,
};

/// SPEC §10 cantilever: L = 4 m, R = 0.05 m, E = 200 GPa (ν 0.3, ρ 7800
/// kg/m³), clamped at x = 0 by position + roll and tangent, tip force
/// `force` (N) at x = L.
#[allow(dead_code)]
pub struct Cantilever {
    pub world: World,
    pub rod: RodHandle,
    pub clamp: ConstraintHandle,
    pub clamp_tangent: ConstraintHandle,
    pub load: LoadHandle,
}

pub fn cantilever(n_ctrl: usize, samples: usize, force: [f64; 3]) -> Result<Cantilever> {
    let steel = Material::new("steel", 200e9, 0.3, 7800.0)?;
    let rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(4.0, 0.0, 0.0))
        .control_points(n_ctrl)
        .section(Section::circle(0.05)?)
        .material(steel)
        .options(RodOptions { samples_per_segment: samples, ..Default::default() })
        .build()?;
    let (u0, u1) = rod.domain();
    let mut world = World::new(IntegrationParameters::default());
    let h = world.add_rod(rod);
    let clamp = world.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true; 4], target: [0.0; 4] }), 0.0)?;
    let clamp_tangent = world.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: [1.0, 0.0, 0.0] }), 0.0)?;
    let load = world.add_load(Load::PointForce(PointForce { rod: h, u: u1, force }))?;
    Ok(Cantilever { world, rod: h, clamp, clamp_tangent, load })
}

/// Elastica references of SPEC §10: (F [N], tip angle [rad], tip x, tip deflection [m]).
pub const CANTILEVER_REFERENCES: [(f64, f64, f64, f64); 5] = [
    (1e4, 0.08129, 3.9930, 0.2166),
    (5e4, 0.38540, 3.8422, 1.0140),
    (1e5, 0.67964, 3.5129, 1.7388),
    (2e5, 1.02631, 2.8979, 2.4945),
    (5e5, 1.37952, 1.9635, 3.1491),
];

/// Tip position and tip angle (rad, from the x axis in the x–y plane).
pub fn tip(world: &World, rod: RodHandle) -> Result<(Vector3<f64>, f64)> {
    let r = world.rod(rod)?;
    let u1 = r.domain().1;
    let p = r.position(u1)?;
    let t = r.tangent(u1)?;
    Ok((p, t.y.atan2(t.x)))
}
