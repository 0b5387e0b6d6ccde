//! Cost of building structures (BENCHMARKS.md, engine-seams issue):
//!
//!   cargo run --release -p strandkit-core --example insert_cost [-- --runs N]
//!
//! 1. 10,000 distance links between two rods of 5,000 control points
//!    (two helical strands, rungs across the axis), inserted as one `Assembly` (`World::insert`: every
//!    check, the sparse dependency check once, the layout): target < 50 ms.
//!    The same links added one `add_link` at a time, for comparison, at
//!    sizes where that is still affordable.
//! 2. Structures of 100 … 3,000 rods (short rods chained by relative
//!    positions, each with a label): time per rod must stay flat (linear).
//!
//! Each figure is the smallest of N runs (default 3).
use nalgebra::Vector3;
use std::time::Instant;
use strandkit_core::prelude::*;

fn rod(a: Vector3<f64>, b: Vector3<f64>, n: usize) -> Rod {
    RodBuilder::straight(a, b)
        .control_points(n)
        .with_roll(false)
        .section(Section::circle(0.001).unwrap())
        .material(Material::preset("nylon").unwrap())
        .build()
        .unwrap()
}

/// A strand of a double helix (radius 1, rise 0.34 per rung, 10 rungs per
/// turn, like B-DNA in nm), `turns` turns, phase `phase`.
fn strand(n: usize, turns: f64, phase: f64) -> Rod {
    let (radius, pitch) = (1.0, 3.4);
    let len = turns * (pitch * pitch + (std::f64::consts::TAU * radius).powi(2)).sqrt();
    let w = std::f64::consts::TAU * turns / len;
    let c = pitch * turns / len;
    RodBuilder::curve(len, move |s| Vector3::new(radius * (w * s + phase).cos(), radius * (w * s + phase).sin(), c * s))
        .control_points(n)
        .with_roll(false)
        .section(Section::circle(0.1).unwrap())
        .material(Material::preset("nylon").unwrap())
        .build()
        .unwrap()
}

/// Two helical strands of `n` control points joined by `k` distance rungs
/// across the helix axis (a duplex: the rungs' directions turn, so their
/// rows are independent up to k = 2n).
fn ladder(n: usize, k: usize) -> Assembly {
    let mut asm = Assembly::new();
    let turns = k as f64 / 10.0;
    let a = asm.add_rod(strand(n, turns, 0.0), Some("strand[0]"));
    let b = asm.add_rod(strand(n, turns, std::f64::consts::PI), Some("strand[1]"));
    let (u0, u1) = asm.rods[a].rod.domain();
    for i in 0..k {
        let u = u0 + (u1 - u0) * (i as f64 + 0.5) / k as f64;
        let d = (asm.rods[a].rod.position(u).unwrap() - asm.rods[b].rod.position(u).unwrap()).norm();
        asm.link(a, b, RelativeDistance { ua: u, ub: u, distance: d }).label(format!("rung[{i}]"));
    }
    asm
}

/// `m` rods of 8 control points in a row, each joined to the next by a
/// relative position (a chain).
fn chain(m: usize) -> Assembly {
    let mut asm = Assembly::new();
    for j in 0..m {
        let x = j as f64 * 0.1;
        let r = asm.add_rod(rod(Vector3::new(x, 0.0, 0.0), Vector3::new(x + 0.1, 0.0, 0.0), 8), Some(&format!("link[{j}]")));
        if j > 0 {
            let (_, end) = asm.rods[r - 1].rod.domain();
            let (start, _) = asm.rods[r].rod.domain();
            asm.link(r - 1, r, RelativePosition { ua: end, ub: start, axes: [true, true, true, false], offset: [0.0; 4] })
                .label(format!("joint[{j}]"));
        }
    }
    asm
}

fn best(runs: usize, mut f: impl FnMut() -> f64) -> f64 {
    (0..runs).map(|_| f()).fold(f64::INFINITY, f64::min)
}

fn main() {
    let runs: usize = std::env::args().skip_while(|a| a != "--runs").nth(1).and_then(|s| s.parse().ok()).unwrap_or(3);
    if std::env::args().any(|a| a == "--profile-chain") {
        let m = std::env::args().skip_while(|a| a != "--profile-chain").nth(1).and_then(|s| s.parse().ok()).unwrap_or(10000);
        let asm = chain(m);
        for _ in 0..runs {
            World::new(IntegrationParameters::default()).insert(&asm).unwrap();
        }
        return;
    }
    if std::env::args().any(|a| a == "--profile") {
        // For `perf record`: the 10,000-link insert, repeated.
        let asm = ladder(5000, 10000);
        for _ in 0..runs {
            World::new(IntegrationParameters::default()).insert(&asm).unwrap();
        }
        return;
    }
    println!("## Ladder: k distance links between two rods of n control points\n");
    println!("| n | k | build Assembly (ms) | World::insert (ms) | bandwidth | add_link one by one (ms) |");
    println!("|---|---|---|---|---|---|");
    for (n, k, one_by_one) in [(500, 1000, true), (1000, 2000, true), (2500, 5000, false), (5000, 10000, false)] {
        let t_build = best(runs, || {
            let t = Instant::now();
            std::hint::black_box(ladder(n, k));
            t.elapsed().as_secs_f64()
        });
        let asm = ladder(n, k);
        let mut band = 0;
        let t_insert = best(runs, || {
            let mut w = World::new(IntegrationParameters::default());
            let t = Instant::now();
            band = w.insert(&asm).unwrap().bandwidth;
            t.elapsed().as_secs_f64()
        });
        let t_single = if one_by_one {
            let t = best(1, || {
                let mut w = World::new(IntegrationParameters::default());
                let (a, b) = (w.add_rod(asm.rods[0].rod.clone()), w.add_rod(asm.rods[1].rod.clone()));
                let t = Instant::now();
                for c in &asm.constraints {
                    w.add_link(a, b, c.kind.clone(), 0.0).unwrap();
                }
                t.elapsed().as_secs_f64()
            });
            format!("{:.1}", t * 1e3)
        } else {
            "—".into()
        };
        println!("| {n} | {k} | {:.1} | {:.1} | {band} | {t_single} |", t_build * 1e3, t_insert * 1e3);
    }
    println!("\n## Chains of m rods (8 control points each, m − 1 joints, labels)\n");
    println!("| rods | World::insert (ms) | µs per rod |");
    println!("|---|---|---|");
    for m in [100, 300, 1000, 3000, 10000] {
        let asm = chain(m);
        let t = best(runs, || {
            let mut w = World::new(IntegrationParameters::default());
            let t = Instant::now();
            w.insert(&asm).unwrap();
            t.elapsed().as_secs_f64()
        });
        println!("| {m} | {:.2} | {:.1} |", t * 1e3, t * 1e6 / m as f64);
    }
}
