//! Zero-temperature elastic constants of a built duplex (issue 17): pair 0
//! held, small loads on the last pair — an axial force, a twisting couple,
//! a bending couple —, relaxed each time; the stretch modulus S, twist–
//! stretch coupling g and twist stiffness C from the 2×2 compliance of
//! (strain, twist) to (force, torque), the bending stiffness B from the
//! curvature under the couple. Everything is read on the duplex axis over
//! the pairs at least a turn away from either end.
//!
//! The axis point of a pair is its rung midpoint moved by R cos(φ/2)
//! toward the axis (along ẑ × x̂, ẑ the axis from the neighbouring rungs).
use crate::dna::{duplex, Duplex, DuplexLayout, Elasticity, BOLTZMANN};
use std::sync::{Mutex, OnceLock};
use nalgebra::Vector3;
use strandkit_core::constraint::kinds::base_pair_step::axis;
use strandkit_core::constraint::kinds::{Position, Tangent};
use strandkit_core::force::PointForce;
use strandkit_core::world::{IntegrationParameters, World};
use strandkit_core::{Error, Inserted, Result};

/// What [`zero_temperature_elasticity`] measured (pN, nm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    /// Stretch modulus at free twist (pN).
    pub stretch_modulus: f64,
    /// Twist–stretch coupling (pN·nm; < 0: overwinds when stretched).
    pub twist_stretch: f64,
    /// Twist stiffness C at fixed extension (pN·nm²).
    pub twist_stiffness: f64,
    /// Bending stiffness B (pN·nm²).
    pub bending_stiffness: f64,
    /// The compliance [[ε/F, ε/M], [τ/F, τ/M]] (1/pN, 1/(pN·nm),
    /// rad/(nm·pN), rad/(nm·pN·nm)); symmetric for a conservative model.
    pub compliance: [[f64; 2]; 2],
}

/// Axis point and rung of pair k (nm), framed as the stacking frames it
/// ([`strandkit_core::constraint::kinds::BasePairStep`]): the axis by its
/// rule ([`axis`]: the difference of the neighbouring rung midpoints),
/// ⟂ the rung.
pub fn pair_axis(w: &World, ins: &Inserted, l: &DuplexLayout, k: usize) -> Result<(Vector3<f64>, Vector3<f64>)> {
    let (ra, rb) = (w.rod(ins.rods[l.strands[0]])?, w.rod(ins.rods[l.strands[1]])?);
    let pair = |j: usize| -> Result<(Vector3<f64>, Vector3<f64>)> { Ok((ra.position(l.abscissae[0][j])?, rb.position(l.abscissae[1][l.partner[j]])?)) };
    let mid = |j: usize| -> Result<Vector3<f64>> {
        let (a, b) = pair(j)?;
        Ok((a + b) * 0.5)
    };
    let n = l.partner.len();
    let (a, b) = pair(k)?;
    let x = (b - a).normalize();
    // The stacking's own rule, pair k in the slot its frame has there.
    let c = if n < 3 {
        return Err(Error::input(format!("pair_axis: a duplex of {n} bp has no axis rule (3 pairs at least)")));
    } else if k == 0 {
        axis(&[mid(0)?, mid(0)?, mid(1)?, mid(2)?], 1, [true, false])
    } else if k == n - 1 {
        axis(&[mid(k - 2)?, mid(k - 1)?, mid(k)?, mid(k)?], 2, [false, true])
    } else {
        axis(&[mid(k - 1)?, mid(k)?, mid(k + 1)?, mid(k + 1)?], 1, [false, false])
    };
    let z = (c - x * x.dot(&c)).normalize();
    let offset = 0.5 * l.rung_length / (0.5 * l.phase).tan(); // R cos(φ/2)
    Ok(((a + b) * 0.5 + z.cross(&x) * offset, b - a))
}

/// The duplex relaxed with forces `fa`, `fb` (pN) on the last pair's
/// nucleotides of strands a and b; pair 0 held (strand a clamped, strand
/// b's height and tangent: the rung already fixes its distance to a).
fn loaded(p: &Duplex, fa: Vector3<f64>, fb: Vector3<f64>) -> Result<(World, Inserted, DuplexLayout)> {
    loaded_within(p, fa, fb, 1e-8)
}

/// [`loaded`] to a relax tolerance `tolerance` (of the length).
pub(crate) fn loaded_within(p: &Duplex, fa: Vector3<f64>, fb: Vector3<f64>, tolerance: f64) -> Result<(World, Inserted, DuplexLayout)> {
    let (asm, l) = duplex(p)?;
    // Tolerance 1e-8 of the length: the responses read (≈ 1e-2 nm) to 1e-5;
    // the default 1e-10 stalls on a long duplex (the stacking's second
    // derivatives are not in the Newton matrix: linear convergence).
    let mut w = World::new(IntegrationParameters { relax_max_iterations: 200, relax_tolerance: tolerance, ..Default::default() });
    let ins = w.insert(&asm)?;
    let (ra, rb) = (ins.rods[l.strands[0]], ins.rods[l.strands[1]]);
    let n = l.partner.len();
    w.clamp(ra, l.abscissae[0][0], 0.0)?;
    let ub = l.abscissae[1][n - 1];
    let (pb, tb) = (w.rod(rb)?.position(ub)?, w.rod(rb)?.tangent(ub)?);
    w.add_constraint(rb, Position { u: ub, axes: [false, false, true, false], target: [0.0, 0.0, pb.z, 0.0] }, 0.0)?;
    w.add_constraint(rb, Tangent { u: ub, direction: tb.into() }, 0.0)?;
    w.add_load(PointForce { rod: ra, u: l.abscissae[0][n - 1], force: fa.into() }.into())?;
    w.add_load(PointForce { rod: rb, u: l.abscissae[1][0], force: fb.into() }.into())?;
    w.relax()?;
    Ok((w, ins, l))
}

/// Measures S, g, C and B of the duplex `p` (at least 4 turns long) by
/// three relaxations under loads of 1 pN, 1 pN·nm and a 0.2 pN couple.
pub fn zero_temperature_elasticity(p: &Duplex) -> Result<Measured> {
    let (w0, ins0, l) = loaded(p, Vector3::zeros(), Vector3::zeros())?;
    let n = l.partner.len();
    let turn = p.bp_per_turn.ceil() as usize;
    if n < 4 * turn {
        return Err(Error::invalid("duplex length", format!("{n} bp"), format!("at least 4 turns ({} bp)", 4 * turn)));
    }
    let (k1, k2) = (turn, n - 1 - turn);
    let len = (k2 - k1) as f64 * p.rise;
    let z = |w: &World, ins: &Inserted| -> Result<f64> { Ok(pair_axis(w, ins, &l, k2)?.0.z - pair_axis(w, ins, &l, k1)?.0.z) };
    // Rotation of the rung about z from k1 to k2, summed pair by pair.
    let angle = |w: &World, ins: &Inserted| -> Result<f64> {
        let mut tot = 0.0;
        for k in k1..k2 {
            let (x0, x1) = (pair_axis(w, ins, &l, k)?.1, pair_axis(w, ins, &l, k + 1)?.1);
            tot += (x0.x * x1.y - x0.y * x1.x).atan2(x0.x * x1.x + x0.y * x1.y);
        }
        Ok(tot)
    };
    let (z0, t0) = (z(&w0, &ins0)?, angle(&w0, &ins0)?);
    let response = |w: &World, ins: &Inserted| -> Result<(f64, f64)> { Ok(((z(w, ins)? - z0) / z0, (angle(w, ins)? - t0) / len)) };

    let f = 1.0; // pN along the axis, shared by the two nucleotides
    let (w, ins, _) = loaded(p, Vector3::new(0.0, 0.0, f / 2.0), Vector3::new(0.0, 0.0, f / 2.0))?;
    let (eps_f, tau_f) = response(&w, &ins)?;
    let m = 1.0; // pN·nm about the axis: ±M/|x| ⟂ the end rung
    let (_, x) = pair_axis(&w0, &ins0, &l, n - 1)?;
    let y = Vector3::z().cross(&x.normalize()) * (m / x.norm());
    let (w, ins, _) = loaded(p, -y, y)?;
    let (eps_m, tau_m) = response(&w, &ins)?;
    let c = [[eps_f / f, eps_m / m], [tau_f / f, tau_m / m]];
    let det = c[0][0] * c[1][1] - c[0][1] * c[1][0];

    // Bending: ±fb ẑ on the end pair, a couple |x| fb about x̂ × ẑ; κ is
    // the slope of the axis direction's rotation (from rest, about that
    // axis) along the duplex, by least squares over the measured steps.
    let fb = 0.2;
    let (w, ins, _) = loaded(p, Vector3::new(0.0, 0.0, -fb), Vector3::new(0.0, 0.0, fb))?;
    let dir = |w: &World, ins: &Inserted, k: usize| -> Result<Vector3<f64>> { Ok((pair_axis(w, ins, &l, k + 1)?.0 - pair_axis(w, ins, &l, k)?.0).normalize()) };
    let about = x.normalize().cross(&Vector3::z());
    let (mut sx, mut sy, mut sxx, mut sxy, mut cnt) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for k in k1..k2 {
        let th = dir(&w0, &ins0, k)?.cross(&dir(&w, &ins, k)?).dot(&about);
        let s = k as f64 * p.rise;
        sx += s;
        sy += th;
        sxx += s * s;
        sxy += s * th;
        cnt += 1.0;
    }
    let kappa = ((cnt * sxy - sx * sy) / (cnt * sxx - sx * sx)).abs();
    Ok(Measured {
        stretch_modulus: c[1][1] / det,
        twist_stretch: -c[0][1] / det,
        twist_stiffness: c[0][0] / det,
        bending_stiffness: fb * x.norm() / kappa,
        compliance: c,
    })
}

/// A stacking calibrated for a duplex's target elasticity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Calibration {
    /// The stacking's own constants (what [`Duplex::stacking`] takes).
    pub stacking: Elasticity,
    /// The whole duplex's constants with that stacking, measured.
    pub measured: Measured,
    /// Probes run (each: four relaxations of a 64 bp duplex).
    pub iterations: usize,
}

/// Most probes a calibration runs before giving up.
const CALIBRATION_ROUNDS: usize = 6;
/// Relative error on S, g, C and B at which a calibration stops.
const CALIBRATION_TOLERANCE: f64 = 2e-3;

/// The stacking that gives the duplex `p` (its geometry, strands and rungs;
/// not its sequence, which the mechanics does not see) the zero-
/// temperature elasticity `p.elasticity`: the strands add their own share
/// (helical strands stretch when the duplex twists or stretches), so the
/// stacking's constants are corrected by the measured misfit, S, g, C and
/// B each, until all are within 0.2 % — a fixed-point iteration, as the
/// strands' share hardly depends on the stacking. Errors when no stable
/// stacking (g² < S·C, all positive) makes up the difference: strands too
/// stiff for the target. Cached per parameter set for the process.
pub fn calibrated(p: &Duplex) -> Result<Calibration> {
    let key: Vec<u64> = [
        p.bp_per_turn,
        p.rise,
        p.radius,
        p.minor_groove,
        p.hbond_compliance,
        match p.hbond {
            crate::dna::HBond::Distance => -1.0,
            crate::dna::HBond::Position { stagger_compliance } => stagger_compliance,
        },
        p.strand.stretch_modulus,
        p.strand.persistence_length,
        p.temperature,
        p.elasticity.bending_persistence,
        p.elasticity.stretch_modulus,
        p.elasticity.twist_persistence,
        p.elasticity.twist_stretch,
        p.elasticity.shear_modulus,
    ]
    .iter()
    .map(|v| v.to_bits())
    .collect();
    static CACHE: OnceLock<Mutex<Vec<(Vec<u64>, Calibration)>>> = OnceLock::new();
    let cache = CACHE.get_or_init(|| Mutex::new(Vec::new()));
    // A poisoned lock only means another thread panicked mid-push: the
    // entries already there are whole.
    if let Some((_, c)) = cache.lock().unwrap_or_else(|e| e.into_inner()).iter().find(|(k, _)| *k == key) {
        return Ok(*c);
    }
    let c = calibrate(p)?;
    cache.lock().unwrap_or_else(|e| e.into_inner()).push((key, c));
    Ok(c)
}

fn calibrate(p: &Duplex) -> Result<Calibration> {
    let kt = BOLTZMANN * p.temperature;
    let target = p.elasticity;
    let mut probe = Duplex { sequence: "GATTACA".chars().cycle().take(64.max(6 * p.bp_per_turn.ceil() as usize)).collect(), complement: None, break_forces: None, stagger_break_forces: None, ..p.clone() };
    let mut s = target;
    let mut worst = f64::INFINITY;
    for round in 1..=CALIBRATION_ROUNDS {
        probe.stacking = Some(s);
        let m = zero_temperature_elasticity(&probe)?;
        let misfit = [
            (target.stretch_modulus - m.stretch_modulus) / target.stretch_modulus,
            (target.twist_stretch - m.twist_stretch) / target.twist_stretch.abs().max(1e-3 * target.stretch_modulus),
            (target.twist_persistence * kt - m.twist_stiffness) / (target.twist_persistence * kt),
            (target.bending_persistence * kt - m.bending_stiffness) / (target.bending_persistence * kt),
        ];
        worst = misfit.iter().fold(0.0f64, |w, e| w.max(e.abs()));
        if worst < CALIBRATION_TOLERANCE {
            return Ok(Calibration { stacking: s, measured: m, iterations: round });
        }
        s.stretch_modulus += target.stretch_modulus - m.stretch_modulus;
        s.twist_stretch += target.twist_stretch - m.twist_stretch;
        s.twist_persistence += target.twist_persistence - m.twist_stiffness / kt;
        s.bending_persistence += target.bending_persistence - m.bending_stiffness / kt;
        if s.validate("stacking", p.temperature).is_err() {
            return Err(Error::invalid(
                "duplex elasticity",
                format!(
                    "S {} pN, g {} pN·nm, C/kT {} nm, A {} nm with strands of {} pN and {} nm (the stacking would need S {:.0}, g {:.0}, C/kT {:.1}, A {:.1})",
                    target.stretch_modulus, target.twist_stretch, target.twist_persistence, target.bending_persistence, p.strand.stretch_modulus, p.strand.persistence_length, s.stretch_modulus, s.twist_stretch, s.twist_persistence, s.bending_persistence
                ),
                "strands soft enough that a stable stacking (g² < S·C) makes up the rest (a softer strand stretch modulus)",
            ));
        }
    }
    Err(Error::not_converged(CALIBRATION_ROUNDS, worst, "DNA stacking calibration: S, g, C, B not within 0.2 % of the target"))
}
