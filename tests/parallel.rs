//! Steps on rayon's pool give the one-thread answer bit for bit: the
//! kernels, the pipelined scatter, the guard's per-rod energies and the
//! band LDLᵀ of a system that falls apart in two (free rods) all keep the
//! serial order of every sum. Worlds of ≥ 2048 segments, where the pool is
//! used.
use nalgebra::Vector3;
use strandkit::prelude::*;
use strandkit::RodContacts;

/// `n` hanging rods of 25 control points side by side, bent, the first
/// `linked` of them joined end to end in pairs (a relative position ties
/// rod 2k's end to rod 2k+1's start: a coupled system), every rod's start
/// pinned; optional contact detection.
fn world(parallel: bool, n: usize, linked: usize, contact: bool) -> World {
    let mut w = World::new(IntegrationParameters { dt: 2e-3, gravity: [0.0, -9.81, 0.0], parallel, ..Default::default() });
    let mut hs = Vec::new();
    for i in 0..n {
        let z = 0.05 * i as f64;
        let rod = RodBuilder::straight(Vector3::new(0.0, 0.0, z), Vector3::new(1.0, 0.1 * (i % 3) as f64, z))
            .control_points(25)
            .section(Section::circle(0.01).unwrap())
            .material(Material::new("rubber", 1e7, 0.45, 1000.0).unwrap())
            .options(RodOptions { drag: 1.0, ..Default::default() })
            .build()
            .unwrap();
        let h = w.add_rod(rod);
        let (u0, _) = w.rod(h).unwrap().domain();
        let p = w.rod(h).unwrap().position(u0).unwrap();
        w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true, true, true, false], target: [p.x, p.y, p.z, 0.0] }), 0.0).unwrap();
        hs.push(h);
    }
    for k in 0..linked / 2 {
        let (a, b) = (hs[2 * k], hs[2 * k + 1]);
        let (_, ua) = w.rod(a).unwrap().domain();
        let (ub, _) = w.rod(b).unwrap().domain();
        let d = w.rod(a).unwrap().position(ua).unwrap() - w.rod(b).unwrap().position(ub).unwrap();
        let offset = [d.x, d.y, d.z, 0.0];
        w.add_link(a, b, ConstraintKind::RelativePosition(RelativePosition { ua, ub, axes: [true, true, true, false], offset }), 0.0).unwrap();
    }
    if contact {
        w.add_contact_detector(RodContacts::new(0.005, false, true).unwrap()).unwrap();
    }
    w
}

fn same_after_steps(n: usize, linked: usize, contact: bool, steps: usize) {
    let (mut a, mut b) = (world(false, n, linked, contact), world(true, n, linked, contact));
    for k in 0..steps {
        let (ra, rb) = (a.step().unwrap(), b.step().unwrap());
        assert_eq!(ra.elastic_energy.to_bits(), rb.elastic_energy.to_bits(), "step {k}: elastic energy");
    }
    for ((_, ra), (_, rb)) in a.rods().zip(b.rods()) {
        for (x, y) in ra.coords().iter().zip(rb.coords()) {
            assert_eq!(x, y, "coordinates differ after {steps} steps");
        }
        for (x, y) in ra.velocities().iter().zip(rb.velocities()) {
            assert_eq!(x, y, "velocities differ after {steps} steps");
        }
    }
}

#[test]
fn free_rods_step_alike_on_one_thread_and_on_the_pool() {
    // 100 rods × 22 segments = 2200 ≥ 2048: kernels, scatter, energies and
    // the split LDLᵀ on the pool.
    same_after_steps(100, 0, false, 6);
}

#[test]
fn linked_rods_with_contacts_step_alike_on_one_thread_and_on_the_pool() {
    // Rods tied in pairs (the system splits between pairs, not within
    // them) and contact detection on.
    same_after_steps(100, 100, true, 4);
}
