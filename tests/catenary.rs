//! SPEC §10 catenary (II.105, annex E): span 1 m, length 1.2 m, weight 1 N/m
//! → a = 0.4695 m, sag 0.2923 m, H = 0.4695 N, T_max = 0.762 N.
//! A nearly inextensible, nearly perfectly flexible rope: EA = 1e4 N (strain
//! < 1e-4), EI = 1e-6 N·m² (bending boundary layer √(EI/H) ≈ 1.5 mm).
mod common;
use strandkit::prelude::*;
use nalgebra::Vector3;

#[test]
fn catenary_sag_and_tensions() {
    let r = 2e-5;
    let area = std::f64::consts::PI * r * r;
    let e = 1e4 / area;
    let rope = Material::new("rope", e, 0.3, 1000.0).unwrap();
    let n = 30;
    let mut rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(1.2, 0.0, 0.0))
        .control_points(n)
        .with_roll(false)
        .section(Section::circle(r).unwrap())
        .material(rope)
        .build()
        .unwrap();
    // Start from a sagging arc (the rest shape stays straight).
    common::sag(&mut rod, 1.2, 1.0);
    let (u0, u1) = rod.domain();
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(rod);
    let xyz = [true, true, true, false];
    let a = w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: xyz, target: [0.0; 4] }), 0.0).unwrap();
    let b = w
        .add_constraint(h, ConstraintKind::Position(Position { u: u1, axes: xyz, target: [1.0, 0.0, 0.0, 0.0] }), 0.0)
        .unwrap();
    w.add_load(Load::Distributed(Distributed { rod: h, force_per_length: [0.0, -1.0, 0.0] })).unwrap();
    let rep = w.relax().unwrap();
    let rod = w.rod(h).unwrap();
    let (um, _) = rod.domain();
    let mid = rod.position(0.5 * (um + u1)).unwrap();
    let sag = -rod.sample_points().iter().map(|p| p.y).fold(0.0, f64::min).min(mid.y);
    let (fa, fb) = (w.reaction(a).unwrap().force, w.reaction(b).unwrap().force);
    let hor = fb[0].abs();
    let tmax = Vector3::from(fb).norm().max(Vector3::from(fa).norm());
    println!("catenary: sag {sag:.5} (0.2923), H {hor:.5} (0.4695), T_max {tmax:.5} (0.762); {} iterations", rep.iterations);
    assert!((sag - 0.2923).abs() < 5e-3 * 0.2923, "sag {sag}");
    assert!((hor - 0.4695).abs() < 1e-2 * 0.4695, "H {hor}");
    assert!((tmax - 0.762).abs() < 1e-2 * 0.762, "T_max {tmax}");
    // Vertical reactions carry the whole weight (1.2 N) equally.
    assert!((fa[1] + fb[1] - 1.2).abs() < 1e-6 && (fa[1] - fb[1]).abs() < 1e-6);
}
