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
    let rod = RodBuilder::straight(Vector3::zeros(), end)
        .control_points(12)
        .with_roll(false)
        .section(Section::circle(0.02).unwrap())
        .material(Material::new("steel", 200e9, 0.3, 7800.0).unwrap())
        .build()
        .unwrap();
    let h = w.add_rod(rod);
    let (u0, u1) = w.rod(h).unwrap().domain();
    let xyz = [true, true, true, false];
    w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: xyz, target: [0.0; 4] }), 0.0).unwrap();
    w.add_constraint(h, ConstraintKind::Position(Position { u: u1, axes: xyz, target: [end.x, end.y, 0.0, 0.0] }), 0.0).unwrap();
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
