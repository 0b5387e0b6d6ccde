//! Sliding constraints (III.37–III.42, issue 3).
use nalgebra::Vector3;
use strandkit::*;

fn rope(a: Vector3<f64>, b: Vector3<f64>, n: usize) -> Rod {
    rod_of(a, b, n, 0.002)
}

fn rod_of(a: Vector3<f64>, b: Vector3<f64>, n: usize, radius: f64) -> Rod {
    RodBuilder::straight(a, b)
        .control_points(n)
        .with_roll(false)
        .section(Section::circle(radius).unwrap())
        .material(Material::preset("nylon").unwrap())
        .build()
        .unwrap()
}

/// A pre-tensioned rod pinned at both ends passes through a frictionless
/// ring off the line between them: the ring force has no tangential
/// component, the axial force is the same on both sides of the ring, and
/// the forces balance. The rod (r = 3 cm) has a bending boundary layer
/// √(EI/T) ≈ 0.1 m resolved by the control points: a spline cannot form the
/// kink a string would make at the ring, so for a thin rope the corner is
/// smoothed over one segment and the two tensions differ by ~0.3 %,
/// whatever the refinement.
#[test]
fn frictionless_ring_transmits_equal_tension() {
    let mut w = World::new(IntegrationParameters::default());
    // Rest length 2 m; the path through the ring is longer, so the rod is stretched.
    let h = w.add_rod(rod_of(Vector3::new(-1.0, 0.0, 0.0), Vector3::new(1.0, 0.0, 0.0), 60, 0.03));
    let (u0, u1) = w.rod(h).unwrap().domain();
    let xyz = [true, true, true, false];
    let a = w.add_constraint(h, ConstraintKind::Position { u: u0, axes: xyz, target: [-1.0, 0.0, 0.0, 0.0] }, 0.0).unwrap();
    let b = w.add_constraint(h, ConstraintKind::Position { u: u1, axes: xyz, target: [1.0, 0.0, 0.0, 0.0] }, 0.0).unwrap();
    let ring = [0.3, -0.2, 0.0];
    // Start the slider at the abscissa closest to the ring and move the ring
    // there gradually (a moving target), then relax.
    let um = u0 + (u1 - u0) * 0.65;
    let s = w.add_constraint(h, ConstraintKind::SlidingPoint { u: um, point: [0.3, 0.0, 0.0], friction: 0.0 }, 0.0).unwrap();
    for k in 1..=10 {
        let y = ring[1] * k as f64 / 10.0;
        let u = match w.constraint(s).unwrap().kind {
            ConstraintKind::SlidingPoint { u, .. } => u,
            _ => unreachable!(),
        };
        w.set_constraint(s, ConstraintKind::SlidingPoint { u, point: [0.3, y, 0.0], friction: 0.0 }).unwrap();
        w.relax().unwrap();
    }
    let (fa, fb) = (Vector3::from(w.reaction(a).unwrap().force), Vector3::from(w.reaction(b).unwrap().force));
    let fr = Vector3::from(w.reaction(s).unwrap().force);
    let u = match w.constraint(s).unwrap().kind {
        ConstraintKind::SlidingPoint { u, .. } => u,
        _ => unreachable!(),
    };
    let rod = w.rod(h).unwrap();
    let t = rod.tangent(u).unwrap();
    let p = rod.position(u).unwrap();
    // Axial force EA ε on each side, 0.15 m from the ring (outside the bend).
    let ea = rod.material().young * std::f64::consts::PI * 0.03f64.powi(2);
    let us = rod.sample_params();
    let strains = rod.strains();
    let axial_at = |x: f64| {
        let i = us.iter().enumerate().min_by(|a, b| {
            (rod.position(*a.1).unwrap().x - x).abs().total_cmp(&(rod.position(*b.1).unwrap().x - x).abs())
        });
        ea * strains[i.unwrap().0].eps
    };
    let (nl, nr) = (axial_at(p.x - 0.15), axial_at(p.x + 0.15));
    println!("end reactions {:.3} {:.3} N, axial force {nl:.3} | {nr:.3} N, ring force {fr:?}, tangential {:.3e}, u = {u:.5}", fa.norm(), fb.norm(), fr.dot(&t));
    assert!((p - Vector3::from(ring)).norm() < 1e-9, "the rod passes through the ring");
    assert!(nl > 1.0, "the rod is in tension");
    assert!((nl - nr).abs() < 2e-3 * nl, "equal axial force on both sides: {nl} vs {nr}");
    assert!(fr.dot(&t).abs() < 1e-8 * fr.norm(), "no tangential force at a frictionless ring");
    assert!((fa + fb + fr).norm() < 1e-8 * fr.norm(), "global balance");
}

/// A slider pushed past the end of its rod is removed with an event.
#[test]
fn slider_leaving_the_rod_is_reported() {
    let mut w = World::new(IntegrationParameters { dt: 1e-3, gravity: [0.0, -9.81, 0.0], ..Default::default() });
    // A short vertical rope held at its top by a ring: it falls through it.
    let h = w.add_rod(rope(Vector3::new(0.0, 0.0, 0.0), Vector3::new(0.0, -0.2, 0.0), 8));
    let (u0, u1) = w.rod(h).unwrap().domain();
    let s = w
        .add_constraint(h, ConstraintKind::SlidingPoint { u: u0 + 0.01 * (u1 - u0), point: [0.0, -0.002, 0.0], friction: 0.0 }, 0.0)
        .unwrap();
    for k in 0..2000 {
        let rep = w.step().unwrap();
        if let Some(Event::SliderLeft { constraint, .. }) = rep.events.first() {
            assert_eq!(*constraint, s);
            assert!(w.constraint(s).is_err());
            let v = w.rod(h).unwrap().velocities()[1];
            println!("left after {} steps, rope velocity {v:.3} m/s", k + 1);
            // Free fall through a frictionless ring: v ≈ −g t once it has left.
            assert!(v < 0.0);
            return;
        }
    }
    panic!("the slider never left the rope");
}
