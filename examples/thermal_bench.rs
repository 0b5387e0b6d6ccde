//! Issue 16's performance figures: what thermal noise costs per step, and
//! the throughput of a 1 µm DNA chain (molecular units: nm, pN, ns) at
//! 298.15 K in water (η = 1 pN·ns/nm²).
//! Run: cargo run --release --example thermal_bench
//!
//! The same world is stepped with and without temperature, the two
//! alternating in passes of 200 steps (this shared 2-core machine drifts
//! ±30 % within minutes, so only ratios measured side by side mean much);
//! each figure is the median over passes of the pass's mean step.
use nalgebra::Vector3;
use std::time::Instant;
use strandkit::prelude::*;
use strandkit_core::energy::FrameModel;
use strandkit_core::{Scheme, Units};

const T: f64 = 298.15;

/// 1 µm of DNA: radius 1 nm, bending persistence 50 nm, twist 100 nm,
/// `n` control points, with roll (reference-frame model).
fn chain(n: usize) -> Rod {
    let kt = Units::Molecular.boltzmann() * T;
    let i = std::f64::consts::PI / 4.0;
    let (e, g) = (50.0 * kt / i, 100.0 * kt / (2.0 * i));
    RodBuilder::straight(Vector3::zeros(), Vector3::new(1000.0, 0.0, 0.0))
        .control_points(n)
        .section(Section::circle(1.0).unwrap())
        .material(Material::new("dna", e, e / (2.0 * g) - 1.0, 1.7e-3).unwrap())
        .options(RodOptions { model: FrameModel::Reference, ..Default::default() })
        .build()
        .unwrap()
}

fn world(n: usize, scheme: Scheme, temperature: f64, dt: f64) -> World {
    let mut w = World::new(IntegrationParameters {
        dt,
        scheme,
        temperature,
        viscosity: 1.0,
        units: Units::Molecular,
        seed: 1,
        parallel: false,
        ..Default::default()
    });
    w.add_rod(chain(n));
    w
}

/// Mean wall time (s) of `steps` steps, and the solves they took.
fn pass(w: &mut World, steps: usize) -> (f64, u32) {
    let t = Instant::now();
    let solves: u32 = (0..steps).map(|_| w.step().expect("step").solves).sum();
    (t.elapsed().as_secs_f64() / steps as f64, solves)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let passes = 7;
    let steps = 200;
    println!("1 µm DNA chain, 298.15 K, water; {passes} alternating passes of {steps} steps, one thread");
    println!("| control points (h) | scheme | dt (ns) | step, T = 0 (ms) | step, T > 0 (ms) | per solve, T > 0 / T = 0 | solves/step (T > 0) | segment-steps/s | simulated ns per wall s |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for (n, dt) in [(101usize, 2e-3), (334, 1e-3)] {
        for scheme in [Scheme::ImplicitEuler, Scheme::Trapezoidal] {
            let (mut cold, mut hot) = (world(n, scheme, 0.0, dt), world(n, scheme, T, dt));
            // Warm up: buffers, and the thermal chain off its straight start.
            pass(&mut cold, 50);
            pass(&mut hot, 50);
            let (mut tc, mut th, mut sc, mut sh) = (Vec::new(), Vec::new(), 0, 0);
            for _ in 0..passes {
                let (t, s) = pass(&mut cold, steps);
                tc.push(t / (s as f64 / steps as f64));
                sc += s;
                let (t, s) = pass(&mut hot, steps);
                th.push(t);
                sh += s;
            }
            let solves_hot = sh as f64 / (passes * steps) as f64;
            let solves_cold = sc as f64 / (passes * steps) as f64;
            let (per_solve_cold, step_hot) = (median(tc), median(th));
            let segments = (n - 3) as f64;
            println!(
                "| {n} ({:.1} nm) | {scheme:?} | {dt:e} | {:.3} ({solves_cold:.2} solves) | {:.3} | {:.3} | {solves_hot:.2} | {:.3e} | {:.3} |",
                1000.0 / segments,
                per_solve_cold * solves_cold * 1e3,
                step_hot * 1e3,
                step_hot / solves_hot / per_solve_cold,
                segments / step_hot,
                dt / step_hot,
            );
        }
    }
    // The anisotropic drag's cost (3×3 tangential blocks, and under noise
    // 3 more normals per Gauss sample) against the isotropic drag.
    println!("\n| control points | scheme | T | step, isotropic drag (ms) | step, anisotropic (ms) | ratio |");
    println!("|---|---|---|---|---|---|");
    for scheme in [Scheme::ImplicitEuler, Scheme::Trapezoidal] {
        for temperature in [0.0, T] {
            let n = 334;
            let mut iso = world(n, scheme, temperature, 1e-3);
            iso.params.isotropic_drag = true;
            let mut aniso = world(n, scheme, temperature, 1e-3);
            pass(&mut iso, 50);
            pass(&mut aniso, 50);
            let (mut ti, mut ta) = (Vec::new(), Vec::new());
            for _ in 0..passes {
                ti.push(pass(&mut iso, steps).0);
                ta.push(pass(&mut aniso, steps).0);
            }
            let (ti, ta) = (median(ti), median(ta));
            println!("| {n} | {scheme:?} | {temperature} K | {:.3} | {:.3} | {:.3} |", ti * 1e3, ta * 1e3, ta / ti);
        }
    }
    // oxDNA: ≈ 3e5 nucleotide-steps per second per core (SPEC §9.1) at
    // dt ≈ 15 fs; 1 µm = 2941 bp = 5882 nucleotides.
    let ox_steps = 3e5 / 5882.0;
    println!("oxDNA (SPEC §9.1): {ox_steps:.0} steps/s of the 1 µm duplex at 15 fs = {:.2e} simulated ns per wall s", ox_steps * 15e-6);
}
