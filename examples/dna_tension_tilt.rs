//! The duplex's harmonic tilt under a pull against a plain rod's of the
//! same A held and pulled the same way (`strandkit_builders::dna_harmonic::
//! tension_tilt`, `rod_tension_tilt`; issue 17): ⟨θ²⟩ of each pair's axis,
//! whose interior value × rise / 2 is the entropic shortening per length.
//! 100 bp at 10 pN: 0.991–0.994 of the rod's in the interior (30 s).
//!
//!     cargo run --release --example dna_tension_tilt [-- N_BP [F_PN]]
use strandkit::prelude::*;
use strandkit_builders::dna::Duplex;
use strandkit_builders::dna::BOLTZMANN;
use strandkit_builders::dna_harmonic::{rod_tension_tilt, tension_tilt};

fn main() -> Result<()> {
    let n: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(40);
    let f: f64 = std::env::args().nth(2).and_then(|s| s.parse().ok()).unwrap_or(10.0);
    let p = Duplex::new(&"GATTACA".chars().cycle().take(n).collect::<String>());
    let t = std::time::Instant::now();
    let r = tension_tilt(&p, f)?;
    println!("{n} bp, {f} pN: residual {:.1e}, zero modes {}, {:.1} s", r.residual, r.zero_modes, t.elapsed().as_secs_f64());
    println!("worm-like chain kT/√(BF) = {:.5}", r.worm_like_chain);
    let at: Vec<f64> = (1..n - 1).map(|k| k as f64 * p.rise).collect();
    let kt = BOLTZMANN * p.temperature;
    let rod = rod_tension_tilt((n - 1) as f64 * p.rise, 2 * n, p.elasticity.bending_persistence, p.elasticity.stretch_modulus, kt, f, &at)?;
    println!("pair | duplex ⟨θ²⟩ | rod ⟨θ²⟩ (A = {} nm) | duplex / rod", p.elasticity.bending_persistence);
    for (i, (v, w)) in r.tilt.iter().zip(&rod).enumerate() {
        println!("{:3} | {:.5} | {:.5} | {:.3}", i + 1, v, w, v / w);
    }
    Ok(())
}
