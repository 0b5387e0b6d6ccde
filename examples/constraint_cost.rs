//! Cost of constraints per step (thesis fig. IV.13) and step time versus the
//! number of constraints spread along a 400-control-point rod (issue 3).
//! Run: cargo run --release --example constraint_cost
//! One thread; each figure is the median over repeated steps of a rod in
//! equilibrium (the constraints hold it where it is, so every step solves
//! the same kind of system).
use nalgebra::Vector3;
use std::time::Instant;
use strandkit::*;

fn rod_world(n: usize) -> (World, RodHandle) {
    let rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(4.0, 0.0, 0.0))
        .control_points(n)
        .section(Section::circle(0.05).unwrap())
        .material(Material::new("steel", 200e9, 0.3, 7800.0).unwrap())
        .build()
        .unwrap();
    let mut w = World::new(IntegrationParameters { dt: 1e-3, parallel: false, linear_solver: LinearSolver::Band, ..Default::default() });
    let h = w.add_rod(rod);
    (w, h)
}

fn median_step(w: &mut World, reps: usize) -> f64 {
    for _ in 0..5 {
        w.step().unwrap();
    }
    let mut t: Vec<f64> = (0..reps)
        .map(|_| {
            let s = Instant::now();
            w.step().unwrap();
            s.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[reps / 2]
}

/// A constraint of family `kind` at abscissa u, holding the rod where it is.
fn make(kind: &str, w: &World, h: RodHandle, u: f64) -> ConstraintKind {
    let r = w.rod(h).unwrap();
    let p = r.position(u).unwrap();
    let t = r.tangent(u).unwrap();
    match kind {
        "position (3 rows)" => ConstraintKind::Position { u, axes: [true, true, true, false], target: [p.x, p.y, p.z, 0.0] },
        "tangent (2 rows)" => ConstraintKind::Tangent { u, direction: t.into() },
        "plane (1 row)" => ConstraintKind::Plane { u, origin: p.into(), normal: [0.0, 1.0, 0.0] },
        "distance (1 row)" => ConstraintKind::Distance { u, point: [p.x, p.y + 1.0, p.z], distance: 1.0 },
        _ => ConstraintKind::SlidingPoint { u, point: p.into(), friction: 0.0 },
    }
}

fn main() {
    let n = 400;
    let reps = 300;
    let (mut w0, _) = rod_world(n);
    let base = median_step(&mut w0, reps);
    println!("free rod, {n} control points: {:.1} µs/step (one thread, band LU)\n", base * 1e6);
    println!("| constraint family | constraints | step (µs) | extra per constraint (µs) | half-bandwidth |");
    println!("|---|---|---|---|---|");
    for kind in ["position (3 rows)", "tangent (2 rows)", "plane (1 row)", "distance (1 row)", "sliding point (3 rows + 1 unknown)"] {
        for count in [10usize, 50, 100] {
            let (mut w, h) = rod_world(n);
            let (u0, u1) = w.rod(h).unwrap().domain();
            for k in 0..count {
                let u = u0 + (u1 - u0) * (k as f64 + 0.5) / count as f64;
                let c = make(kind, &w, h, u);
                w.add_constraint(h, c, 0.0).unwrap();
            }
            let t = median_step(&mut w, reps);
            let bw = w.step().unwrap().bandwidth;
            println!("| {kind} | {count} | {:.1} | {:.2} | {bw} |", t * 1e6, (t - base) / count as f64 * 1e6);
        }
    }
}
