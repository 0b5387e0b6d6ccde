//! II.D.1.c torsion coupling: a curved cable clamped at one end (position,
//! tangent and absolute material roll) whose clamp roll is turned through a
//! full turn sweeps a circle with its free end: the tip's distance to the
//! clamp axis stays constant (within 2 %) while its azimuth covers 2π.
use strandkit::prelude::*;
use nalgebra::Vector3;

#[test]
fn turning_the_clamp_roll_sweeps_a_circle() {
    let radius = 0.2;
    let length = 0.5; // 2.5 rad of arc, curving from +x towards +y
    let cable = Material::new("cable", 1e9, 0.35, 1500.0).unwrap();
    let rod = RodBuilder::curve(length, move |s| {
        Vector3::new(radius * (s / radius).sin(), radius * (1.0 - (s / radius).cos()), 0.0)
    })
    .control_points(16)
    .section(Section::circle(0.003).unwrap())
    .material(cable)
    .options(RodOptions { curvature_threshold: 0.1 / length, ..Default::default() })
    .build()
    .unwrap();
    let (u0, u1) = rod.domain();
    let mut w = World::new(IntegrationParameters { relax_max_iterations: 3000, ..Default::default() });
    let h = w.add_rod(rod);
    w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true, true, true, false], target: [0.0; 4] }), 0.0)
        .unwrap();
    w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    let roll = w
        .add_constraint(h, ConstraintKind::MaterialRoll(MaterialRoll { u: u0, reference: [0.0, 1.0, 0.0], angle: 0.0 }), 0.0)
        .unwrap();
    w.relax().unwrap();
    let tip0 = w.rod(h).unwrap().position(u1).unwrap();
    let rho0 = (tip0.y * tip0.y + tip0.z * tip0.z).sqrt();
    let (mut min_r, mut max_r) = (rho0, rho0);
    let mut swept = 0.0;
    let mut prev_az = tip0.z.atan2(tip0.y);
    let steps = 90;
    for k in 1..=steps {
        let angle = 2.0 * std::f64::consts::PI * k as f64 / steps as f64;
        w.set_constraint(roll, ConstraintKind::MaterialRoll(MaterialRoll { u: u0, reference: [0.0, 1.0, 0.0], angle })).unwrap();
        w.relax().unwrap();
        let p = w.rod(h).unwrap().position(u1).unwrap();
        let rho = (p.y * p.y + p.z * p.z).sqrt();
        min_r = min_r.min(rho);
        max_r = max_r.max(rho);
        let az = p.z.atan2(p.y);
        let mut d = az - prev_az;
        if d > std::f64::consts::PI {
            d -= 2.0 * std::f64::consts::PI;
        }
        if d < -std::f64::consts::PI {
            d += 2.0 * std::f64::consts::PI;
        }
        swept += d;
        prev_az = az;
        assert!((p.x - tip0.x).abs() < 0.02 * rho0, "tip left the sweep plane: x {} vs {}", p.x, tip0.x);
    }
    println!("tip radius {rho0:.5} m, range [{min_r:.5}, {max_r:.5}], swept {swept:.4} rad");
    assert!((max_r - min_r) < 1e-5 * rho0, "tip radius range {} of {rho0}", max_r - min_r);
    assert!((swept.abs() - 2.0 * std::f64::consts::PI).abs() < 1e-6, "swept {swept}");
    // The clamp torque vanishes: the rigidly rotated cable is stress-free.
    assert!(w.reaction(roll).unwrap().torque.iter().all(|t| t.abs() < 1e-6));
}
