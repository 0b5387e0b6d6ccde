//! The duplex's harmonic tilt under a pull against a plain rod's of the
//! same A held and pulled the same way (`strandkit_builders::dna_harmonic::
//! tension_tilt`, `rod_tension_tilt`; issue 17): ⟨θ²⟩ of each pair's axis,
//! whose interior value × rise / 2 is the entropic shortening per length.
//! 100 bp at 10 pN: 0.991–0.994 of the rod's in the interior (30 s).
//!
//! With STEPS, the duplex pulled the same way (pair 0 in traps, not
//! clamped: near pair 0 the profiles differ) is stepped with thermal noise
//! (298.15 K, trapezoidal rule, steps of DT ns, viscosity VISC pN·ns/nm²,
//! seed 1, the first fifth dropped) and its sampled ⟨θ²⟩ (from each pair's
//! axis at the loaded equilibrium) is printed beside. Environment: IE=1
//! implicit Euler; AVG=1 the stacking averaged over each step; HC the
//! bonds' compliance (nm/pN); FIXED=1 no adaptive steps; T the
//! temperature (K); ROD=1 samples the plain rod instead (clamped, the
//! duplex's mass per length, CPS control points), against its harmonic
//! values. Measured 2026-11-29 (100 bp, 10 pN, steps of 5 ps): over 20 ns
//! the sampled duplex tilts 0.45–0.80 of the exact values in the interior,
//! trapezoidal or implicit Euler alike; over 400 ns (implicit Euler,
//! 80000 steps, 12 min) 0.80 ± 0.04, at 2 ps 0.77 ± 0.04
//! (`docs/dna_calibration.md`). The plain rod on its default 2 N_BP
//! points (0.16 nm apart, where a kT stretches a segment by 15 %) is not
//! sampled at viscosity 0.1: the trapezoidal Newton iterations diverge and
//! ten halvings of the step do not rescue them; on 24 points for 24 bp
//! it runs, at the cost of halved steps (2000 steps in 90 s). ISO=1
//! isotropic drag; OD=1 Brownian (overdamped, isotropic drag) dynamics;
//! KE=1 prints the energies after each step; SEED the
//! noise's seed (1). PRED=1
//! prints what the stepped samplers read in the harmonic approximation
//! (`tension_tilt_stepped`, `rod_tension_tilt_stepped`: implicit Euler,
//! the trapezoidal rule, and with the stacking held) at DT and VISC, for
//! the rod on CPS points and the duplex (100 bp: 90 s).
//!
//!     cargo run --release --example dna_tension_tilt [-- N_BP [F_PN [STEPS]]]
use nalgebra::Vector3;
use strandkit::prelude::*;
use strandkit_builders::dna::{duplex, Duplex, BOLTZMANN};
use strandkit_builders::dna_harmonic::{pair_axes, reference_rod, rod_tension_tilt, rod_tension_tilt_stepped, tension_tilt, tension_tilt_stepped, Stepper};

fn env(k: &str) -> Option<f64> {
    std::env::var(k).ok().and_then(|v| v.parse().ok())
}

fn main() -> Result<()> {
    let arg = |i: usize| std::env::args().nth(i).and_then(|s| s.parse::<f64>().ok());
    let n = arg(1).unwrap_or(40.0) as usize;
    let f = arg(2).unwrap_or(10.0);
    let steps = arg(3).unwrap_or(0.0) as usize;
    let mut p = Duplex::new(&"GATTACA".chars().cycle().take(n).collect::<String>());
    p.averaged_stacking = env("AVG").is_some_and(|v| v != 0.0);
    p.break_forces = Some(vec![f64::INFINITY; n]); // the pull must not unzip it
    p.hbond_compliance = env("HC").unwrap_or(p.hbond_compliance);
    let t = std::time::Instant::now();
    let r = tension_tilt(&p, f)?;
    println!("{n} bp, {f} pN: residual {:.1e}, zero modes {}, {:.1} s", r.residual, r.zero_modes, t.elapsed().as_secs_f64());
    println!("worm-like chain kT/√(BF) = {:.5}", r.worm_like_chain);
    let at: Vec<f64> = (1..n - 1).map(|k| k as f64 * p.rise).collect();
    let kt = BOLTZMANN * p.temperature;
    let rod = rod_tension_tilt((n - 1) as f64 * p.rise, 2 * n, p.elasticity.bending_persistence, p.elasticity.stretch_modulus, kt, f, &at)?;
    if env("PRED").is_some() {
        // The stepped samplers' harmonic values for the rod as sampled.
        let cps = env("CPS").map_or(2 * n, |c| c as usize);
        let mu = 2.0 * 330.0 * 1.6605e-6 / p.rise;
        let exact = rod_tension_tilt((n - 1) as f64 * p.rise, cps, p.elasticity.bending_persistence, p.elasticity.stretch_modulus, kt, f, &at)?;
        let (h, eta) = (params().dt, params().viscosity);
        let stepped = |s| rod_tension_tilt_stepped((n - 1) as f64 * p.rise, cps, p.elasticity.bending_persistence, p.elasticity.stretch_modulus, kt, f, &at, mu, eta, h, s);
        let (ie, tr) = (stepped(Stepper::ImplicitEuler)?, stepped(Stepper::Trapezoidal)?);
        println!("rod on {cps} points, steps of {h} ns, viscosity {eta}: pair | exact | implicit Euler / exact | trapezoidal / exact");
        for (i, ((e, a), b)) in exact.iter().zip(&ie).zip(&tr).enumerate() {
            println!("{:3} | {e:.5} | {:.3} | {:.4}", i + 1, a / e, b / e);
        }
        let t = std::time::Instant::now();
        let steppers = [Stepper::ImplicitEuler, Stepper::Trapezoidal, Stepper::TrapezoidalHeld];
        let d: Vec<Vec<f64>> = steppers.iter().map(|&s| tension_tilt_stepped(&p, f, h, eta, s)).collect::<Result<_>>()?;
        println!("duplex, steps of {h} ns ({:.0} s): pair | exact | implicit Euler / exact | trapezoidal / exact | trapezoidal, stacking held / exact", t.elapsed().as_secs_f64());
        for (i, e) in r.tilt.iter().enumerate() {
            println!("{:3} | {e:.5} | {:.3} | {:.4} | {:.3}", i + 1, d[0][i] / e, d[1][i] / e, d[2][i] / e);
        }
    }
    let sampled = if steps > 0 && env("ROD").is_some() {
        sample_rod(&p, f, steps, &at, env("CPS").map_or(2 * n, |c| c as usize))?
    } else if steps > 0 {
        sample(&p, f, steps, &r.axes)?
    } else {
        vec![f64::NAN; n - 2]
    };
    println!("pair | duplex ⟨θ²⟩ | rod ⟨θ²⟩ (A = {} nm) | duplex / rod | sampled | sampled / duplex", p.elasticity.bending_persistence);
    for (i, ((v, w), s)) in r.tilt.iter().zip(&rod).zip(&sampled).enumerate() {
        println!("{:3} | {:.5} | {:.5} | {:.3} | {:.5} | {:.3}", i + 1, v, w, v / w, s, s / v);
    }
    Ok(())
}

/// ⟨|z_i − z_i⁰|²⟩ of each pair's axis, sampled.
fn sample(p: &Duplex, f: f64, steps: usize, z0: &[Vector3<f64>]) -> Result<Vec<f64>> {
    let (asm, l) = duplex(p)?;
    let mut w = World::new(params());
    let ins = w.insert(&asm)?;
    // Pair 0's nucleotides in traps of 10 pN/nm (a stepped duplex refuses
    // the zero-temperature probes' clamp as contradictory rows), the last
    // pair's pulled by f/2 each along z, as `tension_tilt` pulls them.
    let (a, b) = (ins.rods[l.strands[0]], ins.rods[l.strands[1]]);
    let n = l.partner.len();
    for (rod, u) in [(a, l.abscissae[0][0]), (b, l.abscissae[1][l.partner[0]])] {
        let x = w.rod(rod)?.position(u)?;
        w.add_load(strandkit_core::force::Trap { rod, u, anchor: x.into(), velocity: [0.0; 3], stiffness: 10.0, t0: 0.0 }.into())?;
    }
    for (rod, u) in [(a, l.abscissae[0][n - 1]), (b, l.abscissae[1][0])] {
        w.add_load(strandkit_core::force::PointForce { rod, u, force: [0.0, 0.0, f / 2.0] }.into())?;
    }
    run(&mut w, steps, |w| Ok(pair_axes([w.rod(a)?, w.rod(b)?], &l)?.iter().zip(z0).map(|(a, b)| (a - b).norm_squared()).collect()))
}

/// `steps` steps of `w`, `observe` after each; the mean of its values
/// after the first fifth of the run. Prints the middle half's mean per
/// tenth of the run (to see equilibration) and the time taken.
fn run(w: &mut World, steps: usize, observe: impl Fn(&World) -> Result<Vec<f64>>) -> Result<Vec<f64>> {
    let (mut sum, mut count) = (Vec::new(), 0usize);
    let (mut block, mut in_block) = (0.0, 0usize);
    let t = std::time::Instant::now();
    for s in 0..steps {
        if let Err(e) = w.step() {
            eprintln!("step {s} failed: {e}");
            return Err(e);
        }
        let x = observe(w)?;
        if std::env::var("KE").is_ok() {
            let (k, e) = w.rods().fold((0.0, 0.0), |(k, e), (_, r)| (k + r.kinetic_energy(), e + r.elastic_energy()));
            eprintln!("step {s}: kinetic {k:.1}, elastic {e:.1} pN nm");
        }
        let mid = x.len() / 4..(3 * x.len() / 4).max(x.len() / 4 + 1);
        block += x[mid.clone()].iter().sum::<f64>() / mid.len() as f64;
        in_block += 1;
        if (s + 1) % (steps / 10).max(1) == 0 {
            eprintln!("t = {:.1} ns: middle half ⟨θ²⟩ {:.4}", w.time(), block / in_block as f64);
            (block, in_block) = (0.0, 0);
        }
        if s >= steps / 5 {
            sum.resize(x.len(), 0.0);
            sum.iter_mut().zip(&x).for_each(|(acc, v)| *acc += v);
            count += 1;
        }
    }
    eprintln!("sampled {steps} steps in {:.0} s", t.elapsed().as_secs_f64());
    Ok(sum.into_iter().map(|v| v / count as f64).collect())
}

fn params() -> IntegrationParameters {
    IntegrationParameters {
        dt: env("DT").unwrap_or(0.005),
        scheme: if std::env::var("IE").is_ok() { strandkit::Scheme::ImplicitEuler } else { strandkit::Scheme::Trapezoidal },
        temperature: env("T").unwrap_or(298.15),
        viscosity: env("VISC").unwrap_or(0.1),
        units: strandkit::Units::Molecular,
        seed: env("SEED").map_or(1, |s| s as u64),
        adaptive_dt: std::env::var("FIXED").is_err(),
        isotropic_drag: std::env::var("ISO").is_ok() || std::env::var("OD").is_ok(),
        overdamped: std::env::var("OD").is_ok(),
        ..Default::default()
    }
}

/// ⟨|t(s) − ẑ|²⟩ of the plain rod's tangent at arc lengths `at`, sampled:
/// clamped at s = 0, pulled by `f` at its end.
fn sample_rod(p: &Duplex, f: f64, steps: usize, at: &[f64], cps: usize) -> Result<Vec<f64>> {
    let length = (p.sequence.len() - 1) as f64 * p.rise;
    // Two nucleotides of ≈ 330 Da per rise (1 Da = 1.66e-6 molecular mass units).
    let mu = 2.0 * 330.0 * 1.6605e-6 / p.rise;
    let rod = reference_rod(length, cps, p.elasticity.bending_persistence, p.elasticity.stretch_modulus, BOLTZMANN * p.temperature, mu)?;
    let (u0, u1) = rod.domain();
    let mut w = World::new(params());
    let h = w.add_rod(rod);
    w.clamp(h, u0, 0.0)?;
    w.add_load(strandkit_core::force::PointForce { rod: h, u: u1, force: [0.0, 0.0, f] }.into())?;
    let scale = (u1 - u0) / length;
    run(&mut w, steps, |w| {
        let rod = w.rod(h)?;
        at.iter().map(|&x| Ok((rod.tangent(u0 + x * scale)?.normalize() - Vector3::z()).norm_squared())).collect()
    })
}
