//! Beads (sliding-abscissa particles, SPEC §4 and §9.4).
mod common;
use strandkit::prelude::*;
use nalgebra::Vector3;

/// A light, nearly inextensible string (EA = 1e4 N, 4.5e-7 kg/m) of length
/// `len` between (0,0,0) and (span,0,0), started from a sagging arc. Its
/// bending stiffness EI = `ei` gives the corner under a bead a boundary
/// layer √(EI/T) that the control points must resolve: a spline cannot form
/// the kink of a perfectly flexible string.
fn string(world: &mut World, len: f64, span: f64, n: usize, ei: f64) -> RodHandle {
    let r = (4.0 * ei / 1e4f64).sqrt();
    let e = 1e4 / (std::f64::consts::PI * r * r);
    let mut rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(len, 0.0, 0.0))
        .control_points(n)
        .with_roll(false)
        .section(Section::circle(r).unwrap())
        .material(Material::new("string", e, 0.3, 1.0).unwrap())
        .build()
        .unwrap();
    common::sag(&mut rod, len, span);
    world.add_rod(rod)
}

/// SPEC §9.4: one frictionless bead (m = 0.1 kg) on a light inextensible
/// string of length 1.2 m between supports 1 m apart at equal height: both
/// halves at θ = 56.44° from the vertical, sag 0.3317 m, tension 0.887 N
/// (within 1 %). The string's bending boundary layer √(EI/T) = 5 mm rounds
/// the corner under the bead over ~3 control-point spacings (with 2 cm the
/// rounding shortened the effective string by 1.3 cm: θ 55.5°, T 0.866 N).
#[test]
fn bead_on_a_string_matches_the_reference() {
    // ~500 damped Newton iterations: the string is nearly a mechanism.
    let params = IntegrationParameters { gravity: [0.0, -9.81, 0.0], relax_max_iterations: 3000, ..Default::default() };
    let mut w = World::new(params);
    let h = string(&mut w, 1.2, 1.0, 721, 2.2e-5);
    let (u0, u1) = w.rod(h).unwrap().domain();
    let xyz = [true, true, true, false];
    let a = w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: xyz, target: [0.0; 4] }), 0.0).unwrap();
    let b = w.add_constraint(h, ConstraintKind::Position(Position { u: u1, axes: xyz, target: [1.0, 0.0, 0.0, 0.0] }), 0.0).unwrap();
    // Off-centre start: the bead must find the middle by itself.
    let bead = w.add_bead(h, u0 + 0.4 * (u1 - u0), 0.1, 0.0, 0.0).unwrap();
    let rep = w.relax().unwrap();
    let p = w.bead_position(bead).unwrap();
    let (fa, fb) = (Vector3::from(w.reaction(a).unwrap().force), Vector3::from(w.reaction(b).unwrap().force));
    let theta = (fa.x.abs()).atan2(fa.y.abs()).to_degrees();
    let (sag, t) = (-p.y, fa.norm());
    println!("bead at {p:?}: θ = {theta:.3}° (56.44), sag {sag:.4} (0.3317), T {t:.4} | {:.4} N (0.887); {} iterations", fb.norm(), rep.iterations);
    assert!((theta - 56.44).abs() < 0.01 * 56.44);
    assert!((sag - 0.3317).abs() < 0.01 * 0.3317);
    assert!((t - 0.887).abs() < 0.01 * 0.887 && (fb.norm() - 0.887).abs() < 0.01 * 0.887);
    assert!((p.x - 0.5).abs() < 1e-3, "the bead sits in the middle");
}

fn inclined_rod(w: &mut World, alpha: f64) -> RodHandle {
    let end = Vector3::new(alpha.cos(), alpha.sin(), 0.0) * 2.0;
    pinned_straight(w, end, 0.02, Material::new("steel", 200e9, 0.3, 7800.0).unwrap())
}

/// A straight rod (12 control points, circle of `radius`) from the origin
/// to `end`, pinned at both ends.
fn pinned_straight(w: &mut World, end: Vector3<f64>, radius: f64, material: Material) -> RodHandle {
    let rod = RodBuilder::straight(Vector3::zeros(), end)
        .control_points(12)
        .with_roll(false)
        .section(Section::circle(radius).unwrap())
        .material(material)
        .build()
        .unwrap();
    let h = w.add_rod(rod);
    let (u0, u1) = w.rod(h).unwrap().domain();
    let xyz = [true, true, true, false];
    w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: xyz, target: [0.0; 4] }), 0.0).unwrap();
    w.add_constraint(h, ConstraintKind::Position(Position { u: u1, axes: xyz, target: [end.x, end.y, end.z, 0.0] }), 0.0).unwrap();
    h
}

/// A frictionless bead on a stiff inclined rod slides with acceleration
/// g sin α, and (momentum-consistent coupling) loads the rod with the normal
/// part of its weight only: the supports carry the rod's weight plus
/// m g cos α along the normal.
#[test]
fn free_bead_slides_at_g_sin_alpha_and_loads_the_normal_weight() {
    let (g, alpha, m) = (9.81, 0.5f64, 2.0);
    let mut w = World::new(IntegrationParameters { dt: 1e-3, gravity: [0.0, -g, 0.0], ..Default::default() });
    let h = inclined_rod(&mut w, alpha);
    let (u0, u1) = w.rod(h).unwrap().domain();
    let bead = w.add_bead(h, u0 + 0.8 * (u1 - u0), m, 0.0, 0.0).unwrap();
    let p0 = w.bead_position(bead).unwrap();
    let steps = 300;
    // Support reactions averaged over the last 100 steps (the rod's own
    // vibration after the load appears averages out).
    let mut supports = Vector3::zeros();
    for k in 0..steps {
        w.step().unwrap();
        if k >= steps - 100 {
            for c in [ConstraintHandle { index: 0, generation: 0 }, ConstraintHandle { index: 1, generation: 0 }] {
                supports += Vector3::from(w.reaction(c).unwrap().force) / 100.0;
            }
        }
    }
    let t = steps as f64 * 1e-3;
    let s = (w.bead_position(bead).unwrap() - p0).norm();
    let expected = 0.5 * g * alpha.sin() * t * t;
    let weight = w.rod(h).unwrap().mass() * g;
    let normal = Vector3::new(-alpha.sin(), alpha.cos(), 0.0) * (m * g * alpha.cos());
    let expected_support = Vector3::new(0.0, weight, 0.0) + normal;
    println!("slid {s:.5} m (½ g sinα t² = {expected:.5}), supports {supports:?} vs {expected_support:?}");
    assert!((s - expected).abs() < 1e-2 * expected);
    assert!((supports - expected_support).norm() < 1e-2 * expected_support.norm());
}

/// Two beads on a horizontal rod, one thrown at the other: they never pass
/// each other (centres ≥ r_a + r_b apart along the rod), and the inelastic
/// contact conserves their momentum along the rod to 1e-8 (measured
/// 5.7e-9: a bead's position N(u)·q is bilinear in its abscissa and the
/// rod's coordinates, which vibrate axially under the impact, and the
/// step linearises it; 1e-9 when the contact was a projection of the
/// beads' increments outside the rod's solve).
#[test]
fn beads_do_not_pass_each_other() {
    let mut w = World::new(IntegrationParameters { dt: 1e-3, ..Default::default() });
    let h = inclined_rod(&mut w, 0.0);
    let (u0, u1) = w.rod(h).unwrap().domain();
    let a = w.add_bead(h, u0 + 0.2 * (u1 - u0), 1.0, 0.0, 0.02).unwrap();
    let b = w.add_bead(h, u0 + 0.5 * (u1 - u0), 3.0, 0.0, 0.03).unwrap();
    let push = [10.0, 0.0, 0.0];
    w.set_bead_force(a, push).unwrap();
    for _ in 0..50 {
        w.step().unwrap();
    }
    w.set_bead_force(a, [0.0; 3]).unwrap();
    // Momentum along the rod: the beads' own velocities (the pinned rod's
    // axial vibration does not count).
    let momentum = |w: &World| {
        let rod = w.rod(h).unwrap();
        [a, b].iter().map(|&k| w.bead(k).unwrap().mass * w.bead(k).unwrap().absolute_velocity(rod).unwrap().x).sum::<f64>()
    };
    let p_before = momentum(&w);
    let mut min_gap = f64::INFINITY;
    for _ in 0..1500 {
        w.step().unwrap();
        let gap = w.bead_position(b).unwrap().x - w.bead_position(a).unwrap().x;
        min_gap = min_gap.min(gap);
    }
    let (ba, bb) = (w.bead(a).unwrap(), w.bead(b).unwrap());
    let p_after = momentum(&w);
    println!("min gap {min_gap:.5} m (≥ 0.05), momentum {p_before:.12} → {p_after:.12}, velocities {:.4} {:.4}", ba.velocity, bb.velocity);
    assert!(min_gap >= 0.05 - 1e-6, "beads passed or overlapped: {min_gap}");
    assert!(bb.velocity > 0.0, "the struck bead moves");
    assert!((p_after - p_before).abs() < 1e-8 * p_before.abs());
}

/// A straight nylon string (1 m, 12 control points) pinned at both ends.
fn pinned_string(w: &mut World) -> RodHandle {
    pinned_straight(w, Vector3::new(1.0, 0.0, 0.0), 0.002, Material::new("nylon", 3e9, 0.4, 1150.0).unwrap())
}

/// Trains of 2–6 sliding beads of random sizes and masses between two
/// knotted ones on a pinned string, under random gravity in the string's
/// plane and random pushes along it re-drawn every 50 steps (fixed seed;
/// 10 trains × 400 steps of 1 ms): at the end of every step each pair of
/// neighbours is apart by at least r_a + r_b less the slack a gap row may
/// hold (0.5 % of the mean radius). Rows that pull in the same round all
/// leave; one of them may still be needed, and must be able to come back
/// within the step (when it could not, 16 of 20 such trains ended steps
/// up to 3e-4 m beyond the slack).
#[test]
fn trains_of_beads_pushed_about_never_overlap_beyond_the_slack() {
    let mut seed = 12345u64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % 1_000_000) as f64 / 1_000_000.0
    };
    let chord = |w: &World, a: BeadHandle, b: BeadHandle| (w.bead_position(b).unwrap() - w.bead_position(a).unwrap()).norm();
    let mut worst = f64::INFINITY;
    for case in 0..10 {
        let g = [(rnd() - 0.5) * 40.0, (rnd() - 0.5) * 20.0, 0.0];
        let mut w = World::new(IntegrationParameters { dt: 1e-3, gravity: g, ..Default::default() });
        let r = pinned_string(&mut w);
        let (u0, u1) = w.rod(r).unwrap().domain();
        let at = |x: f64| u0 + x * (u1 - u0);
        let first = w.add_bead(r, at(0.2), 0.01, 0.0, 0.01).unwrap();
        w.set_bead_fixed(first, true).unwrap();
        let mut beads = vec![(first, 0.01)];
        let mut x = 0.21;
        for _ in 0..2 + (rnd() * 5.0) as usize {
            let rad = 0.005 + 0.03 * rnd();
            x += rad + 1e-4 * rnd();
            let b = w.add_bead(r, at(x), 0.005 + 0.02 * rnd(), 0.0, rad).unwrap();
            beads.push((b, rad));
            x += rad;
        }
        let last = w.add_bead(r, at((x + 0.01 + 1e-4 * rnd()).max(0.8)), 0.01, 0.0, 0.01).unwrap();
        w.set_bead_fixed(last, true).unwrap();
        beads.push((last, 0.01));
        for k in 0..400 {
            if k % 50 == 0 {
                for &(b, _) in &beads[1..beads.len() - 1] {
                    w.set_bead_force(b, [(rnd() - 0.5) * 4.0, 0.0, 0.0]).unwrap();
                }
            }
            w.step().unwrap_or_else(|e| panic!("train {case}, step {k}: {e}"));
            for pair in beads.windows(2) {
                let ((a, ra), (b, rb)) = (pair[0], pair[1]);
                let beyond = chord(&w, a, b) - ra - rb + 5e-3 * 0.5 * (ra + rb);
                worst = worst.min(beyond);
                assert!(beyond > -1e-9, "train {case}, step {k}: neighbours overlap by {:.3e} m beyond the slack", -beyond);
            }
        }
    }
    println!("closest approach, relative to r_a + r_b less the slack: {worst:.3e} m");
}

/// A 10 g frictionless bead near the top of a steel arch (radius 0.1 m):
/// a step of 0.2 s is longer than √(R/g) = 0.1 s, so its inertia along the
/// rod, m |r′|²/h², falls below its weight's pull off the bend. The step is
/// refused as diverged with the world as it was (its snapshot the same, the
/// beads' step state included); with `adaptive_dt` it is taken in
/// sub-steps.
#[test]
fn a_step_too_long_for_a_bead_on_a_bend_is_refused_and_the_world_kept() {
    for adaptive in [false, true] {
        let mut w = World::new(IntegrationParameters { dt: 0.01, gravity: [0.0, -9.81, 0.0], adaptive_dt: adaptive, ..Default::default() });
        let rr = 0.1;
        let rod = RodBuilder::curve(std::f64::consts::PI * rr, move |s| {
            let t = std::f64::consts::PI - s / rr;
            Vector3::new(rr * t.cos(), rr * t.sin(), 0.0)
        })
        .control_points(16)
        .with_roll(false)
        .section(Section::circle(0.002).unwrap())
        .material(Material::new("steel", 200e9, 0.3, 7800.0).unwrap())
        .build()
        .unwrap();
        let r = w.add_rod(rod);
        let (u0, u1) = w.rod(r).unwrap().domain();
        for u in [u0, u1] {
            let p = w.rod(r).unwrap().position(u).unwrap();
            w.add_constraint(r, ConstraintKind::Position(Position { u, axes: [true, true, true, false], target: [p.x, p.y, p.z, 0.0] }), 0.0).unwrap();
        }
        w.add_bead(r, 0.5 * (u0 + u1) + 0.1, 0.01, 0.0, 0.0).unwrap();
        // A short step first: the bead carries a step state into the long one.
        w.step().unwrap();
        w.params.dt = 0.2;
        let before = w.to_json().unwrap();
        match (adaptive, w.step()) {
            (false, Err(e)) => {
                assert_eq!(e.kind(), "Diverged", "{e}");
                assert!(e.to_string().contains("time step is too long"), "{e}");
                assert_eq!(w.to_json().unwrap(), before, "the refused step changed the world");
            }
            (true, Ok(report)) => assert!(report.substeps > 1, "taken in {} sub-steps", report.substeps),
            (a, other) => panic!("adaptive_dt {a}: {other:?}"),
        }
    }
}
