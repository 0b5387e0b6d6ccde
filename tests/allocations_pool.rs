//! Steps on rayon's pool do not allocate either, once warmed up: free rods
//! whose assembly splits in two halves, one long rod whose kernels run in
//! pool batches, ropes resting on a slope with friction whose contacts are
//! detected in blocks on the pool, and a pinned mat whose crossings are
//! found, chosen and sorted there. The
//! count is global (the pool's threads do the work), so this file holds
//! one test: no other test's allocations run beside it. The steps run
//! inside the pool (as `World::step` moves them there itself), so that no
//! job is injected from outside, which rayon's queue pays for with a block
//! every 63 jobs.
#[path = "common/alloc_count.rs"]
mod alloc_count;

#[global_allocator]
static A: alloc_count::Counting = alloc_count::Counting;

#[test]
fn steps_on_the_pool_do_not_allocate() {
    use nalgebra::Vector3;
    use strandkit::prelude::*;
    use strandkit::{Obstacle, RodContacts};
    let rubber = Material::new("rubber", 1e7, 0.45, 1000.0).unwrap();
    let straight = |a: Vector3<f64>, b: Vector3<f64>, n: usize, r: f64| {
        RodBuilder::straight(a, b).control_points(n).with_roll(false).section(Section::circle(r).unwrap()).material(rubber.clone()).build().unwrap()
    };
    let params = IntegrationParameters { dt: 1e-3, gravity: [0.0, -9.81, 0.0], parallel: true, ..Default::default() };
    // 400 free rods of 25 control points side by side.
    let mut rods = World::new(params.clone());
    for i in 0..400 {
        let z = 0.2 * i as f64;
        rods.add_rod(straight(Vector3::new(0.0, 0.0, z), Vector3::new(1.0, 0.0, z), 25, 0.01));
    }
    // One rod of 10,000 control points.
    let mut long = World::new(params.clone());
    long.add_rod(straight(Vector3::zeros(), Vector3::new(10.0, 0.0, 0.0), 10_000, 0.01));
    // 125 nylon ropes of 20 control points lying across a slope below its
    // friction angle (tan α = 0.9 μ, μ = 0.4), 5 cm apart: the plane's
    // pairs stick; rod–rod detection runs in blocks on the pool and finds
    // no pair closer than its margin.
    let nylon = Material::new("nylon", 3e9, 0.4, 1140.0).unwrap();
    let ropes = |count: usize| {
        let (r, mu) = (0.01, 0.4);
        let alpha = (0.9f64 * mu).atan();
        let n = Vector3::new(alpha.sin(), 0.0, alpha.cos());
        let down = Vector3::new(alpha.cos(), 0.0, -alpha.sin());
        let mut slope = World::new(IntegrationParameters { dt: 2e-3, gravity: [0.0, 0.0, -9.81], ..params.clone() });
        for i in 0..count {
            let start = n * r + down * (0.05 * i as f64);
            slope.add_rod(RodBuilder::straight(start, start + Vector3::new(0.0, 0.5, 0.0)).control_points(20).with_roll(false).section(Section::circle(r).unwrap()).material(nylon.clone()).build().unwrap());
        }
        slope.add_contact_detector(Obstacle::plane([0.0; 3], n.into()).unwrap().with_margin(0.005).unwrap().with_friction(mu).unwrap()).unwrap();
        slope.add_contact_detector(RodContacts::new(0.005, true, true).unwrap().with_friction(mu).unwrap()).unwrap();
        slope
    };
    let mut slope = ropes(125);
    // 373 of them: 4,103 runs of capsules, so the pair tests' last chunk
    // of 1,024 runs has 7, fewer than its blocks elsewhere (their buffers
    // are kept, not dropped and built again).
    let mut many = ropes(373);
    // A mat of 12 + 12 rubber rods of 90 control points, pinned at their
    // ends, the upper layer resting on the lower: rod–rod pairs found,
    // chosen and sorted on the pool, μ = 0.3.
    let mut mat = World::new(IntegrationParameters { gravity: [0.0, 0.0, -9.81], ..params.clone() });
    let (r, pitch) = (0.003, 0.01);
    for layer in 0..2 {
        for i in 0..12 {
            let (c, z, len) = ((i as f64 + 0.5) * pitch, layer as f64 * 2.0 * r, 12.0 * pitch);
            let (a, b) = if layer == 0 { (Vector3::new(0.0, c, z), Vector3::new(len, c, z)) } else { (Vector3::new(c, 0.0, z), Vector3::new(c, len, z)) };
            let h = mat.add_rod(straight(a, b, 90, r));
            let (u0, u1) = mat.rod(h).unwrap().domain();
            for u in [u0, u1] {
                let p = mat.rod(h).unwrap().position(u).unwrap();
                mat.add_constraint(h, ConstraintKind::Position(Position { u, axes: [true, true, true, false], target: [p.x, p.y, p.z, 0.0] }), 0.0).unwrap();
            }
        }
    }
    mat.add_contact_detector(RodContacts::new(0.002, false, true).unwrap().with_friction(0.3).unwrap()).unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    for (name, w, warm_up) in [("400 free rods", &mut rods, 30), ("one rod of 10,000 points", &mut long, 30), ("ropes on a slope", &mut slope, 100), ("373 ropes on a slope", &mut many, 100), ("a pinned mat", &mut mat, 600)] {
        // Warmed up until the active set holds (a change of topology
        // allocates). Since sticking rows hold their slack the mat's last
        // pairs stop slipping by step 400 and its set settles later: 0.9
        // allocations a step after 450 steps, none after 600 (after 300
        // before).
        let (n, active) = pool.install(|| {
            for _ in 0..warm_up {
                w.step().unwrap();
            }
            let (count, ()) = alloc_count::on_all_threads(|| {
                for _ in 0..10 {
                    w.step().unwrap();
                }
            });
            (count as f64 / 10.0, w.contacts().active().count())
        });
        println!("{name} ({active} active contacts): {n} heap allocations per step on a pool of two");
        assert_eq!(n, 0.0, "{name}");
        if !name.contains("free") && !name.contains("one rod") {
            assert!(active > 0, "{name}: no contact");
        }
    }
}
