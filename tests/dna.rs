//! DNA duplex builder (issue 17, SPEC §9.1): geometry exact, sequences
//! checked, stacking that goes with its base pairs, the stacking carrying
//! the duplex elasticity and the calibrated duplex B-DNA at zero temperature.
use nalgebra::Vector3;
use std::f64::consts::PI;
use strandkit::prelude::*;
use strandkit::Event;
use strandkit_builders::dna::{duplex, parse_sequence, Duplex, Elasticity, HBond, BOLTZMANN};
use strandkit_builders::dna_elasticity::zero_temperature_elasticity;

/// Rise, bp per turn, radius, strand phase, rung length and groove widths
/// read back from the built strands (rods evaluated at the nucleotides'
/// abscissae) equal the parameters to 1e-9 nm, for the SPEC's default and
/// the thesis' 10 bp / 3.4 nm with a minor groove of 2/5 of the pitch.
#[test]
fn duplex_geometry_is_exact() {
    for (bp_per_turn, rise, groove) in [(10.5, 0.34, 12.0 / 34.0), (10.0, 0.34, 0.4)] {
        let mut p = Duplex::new("ATGCGTACGTTAGCCGATAGCTAGGCAT");
        p.bp_per_turn = bp_per_turn;
        p.rise = rise;
        p.minor_groove = groove;
        let (asm, l) = duplex(&p).unwrap();
        let n = l.partner.len();
        let mut w = World::new(IntegrationParameters::default());
        let ins = w.insert(&asm).unwrap();
        let (ra, rb) = (w.rod(ins.rods[l.strands[0]]).unwrap(), w.rod(ins.rods[l.strands[1]]).unwrap());
        let a: Vec<Vector3<f64>> = (0..n).map(|k| ra.position(l.abscissae[0][k]).unwrap()).collect();
        let b: Vec<Vector3<f64>> = (0..n).map(|k| rb.position(l.abscissae[1][l.partner[k]]).unwrap()).collect();
        let ang = |v: &Vector3<f64>| v.y.atan2(v.x);
        let wrap = |x: f64| (x + PI).rem_euclid(2.0 * PI) - PI;
        let phase = 2.0 * PI * groove;
        for k in 0..n {
            for v in [a[k], b[k]] {
                assert!(((v.x * v.x + v.y * v.y).sqrt() - 1.0).abs() < 1e-9, "radius at pair {k}");
            }
            assert!((b[k].z - a[k].z).abs() < 1e-9, "paired nucleotides at one height (pair {k})");
            assert!((wrap(ang(&b[k]) - ang(&a[k])) - wrap(phase)).abs() < 1e-9, "strand phase at pair {k}");
            assert!(((b[k] - a[k]).norm() - 2.0 * (0.5 * phase).sin()).abs() < 1e-9, "rung length at pair {k}");
            assert!(((b[k] - a[k]).norm() - l.rung_length).abs() < 1e-9);
            if k + 1 < n {
                assert!((a[k + 1].z - a[k].z - rise).abs() < 1e-9, "rise at pair {k}");
                // Right-handed: the angle grows with height by 2π per turn.
                assert!((wrap(ang(&a[k + 1]) - ang(&a[k])) - 2.0 * PI / bp_per_turn).abs() < 1e-9, "twist at pair {k}");
            }
        }
        // Grooves along the axis: strand b is strand a turned by φ, so it
        // reaches a's angle φ / (2π / bp_per_turn) pairs' rise lower.
        let measured_phase = wrap(ang(&b[0]) - ang(&a[0])).rem_euclid(2.0 * PI);
        let rise_per_rad = (a[1].z - a[0].z) / wrap(ang(&a[1]) - ang(&a[0]));
        let minor = measured_phase * rise_per_rad;
        let pitch = 2.0 * PI * rise_per_rad;
        assert!((minor - l.grooves[0]).abs() < 1e-9 && (pitch - minor - l.grooves[1]).abs() < 1e-9, "grooves {:?} vs {minor}", l.grooves);
        assert!((minor - groove * bp_per_turn * rise).abs() < 1e-9);
        // 5′→3′: strand a up the axis, strand b down it; each ends at its domain's ends.
        assert!(ra.tangent(l.abscissae[0][0]).unwrap().z > 0.0 && rb.tangent(l.abscissae[1][0]).unwrap().z < 0.0);
        assert_eq!((l.abscissae[0][0], l.abscissae[0][n - 1]), ra.domain());
        assert_eq!((l.abscissae[1][0], l.abscissae[1][n - 1]), rb.domain());
    }
}

/// Sequences in either case are accepted; anything but A, C, G, T is
/// refused with its position; the complement is generated (antiparallel)
/// or given, with mismatches flagged and left unbonded.
#[test]
fn sequences_are_checked_and_paired() {
    assert_eq!(parse_sequence("acgT", "sequence").unwrap(), b"ACGT".to_vec());
    for (bad, pos) in [("ACGNT", "position 4"), ("ACGU", "position 4"), ("AC GT", "position 3")] {
        let e = duplex(&Duplex::new(bad)).unwrap_err().to_string();
        assert!(e.contains(pos), "{bad}: {e}");
    }
    assert!(duplex(&Duplex::new("")).unwrap_err().to_string().contains("empty"));
    assert!(duplex(&Duplex::new("ACG")).is_err(), "3 bp is below a cubic strand");
    let (_, l) = duplex(&Duplex::new("AACGTG")).unwrap();
    assert_eq!(l.sequences[1], "CACGTT");
    assert!(l.mismatches.is_empty());
    let mut p = Duplex::new("AACGTG");
    p.complement = Some("CACTTT".into()); // pair 2 (C) faces T; pair 0 (A) faces the 3′ T
    let (asm, l) = duplex(&p).unwrap();
    assert_eq!(l.mismatches, vec![2]);
    assert!(l.hbonds[2].is_none() && l.stacks[1].is_none() && l.stacks[2].is_none());
    assert_eq!(asm.constraints.iter().filter(|c| c.label.as_deref().is_some_and(|s| s.starts_with("hbond"))).count(), 5);
    p.complement = Some("CACG".into());
    assert!(duplex(&p).unwrap_err().to_string().contains("as many as the sequence"));
    // Break forces: A·T weaker than G·C by default, per pair when given.
    let (_, l) = duplex(&Duplex::new("ATGC")).unwrap();
    assert_eq!(l.break_forces, vec![9.0, 9.0, 20.0, 20.0]);
    let mut p = Duplex::new("ATGC");
    p.break_forces = Some(vec![1.0, 2.0, -3.0, 4.0]);
    assert!(duplex(&p).is_err());
}

/// The duplex `p` built and stepped `steps` times (dt 1 ps), strand a
/// clamped at its 3′ end, pair `k`'s two nucleotides pushed by `force_a`
/// (of their positions a, b: the force on a, pN) and its opposite: the
/// labelled constraints broken, with their events' forces, in order (and
/// the world).
fn broken_under(p: &Duplex, k: usize, force_a: impl Fn(Vector3<f64>, Vector3<f64>) -> Vector3<f64>, steps: usize) -> (World, Vec<(String, f64)>) {
    let (asm, l) = duplex(p).unwrap();
    let n = l.partner.len();
    let mut w = World::new(IntegrationParameters { dt: 1e-3, relax_max_iterations: 200, ..Default::default() });
    let ins = w.insert(&asm).unwrap();
    let (ra, rb) = (ins.rods[l.strands[0]], ins.rods[l.strands[1]]);
    w.clamp(ra, l.abscissae[0][n - 1], 0.0).unwrap();
    let (ua, ub) = (l.abscissae[0][k], l.abscissae[1][l.partner[k]]);
    let f = force_a(w.rod(ra).unwrap().position(ua).unwrap(), w.rod(rb).unwrap().position(ub).unwrap());
    w.add_load(PointForce { rod: ra, u: ua, force: f.into() }.into()).unwrap();
    w.add_load(PointForce { rod: rb, u: ub, force: (-f).into() }.into()).unwrap();
    let mut broken = Vec::new();
    for _ in 0..steps {
        for e in w.step().unwrap().events {
            if let Event::ConstraintBroken { label: Some(s), force, .. } = e {
                broken.push((s, force));
            }
        }
    }
    (w, broken)
}

/// Pair 0 pulled apart along its rung by 8 pN.
fn rung_pull(a: Vector3<f64>, b: Vector3<f64>) -> Vector3<f64> {
    -(b - a).normalize() * 8.0
}

/// Pulling the first pair's two nucleotides apart (unzipping the end)
/// breaks its hydrogen bond in tension; the stackings that read that pair
/// (steps 0 and 1) go with it (`breaks_with`, reported at force 0), the
/// next one stays.
#[test]
fn stacking_goes_with_its_base_pairs() {
    let mut p = Duplex::new("GCGCGCGCGCGCGCGCGCGCGC");
    p.break_forces = Some((0..22).map(|k| if k == 0 { 5.0 } else { f64::INFINITY }).collect());
    let (w, broken) = broken_under(&p, 0, rung_pull, 5);
    // Pair 0 frames steps 0 and 1 (the axis at pair 1 is read from pairs 0 and 2).
    assert_eq!(broken.len(), 3, "{broken:?}");
    assert_eq!(broken[0].0, "hbond[0]");
    assert!(broken[0].1 > 5.0, "broke in tension above its 5 pN");
    assert_eq!(broken[1..], [("stack[0]".to_string(), 0.0), ("stack[1]".to_string(), 0.0)]);
    let labels: Vec<String> = w.constraints().filter_map(|(_, c)| c.label.clone()).collect();
    assert!(!labels.contains(&"stack[1]".to_string()) && labels.contains(&"stack[2]".to_string()) && labels.contains(&"hbond[1]".to_string()));
}

/// The stacking alone (strands a hundred times softer than ssDNA, 8 pN
/// and 0.01 nm; the stacking's constants given, not calibrated) carries
/// the duplex's elasticity: measured at zero temperature (64 bp, loads on
/// one end, read over the middle 4 turns) B within 2 % and g, C within 4 %
/// of the stacking's A = 50 nm, g = −90 pN·nm, C = 100 nm kT (measured
/// 207.0 pN·nm², −93.4, 418.8), S within 10 % (1192 vs 1100 pN: the rise
/// read between the pair origins is not quite the axis'), and the
/// compliance is symmetric (Maxwell–Betti: ε/M = τ/F within 6 %), as a
/// conservative model's must be.
#[test]
fn stacking_carries_the_duplex_elasticity() {
    let seq: String = "GATTACA".chars().cycle().take(64).collect();
    let mut p = Duplex::new(&seq);
    p.strand.stretch_modulus = 8.0;
    p.strand.persistence_length = 0.01;
    p.stacking = Some(Elasticity::default());
    let m = zero_temperature_elasticity(&p).unwrap();
    let e = Elasticity::default();
    let kt = BOLTZMANN * p.temperature;
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    assert!(rel(m.stretch_modulus, e.stretch_modulus) < 0.10, "S {}", m.stretch_modulus);
    assert!(rel(m.twist_stretch, e.twist_stretch) < 0.04, "g {}", m.twist_stretch);
    assert!(rel(m.twist_stiffness, e.twist_persistence * kt) < 0.04, "C {}", m.twist_stiffness);
    assert!(rel(m.bending_stiffness, e.bending_persistence * kt) < 0.02, "B {}", m.bending_stiffness);
    let c = m.compliance;
    assert!((c[0][1] - c[1][0]).abs() < 0.06 * c[0][1].abs(), "compliance not symmetric: {c:?}");
}

/// The calibrated default duplex (strands 400 pN, 0.75 nm) on another
/// length than the calibration's 64 bp probe (80 bp of CCGGATAT…; its
/// ends weigh less): zero-temperature S, g, C, B within 2 % of B-DNA's
/// 1100 pN, −90 pN·nm (DNA overwinds when stretched), 100 nm kT and
/// 50 nm kT. Measured 1114.8 pN, −91.1 pN·nm, 412.1 and 205.9 pN·nm².
#[test]
fn calibrated_duplex_is_b_dna() {
    let seq: String = "CCGGATAT".chars().cycle().take(80).collect();
    let p = Duplex::new(&seq);
    assert_b_dna(&p, 0.02, 0.02);
}

/// The zero-temperature S and g of duplex `p` within `tol_sg`, C and B
/// within `tol_cb` of B-DNA's 1100 pN, −90 pN·nm, 100 nm kT, 50 nm kT.
fn assert_b_dna(p: &Duplex, tol_sg: f64, tol_cb: f64) {
    let m = zero_temperature_elasticity(p).unwrap();
    let kt = BOLTZMANN * p.temperature;
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    assert!(rel(m.stretch_modulus, 1100.0) < tol_sg, "S {}", m.stretch_modulus);
    assert!(rel(m.twist_stretch, -90.0) < tol_sg, "g {}", m.twist_stretch);
    assert!(rel(m.twist_stiffness, 100.0 * kt) < tol_cb, "C {}", m.twist_stiffness);
    assert!(rel(m.bending_stiffness, 50.0 * kt) < tol_cb, "B {}", m.bending_stiffness);
}

/// Strands as stiff in stretch as free ssDNA (800 pN) leave no stable
/// stacking that makes the duplex B-DNA (they alone unwind it under
/// tension by more than the stacking can overwind it): a clear error, not
/// a duplex with the wrong sign.
#[test]
fn too_stiff_strands_are_refused() {
    let mut p = Duplex::new("GATTACAGATTACA");
    p.strand.stretch_modulus = 800.0;
    match duplex(&p) {
        Err(Error::InvalidInput { expected, .. }) => assert!(expected.contains("strands soft enough"), "{expected}"),
        other => panic!("{other:?}"),
    }
}

/// Position rungs (`HBond::Position`): the calibrated duplex is B-DNA too
/// (80 bp, not the calibration's probe: C, B within 2 %, S and g within
/// 3 % — measured 1131 pN, −92.5 pN·nm, 412.1 and 205.8 pN·nm²), every
/// bonded pair carries a stagger row, a pair's stagger goes with the
/// bonds of the pairs its axis reads (pair 0 breaking takes stagger[0] and
/// stagger[1]) while the neighbours stay bonded, and a stagger broken
/// under its own load opens its pair, not the neighbours.
#[test]
fn position_rungs_calibrate_and_go_with_their_pairs() {
    let seq: String = "CCGGATAT".chars().cycle().take(80).collect();
    let mut p = Duplex::new(&seq);
    p.hbond = HBond::position(0.04);
    assert_b_dna(&p, 0.03, 0.02);

    let mut p = Duplex::new("GCGCGCGCGCGCGCGCGCGCGC");
    p.hbond = HBond::position(0.04);
    p.break_forces = Some((0..22).map(|k| if k == 0 { 5.0 } else { f64::INFINITY }).collect());
    assert!(duplex(&p).unwrap().1.staggers.iter().all(|s| s.is_some()));
    let gone: Vec<String> = broken_under(&p, 0, rung_pull, 5).1.into_iter().map(|g| g.0).collect();
    for g in ["hbond[0]", "stagger[0]", "stagger[1]", "stack[0]", "stack[1]"] {
        assert!(gone.contains(&g.to_string()), "{g} not gone: {gone:?}");
    }
    assert_eq!(gone.len(), 5, "{gone:?}");

    // Pair 10's two nucleotides slid apart along the axis (±4 pN): its
    // stagger breaks under its load (1 pN) and takes its bond along
    // (`fails_with`), then what goes with that bond — the neighbours'
    // staggers and the stacking it frames — but not the neighbours' bonds.
    p.break_forces = None;
    p.stagger_break_forces = Some((0..22).map(|k| if k == 10 { 1.0 } else { f64::INFINITY }).collect());
    let (_, gone) = broken_under(&p, 10, |_, _| Vector3::new(0.0, 0.0, 4.0), 20);
    assert_eq!(gone[0].0, "stagger[10]", "{gone:?}");
    assert!(gone[0].1 > 1.0, "broke under its load: {gone:?}");
    let labels: Vec<&str> = gone.iter().map(|g| g.0.as_str()).collect();
    for g in ["hbond[10]", "stagger[9]", "stagger[11]", "stack[8]", "stack[9]", "stack[10]", "stack[11]"] {
        assert!(labels.contains(&g), "{g} not gone: {gone:?}");
    }
    assert!(!labels.contains(&"hbond[9]") && !labels.contains(&"hbond[11]"), "{gone:?}");
}

/// Issue 17: the built duplex is a worm-like chain down to the base pair.
/// Its exact harmonic statistics (`dna_harmonic`: kT H⁺ of the energy at
/// rest, no sampling), 30 bp, the axis framed as the stacking frames it:
/// 1 − ⟨z_i·z_{i+k}⟩ against 1 − e^{−k·rise/A}, A = 50 nm, gives A_eff
/// 54.6, 51.3, 50.7, 49.8 nm at k = 1, 2, 3, 5 bp (asserted within 10 %).
/// A sampler that finds the base-pair scale stiffer (A_eff 144 nm at 2 bp
/// with the stacking held at each step's end, `docs/dna_calibration.md`)
/// is cooling the stiff modes, not reading the model. Each stacking row
/// holds at most its kT (⟨λ²⟩/kT 0.91, 0.31, 0.95, 0.85, 0.67, 0.21 for
/// shift … twist): asserted ≤ 1 and, for the bending rows (tilt, roll),
/// ≥ 0.5 — a bend of one step is not held by other energies.
#[test]
fn the_duplex_is_a_worm_like_chain_down_to_the_base_pair() {
    let p = Duplex::new(&"GATTACA".chars().cycle().take(30).collect::<String>());
    let h = strandkit_builders::dna_harmonic::harmonic_statistics(&p, &[1, 2, 3, 5]).unwrap();
    let a = p.elasticity.bending_persistence;
    for &(k, v) in &h.axis_decorrelation {
        let a_eff = -(k as f64) * p.rise / (1.0 - v).ln();
        println!("k = {k} bp: 1 − ⟨z·z⟩ = {v:.5}, A_eff {a_eff:.1} nm");
        assert!((a_eff / a - 1.0).abs() < 0.1, "A_eff {a_eff} nm at {k} bp");
    }
    println!("rows ⟨λ²⟩/kT {:?}; kT's held {:?} of {}", h.row_equipartition, h.held, h.freedoms);
    assert!(h.row_equipartition.iter().all(|&r| r <= 1.0 + 1e-6));
    assert!(h.row_equipartition[3] >= 0.5 && h.row_equipartition[4] >= 0.5);
}

/// Issue 17: under a pull the duplex still tilts as a worm-like chain.
/// The loaded equilibrium's exact harmonic statistics (`dna_harmonic::
/// tension_tilt`: the whole Lagrangian's Hessian, the stacking's and the
/// rigid bonds' curvature under load included) against a plain rod of A =
/// 50 nm held and pulled the same way (`rod_tension_tilt`). The rod's
/// machinery first: 60 nm on 240 points at 10 pN reaches kT/√(BF) = 0.0907 rad² in its
/// interior (asserted within 1 %). Then the duplex, 40 bp at 3 pN: ⟨θ²⟩ of
/// each pair's axis within 2 % of the rod's from pair 14 on (measured
/// 1.5 % at 14, 0.4 % from 23 on), within 5 % at pairs 8–13 (4.1 % at 8);
/// by the clamp the
/// base-pair wobble adds up to 25 % (pairs 1–7, not asserted). On 100 bp at 10 pN (30 s, not run here)
/// the interior reads 0.991–0.994 of the rod's: a sampler whose duplex
/// shortens a quarter less than the rod is not reading the model.
#[test]
fn under_a_pull_the_duplex_tilts_like_a_worm_like_chain() {
    use strandkit_builders::dna::BOLTZMANN;
    use strandkit_builders::dna_harmonic::{rod_tension_tilt, tension_tilt};
    let p = Duplex::new(&"GATTACA".chars().cycle().take(40).collect::<String>());
    let (a, s, kt) = (p.elasticity.bending_persistence, p.elasticity.stretch_modulus, BOLTZMANN * p.temperature);
    let long: Vec<f64> = (5..8).map(|k| k as f64 * 5.0).collect();
    let plateau = rod_tension_tilt(60.0, 240, a, s, kt, 10.0, &long).unwrap();
    let wlc = kt / (a * kt * 10.0).sqrt();
    for v in &plateau {
        assert!((v / wlc - 1.0).abs() < 0.01, "rod ⟨θ²⟩ {v} against kT/√(BF) {wlc}");
    }
    let t = tension_tilt(&p, 3.0).unwrap();
    assert!(t.residual < 1e-8);
    let at: Vec<f64> = (1..39).map(|k| k as f64 * p.rise).collect();
    let rod = rod_tension_tilt(39.0 * p.rise, 80, a, s, kt, 3.0, &at).unwrap();
    for (i, (v, w)) in t.tilt.iter().zip(&rod).enumerate() {
        let tol = match i + 1 {
            1..=7 => continue,
            8..=13 => 0.05,
            _ => 0.02,
        };
        assert!((v / w - 1.0).abs() < tol, "pair {}: duplex ⟨θ²⟩ {v:.5} against the rod's {w:.5}", i + 1);
    }
}

/// Issue 17: what a stepped sampler reads is its own harmonic covariance
/// (`dna_harmonic::rod_tension_tilt_stepped`, `tension_tilt_stepped`: the
/// stationary covariance of the linearised step with thermal noise, by a
/// discrete Lyapunov equation). The recursion's check: the trapezoidal
/// rule averaged whole gives the exact harmonic ⟨θ²⟩ (Gibbs-exact),
/// asserted within 1e-6 for the plain rod (7.8 nm on 12 points, 5 pN) and
/// 1e-4 for a 12 bp duplex (3 pN). Then the sampler: the rod stepped by
/// implicit Euler (5 ps, viscosity 0.1, 298.15 K, seed 1, 1 µs after
/// 0.25 µs) tilts 0.853 of the exact value over its middle half and 0.966
/// of implicit Euler's prediction (0.884 of exact there; asserted within
/// 5 %, and below 0.93 of exact). What is measured, 2(1 − cos θ), is θ²
/// less ≈ 1.5 % at θ² ≈ 0.09; over 10 µs the profile reads 0.98–0.99 of
/// the prediction by the clamp and mid-rod, 0.96 at the pulled end. The
/// deficit of a noisy implicit Euler run is its time step's: modes with
/// ωh ≳ 0.3 keep less than their kT.
#[test]
fn a_stepped_sampler_reads_its_own_harmonic_covariance() {
    use strandkit_builders::dna_harmonic::{reference_rod, rod_tension_tilt, rod_tension_tilt_stepped, tension_tilt, tension_tilt_stepped, Stepper};
    let p = Duplex::new("GATTACAGATTA");
    let (a, s, kt) = (p.elasticity.bending_persistence, p.elasticity.stretch_modulus, BOLTZMANN * p.temperature);
    let (length, cps, force, h, eta) = (23.0 * p.rise, 12, 5.0, 0.005, 0.1);
    let mu = 2.0 * 330.0 * 1.6605e-6 / p.rise; // two nucleotides per rise (molecular mass units)
    let at: Vec<f64> = (1..23).map(|k| k as f64 * p.rise).collect();
    let exact = rod_tension_tilt(length, cps, a, s, kt, force, &at).unwrap();
    let stepped = |st| rod_tension_tilt_stepped(length, cps, a, s, kt, force, &at, mu, eta, h, st).unwrap();
    let (ie, tr) = (stepped(Stepper::ImplicitEuler), stepped(Stepper::Trapezoidal));
    for (e, t) in exact.iter().zip(&tr) {
        assert!((t / e - 1.0).abs() < 1e-6, "trapezoidal {t} against exact {e}");
    }
    for (h, eta) in [(0.0, 0.1), (f64::NAN, 0.1), (0.005, -1.0), (0.005, f64::INFINITY)] {
        assert!(matches!(tension_tilt_stepped(&p, 3.0, h, eta, Stepper::ImplicitEuler), Err(Error::InvalidInput { .. })), "h {h}, viscosity {eta}");
        assert!(rod_tension_tilt_stepped(length, cps, a, s, kt, force, &at, mu, eta, h, Stepper::Trapezoidal).is_err());
    }
    let d = tension_tilt(&p, 3.0).unwrap().tilt;
    let dt = tension_tilt_stepped(&p, 3.0, h, eta, Stepper::Trapezoidal).unwrap();
    for (e, t) in d.iter().zip(&dt) {
        assert!((t / e - 1.0).abs() < 1e-4, "duplex: trapezoidal {t} against exact {e}");
    }

    let rod = reference_rod(length, cps, a, s, kt, mu).unwrap();
    let (u0, u1) = rod.domain();
    let mut w = World::new(IntegrationParameters {
        dt: h,
        scheme: strandkit::Scheme::ImplicitEuler,
        temperature: p.temperature,
        viscosity: eta,
        isotropic_drag: true,
        units: strandkit::Units::Molecular,
        seed: 1,
        parallel: false,
        ..Default::default()
    });
    let r = w.add_rod(rod);
    w.clamp(r, u0, 0.0).unwrap();
    w.add_load(strandkit::force::PointForce { rod: r, u: u1, force: [0.0, 0.0, force] }.into()).unwrap();
    let mid = at.len() / 4..3 * at.len() / 4;
    let scale = (u1 - u0) / length;
    let (mut sum, mut count) = (0.0, 0usize);
    for step in 0..250_000 {
        w.step().unwrap();
        if step >= 50_000 && step % 5 == 0 {
            let rod = w.rod(r).unwrap();
            sum += mid.clone().map(|i| (rod.tangent(u0 + at[i] * scale).unwrap().normalize() - Vector3::z()).norm_squared()).sum::<f64>() / mid.len() as f64;
            count += 1;
        }
    }
    let mean = |v: &[f64]| mid.clone().map(|i| v[i]).sum::<f64>() / mid.len() as f64;
    let sampled = sum / count as f64;
    println!("middle half: exact {:.4}, implicit Euler predicted {:.4}, sampled {sampled:.4} ({:.3} of exact, {:.3} of predicted)", mean(&exact), mean(&ie), sampled / mean(&exact), sampled / mean(&ie));
    assert!((sampled / mean(&ie) - 1.0).abs() < 0.05);
    assert!(sampled / mean(&exact) < 0.93, "implicit Euler's deficit not seen");
}

/// 1 − ⟨z_i·z_{i+k}⟩ over the interior pairs of a free `n` bp duplex
/// (unbreakable bonds) stepped with thermal noise at 298.15 K (trapezoidal,
/// viscosity 0.1 pN·ns/nm², seed 1): `steps` of `dt` ns, the first fifth
/// dropped, sampled every `every` steps.
/// With `brownian`, overdamped dynamics (isotropic drag) in water
/// (viscosity 1 pN·ns/nm²); else with inertia at a tenth of it.
fn sampled_axis_decorrelation(p: &Duplex, dt: f64, steps: usize, every: usize, ks: &[usize], brownian: bool) -> Vec<f64> {
    use strandkit_builders::dna_harmonic::{interior_pairs, pair_axes};
    let (asm, l) = duplex(p).unwrap();
    let mut w = World::new(IntegrationParameters {
        dt,
        scheme: strandkit::Scheme::Trapezoidal,
        temperature: 298.15,
        viscosity: if brownian { 1.0 } else { 0.1 },
        overdamped: brownian,
        isotropic_drag: brownian,
        units: strandkit::Units::Molecular,
        seed: 1,
        adaptive_dt: true,
        ..Default::default()
    });
    let ins = w.insert(&asm).unwrap();
    let n = l.partner.len();
    let ranges: Vec<_> = ks.iter().map(|&k| interior_pairs(n, k).unwrap()).collect();
    let (mut sums, mut count) = (vec![0.0; ks.len()], 0usize);
    for s in 0..steps {
        w.step().unwrap();
        if s >= steps / 5 && s % every == 0 {
            let z = pair_axes([w.rod(ins.rods[l.strands[0]]).unwrap(), w.rod(ins.rods[l.strands[1]]).unwrap()], &l).unwrap();
            for ((sum, &k), r) in sums.iter_mut().zip(ks).zip(&ranges) {
                *sum += r.clone().map(|i| 1.0 - z[i].dot(&z[i + k])).sum::<f64>() / r.len() as f64;
            }
            count += 1;
        }
    }
    sums.iter().map(|s| s / count as f64).collect()
}

/// Issue 17: in Brownian dynamics (overdamped, isotropic drag, water) the
/// trapezoidal rule with the stacking averaged samples the duplex's exact
/// statistics at steps of 5 ps, twenty times the inertial sampler's 0.25 ps:
/// the rule keeps kT/k of every linear mode at any step (Crank–Nicolson on
/// an Ornstein–Uhlenbeck process), and without inertia there is no fast
/// oscillation for the nonlinearity to pump (with inertia at 5 ps the same
/// duplex runs 15–24 % warm, at 2 ps 7–11 %; held, it is cold). 20 bp,
/// 10 ns (2000 steps, `adaptive_dt` splitting about one in ten), 1 − ⟨z_i·
/// z_{i+k}⟩ at k = 2, 5 bp against `dna_harmonic`'s 0.01317, 0.03355:
/// 1.020 and 1.025 of them (asserted within 10 %).
#[test]
fn a_brownian_duplex_with_averaged_stacking_samples_its_statistics_at_five_picoseconds() {
    let mut p = Duplex::new(&"GATTACA".chars().cycle().take(20).collect::<String>());
    p.break_forces = Some(vec![f64::INFINITY; 20]);
    p.averaged_stacking = true;
    let ks = [2usize, 5];
    let exact: Vec<f64> = strandkit_builders::dna_harmonic::harmonic_statistics(&p, &ks).unwrap().axis_decorrelation.iter().map(|x| x.1).collect();
    let sampled = sampled_axis_decorrelation(&p, 5e-3, 2000, 5, &ks, true);
    println!("k = {ks:?}: harmonic {exact:.5?}, Brownian at 5 ps {sampled:.5?}");
    for ((e, s), k) in exact.iter().zip(&sampled).zip(ks) {
        assert!((s / e - 1.0).abs() < 0.10, "Brownian, averaged stacking, 5 ps, at {k} bp: {s} against {e}");
    }
}

/// Issue 17: with its compliant stacking averaged over each trapezoidal
/// step (`averaged_stacking`, steps of 0.25 ps) a noisy free 20 bp duplex
/// samples its exact harmonic statistics at the base-pair scale; held at
/// each step's end (the default, robust at 5 ps) its stiff modes are damped
/// and the base-pair scale comes out cold. 1 − ⟨z_i·z_{i+k}⟩ at k = 2, 5
/// bp against `dna_harmonic`'s 0.01317, 0.03355: averaged (3 ns) 0.01367,
/// 0.03567 (+3.8 %, +6.3 %; asserted within 15 %; a 30 bp duplex over 5 ns
/// came within 1.5 % at k = 1 … 10); held (5 ps, 10 ns) 0.00469, 0.02104,
/// 0.36 and 0.63 of them (asserted below 0.6 at 2 bp).
#[test]
fn a_noisy_duplex_samples_its_harmonic_statistics_with_averaged_stacking() {
    let mut p = Duplex::new(&"GATTACA".chars().cycle().take(20).collect::<String>());
    p.break_forces = Some(vec![f64::INFINITY; 20]);
    let ks = [2usize, 5];
    let exact: Vec<f64> = strandkit_builders::dna_harmonic::harmonic_statistics(&p, &ks).unwrap().axis_decorrelation.iter().map(|x| x.1).collect();
    p.averaged_stacking = true;
    let averaged = sampled_axis_decorrelation(&p, 2.5e-4, 12000, 10, &ks, false);
    p.averaged_stacking = false;
    let held = sampled_axis_decorrelation(&p, 5e-3, 2000, 5, &ks, false);
    println!("k = {ks:?}: harmonic {exact:.5?}, averaged {averaged:.5?}, held {held:.5?}");
    for ((e, a), k) in exact.iter().zip(&averaged).zip(ks) {
        assert!((a / e - 1.0).abs() < 0.15, "averaged stacking at {k} bp: {a} against {e}");
    }
    assert!(held[0] < 0.6 * exact[0], "held stacking at 2 bp: {} against {}", held[0], exact[0]);
}
