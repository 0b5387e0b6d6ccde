//! Steps on rayon's pool give the one-thread answer bit for bit: the
//! kernels, the pipelined scatter (or, for free rods, the two halves'
//! assemblies), the guard's per-rod energies and the band LDLᵀ of a
//! system that falls apart in two (free rods) all keep the serial order of
//! every sum. Worlds of ≥ 2048 segments, where the pool is used.
use nalgebra::Vector3;
use strandkit::prelude::*;
use strandkit::{RodContacts, Scheme};

/// `n` rods of 25 control points along x, 3 cm apart in z, their starts
/// pinned. Without `pairs` they are free (gravity −y). With `pairs`, under
/// gravity −z, rod 2k is also pinned at its middle and end and rod 2k+1 above it is
/// tied by its end to rod 2k's end (a relative position: a coupled
/// system), so that it sags onto rod 2k: contact detection on, pairs
/// active.
fn world(parallel: bool, n: usize, pairs: bool) -> World {
    world_with(parallel, n, pairs, Scheme::ImplicitEuler, false, None)
}

/// [`world`] stepped by `scheme`, with a 20 g bead sliding on every
/// seventh free rod and on rods 49 and 50 when `beads`; the pairs'
/// contact on distributed rows of stiffness `line` (N/m²) when given.
fn world_with(parallel: bool, n: usize, pairs: bool, scheme: Scheme, beads: bool, line: Option<f64>) -> World {
    let gravity = if pairs { [0.0, 0.0, -9.81] } else { [0.0, -9.81, 0.0] };
    let mut w = World::new(IntegrationParameters { dt: 2e-3, gravity, parallel, scheme, ..Default::default() });
    let mut hs = Vec::new();
    for i in 0..n {
        let z = 0.03 * i as f64;
        // Free rods in three directions; a pair's rods one above the other.
        let y = if pairs { 0.0 } else { 0.1 * (i % 3) as f64 };
        let rod = RodBuilder::straight(Vector3::new(0.0, 0.0, z), Vector3::new(1.0, y, z))
            .control_points(25)
            .section(Section::circle(0.01).unwrap())
            .material(Material::new("rubber", 1e7, 0.45, 1000.0).unwrap())
            .options(RodOptions { drag: 1.0, ..Default::default() })
            .build()
            .unwrap();
        let h = w.add_rod(rod);
        let (u0, u1) = w.rod(h).unwrap().domain();
        // The lower rod of a pair is pinned at its middle too: it sags a
        // sixteenth of what the upper one does, which falls onto it.
        let ends: &[f64] = if pairs && i % 2 == 0 { &[u0, 0.5 * (u0 + u1), u1] } else { &[u0] };
        for &u in ends {
            let p = w.rod(h).unwrap().position(u).unwrap();
            w.add_constraint(h, ConstraintKind::Position(Position { u, axes: [true, true, true, false], target: [p.x, p.y, p.z, 0.0] }), 0.0).unwrap();
        }
        // Either side of the middle too, where the free rods' assembly
        // splits in two (rods 49 and 50).
        if beads && (i % 7 == 3 || i == 49 || i == 50) {
            w.add_bead(h, u0 + 0.6 * (u1 - u0), 0.02, 0.0, 0.0).unwrap();
        }
        hs.push(h);
    }
    if pairs {
        for k in 0..n / 2 {
            let (a, b) = (hs[2 * k], hs[2 * k + 1]);
            let (_, ua) = w.rod(a).unwrap().domain();
            let (_, ub) = w.rod(b).unwrap().domain();
            let d = w.rod(a).unwrap().position(ua).unwrap() - w.rod(b).unwrap().position(ub).unwrap();
            let offset = [d.x, d.y, d.z, 0.0];
            w.add_link(a, b, ConstraintKind::RelativePosition(RelativePosition { ua, ub, axes: [true, true, true, false], offset }), 0.0).unwrap();
        }
        let detector = RodContacts::new(0.005, false, true).unwrap();
        let detector = match line {
            Some(k) => detector.with_line_stiffness(k).unwrap(),
            None => detector,
        };
        w.add_contact_detector(detector).unwrap();
    }
    w
}

fn same_after_steps(n: usize, pairs: bool, steps: usize) -> usize {
    same_worlds_after_steps(world(false, n, pairs), world(true, n, pairs), steps)
}

fn same_worlds_after_steps(mut a: World, mut b: World, steps: usize) -> usize {
    let mut most = 0;
    for k in 0..steps {
        let (ra, rb) = (a.step().unwrap(), b.step().unwrap());
        assert_eq!(ra.elastic_energy.to_bits(), rb.elastic_energy.to_bits(), "step {k}: elastic energy");
        assert_eq!(ra.active_contacts, rb.active_contacts, "step {k}: active contacts");
        most = most.max(ra.active_contacts);
    }
    for ((_, ra), (_, rb)) in a.rods().zip(b.rods()) {
        for (x, y) in ra.coords().iter().zip(rb.coords()) {
            assert_eq!(x, y, "coordinates differ after {steps} steps");
        }
        for (x, y) in ra.velocities().iter().zip(rb.velocities()) {
            assert_eq!(x, y, "velocities differ after {steps} steps");
        }
    }
    for ((_, ba), (_, bb)) in a.beads().zip(b.beads()) {
        assert_eq!(ba.u.to_bits(), bb.u.to_bits(), "bead abscissae differ after {steps} steps");
    }
    most
}

/// Free rods carrying sliding beads (point masses scattered with their
/// segments, in either half, on the last rod of the first and the first
/// of the second), and free rods stepped by the trapezoidal
/// rule (whose first solve records the rods' elastic forces, split by
/// rod like the right-hand side).
#[test]
fn free_rods_with_beads_or_the_trapezoidal_rule_step_alike_on_the_pool() {
    let beads = |parallel| world_with(parallel, 100, false, Scheme::ImplicitEuler, true, None);
    assert_eq!(beads(true).beads().count(), 16);
    same_worlds_after_steps(beads(false), beads(true), 6);
    let trapezoidal = |parallel| world_with(parallel, 100, false, Scheme::Trapezoidal, false, None);
    same_worlds_after_steps(trapezoidal(false), trapezoidal(true), 4);
}

#[test]
fn free_rods_step_alike_on_one_thread_and_on_the_pool() {
    // 100 rods × 22 segments = 2200 ≥ 2048: kernels, scatter, energies and
    // the split LDLᵀ on the pool (`pipeline::tests` checks the split).
    same_after_steps(100, false, 6);
}

#[test]
fn linked_rods_in_contact_step_alike_on_one_thread_and_on_the_pool() {
    // Pairs tied and pressed together (the system can split between
    // pairs, not within them), with their contacts' active set.
    let most = same_after_steps(100, true, 40);
    assert!(most >= 50, "the sagging rods should touch the rods below: {most} active pairs at most");
}

#[test]
fn rods_on_distributed_contact_rows_step_alike_on_one_thread_and_on_the_pool() {
    // The rows are found in blocks on the pool (`distributed_rows`); a
    // row per capsule within reach, so many more than the closest rows.
    let line = |parallel| world_with(parallel, 100, true, Scheme::ImplicitEuler, false, Some(2e5));
    let most = same_worlds_after_steps(line(false), line(true), 40);
    assert!(most >= 200, "the sagging rods should press on the rods below along lines: {most} active rows at most");
}
