//! Zero-temperature elastic constants of the built DNA duplex (issue 17),
//! by `strandkit_builders::dna_elasticity`: S, g, C, B against the
//! stacking's nominal values. Environment: SS (strand stretch modulus,
//! pN), SP (strand persistence, nm), MG (minor groove share of the pitch),
//! SC (stagger compliance, nm/pN: position rungs), NOCAL (the stacking at
//! the nominal values, uncalibrated).
//!
//!     cargo run --release --example dna_probe [-- N_BP]
use strandkit::prelude::*;
use strandkit_builders::dna::{Duplex, BOLTZMANN};
use strandkit_builders::dna_elasticity::zero_temperature_elasticity;

fn env(k: &str) -> Option<f64> {
    std::env::var(k).ok().and_then(|v| v.parse().ok())
}

fn main() -> Result<()> {
    let n: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(64);
    let seq: String = "GATTACA".chars().cycle().take(n).collect();
    let mut p = Duplex::new(&seq);
    p.strand.stretch_modulus = env("SS").unwrap_or(p.strand.stretch_modulus);
    p.strand.persistence_length = env("SP").unwrap_or(p.strand.persistence_length);
    p.minor_groove = env("MG").unwrap_or(p.minor_groove);
    p.radius = env("R").unwrap_or(p.radius);
    p.bp_per_turn = env("BPT").unwrap_or(p.bp_per_turn);
    p.elasticity.shear_modulus = env("SH").unwrap_or(p.elasticity.shear_modulus);
    if let Some(c) = env("SC") {
        p.hbond = strandkit_builders::dna::HBond::Position { stagger_compliance: c };
    }
    if env("NOCAL").is_some() {
        p.stacking = Some(p.elasticity);
    } else {
        let cal = strandkit_builders::dna_elasticity::calibrated(&p)?;
        println!("calibrated in {} probes: stacking {:?}", cal.iterations, cal.stacking);
    }
    let m = zero_temperature_elasticity(&p)?;
    let kt = BOLTZMANN * p.temperature;
    let e = p.elasticity;
    println!("{n} bp, strands {} pN, {} nm; duplex calibrated for S {} pN, g {} pN·nm, C {:.0} pN·nm², B {:.0} pN·nm²",
        p.strand.stretch_modulus, p.strand.persistence_length, e.stretch_modulus, e.twist_stretch, e.twist_persistence * kt, e.bending_persistence * kt);
    println!("  measured: S = {:.1} pN, g = {:.1} pN·nm, C = {:.1} pN·nm² ({:.1} nm), B = {:.1} pN·nm² (A = {:.1} nm)",
        m.stretch_modulus, m.twist_stretch, m.twist_stiffness, m.twist_stiffness / kt, m.bending_stiffness, m.bending_stiffness / kt);
    println!("  compliance: ε/F {:.4e}, ε/M {:.4e}, τ/F {:.4e}, τ/M {:.4e}", m.compliance[0][0], m.compliance[0][1], m.compliance[1][0], m.compliance[1][1]);
    Ok(())
}
