//! Table IV.2 scenes side by side with the thesis (SPEC §11, issue 12): per
//! dynamic step time of the builders' scenes at the thesis' sizes.
//! Run: cargo run --release --example scenes_bench
//! One thread. Each scene is relaxed under gravity, then set swinging (a
//! lateral push) and stepped; the figure is the median of 5 passes' minima
//! over 400 steps (the minimum per pass because this shared 2-core machine
//! moves medians by ±30 %). The thesis ran a 2 GHz Core Duo (2007).
use std::time::Instant;
use strandkit::prelude::*;
use strandkit_builders::dna::{duplex, Duplex, HBond};
use strandkit_builders::{beads_on_spring, cable_on_clips, harness, necklace, rope_bridge, BeadsOnSpring, CableOnClips, Hang, Harness, Necklace, PlankModel, RopeBridge};

fn time_steps(w: &mut World, steps: usize) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..steps {
        let t = Instant::now();
        w.step().expect("step");
        best = best.min(t.elapsed().as_secs_f64());
    }
    best
}

/// Median over 5 passes of each pass's fastest step (s); `PASSES=n` in the
/// environment runs n passes instead (e.g. many, under a profiler).
fn median_step(w: &mut World, steps: usize) -> f64 {
    let passes = std::env::var("PASSES").ok().and_then(|s| s.parse().ok()).unwrap_or(5usize).max(1);
    let mut mins: Vec<f64> = (0..passes).map(|_| time_steps(w, steps)).collect();
    mins.sort_by(f64::total_cmp);
    mins[passes / 2]
}

/// `SCENE=word` in the environment runs only the scenes whose name holds it.
fn wanted(name: &str) -> bool {
    std::env::var("SCENE").map(|s| name.contains(s.as_str())).unwrap_or(true)
}

/// Sets `rods` moving at `vz` (m/s) along z: the push that starts a scene.
fn push(w: &mut World, rods: &[RodHandle], vz: f64) {
    for &r in rods {
        let v: Vec<f64> = w.rod(r).unwrap().velocities().chunks(3).flat_map(|_| [0.0, 0.0, vz]).collect();
        w.rod_mut(r).unwrap().set_velocities(&v).unwrap();
    }
}

fn main() {
    println!("scene              cp  multipliers  thesis [ms]  here [ms]  ratio");
    // Bridge at the thesis' size: 4 ropes × 8 control points = 32, planks
    // as distance links (the thesis' model): 24 anchor rows + 6 planks +
    // 12 verticals = 42 multipliers (thesis: 49; 8 planks on 8-point ropes
    // make the end rows dependent).
    if wanted("bridge") {
        let p = RopeBridge { n_planks: 6, plank_model: PlankModel::Link, rope_control_points: Some(8), ..Default::default() };
        let (asm, _) = rope_bridge(&p).expect("bridge");
        let mut w = World::new(IntegrationParameters { gravity: [0.0, -9.81, 0.0], dt: 1e-2, parallel: false, linear_solver: std::env::var("SOLVER").map(|s| if s == "band" { strandkit::LinearSolver::Band } else { strandkit::LinearSolver::Auto }).unwrap_or(strandkit::LinearSolver::Auto), ..Default::default() });
        let ins = w.insert(&asm).expect("insert");
        w.relax().expect("relax");
        // A lateral push on the floor ropes sets the bridge swinging.
        push(&mut w, &ins.rods[..2], 0.5);
        w.step().expect("step");
        let cps: usize = w.rods().map(|(_, r)| r.n_ctrl()).sum();
        let t = median_step(&mut w, 400);
        // What the timed steps used (the first steps may differ).
        let rep = w.step().expect("step");
        println!("bridge (links)    {cps:3}  {:11}  {:>11}  {:9.4}  {:5.0}×   (n {}, half-bandwidth {}, {:?})", rep.n_multipliers, "2", t * 1e3, 2e-3 / t, rep.n_unknowns, rep.bandwidth, rep.factorisation);
    }
    // Necklace at the thesis' size: 16 control points, 12 beads, dt 0.8 ms;
    // the ratio is taken against the thesis' fastest figure (0.4 ms). The
    // thesis' necklace is the open string (13 segments, table IV.2); the
    // loop over a peg (16 segments) is ours.
    for (name, p) in [
        ("necklace (2 pts)", Necklace { closed: false, hang: Hang::TwoPoints([-0.15, 0.0, 0.0], [0.15, 0.0, 0.0]), ..Default::default() }),
        ("necklace (peg)", Necklace::default()),
    ] {
        if !wanted(name) {
            continue;
        }
        let (asm, _) = necklace(&p).expect("necklace");
        let mut w = World::new(IntegrationParameters { gravity: [0.0, -9.81, 0.0], dt: 8e-4, parallel: false, ..Default::default() });
        w.insert(&asm).expect("insert");
        w.step().expect("step");
        let t = median_step(&mut w, 400);
        // What the timed steps used (the first steps may differ).
        let rep = w.step().expect("step");
        println!("{name:17} {:3}  {:11}  {:>11}  {:9.4}  {:5.0}×   (n {}, 12 beads, {:?})", 16, rep.n_multipliers, "0.4–0.8", t * 1e3, 0.4e-3 / t, rep.n_unknowns, rep.factorisation);
    }
    // Particles on a spring at the thesis' size: 31 control points (the
    // builder's default has 61 for accuracy), 4 beads, dt 1 ms; 5 passes
    // of 200 steps (the beads leave the spring after ~1.6 s).
    // The thesis' Frenet model, then the rods' default (the reference-frame
    // model, whose curved-rod bending costs more: BENCHMARKS §28).
    for (name, model) in [("beads on spring", FrameModel::Frenet), ("spring (reference)", FrameModel::Reference)] {
        if !wanted(name) {
            continue;
        }
        let (asm, _) = beads_on_spring(&BeadsOnSpring { control_points: 31, model, ..Default::default() }).expect("spring");
        let mut w = World::new(IntegrationParameters { gravity: [0.0, -9.81, 0.0], dt: 1e-3, parallel: false, ..Default::default() });
        w.insert(&asm).expect("insert");
        w.step().expect("step");
        let t = median_step(&mut w, 200);
        // What the timed steps used (the first steps may differ).
        let rep = w.step().expect("step");
        println!("{:17} {:3}  {:11}  {:>11}  {:9.4}  {:5.0}×   (n {}, 4 beads, half-bandwidth {}, {:?})", name, 31, rep.n_multipliers, "0.7", t * 1e3, 0.7e-3 / t, rep.n_unknowns, rep.bandwidth, rep.factorisation);
    }
    // Cable on a door (18 control points, 4 clips, a connector; dt 3 ms),
    // and the harness (the thesis' harness had 40 control points and 42–87
    // multipliers); both relaxed, then pushed out of their plane.
    for (name, asm, thesis, fastest) in [
        ("cable on door", cable_on_clips(&CableOnClips::default()).expect("cable").0, "0.72–1", 0.72e-3),
        ("harness", harness(&Harness::default()).expect("harness").0, "1–1.2", 1e-3),
    ] {
        if !wanted(name) {
            continue;
        }
        let mut w = World::new(IntegrationParameters { gravity: [0.0, -9.81, 0.0], dt: 3e-3, parallel: false, ..Default::default() });
        let ins = w.insert(&asm).expect("insert");
        w.relax().expect("relax");
        push(&mut w, &ins.rods, 0.2);
        w.step().expect("step");
        let cps: usize = w.rods().map(|(_, r)| r.n_ctrl()).sum();
        let t = median_step(&mut w, 400);
        // What the timed steps used (the first steps may differ).
        let rep = w.step().expect("step");
        println!("{name:17} {cps:3}  {:11}  {:>11}  {:9.4}  {:5.0}×   (n {}, {:?})", rep.n_multipliers, thesis, t * 1e3, fastest / t, rep.n_unknowns, rep.factorisation);
    }
    // DNA at the thesis' size: a 17 bp duplex is 2 strands × 17 control
    // points = 34 (28 segments, as the thesis'); in water at zero
    // temperature, dt 1 ps. The thesis' DNA had 38 multipliers (hydrogen
    // bonds and a few links); ours adds six stacking rows per step (the
    // duplex's bending, stretch and twist), compliant, and with position
    // rungs a stagger row per pair.
    for (name, hbond) in [("dna (distance)", HBond::Distance), ("dna (position)", HBond::position(0.04))] {
        if !wanted(name) {
            continue;
        }
        let mut p = Duplex::new("GATTACAGATTACAGAT");
        p.hbond = hbond;
        let (asm, _) = duplex(&p).expect("duplex");
        let solver = if std::env::var("SOLVER").is_ok_and(|s| s == "band") { strandkit::LinearSolver::Band } else { strandkit::LinearSolver::Auto };
        let mut w = World::new(IntegrationParameters { dt: 1e-3, viscosity: 1.0, units: strandkit::world::Units::Molecular, parallel: false, linear_solver: solver, ..Default::default() });
        let ins = w.insert(&asm).expect("insert");
        push(&mut w, &ins.rods, 0.5);
        w.step().expect("step");
        let t = median_step(&mut w, 400);
        // What the timed steps used (the first steps may differ).
        let rep = w.step().expect("step");
        println!("{name:17} {:3}  {:11}  {:>11}  {:9.4}  {:5.0}×   (n {}, {:?})", 34, rep.n_multipliers, "1.2", t * 1e3, 1.2e-3 / t, rep.n_unknowns, rep.factorisation);
    }
}
