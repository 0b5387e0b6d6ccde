//! Contact detection cost (issue 15): a woven mat of two layers of rods
//! crossing at right angles and touching at every crossing,
//!
//!   cargo run --release -p strandkit-core --example contact_bench [-- --rods 100 --ctrl 103 --runs 3 [--detect-only | --bare] [--pool]]
//!
//! Prints the number of capsules, the detection time alone (the rod–rod
//! detector over all rods), a full dynamic step without contact (gravity
//! pressing the top layer, no detector) and with it, per capsule and per
//! active contact. `--detect-only`: detection alone, on the mat as built;
//! `--bare`: detection and the contact-free step alternated one by one
//! (after a first `runs` of each), and their ratio of the smallest times
//! (issue 15's goal: ≤ 1). `--pool`: the worlds use rayon's pool
//! (`parallel`, the default of `IntegrationParameters`) and detection runs
//! on it as in such a world's step; without it, one thread (run the two
//! modes in separate processes: the pool's idle workers spin). Times are
//! the smallest of `runs`.
use std::time::Instant;
use strandkit_core::contact::ContactDetector;
use strandkit_core::constraint::kinds::Position;
use strandkit_core::*;

fn arg(name: &str, default: usize) -> usize {
    let a: Vec<String> = std::env::args().collect();
    a.iter().position(|x| x == name).and_then(|i| a.get(i + 1)).and_then(|v| v.parse().ok()).unwrap_or(default)
}

fn mat(n: usize, ctrl: usize, parallel: bool) -> (World, f64) {
    let (r, pitch) = (0.003, 0.01);
    let len = pitch * n as f64;
    let mut w = World::new(IntegrationParameters { dt: 1e-3, gravity: [0.0, 0.0, -9.81], parallel, ..Default::default() });
    for layer in 0..2 {
        for i in 0..n {
            let c = (i as f64 + 0.5) * pitch;
            let z = layer as f64 * 2.0 * r;
            let (a, b) = if layer == 0 { ([0.0, c, z], [len, c, z]) } else { ([c, 0.0, z], [c, len, z]) };
            let rod = RodBuilder::straight(a.into(), b.into())
                .control_points(ctrl)
                .with_roll(false)
                .section(Section::circle(r).expect("positive radius"))
                .material(Material::new("nylon", 2e9, 0.4, 1140.0).expect("valid material"))
                .build()
                .expect("valid rod");
            let h = w.add_rod(rod);
            // Both ends pinned, so the mat hangs between them.
            let (u0, u1) = w.rod(h).expect("just added").domain();
            for u in [u0, u1] {
                let p = w.rod(h).expect("just added").position(u).expect("inside the domain");
                w.add_constraint(h, ConstraintKind::Position(Position { u, axes: [true, true, true, false], target: [p.x, p.y, p.z, 0.0] }), 0.0)
                    .expect("valid pin");
            }
        }
    }
    (w, r)
}

fn main() {
    let (n, ctrl, runs) = (arg("--rods", 100), arg("--ctrl", 103), arg("--runs", 3));
    let detector = RodContacts::new(0.002, false, true).expect("valid margin");
    let pool = std::env::args().any(|a| a == "--pool");
    let (mut bare, _) = mat(n, ctrl, pool);
    let (mut with, _) = mat(n, ctrl, pool);
    with.add_contact_detector(detector.clone()).expect("valid detector");
    let capsules: usize = bare.rods().map(|(_, r)| r.sample_params().len() + 1).sum();
    let best = |f: &mut dyn FnMut() -> f64| (0..runs).map(|_| f()).fold(f64::INFINITY, f64::min);
    // Detection alone on `w`'s rods (seconds) and the pairs it found, with
    // buffers kept from one detection to the next as a world keeps them.
    let scratch = std::cell::RefCell::new(strandkit_core::contact::Scratch::new(pool));
    let time_detection = |w: &World| {
        let list: Vec<_> = w.rods().collect();
        let mut set = ContactSet::default();
        let scratch = &mut *scratch.borrow_mut();
        let t = Instant::now();
        if pool {
            // On a pool thread, as in the step of a world that uses the pool.
            rayon::join(|| detector.detect_with(&list, &mut set, scratch), || ()).0.expect("detection");
        } else {
            detector.detect_with(&list, &mut set, scratch).expect("detection");
        }
        (t.elapsed().as_secs_f64(), set.len())
    };
    let detect = best(&mut || time_detection(&bare).0);
    let pairs = time_detection(&bare).1;
    if std::env::args().any(|a| a == "--detect-only") {
        println!("{capsules} capsules, {pairs} pairs: detection {:.2} ms ({:.3} µs per capsule)", 1e3 * detect, 1e6 * detect / capsules as f64);
        return;
    }
    let step_bare = best(&mut || {
        let t = Instant::now();
        bare.step().expect("step");
        t.elapsed().as_secs_f64()
    });
    if std::env::args().any(|a| a == "--bare") {
        // Detection and the contact-free step alternated one by one, so
        // that the machine's drift reaches both alike.
        let (mut detect, mut step) = (detect, step_bare);
        for _ in 0..runs {
            detect = detect.min(time_detection(&bare).0);
            let t = Instant::now();
            bare.step().expect("step");
            step = step.min(t.elapsed().as_secs_f64());
        }
        println!("{capsules} capsules: detection {:.2} ms, contact-free step {:.2} ms, ratio {:.2}", 1e3 * detect, 1e3 * step, detect / step);
        return;
    }
    let step_with = best(&mut || {
        let t = Instant::now();
        with.step().expect("step");
        t.elapsed().as_secs_f64()
    });
    let active = with.contacts().active().count();
    println!("{} rods × {ctrl} control points, {capsules} capsules, {pairs} pairs detected, {active} active", 2 * n);
    println!("detection alone      {:8.2} ms  ({:.3} µs per capsule)", 1e3 * detect, 1e6 * detect / capsules as f64);
    println!("step without contact {:8.2} ms", 1e3 * step_bare);
    println!("step with contact    {:8.2} ms  (detection / step without contact = {:.3})", 1e3 * step_with, detect / step_bare);
    if active > 0 {
        println!("extra per active contact (step with − without − detection) {:.2} µs", 1e6 * (step_with - step_bare - detect) / active as f64);
    }
}
