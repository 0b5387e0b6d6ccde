//! Steps on rayon's pool do not allocate either, once warmed up: free rods
//! whose assembly splits in two halves, one long rod whose kernels run in
//! pool batches, and rods in contact detected in blocks on the pool. The
//! count is global (the pool's threads do the work), so this file holds
//! one test: no other test's allocations run beside it. The steps run
//! inside the pool (as `World::step` moves them there itself), so that no
//! job is injected from outside, which rayon's queue pays for with a block
//! every 63 jobs.
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

struct Counting;
static ARMED: AtomicBool = AtomicBool::new(false);
static COUNT: AtomicUsize = AtomicUsize::new(0);

fn count() {
    if ARMED.load(Ordering::Relaxed) {
        COUNT.fetch_add(1, Ordering::Relaxed);
    }
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(p, l, n) }
    }
}

#[global_allocator]
static A: Counting = Counting;

/// Steps before counting: long enough for the ropes' active set to settle.
const WARM_UP: usize = 100;

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
    let (r, mu) = (0.01, 0.4);
    let alpha = (0.9f64 * mu).atan();
    let n = Vector3::new(alpha.sin(), 0.0, alpha.cos());
    let down = Vector3::new(alpha.cos(), 0.0, -alpha.sin());
    let mut slope = World::new(IntegrationParameters { dt: 2e-3, gravity: [0.0, 0.0, -9.81], ..params });
    for i in 0..125 {
        let start = n * r + down * (0.05 * i as f64);
        slope.add_rod(RodBuilder::straight(start, start + Vector3::new(0.0, 0.5, 0.0)).control_points(20).with_roll(false).section(Section::circle(r).unwrap()).material(nylon.clone()).build().unwrap());
    }
    slope.add_contact_detector(Obstacle::plane([0.0; 3], n.into()).unwrap().with_margin(0.005).unwrap().with_friction(mu).unwrap()).unwrap();
    slope.add_contact_detector(RodContacts::new(0.005, true, true).unwrap().with_friction(mu).unwrap()).unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    for (name, w) in [("400 free rods", &mut rods), ("one rod of 10,000 points", &mut long), ("ropes on a slope", &mut slope)] {
        let (n, active) = pool.install(|| {
            for _ in 0..WARM_UP {
                w.step().unwrap();
            }
            COUNT.store(0, Ordering::SeqCst);
            ARMED.store(true, Ordering::SeqCst);
            for _ in 0..10 {
                w.step().unwrap();
            }
            ARMED.store(false, Ordering::SeqCst);
            (COUNT.load(Ordering::SeqCst) as f64 / 10.0, w.contacts().active().count())
        });
        println!("{name} ({active} active contacts): {n} heap allocations per step on a pool of two");
        assert_eq!(n, 0.0, "{name}");
        if name.starts_with("ropes") {
            assert!(active > 0);
        }
    }
}
