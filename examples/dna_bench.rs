//! Issue 17's performance figures: a B-DNA duplex (strandkit.dna's
//! builder: two strands, one hydrogen bond and one six-strain stacking per
//! base pair) stepped in water at zero temperature, in molecular units.
//! Prints µs per step, base-pair-steps per second and simulated ns per
//! wall second for each length.
//! Run: cargo run --release --example dna_bench [n_bp ...]   (default 24 80 240)
//! Env: T=298.15 adds thermal noise (K); DT the step (ns, default 0.01);
//! STEPS the steps per length; SCHEME=trapezoidal (default implicit Euler:
//! with noise it freezes the stiff modes, docs/dna_calibration.md); VISC the
//! viscosity (pN·ns/nm², default water's 1); PARALLEL=0 one thread (default:
//! rayon's pool, as `IntegrationParameters::default()`).
use std::time::Instant;
use strandkit::prelude::*;
use strandkit_builders::dna::{duplex, Duplex};
use strandkit_core::{Scheme, Units};

/// An environment variable parsed, else `default`.
fn env<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name).ok().and_then(|s| s.parse().ok()).unwrap_or(default)
}

fn main() -> Result<()> {
    let lengths: Vec<usize> = std::env::args().skip(1).filter_map(|s| s.parse().ok()).collect();
    let lengths = if lengths.is_empty() { vec![24, 80, 240] } else { lengths };
    let dt: f64 = env("DT", 0.01); // ns
    for n in lengths {
        let seq: String = "GATTACA".chars().cycle().take(n).collect();
        let mut p = Duplex::new(&seq);
        // With noise, bonds break on their tension averaged over 1 ns
        // (each step's would melt the duplex at once).
        p.break_averaging_time = 1.0;
        let (asm, _) = duplex(&p)?;
        let temperature = env("T", 0.0);
        let scheme = if env("SCHEME", String::new()) == "trapezoidal" { Scheme::Trapezoidal } else { Scheme::ImplicitEuler };
        let viscosity = env("VISC", 1.0);
        let parallel = env("PARALLEL", 1) != 0;
        let mut w = World::new(IntegrationParameters { dt, viscosity, temperature, seed: 7, scheme, units: Units::Molecular, parallel, ..Default::default() });
        w.insert(&asm)?;
        let cps: usize = w.rods().map(|(_, r)| r.n_ctrl()).sum();
        w.step()?;
        let steps = env("STEPS", (20_000 / n).max(20));
        let t = Instant::now();
        for _ in 0..steps {
            w.step()?;
        }
        let per = t.elapsed().as_secs_f64() / steps as f64;
        println!(
            "{n:>5} bp ({cps} control points, {} constraints): {:>8.1} µs/step, {:>6.2} µs per control point, {:.3e} bp-steps/s, {:.2} ns simulated per wall s",
            w.constraints().count(),
            per * 1e6,
            per * 1e6 / cps as f64,
            n as f64 / per,
            dt / per
        );
    }
    Ok(())
}
