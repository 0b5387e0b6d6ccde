//! SPEC §4 single-rod constraint families, each in a scenario whose answer
//! is known (issue 3): plane, distance, axis, curvature, compliance, and
//! force-threshold rupture.
mod common;
use strandkit::prelude::*;
use nalgebra::Vector3;
use strandkit::*;


fn beam(n: usize, roll: bool) -> Rod {
    common::steel_rod(Vector3::zeros(), Vector3::new(4.0, 0.0, 0.0), n, roll)
}

fn pos(u: f64, axes: [bool; 4], target: [f64; 4]) -> ConstraintKind {
    ConstraintKind::Position(Position { u, axes, target })
}

/// Clamp at x = 0 (position, roll, tangent).
fn clamped(w: &mut World, h: RodHandle) {
    let u0 = w.rod(h).unwrap().domain().0;
    w.add_constraint(h, pos(u0, [true; 4], [0.0; 4]), 0.0).unwrap();
    w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
}

/// A rod resting on a frictionless plane at both ends carries exactly the
/// normal component of its weight there; the tangential load goes to the
/// in-plane supports.
#[test]
fn plane_supports_carry_the_normal_load() {
    let mut w = World::new(IntegrationParameters { gravity: [3.0, 0.0, -9.81], ..Default::default() });
    let h = w.add_rod(beam(12, false));
    let (u0, u1) = w.rod(h).unwrap().domain();
    let m = w.rod(h).unwrap().mass();
    let pin = w.add_constraint(h, pos(u0, [true, true, false, false], [0.0; 4]), 0.0).unwrap();
    w.add_constraint(h, pos(u1, [false, true, false, false], [0.0; 4]), 0.0).unwrap();
    let (p0, p1) = (
        w.add_constraint(h, ConstraintKind::Plane(Plane { u: u0, origin: [0.0; 3], normal: [0.0, 0.0, 1.0] }), 0.0).unwrap(),
        w.add_constraint(h, ConstraintKind::Plane(Plane { u: u1, origin: [0.0; 3], normal: [0.0, 0.0, 1.0] }), 0.0).unwrap(),
    );
    w.relax().unwrap();
    let (r0, r1) = (w.reaction(p0).unwrap().force, w.reaction(p1).unwrap().force);
    assert!((r0[2] + r1[2] - m * 9.81).abs() < 1e-9 * m * 9.81, "normal {} vs weight {}", r0[2] + r1[2], m * 9.81);
    // Symmetric up to the beam-column effect of the axial load (3m at the
    // pin, 0 at the free end) on the ~2 mm sag: ≈ 0.4 N of 1200 N.
    assert!((r0[2] - r1[2]).abs() < 1e-3 * m * 9.81, "symmetric supports: {r0:?} {r1:?}");
    // The tangential load goes to the pin alone (the planes are
    // frictionless), and the whole rod is in equilibrium: the reactions
    // of every constraint balance its weight m g.
    assert!((w.reaction(pin).unwrap().force[0] + 3.0 * m).abs() < 1e-9 * m);
    let total = w.constraints().fold(nalgebra::Vector3::zeros(), |s, (c, _)| s + nalgebra::Vector3::from(w.reaction(c).unwrap().force));
    let weight = nalgebra::Vector3::new(3.0, 0.0, -9.81) * m;
    assert!((total + weight).norm() < 1e-9 * weight.norm(), "reactions {total:?} vs weight {weight:?}");
}

/// Propped cantilever: a clamped beam under its weight w per length, its tip
/// held by a long vertical distance link (or an axis along x): the link
/// carries 3wL/8 (small deflections), in tension.
#[test]
fn distance_link_and_axis_prop_a_cantilever() {
    for which in ["distance", "axis"] {
        let mut w = World::new(IntegrationParameters { gravity: [0.0, -9.81, 0.0], ..Default::default() });
        let h = w.add_rod(beam(16, true));
        clamped(&mut w, h);
        let (_, u1) = w.rod(h).unwrap().domain();
        let kind = match which {
            "distance" => ConstraintKind::Distance(Distance { u: u1, point: [4.0, 1000.0, 0.0], distance: 1000.0 }),
            _ => ConstraintKind::Axis(Axis { u: u1, origin: [0.0; 3], direction: [1.0, 0.0, 0.0] }),
        };
        let c = w.add_constraint(h, kind, 0.0).unwrap();
        w.relax().unwrap();
        let weight = w.rod(h).unwrap().mass() * 9.81;
        let f = w.reaction(c).unwrap().force;
        let expected = 3.0 * weight / 8.0;
        println!("{which}: prop force {:?}, 3wL/8 = {expected}", f);
        assert!((f[1] - expected).abs() < 2e-3 * expected, "{which}: {} vs {expected}", f[1]);
        if which == "distance" {
            assert!(w.constraint(c).unwrap().multipliers[0] < 0.0, "the link is in tension");
        }
    }
}

/// A curvature constraint r''(u1) = target at the tip of a clamped,
/// unloaded rod: met exactly, and its generalised forces Λ b''_k sum to zero
/// force and to the couple r''(u1) × Λ, which the clamp balances (global
/// equilibrium of the multipliers). A target equal to the current r'' costs
/// nothing (Λ = 0).
#[test]
fn curvature_constraint_is_met_and_balanced_by_the_clamp() {
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(beam(20, true));
    let u0 = w.rod(h).unwrap().domain().0;
    let clamp = w.add_constraint(h, pos(u0, [true; 4], [0.0; 4]), 0.0).unwrap();
    let tangent = w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    let u1 = w.rod(h).unwrap().domain().1;
    let now = w.rod(h).unwrap().eval(u1, 2).unwrap();
    let c = w.add_constraint(h, ConstraintKind::Curvature(Curvature { u: u1, target: [now[0], now[1], now[2]] }), 0.0).unwrap();
    w.relax().unwrap();
    assert!(w.constraint(c).unwrap().multipliers.iter().all(|l| l.abs() < 1e-6));
    let target = [0.0, 0.05, 0.02];
    w.set_constraint(c, ConstraintKind::Curvature(Curvature { u: u1, target })).unwrap();
    w.relax().unwrap();
    let rod = w.rod(h).unwrap();
    let r2 = rod.eval(u1, 2).unwrap();
    for a in 0..3 {
        assert!((r2[a] - target[a]).abs() < 1e-9, "r'' {r2:?} vs {target:?}");
    }
    let lam = Vector3::from_column_slice(&w.constraint(c).unwrap().multipliers);
    let couple = Vector3::new(r2[0], r2[1], r2[2]).cross(&lam);
    // The reported reaction is that couple (no net force).
    let r = w.reaction(c).unwrap();
    assert!((Vector3::from(r.torque) - couple).norm() <= 1e-12 * couple.norm() && Vector3::from(r.force).norm() == 0.0);
    let f = Vector3::from(w.reaction(clamp).unwrap().force);
    // Clamp moment = tangent-row moment + roll torque about the tangent (x).
    let m = Vector3::from(w.reaction(tangent).unwrap().torque) + Vector3::from(w.reaction(clamp).unwrap().torque);
    println!("Λ {lam:?}, couple {couple:?}, clamp force {f:?}, clamp moment {m:?}");
    assert!(lam.norm() > 1.0, "a real constraint force");
    assert!(f.norm() < 1e-6 * lam.norm());
    assert!((m + couple).norm() < 1e-6 * couple.norm(), "clamp moment {m:?} vs −couple {couple:?}");
}

/// A compliant link (C > 0) is a spring of stiffness 1/C: its force equals
/// the violation over C, and a cantilever tip on such a spring deflects by
/// F/(3EI/L³ + 1/C).
#[test]
fn compliant_link_is_a_spring() {
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(beam(16, true));
    clamped(&mut w, h);
    let (_, u1) = w.rod(h).unwrap().domain();
    let ei = 200e9 * std::f64::consts::PI * 0.05f64.powi(4) / 4.0;
    let k_beam = 3.0 * ei / 64.0;
    let compliance = 1.0 / k_beam; // as stiff as the beam
    let spring = w.add_constraint(h, pos(u1, [false, true, false, false], [0.0; 4]), compliance).unwrap();
    let f = 1000.0;
    w.add_load(Load::PointForce(PointForce { rod: h, u: u1, force: [0.0, -f, 0.0] })).unwrap();
    w.relax().unwrap();
    let y = w.rod(h).unwrap().position(u1).unwrap().y;
    let lam = w.constraint(spring).unwrap().multipliers[0];
    let expected = -f / (k_beam + 1.0 / compliance);
    println!("tip y {y:.6e} (beam theory {expected:.6e}), spring force {lam} = -y/C {}", -y / compliance);
    assert!((lam + y / compliance).abs() < 1e-9 * lam.abs());
    assert!((y - expected).abs() < 5e-3 * expected.abs());
}

/// Force-threshold rupture: a beam hung from five breakable vertical
/// hangers under a growing point load breaks the most loaded hanger first,
/// at the first load increment where it exceeds its threshold, and reports it.
#[test]
fn most_loaded_hanger_breaks_first() {
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(beam(21, true));
    let (u0, u1) = w.rod(h).unwrap().domain();
    w.add_constraint(h, pos(u0, [true, false, true, true], [0.0; 4]), 0.0).unwrap();
    w.add_constraint(h, pos(u1, [false, false, true, false], [0.0; 4]), 0.0).unwrap();
    let threshold = 3000.0;
    let hangers: Vec<_> = (0..5)
        .map(|i| {
            let x = i as f64;
            let u = u0 + (u1 - u0) * x / 4.0;
            let c = w.add_constraint(h, ConstraintKind::Distance(Distance { u, point: [x, 5.0, 0.0], distance: 5.0 }), 0.0).unwrap();
            w.set_breaking(c, Some(Breaking::new(threshold, BreakPolicy::Tension))).unwrap();
            c
        })
        .collect();
    let ul = u0 + (u1 - u0) * 3.2 / 4.0;
    let load = w.add_load(Load::PointForce(PointForce { rod: h, u: ul, force: [0.0; 3] })).unwrap();
    let step = 250.0;
    let mut previous: Vec<f64> = vec![0.0; 5];
    for k in 1..100 {
        let f = step * k as f64;
        w.set_load(load, Load::PointForce(PointForce { rod: h, u: ul, force: [0.0, -f, 0.0] })).unwrap();
        let rep = w.relax().unwrap();
        if let Some(Event::ConstraintBroken { constraint, force, .. }) = rep.events.first() {
            let i = hangers.iter().position(|c| c == constraint).unwrap();
            let most = (0..5).max_by(|&a, &b| previous[a].total_cmp(&previous[b])).unwrap();
            println!("load {f} N: hanger {i} broke at {force:.1} N (previous tensions {previous:?})");
            assert_eq!(rep.events.len(), 1, "one hanger at a time");
            assert_eq!(i, most, "the most loaded hanger breaks first");
            assert!(*force > threshold && previous[i] <= threshold, "within one load increment");
            assert!(w.constraint(*constraint).is_err(), "broken constraint removed");
            return;
        }
        previous = hangers.iter().map(|c| -w.constraint(*c).unwrap().multipliers[0]).collect();
        let total: f64 = previous.iter().sum();
        assert!((total - f).abs() < 1e-6 * f, "hangers carry the load: {total} vs {f}");
    }
    panic!("no hanger broke");
}
