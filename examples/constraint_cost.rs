//! Cost of constraints per step (thesis fig. IV.13) and step time versus the
//! number of constraints spread along a 400-control-point rod (issue 3).
//! Run: cargo run --release --example constraint_cost
//! One thread; each figure is the fastest of repeated steps of a rod in
//! equilibrium (the constraints hold it where it is, so every step solves
//! the same kind of system): the minimum, because on this shared machine
//! the neighbours' load moves medians by ±30 %. Two columns: the band path
//! (LDLᵀ, falling back to the LU) and the pivoting band LU forced.
use strandkit::prelude::*;
use nalgebra::Vector3;
use std::time::Instant;
use strandkit::*;

fn rod_world(n: usize, solver: LinearSolver) -> (World, RodHandle) {
    let rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(4.0, 0.0, 0.0))
        .control_points(n)
        .section(Section::circle(0.05).unwrap())
        .material(Material::new("steel", 200e9, 0.3, 7800.0).unwrap())
        .build()
        .unwrap();
    let mut w = World::new(IntegrationParameters { dt: 1e-3, parallel: false, linear_solver: solver, ..Default::default() });
    let h = w.add_rod(rod);
    (w, h)
}

/// Fastest step and whether the band LDLᵀ solved it.
fn fastest_step(w: &mut World, reps: usize) -> (f64, bool) {
    for _ in 0..5 {
        w.step().unwrap();
    }
    let mut best = f64::INFINITY;
    let mut ldlt = true;
    for _ in 0..reps {
        let s = Instant::now();
        let r = w.step().unwrap();
        best = best.min(s.elapsed().as_secs_f64());
        ldlt &= r.factorisation == strandkit::Factorisation::BandLdlt;
    }
    (best, ldlt)
}

/// A constraint of family `kind` at abscissa u, holding the rod where it is.
fn make(kind: &str, w: &World, h: RodHandle, u: f64) -> ConstraintKind {
    let r = w.rod(h).unwrap();
    let p = r.position(u).unwrap();
    let t = r.tangent(u).unwrap();
    match kind {
        "position (3 rows)" => ConstraintKind::Position(Position { u, axes: [true, true, true, false], target: [p.x, p.y, p.z, 0.0] }),
        "tangent (2 rows)" => ConstraintKind::Tangent(Tangent { u, direction: t.into() }),
        "plane (1 row)" => ConstraintKind::Plane(Plane { u, origin: p.into(), normal: [0.0, 1.0, 0.0] }),
        "distance (1 row)" => ConstraintKind::Distance(Distance { u, point: [p.x, p.y + 1.0, p.z], distance: 1.0 }),
        _ => ConstraintKind::SlidingPoint(SlidingPoint { u, point: p.into(), friction: 0.0 }),
    }
}

fn main() {
    let n = 400;
    let reps = 300;
    let (base, _) = fastest_step(&mut rod_world(n, LinearSolver::Band).0, reps);
    let (base_lu, _) = fastest_step(&mut rod_world(n, LinearSolver::BandLu).0, reps);
    println!("free rod, {n} control points: {:.1} µs/step band LDLᵀ, {:.1} µs/step band LU (one thread)\n", base * 1e6, base_lu * 1e6);
    println!("| constraint family | constraints | step, band path (µs) | LDLᵀ used | extra per constraint (µs) | step, band LU (µs) | extra per constraint, LU (µs) | half-bandwidth |");
    println!("|---|---|---|---|---|---|---|---|");
    for kind in ["position (3 rows)", "tangent (2 rows)", "plane (1 row)", "distance (1 row)", "sliding point (3 rows + 1 unknown)"] {
        for count in [10usize, 50, 100] {
            let mut row = Vec::new();
            let mut bw = 0;
            for solver in [LinearSolver::Band, LinearSolver::BandLu] {
                let (mut w, h) = rod_world(n, solver);
                let (u0, u1) = w.rod(h).unwrap().domain();
                for k in 0..count {
                    let u = u0 + (u1 - u0) * (k as f64 + 0.5) / count as f64;
                    let c = make(kind, &w, h, u);
                    w.add_constraint(h, c, 0.0).unwrap();
                }
                row.push(fastest_step(&mut w, reps));
                bw = w.step().unwrap().bandwidth;
            }
            let ((t, ldlt), (t_lu, _)) = (row[0], row[1]);
            println!(
                "| {kind} | {count} | {:.1} | {} | {:.2} | {:.1} | {:.2} | {bw} |",
                t * 1e6,
                if ldlt { "yes" } else { "no" },
                (t - base) / count as f64 * 1e6,
                t_lu * 1e6,
                (t_lu - base_lu) / count as f64 * 1e6
            );
        }
    }
}
