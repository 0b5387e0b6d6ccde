//! Issue 15's first slice: rods as capsule chains, detected by a uniform
//! grid and the closed-form segment–segment closest points, entering the
//! step as unilateral contact rows with an active set (SPEC §7). Two rods
//! pressed across each other at right angles (rod a clamped at both ends,
//! rod b clamped in direction and free to move down, pushed at its middle)
//! never pass through, and at rest the contact carries the push.
use nalgebra::Vector3;
use std::sync::Arc;
use strandkit::prelude::*;
use strandkit::RodContacts;

const R: f64 = 0.01;

fn rod(a: Vector3<f64>, b: Vector3<f64>) -> Rod {
    RodBuilder::straight(a, b)
        .control_points(12)
        .with_roll(false)
        .section(Section::circle(R).unwrap())
        .material(Material::new("rubber", 1e7, 0.45, 1000.0).unwrap())
        .options(RodOptions { drag: 50.0, ..Default::default() })
        .build()
        .unwrap()
}

/// Smallest distance between two rods' centrelines (fine sampling).
fn gap(a: &Rod, b: &Rod) -> f64 {
    let pts = |r: &Rod| {
        let (u0, u1) = r.domain();
        (0..=400).map(|k| r.position(u0 + (u1 - u0) * k as f64 / 400.0).unwrap()).collect::<Vec<_>>()
    };
    let (pa, pb) = (pts(a), pts(b));
    pa.iter().flat_map(|p| pb.iter().map(move |q| (p - q).norm())).fold(f64::INFINITY, f64::min)
}

#[test]
fn rods_pressed_across_never_pass_through() {
    let mut w = World::new(IntegrationParameters { dt: 2e-3, ..Default::default() });
    let a = w.add_rod(rod(Vector3::new(-0.5, 0.0, 0.0), Vector3::new(0.5, 0.0, 0.0)));
    let b = w.add_rod(rod(Vector3::new(0.0, -0.5, 0.03), Vector3::new(0.0, 0.5, 0.03)));
    for h in [a, b] {
        let (u0, u1) = w.rod(h).unwrap().domain();
        let axes = if h == a { [true, true, true, false] } else { [true, true, false, false] };
        for u in [u0, u1] {
            let (p, t) = (w.rod(h).unwrap().position(u).unwrap(), w.rod(h).unwrap().tangent(u).unwrap());
            w.add_constraint(h, ConstraintKind::Position(Position { u, axes, target: [p.x, p.y, p.z, 0.0] }), 0.0).unwrap();
            w.add_constraint(h, ConstraintKind::Tangent(Tangent { u, direction: t.into() }), 0.0).unwrap();
        }
    }
    let (u0, u1) = w.rod(b).unwrap().domain();
    let push = 50.0;
    w.add_load(Load::PointForce(PointForce { rod: b, u: 0.5 * (u0 + u1), force: [0.0, 0.0, -push] })).unwrap();
    w.add_contact_detector(Arc::new(RodContacts::new(0.02, false, true).unwrap()));
    let mut closest = f64::INFINITY;
    for k in 0..1500 {
        w.step().unwrap();
        let g = gap(w.rod(a).unwrap(), w.rod(b).unwrap());
        closest = closest.min(g);
        let (ma, mb) = (w.rod(a).unwrap().position(0.5 * (u0 + u1)).unwrap(), w.rod(b).unwrap().position(0.5 * (u0 + u1)).unwrap());
        assert!(mb.z > ma.z, "step {k}: rod b went through rod a ({} below {})", mb.z, ma.z);
        assert!(g > 2.0 * R * (1.0 - 1e-3), "step {k}: centrelines {g} apart, radii sum {}", 2.0 * R);
    }
    // Settled (the drag has taken the motion), the contact carries the push.
    let force: f64 = w.contacts().active().map(|(_, p)| p.force).sum();
    println!("closest approach {closest:.6} m (radii sum {}), contact force {force:.4} N for a push of {push} N, {} active pairs", 2.0 * R, w.contacts().active().count());
    assert!((force / push - 1.0).abs() < 1e-2, "contact force {force} vs push {push}");
}
