//! Perfect plasticity (SPEC §6, thesis II.C.2.a, algorithm 1, II.D.1.f):
//! permanent curvature and elongation after release, elastic return below
//! yield, offsets reset by yielding the other way, plastic letters.
use strandkit::prelude::*;
use nalgebra::Vector3;
use std::f64::consts::PI;
use strandkit::material::StrainLimits;

const L: f64 = 1.0;
const INF: (f64, f64) = (f64::NEG_INFINITY, f64::INFINITY);

/// A 1 m wire (E = 1 GPa, R = 5 mm), no roll coordinate, along x.
fn wire(n_ctrl: usize, limits: StrainLimits) -> Rod {
    let m = Material::new("wire", 1e9, 0.3, 8000.0).unwrap().with_yield(limits).unwrap();
    RodBuilder::straight(Vector3::zeros(), Vector3::new(L, 0.0, 0.0))
        .control_points(n_ctrl)
        .with_roll(false)
        .section(Section::circle(0.005).unwrap())
        .material(m)
        .build()
        .unwrap()
}

fn clamp_start(w: &mut World, h: RodHandle) {
    let u0 = w.rod(h).unwrap().domain().0;
    w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true, true, true, false], target: [0.0; 4] }), 0.0).unwrap();
    w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
}

/// Clamped at s = 0, end tangent turned to angle φ in the xy plane (a pure
/// end moment: uniform curvature φ/L), then the end is released.
/// Returns (curvature at every sample after release, plastic offsets κ2_p).
fn bend_and_release(phi: f64, yield_curvature: f64) -> (World, RodHandle, Vec<f64>, Vec<f64>) {
    let limits = StrainLimits { stretch: INF, bend: (-yield_curvature, yield_curvature), twist: INF };
    let mut w = World::new(IntegrationParameters { parallel: false, ..Default::default() });
    let h = w.add_rod(wire(16, limits));
    clamp_start(&mut w, h);
    let u1 = w.rod(h).unwrap().domain().1;
    let end = w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u1, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    // A rod without roll can spin about its clamped tangent: the wire lies
    // on a frictionless table (z = 0 at its end).
    w.add_constraint(h, ConstraintKind::Plane(Plane { u: u1, origin: [0.0; 3], normal: [0.0, 0.0, 1.0] }), 0.0).unwrap();
    let steps = 20;
    for k in 1..=steps {
        let a = phi * k as f64 / steps as f64;
        w.set_constraint(end, ConstraintKind::Tangent(Tangent { u: u1, direction: [a.cos(), a.sin(), 0.0] })).unwrap();
        w.relax().unwrap();
    }
    // Loaded: uniform moment, so uniform curvature φ/L up to the spline's
    // approximation and the (indeterminate) redistribution of plastic
    // curvature along a rod that is at yield everywhere.
    for s in w.rod(h).unwrap().strains() {
        assert!((s.kappa2 - phi / L).abs() < 0.02 * phi / L, "loaded curvature {} vs {}", s.kappa2, phi / L);
    }
    w.remove_constraint(end).unwrap();
    let r = w.relax().unwrap();
    assert_eq!(r.plastic_samples, 0, "unloading is elastic");
    let rod = w.rod(h).unwrap();
    let kappa: Vec<f64> = rod.strains().iter().map(|s| s.kappa2).collect();
    let offsets: Vec<f64> = rod.plastic_offsets().iter().map(|p| p.kappa2).collect();
    (w, h, kappa, offsets)
}

#[test]
fn bent_past_yield_keeps_the_accumulated_plastic_curvature() {
    let (phi, ky) = (PI, 1.0);
    let (w, h, kappa, offsets) = bend_and_release(phi, ky);
    // Perfect plasticity: all curvature beyond yield is kept, on average
    // exactly φ/L − κ_A (the turning angle is imposed).
    let expected = phi / L - ky;
    let n = offsets.len() as f64;
    let mean = offsets.iter().sum::<f64>() / n;
    assert!((mean - expected).abs() < 0.01 * expected, "mean offset {mean} vs {expected}");
    let mut worst: f64 = 0.0;
    for (k, p) in kappa.iter().zip(&offsets) {
        worst = worst.max((k - p).abs() / p);
    }
    let rod = w.rod(h).unwrap();
    let end_angle = { let t = rod.tangent(rod.domain().1).unwrap(); t.y.atan2(t.x) };
    println!(
        "plastic curvature: mean offset {mean:.5} 1/m (expected {expected:.5}); after release worst |κ − κ_p|/κ_p = {worst:.2e}, end tangent turned {end_angle:.5} rad (expected {:.5})",
        expected * L
    );
    assert!(worst < 0.01);
    assert!((end_angle - expected * L).abs() < 0.01 * expected * L);
}

#[test]
fn bent_below_yield_returns_to_its_rest_shape() {
    let (w, h, kappa, offsets) = bend_and_release(0.5, 1.0);
    assert!(offsets.iter().all(|p| *p == 0.0));
    let rod = w.rod(h).unwrap();
    let tip = rod.position(rod.domain().1).unwrap();
    println!("tip after release {tip:?}, max κ {:.2e}", kappa.iter().fold(0.0f64, |m, k| m.max(k.abs())));
    assert!((tip - Vector3::new(L, 0.0, 0.0)).norm() < 1e-6 * L);
}

#[test]
fn stretched_past_yield_keeps_a_permanent_elongation() {
    let limits = StrainLimits { stretch: (-0.01, 0.01), bend: INF, twist: INF };
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(wire(8, limits));
    clamp_start(&mut w, h);
    let u1 = w.rod(h).unwrap().domain().1;
    let pos = |x: f64| ConstraintKind::Position(Position { u: u1, axes: [true, true, true, false], target: [x, 0.0, 0.0, 0.0] });
    let end = w.add_constraint(h, pos(L), 0.0).unwrap();
    for k in 1..=4 {
        w.set_constraint(end, pos(L * (1.0 + 0.005 * k as f64))).unwrap();
        w.relax().unwrap();
    }
    for p in w.rod(h).unwrap().plastic_offsets() {
        assert!((p.eps - 0.01).abs() < 1e-6, "plastic stretch {}", p.eps);
    }
    w.remove_constraint(end).unwrap();
    w.relax().unwrap();
    let x = w.rod(h).unwrap().position(u1).unwrap().x;
    println!("length after release {x:.6} m (plastic elongation {:.3e} m, expected 1e-2 m)", x - L);
    assert!(((x - L) - 0.01 * L).abs() < 0.01 * 0.01 * L);
}

/// Algorithm 1 on imposed uniform stretches: the offset follows the excess
/// beyond ε_A±, stays put inside, and yielding the other way resets it.
#[test]
fn offsets_move_only_beyond_yield_and_reset_the_other_way() {
    let limits = StrainLimits { stretch: (-0.01, 0.01), bend: INF, twist: INF };
    let mut rod = wire(6, limits);
    let rest = rod.rest_coords().to_vec();
    let mut stretch_to = |e: f64| {
        let q: Vec<f64> = rest.iter().enumerate().map(|(i, x)| if i % 3 == 0 { x * (1.0 + e) } else { *x }).collect();
        rod.set_coords(&q).unwrap();
        rod.update_plasticity();
        let p = rod.plastic_offsets();
        assert!(p.iter().all(|s| (s.eps - p[0].eps).abs() < 1e-12));
        p[0].eps
    };
    let cases = [(0.005, 0.0), (0.02, 0.01), (0.0, 0.01), (-0.01, 0.0), (-0.005, 0.0), (-0.03, -0.02), (0.0, -0.01)];
    for (e, want) in cases {
        let got = stretch_to(e);
        assert!((got - want).abs() < 1e-9, "total strain {e}: offset {got}, expected {want}");
    }
}

/// II.D.1.f: a wire bent into an "S" (two half circles) by point
/// constraints keeps the letter after release; an elastic wire springs back.
#[test]
fn plastic_letter_keeps_its_shape_after_release() {
    let kappa = 2.0 * PI / L; // each half circle is L/2 long
    let shape = |s: f64, k: f64| -> Vector3<f64> {
        // Arc of curvature +k on [0, L/2], then −k: an S with horizontal start.
        let arc = |s: f64, k: f64| if k == 0.0 { Vector3::new(s, 0.0, 0.0) } else { Vector3::new((k * s).sin() / k, (1.0 - (k * s).cos()) / k, 0.0) };
        if s <= 0.5 * L {
            return arc(s, k);
        }
        let (p, a) = (arc(0.5 * L, k), k * 0.5 * L);
        let q = arc(s - 0.5 * L, -k);
        p + Vector3::new(a.cos() * q.x - a.sin() * q.y, a.sin() * q.x + a.cos() * q.y, 0.0)
    };
    let run = |ky: f64| -> (f64, f64) {
        let limits = StrainLimits { stretch: INF, bend: (-ky, ky), twist: INF };
        let mut w = World::new(IntegrationParameters { parallel: false, relax_max_iterations: 2000, ..Default::default() });
        let h = w.add_rod(wire(28, limits));
        clamp_start(&mut w, h);
        let (u0, u1) = w.rod(h).unwrap().domain();
        let points = 8;
        let at = |j: usize| (j as f64 / points as f64, u0 + (u1 - u0) * j as f64 / points as f64);
        let pin = |p: Vector3<f64>, u: f64| ConstraintKind::Position(Position { u, axes: [true, true, false, false], target: [p.x, p.y, 0.0, 0.0] });
        // (the last pin and the table hold the end: x, y by the pin, z by the table)
        let pins: Vec<_> = (1..=points).map(|j| w.add_constraint(h, pin(shape(at(j).0 * L, 0.0), at(j).1), 0.0).unwrap()).collect();
        // On a frictionless table (z = 0 at the end): a rod without roll could spin about its clamp.
        w.add_constraint(h, ConstraintKind::Plane(Plane { u: u1, origin: [0.0; 3], normal: [0.0, 0.0, 1.0] }), 0.0).unwrap();
        let steps = 24;
        for k in 1..=steps {
            let kk = kappa * k as f64 / steps as f64;
            for (j, c) in pins.iter().enumerate() {
                let (s, u) = at(j + 1);
                w.set_constraint(*c, pin(shape(s * L, kk), u)).unwrap();
            }
            w.relax().unwrap();
        }
        let before = w.rod(h).unwrap().sample_points();
        for c in pins {
            w.remove_constraint(c).unwrap();
        }
        w.relax().unwrap();
        let rod = w.rod(h).unwrap();
        let after = rod.sample_points();
        let springback = before.iter().zip(&after).map(|(a, b)| (a - b).norm()).fold(0.0, f64::max);
        let letter = rod
            .sample_params()
            .iter()
            .zip(&after)
            .map(|(u, p)| (p - shape((u - u0) / (u1 - u0) * L, kappa)).norm())
            .fold(0.0, f64::max);
        (springback, letter)
    };
    let (springback, letter) = run(0.01 * kappa);
    println!("plastic S: springback {springback:.3e} m, distance to the ideal S {letter:.3e} m (L = {L} m)");
    assert!(springback < 0.03 * L && letter < 0.05 * L);
    let (elastic_springback, _) = run(100.0 * kappa);
    println!("elastic S: springback {elastic_springback:.3e} m");
    assert!(elastic_springback > 0.3 * L);
}
