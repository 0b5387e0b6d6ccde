//! Reliability regressions (the defects of `../shared/repro/`): each test
//! asserts the fixed behaviour — a clean typed error, or a correct finite
//! result, with the world left as it was on refusal.
mod common;
use common::steel_rod;
use nalgebra::Vector3;
use strandkit::prelude::*;
use strandkit::{Event, LinearSolver};

/// repro/panic_relax_empty_world.py: relax of a world without rods is a
/// no-op, like step.
#[test]
fn relax_of_an_empty_world_is_a_no_op() {
    let mut w = World::new(IntegrationParameters::default());
    let r = w.relax().expect("empty relax");
    assert_eq!(r.iterations, 0);
    assert_eq!(w.n_rods(), 0);
}

/// repro/relax_refused_zeroes_velocities.py: a relax refused because the
/// rod is not statically defined leaves its velocities as they were.
#[test]
fn refused_relax_keeps_the_velocities() {
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(steel_rod(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0), 6, true));
    let v: Vec<f64> = (0..w.rod(h).unwrap().velocities().len()).map(|i| 0.01 * (i as f64 + 1.0)).collect();
    w.rod_mut(h).unwrap().set_velocities(&v).unwrap();
    let q0 = w.rod(h).unwrap().coords().to_vec();
    let e = w.relax().expect_err("a free rod has no static equilibrium");
    assert!(matches!(e, Error::Singular { .. }), "{e}");
    assert!(e.to_string().contains("not statically defined"), "{e}");
    assert_eq!(w.rod(h).unwrap().velocities(), &v[..]);
    assert_eq!(w.rod(h).unwrap().coords(), &q0[..]);
}

fn nylon_rod(n: usize, opts: RodOptions, material: Material) -> Rod {
    RodBuilder::straight(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0))
        .control_points(n)
        .section(Section::circle(0.01).unwrap())
        .material(material)
        .options(opts)
        .build()
        .unwrap()
}

/// Everything a refused step must leave as it was.
fn state(w: &World) -> (f64, u64, Vec<Vec<f64>>, Vec<Vec<f64>>, Vec<Vec<Section>>) {
    let rods: Vec<_> = w.rods().map(|(_, r)| r).collect();
    (
        w.time(),
        w.n_steps(),
        rods.iter().map(|r| r.coords().to_vec()).collect(),
        rods.iter().map(|r| r.velocities().to_vec()).collect(),
        rods.iter().map(|r| r.sections().to_vec()).collect(),
    )
}

/// repro/poisson_error_after_step_applied.py: a step whose Poisson update
/// is impossible (a rubber rod stretched 300 %, ν = 0.5: 1 − νε < 0) is
/// refused before it changes anything.
#[test]
fn impossible_poisson_update_refuses_the_whole_step() {
    let rubber = Material::new("rubber", 1e6, 0.5, 1000.0).unwrap();
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(nylon_rod(8, RodOptions { poisson_update: true, ..Default::default() }, rubber));
    let mut q = w.rod(h).unwrap().coords().to_vec();
    q.iter_mut().step_by(4).for_each(|x| *x *= 4.0);
    w.rod_mut(h).unwrap().set_coords(&q).unwrap();
    let before = state(&w);
    let e = w.step().expect_err("ε ≈ 3 > 1/ν");
    assert!(e.to_string().contains("Poisson update"), "{e}");
    assert_eq!(state(&w), before, "the refused step changed the world");
    // A sound stretch (10 %) steps and contracts the section: R = R0 (1 − ν ε).
    let q: Vec<f64> = q.iter().enumerate().map(|(i, x)| if i % 4 == 0 { x / 4.0 * 1.1 } else { *x }).collect();
    w.rod_mut(h).unwrap().set_coords(&q).unwrap();
    w.step().expect("10 % stretch");
    let Section::Circle { radius: r } = w.rod(h).unwrap().sections()[4] else { panic!("a circle") };
    assert!((r / 0.01 - (1.0 - 0.5 * 0.1)).abs() < 0.01, "R/R0 = {}", r / 0.01);
}

/// repro/step_returns_nonfinite_state.py: a finite but extreme load whose
/// step would overflow the coordinates is refused as NonFinite naming the
/// rod, the world stays finite and unchanged, and the next step is refused
/// the same way (not a NaN band).
#[test]
fn step_to_a_non_finite_state_is_refused() {
    let mut w = World::new(IntegrationParameters { dt: 0.5, gravity: [0.0, -9.81, 0.0], ..Default::default() });
    let h = w.add_rod(nylon_rod(8, RodOptions::default(), Material::preset("nylon").unwrap()));
    w.add_constraint(h, Tangent { u: 0.5, direction: [1.0, 0.0, 0.0] }, 0.0).unwrap();
    w.add_load(Load::Distributed(Distributed { rod: h, force_per_length: [0.0, 0.0, f64::MAX] })).unwrap();
    let before = state(&w);
    for _ in 0..2 {
        match w.step() {
            Err(Error::NonFinite { rod, .. }) => assert_eq!(rod, Some(h)),
            other => panic!("expected NonFinite, got {other:?}"),
        }
        assert_eq!(state(&w), before);
    }
}

/// repro/sparse_step_nan_state.py: a bead of mass 1e300 whose sliding step
/// overflows is refused (NonFinite naming the string) with every solver,
/// and nothing moves.
#[test]
fn overflowing_bead_is_refused_with_every_solver() {
    for solver in [LinearSolver::Auto, LinearSolver::Sparse, LinearSolver::BandLu] {
        let mut w = World::new(IntegrationParameters { gravity: [0.0, -9.81, 0.0], linear_solver: solver, ..Default::default() });
        let h = w.add_rod(nylon_rod(8, RodOptions::default(), Material::preset("nylon").unwrap()));
        let (start, end) = w.rod(h).unwrap().domain();
        w.clamp(h, start, 0.0).unwrap();
        let p = w.rod(h).unwrap().position(end).unwrap();
        w.add_constraint(h, Position { u: end, axes: [true, true, true, false], target: [p.x, p.y, p.z, 0.0] }, 0.0).unwrap();
        let b = w.add_bead(h, 2.5, 1e300, 0.0, 0.0).unwrap();
        let before = state(&w);
        let e = w.step().expect_err("overflowing bead");
        assert!(matches!(e, Error::NonFinite { .. } | Error::Singular { .. }), "{solver:?}: {e}");
        assert_eq!(state(&w), before, "{solver:?}");
        assert!(w.bead(b).unwrap().u.is_finite());
    }
}

/// repro/panic_sparse_stale_pattern.py: after the sparse path fails on a
/// singular system, removing a constraint (a smaller system) steps or
/// fails cleanly — never a stale pattern inside faer.
#[test]
fn sparse_path_recovers_after_a_failure_and_a_topology_change() {
    let mut w = World::new(IntegrationParameters { dt: 1e6, gravity: [0.0, -9.81, 0.0], linear_solver: LinearSolver::Sparse, ..Default::default() });
    let h = w.add_rod(nylon_rod(8, RodOptions::default(), Material::preset("nylon").unwrap()));
    let (start, end) = w.rod(h).unwrap().domain();
    // The roll is held nowhere: at dt = 1e6 the system is singular.
    w.add_constraint(h, Position { u: start, axes: [true, true, true, false], target: [0.0; 4] }, 0.0).unwrap();
    let p = w.rod(h).unwrap().position(end).unwrap();
    let c = w.add_constraint(h, Position { u: end, axes: [true, true, true, false], target: [p.x, p.y, p.z, 0.0] }, 0.0).unwrap();
    let first = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| w.step().map(|_| ())));
    assert!(matches!(first, Ok(Err(Error::Singular { .. }))), "step 1: {first:?}");
    w.remove_constraint(c).unwrap();
    let second = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| w.step().map(|_| ())));
    match second {
        Err(_) => panic!("step 2 panicked"),
        Ok(r) => {
            if let Err(e) = r {
                assert!(matches!(e, Error::Singular { .. }), "{e}");
            }
        }
    }
}

/// repro/relax_false_not_defined.py: a clamped straight rod is statically
/// defined whatever its number of control points (the definedness
/// threshold is relative); clamped rods relax under their weight to the
/// small-deflection tip sag w L⁴ / 8EI. At 40,000 control points the
/// rod is accepted (a full relax converges too, in ~400 damped Newton
/// iterations, ~100 s: the (L/Δs)⁴ conditioning of static bending — too
/// slow for the suite, so only the acceptance is checked there).
#[test]
fn clamped_rods_of_any_size_are_statically_defined() {
    for (n, iterations) in [(1200, 500), (5000, 500), (40000, 2)] {
        let mut w = World::new(IntegrationParameters { gravity: [0.0, -9.81, 0.0], relax_max_iterations: iterations, ..Default::default() });
        let steel = Material::new("steel", 200e9, 0.3, 7800.0).unwrap();
        let h = w.add_rod(
            RodBuilder::straight(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0))
                .control_points(n)
                .section(Section::circle(0.01).unwrap())
                .material(steel)
                .build()
                .unwrap(),
        );
        let (start, end) = w.rod(h).unwrap().domain();
        w.clamp(h, start, 0.0).unwrap();
        match w.relax() {
            Ok(_) => {
                let y = w.rod(h).unwrap().position(end).unwrap().y;
                // w L⁴ / 8 E I with w = ρ A g, I = π r⁴ / 4.
                let (a, i) = (std::f64::consts::PI * 1e-4, std::f64::consts::PI * 1e-8 / 4.0);
                let sag = 7800.0 * a * 9.81 / (8.0 * 200e9 * i);
                assert!((-y / sag - 1.0).abs() < 1e-3, "n = {n}: tip sag {} vs {sag}", -y);
            }
            Err(Error::NotConverged { .. }) if iterations < 10 => {}
            Err(e) => panic!("n = {n}: {e}"),
        }
    }
}


/// repro/rupture_cascade.py: a tip force beyond the breaking strength
/// (5e5 N on a copper rod of R = 1 cm, EA ε_B = 1.7e5 N) tears the loaded
/// end off; pieces shorter than their thickness leave the world with their
/// load (FragmentRemoved), at most one rupture per rod per step, and the
/// world keeps stepping: the clamped remainder relaxes below its limit.
#[test]
fn rupture_cascades_are_bounded_and_the_world_keeps_stepping() {
    let copper = Material::preset("copper")
        .unwrap()
        .with_rupture(strandkit::material::StrainLimits { stretch: (f64::NEG_INFINITY, 0.005), ..strandkit::material::StrainLimits::unlimited() })
        .unwrap();
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(nylon_rod(8, RodOptions::default(), copper));
    let (start, end) = w.rod(h).unwrap().domain();
    w.clamp(h, start, 0.0).unwrap();
    w.add_load(Load::PointForce(PointForce { rod: h, u: end, force: [5e5, 0.0, 0.0] })).unwrap();
    let (mut ruptures, mut removed) = (0, 0);
    for step in 0..200 {
        let report = w.step().unwrap_or_else(|e| panic!("step {step}: {e}"));
        let r = report.events.iter().filter(|e| matches!(e, Event::RodRuptured { .. })).count();
        assert!(r <= w.n_rods() + 1, "step {step}: {r} ruptures");
        ruptures += r;
        removed += report.events.iter().filter(|e| matches!(e, Event::FragmentRemoved { .. })).count();
    }
    assert!(ruptures >= 1 && removed >= 1, "ruptures {ruptures}, removed {removed}");
    assert_eq!(w.loads().count(), 0, "the torn-off end took its load along");
    // What is left is clamped, unloaded and at rest within its limit.
    for (_, rod) in w.rods() {
        assert!(rod.relative_strains().iter().all(|s| s.eps.abs() < 0.005), "a piece is still past its limit");
        assert!(rod.coords().iter().all(|x| x.is_finite()));
    }
    eprintln!("ruptures {ruptures}, fragments removed {removed}, rods left {}", w.n_rods());
}

/// repro/repro_small_rest_curvature_ignored.py: a gently curved rod (rest
/// radius of curvature 10 L, 2 L, L, L/2, with the default regularisation
/// κ_ε = 1/L) is at zero energy and zero force in its rest shape, and a
/// relax without load leaves it there.
#[test]
fn gentle_rest_curvature_is_kept() {
    let r: f64 = 0.005;
    let mat = Material::new("m", 1.0 / (std::f64::consts::PI * r.powi(4) / 4.0), 0.3, 1.0).unwrap(); // EI = 1
    for rad in [10.0f64, 2.0, 1.0, 0.5] {
        let arc = move |s: f64| Vector3::new(rad * (s / rad).sin(), rad * (1.0 - (s / rad).cos()), 0.0);
        let rod = RodBuilder::curve(1.0, arc).control_points(20).section(Section::circle(r).unwrap()).material(mat.clone()).build().unwrap();
        // ½ EI κ0² L would be the energy if the rest curvature were lost.
        let lost = 0.5 / (rad * rad);
        assert!(rod.elastic_energy() < 1e-12 * lost, "R = {rad}: energy at rest {:e}", rod.elastic_energy());
        let f = rod.internal_forces().iter().fold(0.0f64, |m, x| m.max(x.abs()));
        assert!(f < 1e-9, "R = {rad}: force at rest {f:e}");
        let mut w = World::new(IntegrationParameters::default());
        let h = w.add_rod(rod);
        let (start, end) = w.rod(h).unwrap().domain();
        w.clamp(h, start, 0.0).unwrap();
        w.add_constraint(h, Plane { u: end, origin: [0.0; 3], normal: [0.0, 0.0, 1.0] }, 0.0).unwrap();
        w.relax().unwrap();
        let tip = w.rod(h).unwrap().position(end).unwrap();
        assert!((tip - arc(1.0)).norm() < 1e-6, "R = {rad}: tip moved by {:e}", (tip - arc(1.0)).norm());
    }
}

/// A clamped-free column (L = 1, EI = 1, R = 5 mm, held in the z = 0 plane
/// at its tip) under a dead compressive tip load of `load` × P_cr, started
/// `d0` L off straight in its first mode shape.
fn column(load: f64, d0: f64) -> (World, RodHandle) {
    let r: f64 = 0.005;
    let pcr = std::f64::consts::PI.powi(2) / 4.0;
    let mat = Material::new("m", 1.0 / (std::f64::consts::PI * r.powi(4) / 4.0), 0.3, 1.0).unwrap();
    let mut rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0))
        .control_points(20)
        .with_roll(false)
        .section(Section::circle(r).unwrap())
        .material(mat)
        .build()
        .unwrap();
    let q: Vec<f64> = rod.coords().chunks(3).flat_map(|p| [p[0], d0 * (1.0 - (std::f64::consts::PI * p[0] / 2.0).cos()), p[2]]).collect();
    rod.set_coords(&q).unwrap();
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(rod);
    let (u0, u1) = w.rod(h).unwrap().domain();
    w.add_constraint(h, Position { u: u0, axes: [true, true, true, false], target: [0.0; 4] }, 0.0).unwrap();
    w.add_constraint(h, Tangent { u: u0, direction: [1.0, 0.0, 0.0] }, 0.0).unwrap();
    w.add_constraint(h, Plane { u: u1, origin: [0.0; 3], normal: [0.0, 0.0, 1.0] }, 0.0).unwrap();
    w.add_load(Load::PointForce(PointForce { rod: h, u: u1, force: [-load * pcr, 0.0, 0.0] })).unwrap();
    (w, h)
}

fn tip_of(w: &World, h: RodHandle) -> Vector3<f64> {
    let u1 = w.rod(h).unwrap().domain().1;
    w.rod(h).unwrap().position(u1).unwrap()
}

/// repro/repro_relax_unstable_equilibrium.py: relax reports the stability
/// of what it found. The column under 1.03 P_cr started 1e-6 L off straight
/// relaxes to the straight state, reported unstable with one unstable
/// direction; started 1e-4 L off it finds the buckled elastica (tip
/// deflection 0.30112 L), reported stable; at 0.97 P_cr the straight state
/// is stable.
#[test]
fn relax_reports_the_stability_of_the_equilibrium() {
    let relaxed = |load: f64, d0: f64| {
        let (mut w, h) = column(load, d0);
        let report = w.relax().unwrap();
        (report, tip_of(&w, h))
    };
    let (straight, tip) = relaxed(1.03, 1e-6);
    assert!(tip.y.abs() < 1e-4, "stayed straight: {}", tip.y);
    assert_eq!((straight.stable, straight.unstable_directions), (Some(false), Some(1)), "{straight:?}");
    let (buckled, tip) = relaxed(1.03, 1e-4);
    assert!((tip.y.abs() - 0.30112).abs() < 2e-3, "elastica tip deflection {}", tip.y);
    assert_eq!((buckled.stable, buckled.unstable_directions), (Some(true), Some(0)), "{buckled:?}");
    let (below, _) = relaxed(0.97, 1e-6);
    assert_eq!((below.stable, below.unstable_directions), (Some(true), Some(0)), "{below:?}");
}

/// relax_perturbed leaves the unstable straight column (1.03 P_cr, started
/// 1e-6 L off straight) for the buckled elastica: tip deflection 0.30112 L
/// (±0.002 L), reported stable.
#[test]
fn relax_perturbed_leaves_an_unstable_equilibrium() {
    let (mut w, h) = column(1.03, 1e-6);
    let report = w.relax_perturbed(1e-3).unwrap();
    let tip = tip_of(&w, h);
    assert!((tip.y.abs() - 0.30112).abs() < 2e-3, "tip deflection {}", tip.y);
    assert_eq!(report.stable, Some(true), "{report:?}");
}

/// Material coordinates: `u_at_rest_arc_length` inverts
/// `rest_arc_length` (to 1e-12 L), and on a circular arc of radius R the
/// point at arc length s is at angle s/R (to the spline's fit error);
/// s outside [0, L] or NaN is an error.
#[test]
fn arc_length_coordinates_round_trip() {
    let rad = 0.3;
    let arc = move |s: f64| Vector3::new(rad * (s / rad).sin(), rad * (1.0 - (s / rad).cos()), 0.0);
    let rod = RodBuilder::curve(1.0, arc).control_points(40).section(Section::circle(0.005).unwrap()).material(Material::preset("nylon").unwrap()).build().unwrap();
    let len = rod.rest_length();
    assert!((len - 1.0).abs() < 1e-6, "rest length {len}");
    for k in 0..=20 {
        let s = len * k as f64 / 20.0;
        let u = rod.u_at_rest_arc_length(s).unwrap();
        assert!((rod.rest_arc_length(u).unwrap() - s).abs() < 1e-12 * len, "s = {s}");
        let p = rod.position(u).unwrap();
        assert!((p - arc(s)).norm() < 1e-6, "s = {s}: {} off the arc", (p - arc(s)).norm());
    }
    for bad in [-1e-3, 1.01 * len, f64::NAN] {
        assert!(matches!(rod.u_at_rest_arc_length(bad), Err(Error::InvalidInput { .. })), "{bad}");
    }
}

/// repro/repro_relax_spin_mode.py: a ring (a straight rod bent into a
/// circle, closed by relative position + orientation) clamped by position
/// and tangent can still spin about the clamp tangent (Frenet model: the
/// roll coordinate turns with the Frenet normal). Started squashed, the
/// start's violation hides the mode from the first check; the check at
/// convergence names it, on every linear solver, and the world is left as
/// it was. Held by a plane at the opposite point, the ring relaxes to the
/// circle's bending energy 2π² EI / L (to the spline's 2.5e-4).
#[test]
fn a_ring_free_to_spin_about_its_clamp_is_named_on_every_solver() {
    use std::f64::consts::PI;
    let (l, r): (f64, f64) = (1.0, 0.005);
    let rad = l / (2.0 * PI);
    let young = 1.0 / (PI * r.powi(4) / 4.0); // EI = 1
    for hold in [false, true] {
        for solver in [LinearSolver::Auto, LinearSolver::Band, LinearSolver::Sparse] {
            let mat = Material::new("m", young, 0.3, 1.0).unwrap();
            let circle = RodBuilder::curve(l, move |s| Vector3::new(rad * (s / rad).sin(), 1.15 * rad * (1.0 - (s / rad).cos()), 0.0))
                .control_points(40)
                .with_roll(false)
                .section(Section::circle(r).unwrap())
                .material(mat.clone())
                .build()
                .unwrap();
            let mut rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(l, 0.0, 0.0))
                .control_points(40)
                .with_roll(false)
                .section(Section::circle(r).unwrap())
                .material(mat)
                .build()
                .unwrap();
            rod.set_coords(circle.coords()).unwrap();
            let mut w = World::new(IntegrationParameters { relax_max_iterations: 2000, linear_solver: solver, ..Default::default() });
            let h = w.add_rod(rod);
            let (u0, u1) = w.rod(h).unwrap().domain();
            w.add_link(h, h, ConstraintKind::RelativePosition(RelativePosition { ua: u0, ub: u1, axes: [true, true, true, false], offset: [0.0; 4] }), 0.0).unwrap();
            w.add_link(h, h, ConstraintKind::RelativeOrientation(RelativeOrientation { ua: u0, ub: u1, roll: false }), 0.0).unwrap();
            w.clamp(h, u0, 0.0).unwrap();
            if hold {
                w.add_constraint(h, ConstraintKind::Plane(Plane { u: 0.5 * (u0 + u1), origin: [0.0; 3], normal: [0.0, 0.0, 1.0] }), 0.0).unwrap();
            }
            let q0 = w.rod(h).unwrap().coords().to_vec();
            match (hold, w.relax()) {
                (false, Err(e)) => {
                    assert!(matches!(e, Error::Singular { .. }), "{solver:?}: {e}");
                    assert!(e.to_string().contains("rotation about x is held by no constraint"), "{solver:?}: {e}");
                    assert_eq!(w.rod(h).unwrap().coords(), &q0[..], "{solver:?}: the world moved");
                }
                (true, Ok(rep)) => {
                    let u = w.rod(h).unwrap().elastic_energy();
                    assert!((u / (2.0 * PI * PI) - 1.0).abs() < 5e-4, "{solver:?}: U = {u}");
                    assert!(rep.iterations < 50, "{solver:?}: {} iterations", rep.iterations);
                }
                (hold, other) => panic!("{solver:?} hold={hold}: {other:?}"),
            }
        }
    }
}

/// A system made singular during the run (a moving target turns a second
/// plane onto the first plane's normal, with another offset: contradictory
/// rows the insertion check could not see) is reported as Singular naming
/// the two planes, with every linear solver (the sparse path falls back to
/// the band LU's exact zero-pivot test before calling it singular; a
/// non-finite solution with moderate entries is singular, not an
/// overflow), and the refused step leaves the world as it was.
#[test]
fn a_singular_system_names_the_constraints_involved() {
    for solver in [LinearSolver::Auto, LinearSolver::Band, LinearSolver::BandLu, LinearSolver::Sparse] {
        let mut w = World::new(IntegrationParameters { linear_solver: solver, ..Default::default() });
        let h = w.add_rod(steel_rod(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0), 6, true));
        let (u0, u1) = w.rod(h).unwrap().domain();
        w.clamp(h, u0, 0.0).unwrap();
        let plane = |origin: [f64; 3], normal: [f64; 3]| ConstraintKind::Plane(Plane { u: u1, origin, normal });
        let p1 = w.add_constraint(h, plane([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]), 0.0).unwrap();
        let p2 = w.add_constraint(h, plane([1.0, 0.0, 0.0], [0.0, 0.0, 1.0]), 0.0).unwrap();
        w.set_constraint(p2, plane([1.0, 0.1, 0.0], [0.0, 1.0, 0.0])).unwrap();
        let before = state(&w);
        match w.step() {
            Err(e @ Error::Singular { .. }) => {
                let Error::Singular { constraints, .. } = &e else { unreachable!() };
                assert!(constraints.contains(&p1) && constraints.contains(&p2), "{solver:?}: {e}");
                assert!(e.to_string().contains("constraints involved"), "{e}");
            }
            other => panic!("{solver:?}: {other:?}"),
        }
        assert!(state(&w) == before, "{solver:?}: the world moved");
    }
}
