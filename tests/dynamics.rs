//! Issue "Show 5": momentum and energy of a free rod, the rigid-rod
//! pendulum frequency, and quasi-static = dynamic with a huge step (IV.B.1.c).
mod common;
use strandkit::prelude::*;
use common::*;
use nalgebra::Vector3;

/// A pre-deformed free rod with spinning initial velocities: linear momentum
/// is conserved to 1e-10 (relative to Σ|M V|) and the total energy
/// (kinetic + elastic) never grows over 2000 steps (linearised implicit Euler
/// only dissipates).
#[test]
fn free_rod_conserves_momentum_and_does_not_gain_energy() {
    for roll in [false, true] {
        free_rod_case(roll);
    }
}

fn free_rod_case(roll: bool) {
    let rod = spinning_free_rod(roll);
    let mut w = World::new(IntegrationParameters { dt: 1e-3, parallel: false, ..Default::default() });
    let h = w.add_rod(rod);
    let total = |w: &World| {
        let r = w.rod(h).unwrap();
        r.kinetic_energy() + r.elastic_energy()
    };
    let p0 = w.rod(h).unwrap().momentum();
    let scale = {
        let r = w.rod(h).unwrap();
        let mut mv = vec![0.0; r.velocities().len()];
        r.mass_times(r.velocities(), &mut mv);
        mv.iter().map(|x| x.abs()).sum::<f64>()
    };
    let e0 = total(&w);
    let mut emax: f64 = e0;
    let mut drift: f64 = 0.0;
    for _ in 0..2000 {
        w.step().unwrap();
        emax = emax.max(total(&w));
        let p = w.rod(h).unwrap().momentum();
        drift = drift.max((p - p0).norm() / scale);
    }
    let e1 = total(&w);
    println!("roll {roll}: energy {e0:.6e} -> {e1:.6e} (max {emax:.6e}), momentum drift {drift:.3e}");
    assert!(drift <= 1e-10, "momentum drift {drift}");
    assert!(emax <= e0 * (1.0 + 1e-9), "energy grew: {e0} -> max {emax}");
    assert!(e1 > 0.2 * e0, "implausibly strong numerical damping: {e0} -> {e1}");
}

/// A stiff rod pinned at one end swings with ω = √(3g/(2L)) (rigid rod
/// pendulum, small amplitude), within 2 %.
#[test]
fn pinned_stiff_rod_swings_like_a_rigid_pendulum() {
    let (len, g, phi0) = (1.0, 9.81, 0.05f64);
    let tip = Vector3::new(len * phi0.sin(), -len * phi0.cos(), 0.0);
    let rod = RodBuilder::straight(Vector3::zeros(), tip)
        .control_points(8)
        .with_roll(false)
        .section(Section::circle(0.01).unwrap())
        .material(Material::preset("carbon_steel").unwrap())
        .build()
        .unwrap();
    let u0 = rod.domain().0;
    let u1 = rod.domain().1;
    let dt = 1e-3;
    let mut w = World::new(IntegrationParameters { dt, gravity: [0.0, -g, 0.0], parallel: false, ..Default::default() });
    let h = w.add_rod(rod);
    w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true, true, true, false], target: [0.0; 4] }), 0.0)
        .unwrap();
    let mut crossings = Vec::new();
    let mut prev = w.rod(h).unwrap().position(u1).unwrap().x;
    for _ in 0..6000 {
        w.step().unwrap();
        let x = w.rod(h).unwrap().position(u1).unwrap().x;
        if prev > 0.0 && x <= 0.0 || prev < 0.0 && x >= 0.0 {
            // linear interpolation of the crossing time
            crossings.push(w.time() - dt * x / (x - prev));
        }
        prev = x;
    }
    assert!(crossings.len() >= 5, "too few zero crossings: {}", crossings.len());
    let half = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let omega = std::f64::consts::PI / half;
    let expected = (3.0 * g / (2.0 * len)).sqrt();
    println!("pendulum: ω = {omega:.5} rad/s, rigid rod {expected:.5} ({:.3} %)", 100.0 * (omega / expected - 1.0));
    // README: within 0.016 % (−0.016 % measured; the rod's extensibility).
    assert!((omega / expected - 1.0).abs() < 2e-4);
}

/// Quasi-static and dynamic with a very large step reach the same
/// equilibrium (IV.B.1.c): the cantilever under a 1e4 N tip load.
#[test]
fn quasi_static_equals_dynamic_with_huge_step() {
    let mut a = cantilever(12, 4, [0.0, -1e4, 0.0]);
    a.world.relax().unwrap();
    let mut b = cantilever(12, 4, [0.0, -1e4, 0.0]);
    b.world.params.dt = 1e6;
    for _ in 0..30 {
        b.world.step().unwrap();
    }
    let (pa, _) = tip(&a.world, a.rod);
    let (pb, _) = tip(&b.world, b.rod);
    println!("static tip {pa:?}, dynamic tip {pb:?}");
    assert!((pa - pb).norm() < 1e-8 * 4.0, "{}", (pa - pb).norm());
}

/// Assembly on rayon's pool (batches spanning rods, from 2048 segments on)
/// computes every segment as the serial path does and scatters in the same
/// order: 120 pre-deformed rods (2,640 segments) step bit-identically with
/// `parallel` on and off.
#[test]
fn parallel_assembly_is_bit_identical_to_serial() {
    let build = |parallel: bool| {
        let mut w = World::new(IntegrationParameters { dt: 1e-3, parallel, gravity: [0.0, -9.81, 0.0], ..Default::default() });
        let hs: Vec<RodHandle> = (0..120)
            .map(|i| {
                let z = 0.1 * i as f64;
                let rod = RodBuilder::straight(Vector3::new(0.0, 0.0, z), Vector3::new(1.0, 0.0, z))
                    .control_points(25)
                    .section(Section::circle(0.01).unwrap())
                    .material(Material::new("steel", 200e9, 0.3, 7800.0).unwrap())
                    .build()
                    .unwrap();
                let h = w.add_rod(rod);
                let mut q = w.rod(h).unwrap().coords().to_vec();
                // Smooth bends and twists, a little different per rod.
                for (k, c) in q.chunks_exact_mut(4).enumerate() {
                    let s = std::f64::consts::PI * k as f64 / 24.0;
                    c[1] += 1e-3 * (1.0 + 0.01 * i as f64) * s.sin();
                    c[2] += 5e-4 * (2.0 * s).sin();
                    c[3] += 5e-3 * s.sin();
                }
                w.rod_mut(h).unwrap().set_coords(&q).unwrap();
                h
            })
            .collect();
        (w, hs)
    };
    let (mut a, ha) = build(false);
    let (mut b, hb) = build(true);
    for _ in 0..3 {
        a.step().unwrap();
        b.step().unwrap();
    }
    for (x, y) in ha.iter().zip(&hb) {
        let (qa, qb) = (a.rod(*x).unwrap().coords(), b.rod(*y).unwrap().coords());
        assert!(qa.iter().zip(qb).all(|(u, v)| u.to_bits() == v.to_bits()), "rod {x:?}: parallel and serial differ");
    }
}
