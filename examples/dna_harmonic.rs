//! The built duplex's exact thermal statistics in the harmonic
//! approximation (`strandkit_builders::dna_harmonic`, issue 17): each
//! stacking row's share of equipartition, the kT's each energy holds, and
//! the axis correlation by scale against the worm-like chain of the
//! duplex's A. What a sampler must reproduce at the base-pair scale.
//! Environment: SS (strand stretch modulus, pN), SP (strand persistence,
//! nm), HC (the bonds' compliance, nm/pN), SC (stagger compliance: position
//! rungs).
//!
//!     cargo run --release --example dna_harmonic [-- N_BP]
use strandkit::prelude::*;
use strandkit_builders::dna::Duplex;
use strandkit_builders::dna_harmonic::harmonic_statistics;

fn env(k: &str) -> Option<f64> {
    std::env::var(k).ok().and_then(|v| v.parse().ok())
}

fn main() -> Result<()> {
    let n: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(40);
    let mut p = Duplex::new(&"GATTACA".chars().cycle().take(n).collect::<String>());
    p.strand.stretch_modulus = env("SS").unwrap_or(p.strand.stretch_modulus);
    p.strand.persistence_length = env("SP").unwrap_or(p.strand.persistence_length);
    p.hbond_compliance = env("HC").unwrap_or(p.hbond_compliance);
    if let Some(c) = env("SC") {
        p.hbond = strandkit_builders::dna::HBond::Position { stagger_compliance: c };
    }
    let ks: Vec<usize> = [1, 2, 3, 5, 10, 15, 20].into_iter().filter(|&k| k + 11 <= n).collect();
    let h = harmonic_statistics(&p, &ks)?;
    let names = ["shift", "slide", "rise", "tilt", "roll", "twist"];
    println!("{n} bp: {} freedoms less rigid motions; kT's held: strands {:.1}, stacking {:.1}, other compliant {:.1}", h.freedoms, h.held[0], h.held[1], h.held[2]);
    println!("stacking rows ⟨λ²⟩/kT: {}", names.iter().zip(h.row_equipartition).map(|(n, v)| format!("{n} {v:.3}")).collect::<Vec<_>>().join(", "));
    let a = p.elasticity.bending_persistence;
    println!("k (bp) | 1 − ⟨z·z⟩ | worm-like chain, A = {a} nm | A_eff (nm)");
    for (k, v) in h.axis_decorrelation {
        let span = k as f64 * p.rise;
        println!("{k:3} | {v:.5} | {:.5} | {:.1}", 1.0 - (-span / a).exp(), -span / (1.0 - v).ln());
    }
    Ok(())
}
