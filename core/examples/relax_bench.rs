//! `relax()` on the SPEC §10 cantilever (4 m steel rod, R = 5 cm, clamped,
//! tip load F), with and without the mixed-integration-point merit
//! (`IntegrationParameters::relax_mixed`), alternated in one run so the
//! ratios hold on a drifting machine:
//!
//!   cargo run --release -p strandkit-core --example relax_bench [-- --runs N]
//!
//! Prints, per load and control-point count, the linear solves
//! (factorisations + second-order corrections' back-substitutions) and the
//! median wall time of each (world built outside the timing), one thread.
#[path = "common/table_rod.rs"]
mod table_rod;

use std::time::Instant;
use strandkit_core::energy::EnergyTerms;
use strandkit_core::prelude::*;
use table_rod::{rod, steel};

fn cantilever(n: usize, force: f64, mixed: bool) -> (World, RodHandle) {
    let r = rod(n, EnergyTerms::default(), 0.0, steel());
    let (u0, u1) = r.domain();
    let mut world = World::new(IntegrationParameters { parallel: false, relax_mixed: mixed, ..Default::default() });
    let h = world.add_rod(r);
    world.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true; 4], target: [0.0; 4] }), 0.0).unwrap();
    world.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    world.add_load(Load::PointForce(PointForce { rod: h, u: u1, force: [0.0, -force, 0.0] })).unwrap();
    (world, h)
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let runs: usize = std::env::args().skip_while(|a| a != "--runs").nth(1).and_then(|v| v.parse().ok()).unwrap_or(21);
    println!("| F (N) | cp | solves mixed | solves plain | relax mixed | relax plain | plain / mixed | tips apart (m) |");
    println!("|---|---|---|---|---|---|---|---|");
    for force in [1e5, 2e5] {
        for n in [8, 20, 100, 1000] {
            let reps = if n >= 1000 { runs.div_ceil(4).max(3) } else { runs };
            let (mut times, mut solves, mut tips) = ([Vec::new(), Vec::new()], [0; 2], [nalgebra::Vector3::zeros(); 2]);
            for _ in 0..reps {
                for (k, mixed) in [true, false].into_iter().enumerate() {
                    let (mut w, h) = cantilever(n, force, mixed);
                    let s = Instant::now();
                    let rep = w.relax().expect("the cantilever relaxes");
                    times[k].push(s.elapsed().as_secs_f64());
                    solves[k] = rep.iterations + rep.corrections;
                    let r = w.rod(h).unwrap();
                    tips[k] = r.position(r.domain().1).unwrap();
                }
            }
            let (tm, tp) = (median(&mut times[0]), median(&mut times[1]));
            println!(
                "| {force:.0e} | {n} | {} | {} | {:.3} ms | {:.3} ms | {:.2}× | {:.1e} |",
                solves[0],
                solves[1],
                tm * 1e3,
                tp * 1e3,
                tp / tm,
                (tips[0] - tips[1]).norm()
            );
        }
    }
}
