//! Distributed contact rows (`RodContacts::with_line_stiffness`): a
//! compliant row at every capsule of a strand within reach of another,
//! against the other's closest point, instead of one rigid row where the
//! strands come closest. Two straight rods pressed together along their
//! length by opposite line loads q settle with their centrelines 2R − q/k
//! apart (the closed form of a uniform line of stiffness k per length),
//! the rows' forces adding up to q L. With friction, pulled along by less
//! than μ q the upper rod is held; by more it slides against μ q.
use nalgebra::Vector3;
use strandkit::prelude::*;
use strandkit::RodContacts;

const R: f64 = 0.01;

fn rod(a: Vector3<f64>, b: Vector3<f64>, n: usize) -> Rod {
    RodBuilder::straight(a, b)
        .control_points(n)
        .with_roll(false)
        .section(Section::circle(R).unwrap())
        .material(Material::new("rubber", 1e7, 0.45, 1000.0).unwrap())
        .build()
        .unwrap()
}

/// Distance from rod `a`'s point at `u` to rod `b`'s centreline (fine sampling, then refined).
fn distance_to(a: &Rod, u: f64, b: &Rod) -> f64 {
    let p = a.position(u).unwrap();
    let (u0, u1) = b.domain();
    let n = 2000;
    let k = (0..=n).min_by(|&i, &j| {
        let d = |k: usize| (b.position(u0 + (u1 - u0) * k as f64 / n as f64).unwrap() - p).norm();
        d(i).total_cmp(&d(j))
    });
    // The best sample's neighbourhood, golden-section refined.
    let k = k.unwrap() as f64; // (0..=n) is not empty
    let (mut lo, mut hi) = ((u0 + (u1 - u0) * (k - 1.0) / n as f64).max(u0), (u0 + (u1 - u0) * (k + 1.0) / n as f64).min(u1));
    let d = |u: f64| (b.position(u).unwrap() - p).norm();
    for _ in 0..60 {
        let (m1, m2) = (hi - 0.618 * (hi - lo), lo + 0.618 * (hi - lo));
        if d(m1) < d(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    d(0.5 * (lo + hi))
}

/// Overdamped steps (the fluid's drag only) until no control point moves
/// more than `tol` (m) in a step, at most `max` steps; returns the steps.
fn settle(w: &mut World, tol: f64, max: usize) -> usize {
    for k in 0..max {
        let before: Vec<Vec<f64>> = w.rods().map(|(_, r)| r.coords().to_vec()).collect();
        w.step().unwrap();
        let moved = w.rods().zip(&before).flat_map(|((_, r), q)| r.coords().iter().zip(q).map(|(x, y)| (x - y).abs()).collect::<Vec<_>>()).fold(0.0, f64::max);
        if moved < tol {
            return k + 1;
        }
    }
    panic!("not settled in {max} steps");
}

#[test]
fn rods_pressed_along_their_length_sink_by_q_over_k() {
    let (q, k, length) = (200.0, 1e6, 1.0); // N/m, N/m², m: q/k = 2e-4 m (2 % of R)
    let params = IntegrationParameters { dt: 1e-3, overdamped: true, viscosity: 10.0, gravity: [0.0; 3], ..Default::default() };
    let mut w = World::new(params);
    let a = w.add_rod(rod(Vector3::zeros(), Vector3::new(length, 0.0, 0.0), 12));
    let b = w.add_rod(rod(Vector3::new(0.0, 0.0, 2.0 * R * 1.001), Vector3::new(length, 0.0, 2.0 * R * 1.001), 12));
    w.add_load(Load::Distributed(Distributed { rod: a, force_per_length: [0.0, 0.0, q] })).unwrap();
    w.add_load(Load::Distributed(Distributed { rod: b, force_per_length: [0.0, 0.0, -q] })).unwrap();
    w.add_contact_detector(RodContacts::new(0.25 * R, false, true).unwrap().with_line_stiffness(k).unwrap()).unwrap();
    let steps = settle(&mut w, 1e-10, 400);
    let (ra, rb) = (w.rod(a).unwrap(), w.rod(b).unwrap());
    let (u0, u1) = ra.domain();
    let expected = 2.0 * R - q / k;
    // Along the whole length, the ends' last tenth aside (a capsule there
    // is half a sample long, and the line's end is free).
    let mut worst: f64 = 0.0;
    for i in 1..10 {
        let d = distance_to(ra, u0 + (u1 - u0) * i as f64 / 10.0, rb);
        worst = worst.max(((2.0 * R - d) / (q / k) - 1.0).abs());
    }
    let total: f64 = w.contacts().active().map(|(_, p)| p.force).sum();
    println!("{steps} steps; sink (2R − distance) within {:.2} % of q/k = {:.3e} m; rows {}, their forces {total:.4} N for q L = {} N", 100.0 * worst, q / k, w.contacts().active().count(), q * length);
    assert!(worst < 0.01, "sink off q/k by {worst} (centrelines should be {expected} m apart)");
    assert!((total / (q * length) - 1.0).abs() < 1e-6, "row forces {total} N against q L = {} N", q * length);
}

#[test]
fn distributed_rows_refuse_a_bad_stiffness() {
    for k in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(RodContacts::new(1e-3, true, true).unwrap().with_line_stiffness(k), Err(Error::InvalidInput { .. })), "stiffness {k}");
    }
    let d = RodContacts::new(1e-3, true, true).unwrap();
    // A snapshot's detector keeps it; one written before it reads as rigid rows.
    let d = RodContacts::new(1e-3, true, true).unwrap().with_line_stiffness(5e8).unwrap();
    let read: RodContacts = serde_json::from_str(&serde_json::to_string(&d).unwrap()).unwrap();
    assert_eq!(read, d);
    let mut old = serde_json::to_value(RodContacts::new(1e-3, true, true).unwrap()).unwrap();
    old.as_object_mut().unwrap().remove("line_stiffness");
    assert_eq!(serde_json::from_value::<RodContacts>(old).unwrap().line_stiffness, None);
}

/// Rod b pressed onto rod a by q (N/m) along their length and pulled along
/// it by t (N/m); rod a pinned at its ends. Returns, after `steps`
/// overdamped steps of `dt`: rod b's axial move over the last half of the
/// steps (m), the rows' friction force on b along the rods summed (N), their
/// normal forces summed (N), and the largest |F_t|/(μ N) of a row.
fn pressed_and_pulled(mu: f64, t: f64, steps: usize, dt: f64) -> (f64, f64, f64, f64) {
    let (q, k, length) = (200.0, 1e6, 1.0);
    let params = IntegrationParameters { dt, overdamped: true, viscosity: 10.0, gravity: [0.0; 3], ..Default::default() };
    let mut w = World::new(params);
    let a = w.add_rod(rod(Vector3::zeros(), Vector3::new(length, 0.0, 0.0), 12));
    let b = w.add_rod(rod(Vector3::new(0.0, 0.0, 2.0 * R - q / k), Vector3::new(length, 0.0, 2.0 * R - q / k), 12));
    let (u0, u1) = w.rod(a).unwrap().domain();
    for u in [u0, u1] {
        let p = w.rod(a).unwrap().position(u).unwrap();
        w.add_constraint(a, ConstraintKind::Position(Position { u, axes: [true, true, true, false], target: [p.x, p.y, p.z, 0.0] }), 0.0).unwrap();
    }
    w.add_load(Load::Distributed(Distributed { rod: a, force_per_length: [0.0, 0.0, q] })).unwrap();
    w.add_load(Load::Distributed(Distributed { rod: b, force_per_length: [t, 0.0, -q] })).unwrap();
    w.add_contact_detector(RodContacts::new(0.25 * R, false, true).unwrap().with_friction(mu).unwrap().with_line_stiffness(k).unwrap()).unwrap();
    let x = |w: &World| w.rod(b).unwrap().position(0.5 * (u0 + u1)).unwrap().x;
    let mut half = 0.0;
    for s in 0..steps {
        if s == steps / 2 {
            half = x(&w);
        }
        w.step().unwrap();
    }
    let (mut friction, mut normal, mut worst) = (0.0, 0.0, 0.0f64);
    for (_, p) in w.contacts().active() {
        let f = p.friction_force()[0] * if p.rods[0] == b { 1.0 } else { -1.0 };
        friction += f;
        normal += p.force;
        worst = worst.max(Vector3::from(p.friction_force()).norm() / (mu * p.force));
    }
    (x(&w) - half, friction, normal, worst)
}

#[test]
fn friction_on_distributed_rows_holds_below_mu_q_and_slides_at_it_above() {
    let (mu, q, k) = (0.3, 200.0, 1e6);
    // Pulled by half of μ q: held. Each row's spring stretches by
    // μ N C = μ q/k at most before it slips; rod a, pinned at its ends,
    // stretches under the friction, so the rows near the ends take the
    // most (shear lag) and slip (26 of 92 at the cone), and those between
    // hold the rest. The pair, one rod pulled and the other held, bends as
    // a two-layer beam (its middle rises 5 mm) over the overdamped bending
    // time ζL⁴/(π⁴EI) ≈ 1.7 s, shifting normal force between the rows:
    // rod b slides on while it bends (7e-9 m a step at step 800 of 1 ms)
    // and stops when it has (1e-14 m a step at 30 s). Over the last
    // 2000 steps of 10 ms it moves by less than 1e-3 of μ q/k; the rows'
    // friction carries the pull (to 4e-4 measured: on the bent pair the
    // normal forces take a part along x), each row within μ N.
    let (moved, friction, normal, worst) = pressed_and_pulled(mu, 0.5 * mu * q, 4000, 1e-2);
    println!("held: moved {moved:.3e} m (μ q/k = {:.1e} m); friction {friction:.4} N, normal {normal:.4} N, worst |F_t|/(μN) {worst:.4}", mu * q / k);
    assert!(moved.abs() < 1e-3 * mu * q / k, "the held rod crept by {moved} m");
    assert!((friction / (-0.5 * mu * q) - 1.0).abs() < 2e-3, "friction {friction} N should carry the pull {} N", 0.5 * mu * q);
    assert!(worst <= 1.0 + 1e-6, "a held row's friction is {worst} μN");
    // Pulled by twice μ q: it slides. A row's spring is trimmed to μ N at
    // the start of each step and stiffens the step by k over what it slides
    // in it: against the fluid's drag ζ per length the sliding friction is
    // μ q + (t − μ q) k dt/(ζ + k dt) per length, μ q as dt → 0 (with
    // ζ ≈ 13 N·s/m² here: 1.43 μ q measured at dt = 1e-5 s, 1.93 at 2e-4).
    let (moved, friction, normal, worst) = pressed_and_pulled(mu, 2.0 * mu * q, 2000, 1e-7);
    let ratio = -friction / (mu * normal);
    println!("sliding: moved {moved:.3e} m in 1000 steps; friction {friction:.4} N = {ratio:.4} μ N (N = {normal:.4} N), worst row {worst:.4}");
    assert!(moved > 4.0 * mu * q / k, "the pulled rod should slide well past its springs' μ q/k: {moved} m");
    assert!((ratio - 1.0).abs() < 0.02, "sliding friction {ratio} μN");
}
