//! Scenario builders shared by the validation tests (SPEC §10).
#![allow(dead_code)]
use nalgebra::Vector3;
use strandkit::*;

/// SPEC §10 cantilever: L = 4 m, R = 0.05 m, E = 200 GPa, clamped at x = 0
/// (position + roll, tangent), tip load `force` (N) at x = L.
pub struct Cantilever {
    pub world: World,
    pub rod: RodHandle,
    pub clamp: ConstraintHandle,
    pub clamp_tangent: ConstraintHandle,
    pub load: LoadHandle,
}

pub fn cantilever(n_ctrl: usize, samples: usize, force: [f64; 3]) -> Cantilever {
    let steel = Material::new("steel", 200e9, 0.3, 7800.0).unwrap();
    let rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(4.0, 0.0, 0.0))
        .control_points(n_ctrl)
        .section(Section::circle(0.05).unwrap())
        .material(steel)
        .options(RodOptions { samples_per_segment: samples, ..Default::default() })
        .build()
        .unwrap();
    let (u0, u1) = rod.domain();
    let mut world = World::new(IntegrationParameters::default());
    let h = world.add_rod(rod);
    let clamp = world
        .add_constraint(h, ConstraintKind::Position { u: u0, axes: [true; 4], target: [0.0; 4] }, 0.0)
        .unwrap();
    let clamp_tangent = world.add_constraint(h, ConstraintKind::Tangent { u: u0, direction: [1.0, 0.0, 0.0] }, 0.0).unwrap();
    let load = world.add_load(Load::PointForce { rod: h, u: u1, force }).unwrap();
    Cantilever { world, rod: h, clamp, clamp_tangent, load }
}

/// Tip position and tip angle (rad, from the x axis in the x–y plane).
pub fn tip(world: &World, rod: RodHandle) -> (Vector3<f64>, f64) {
    let r = world.rod(rod).unwrap();
    let u1 = r.domain().1;
    let p = r.position(u1).unwrap();
    let t = r.tangent(u1).unwrap();
    (p, t.y.atan2(t.x))
}
