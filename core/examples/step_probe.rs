//! Quick per-step probe used while optimising (not the reference benchmark,
//! see `bench_table` and BENCHMARKS.md):
//!
//!   cargo run --release -p strandkit-core --example step_probe [-- --runs N] [--rows sbtd] [--sizes 100,400,40000] [--no-guard]
//!
//! Prints, for each energy row (s = stretch only, b = stretch+bend, t = full
//! static, d = full dynamic) and size, the smallest of N medians of the
//! per-step wall time (1 thread) and µs per control point, with the same
//! rod, pre-deformation and reset policy as `bench_table`.
use std::time::{Duration, Instant};
use strandkit_core::energy::EnergyTerms;
use strandkit_core::*;

#[path = "common/table_rod.rs"]
mod table_rod;
use table_rod::{reset, rod, steel};

fn setup(n: usize, row: char) -> (World, RodHandle, Vec<f64>) {
    let terms = match row {
        's' => EnergyTerms { stretch: true, bend: false, twist: false },
        'b' => EnergyTerms { stretch: true, bend: true, twist: false },
        _ => EnergyTerms::default(),
    };
    let r = rod(n, terms, 0.0, steel());
    let (mut w, h, q0) = if row == 't' { table_rod::static_world(r) } else { table_rod::dynamic_world(r, false) };
    // `--no-guard`: without the divergence guard (to measure its cost).
    if std::env::args().any(|a| a == "--no-guard") {
        w.params.divergence_factor = f64::INFINITY;
    }
    (w, h, q0)
}

fn median_step(n: usize, row: char) -> (f64, usize) {
    let (mut w, h, q0) = setup(n, row);
    let big = n >= 40000;
    for _ in 0..if big { 1 } else { 5 } {
        let _ = w.step();
    }
    reset(&mut w, h, &q0);
    let (min_reps, min_time) = if big { (3, Duration::ZERO) } else { (20, Duration::from_millis(200)) };
    let mut t = Vec::new();
    let mut total = Duration::ZERO;
    let mut fails = 0;
    let mut k = 0;
    while t.len() < min_reps || total < min_time {
        if k == 50 {
            reset(&mut w, h, &q0);
            k = 0;
        }
        k += 1;
        let s = Instant::now();
        let r = w.step();
        let dt = s.elapsed();
        if r.is_ok() {
            t.push(dt.as_secs_f64());
            total += dt;
        } else {
            fails += 1;
            reset(&mut w, h, &q0);
            k = 0;
        }
    }
    t.sort_by(|a, b| a.partial_cmp(b).unwrap());
    (t[t.len() / 2], fails)
}

/// Smallest wall time of `reps` calls of `f` (seconds).
fn fastest(reps: usize, mut f: impl FnMut()) -> f64 {
    (0..reps)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn arg(name: &str) -> Option<String> {
    std::env::args().skip_while(|a| a != name).nth(1)
}

fn main() {
    let runs: usize = arg("--runs").and_then(|v| v.parse().ok()).unwrap_or(3);
    let rows = arg("--rows").unwrap_or_else(|| "d".into());
    let sizes: Vec<usize> = arg("--sizes")
        .unwrap_or_else(|| "100,400,4000,40000".into())
        .split(',')
        .filter_map(|s| s.parse().ok())
        .collect();
    // --rods N: N free pre-deformed table rods of 25 control points each
    // (10,000 control points at N = 400), one thread against rayon's pool
    // (params.parallel), interleaved step by step; 40 steps a run.
    if let Some(nr) = arg("--rods").and_then(|v| v.parse::<usize>().ok()) {
        let per = arg("--cp").and_then(|v| v.parse().ok()).unwrap_or(25);
        // --par-only / --serial-only: one world (the other's pool threads,
        // spinning after their work, would slow the serial world's steps).
        let modes: &[bool] = if std::env::args().any(|a| a == "--par-only") {
            &[true]
        } else if std::env::args().any(|a| a == "--serial-only") {
            &[false]
        } else {
            &[false, true]
        };
        let mut worlds: Vec<(World, Vec<(RodHandle, Vec<f64>)>)> = modes
            .iter()
            .map(|&par| {
                let mut w = World::new(IntegrationParameters { dt: 1e-3, parallel: par, ..Default::default() });
                let hs = (0..nr)
                    .map(|i| {
                        let r = table_rod::rod(per, EnergyTerms::default(), 0.0, steel());
                        let mut q0 = table_rod::deformed(r.coords());
                        for c in q0.chunks_exact_mut(4) {
                            c[2] += 0.2 * i as f64; // side by side, 20 cm apart
                        }
                        let h = w.add_rod(r);
                        w.rod_mut(h).unwrap().set_coords(&q0).unwrap();
                        (h, q0)
                    })
                    .collect();
                (w, hs)
            })
            .collect();
        // The two worlds step in turn, step by step, so that the machine's
        // drift hits both alike; the median of the per-pair ratios.
        let mut times: Vec<Vec<f64>> = vec![Vec::new(); worlds.len()];
        for _ in 0..runs {
            for (w, hs) in worlds.iter_mut() {
                for (h, q0) in hs.iter() {
                    reset(w, *h, q0);
                }
                let _ = w.step();
            }
            for _ in 0..40 {
                for (k, (w, _)) in worlds.iter_mut().enumerate() {
                    let s = Instant::now();
                    w.step().expect("the free rods step");
                    times[k].push(s.elapsed().as_secs_f64());
                }
            }
        }
        let median = |v: &mut Vec<f64>| {
            v.sort_by(|a, b| a.total_cmp(b));
            v[v.len() / 2]
        };
        if times.len() == 1 {
            let threads = if modes[0] { rayon::current_num_threads() } else { 1 };
            println!("{nr} rods × {per} cp: {threads} thread(s) {:.3} ms", median(&mut times[0]) * 1e3);
            return;
        }
        let mut ratios: Vec<f64> = times[0].iter().zip(&times[1]).map(|(a, b)| a / b).collect();
        println!(
            "{nr} rods × {per} cp: 1 thread {:.3} ms, {} threads {:.3} ms (medians), speed-up {:.2}× (median of {} paired steps)",
            median(&mut times[0]) * 1e3,
            rayon::current_num_threads(),
            median(&mut times[1]) * 1e3,
            median(&mut ratios),
            ratios.len()
        );
        return;
    }
    // --kernel N: smallest of N timings of the segment kernels alone
    // (Rod::assemble with Hessians) and of a whole step; minima of many short
    // timings are robust to other processes on a shared machine.
    if let Some(reps) = arg("--kernel").and_then(|v| v.parse::<usize>().ok()) {
        for row in rows.chars() {
            for &n in &sizes {
                let (mut w, h, q0) = setup(n, row);
                let _ = w.step();
                let rod = w.rod(h).unwrap().clone();
                let mut blocks = Vec::new();
                use strandkit_core::rod::assemble::Need;
                let kmin = fastest(reps, || rod.assemble(&mut blocks, Need::Hessian, false));
                let pmin = fastest(reps, || rod.assemble(&mut blocks, Need::Hessian, true));
                eprintln!("kernels on rayon's pool ({} threads): {:.1} µs", rayon::current_num_threads(), pmin * 1e6);
                // Without Hessians (the share of the Hessian chain rule), and
                // the energy alone (the divergence guard's pass).
                let gmin = fastest(reps, || rod.assemble(&mut blocks, Need::Gradient, false));
                let emin = fastest(reps, || {
                    std::hint::black_box(rod.elastic_energy());
                });
                let mut smin = f64::INFINITY;
                for i in 0..reps {
                    if i % 50 == 0 {
                        reset(&mut w, h, &q0);
                    }
                    let s = Instant::now();
                    let _ = w.step();
                    smin = smin.min(s.elapsed().as_secs_f64());
                }
                println!(
                    "row {row} n={n:6}: kernels {:.1} µs (gradient only {:.1}, energy only {:.1}), step {:.1} µs (minima of {reps})",
                    kmin * 1e6,
                    gmin * 1e6,
                    emin * 1e6,
                    smin * 1e6
                );
            }
        }
        return;
    }
    // --fixed N: exactly N steps per (row, size) and no timing, for
    // `perf stat -e cycles:u` (cycle counts are not inflated by other
    // processes holding the CPU, unlike wall time on a shared machine).
    if let Some(steps) = arg("--fixed").and_then(|v| v.parse::<usize>().ok()) {
        for row in rows.chars() {
            for &n in &sizes {
                let (mut w, h, q0) = setup(n, row);
                let mut t = Vec::with_capacity(steps);
                for i in 0..steps {
                    if i % 50 == 0 {
                        reset(&mut w, h, &q0);
                    }
                    let s = Instant::now();
                    let _ = w.step();
                    t.push(s.elapsed().as_secs_f64());
                }
                if std::env::args().any(|a| a == "--dist") {
                    for (i, x) in t.iter().enumerate().take(100) {
                        eprint!("{i}:{:.0} ", x * 1e6);
                    }
                    eprintln!();
                }
            }
        }
        return;
    }
    for row in rows.chars() {
        let mut per_cp = Vec::new();
        for &n in &sizes {
            let mut best = f64::INFINITY;
            let mut fails = 0;
            for _ in 0..runs {
                let (t, f) = median_step(n, row);
                best = best.min(t);
                fails += f;
            }
            per_cp.push(1e6 * best / n as f64);
            println!("row {row} n={n:6}: {:.4e} s/step, {:.3} µs/cp{}", best, 1e6 * best / n as f64,
                if fails > 0 { format!(" ({fails} failed steps)") } else { String::new() });
        }
        let mean = per_cp.iter().sum::<f64>() / per_cp.len() as f64;
        let dev = per_cp.iter().map(|v| (v / mean - 1.0).abs()).fold(0.0, f64::max);
        println!("row {row}: µs/cp mean {mean:.3}, max deviation {:.1} %", 100.0 * dev);
    }
}
