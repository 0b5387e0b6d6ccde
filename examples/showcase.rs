//! strandkit showcase: the SPEC §10 cantilever under five tip loads against
//! the elastica references, its convergence in control points × samples per
//! segment, and a short dynamic run of the same beam dropped under its load.
//! Run: cargo run --release --example showcase
use std::time::Instant;
#[path = "../tests/common/scenarios.rs"]
mod scenarios;
use scenarios::{cantilever, tip, CANTILEVER_REFERENCES};

fn main() -> strandkit::Result<()> {
    println!("Cantilever L = 4 m, R = 0.05 m, E = 200 GPa, 20 control points, 5 Gauss points/segment");
    println!("| F (N) | tip angle (rad) | ref | err % | tip x, y (m) | ref | err % of L | clamp Fy (N) | clamp Mz (N·m) | F·x_tip | relax |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for &(f, angle, x, y) in &CANTILEVER_REFERENCES {
        let mut c = cantilever(20, 5, [0.0, -f, 0.0])?;
        let t0 = Instant::now();
        let rep = c.world.relax()?;
        let dt = t0.elapsed();
        let (p, a) = tip(&c.world, c.rod)?;
        let rf = c.world.reaction(c.clamp)?.force;
        let rm = c.world.reaction(c.clamp_tangent)?.torque;
        println!(
            "| {f:.0e} | {:.5} | {angle} | {:.3} | {:.4}, {:.4} | {x}, {y} | {:.3} | {:.1} | {:.1} | {:.1} | {} it, {:.1} ms |",
            -a,
            100.0 * (-a - angle).abs() / angle,
            p.x,
            -p.y,
            100.0 * ((p.x - x).abs().max((-p.y - y).abs())) / 4.0,
            rf[1],
            rm[2],
            f * p.x,
            rep.iterations,
            dt.as_secs_f64() * 1e3
        );
    }
    println!("\nConvergence at F = 5e5 N: tip-angle error (%) by control points × samples per segment");
    let (f, angle, _, _) = CANTILEVER_REFERENCES[4];
    print!("| cp \\ samples |");
    let samples = [2, 3, 5];
    for s in samples {
        print!(" {s} |");
    }
    println!("\n|---|---|---|---|");
    for n in [6, 8, 12, 20, 40] {
        print!("| {n} |");
        for s in samples {
            let mut c = cantilever(n, s, [0.0, -f, 0.0])?;
            c.world.relax()?;
            let (_, a) = tip(&c.world, c.rod)?;
            print!(" {:.4} |", 100.0 * (-a - angle).abs() / angle);
        }
        println!();
    }
    // Dynamics: the unloaded straight beam receives the 1e5 N tip load and
    // swings (implicit Euler, h = 1 ms, no drag) about the static shape.
    let mut c = cantilever(20, 5, [0.0, -1e5, 0.0])?;
    c.world.params.dt = 1e-3;
    let t0 = Instant::now();
    let mut ymin: f64 = 0.0;
    for _ in 0..500 {
        c.world.step()?;
        ymin = ymin.min(tip(&c.world, c.rod)?.0.y);
    }
    let (p, _) = tip(&c.world, c.rod)?;
    println!(
        "\nDynamic drop under 1e5 N: 500 steps of 1 ms in {:.1} ms; deepest tip y {ymin:.3} m (static {:.3} m), at t = 0.5 s y = {:.3} m",
        t0.elapsed().as_secs_f64() * 1e3,
        -CANTILEVER_REFERENCES[2].3,
        p.y
    );
    Ok(())
}
