//! Bending and twist in the Frenet model (SPEC §2.2, II.57–II.63):
//!
//!   κ = |r'×r''| / |r'|³,  κ1 = κ sin θ,  κ2 = κ cos θ
//!   W_b = ½ EI1 (κ1 − κ1⁰)² + ½ EI2 (κ2 − κ2⁰)²
//!       = A(θ) κ² − B(θ) κ + const,  A = ½(EI1 sin²θ + EI2 cos²θ),
//!         B = EI1 κ1⁰ sin θ + EI2 κ2⁰ cos θ
//!   ω = τ + θ'/|r'|,  τ = p / |r'×r''|²,  W_t = ½ GJ (ω − ω⁰)²
//!
//! Continuity extension where κ → 0 (the Frenet frame is undefined there,
//! thesis II.D.3). With δ = κ_ε |r0'|³:
//! - τ is evaluated as p |C|² / (|C|² + δ²)²: smooth, equal to the Frenet
//!   torsion to relative 2(κ_ε/κ)², and going to τ := 0 with zero slope as
//!   κ → 0 (so the twist stiffness stays bounded near inflections and
//!   free ends, where the Frenet frame flips);
//! - the linear term B κ (present only for curved rest shapes) uses a
//!   C¹ Huber extension of |C| below δ, so its gradient stays bounded;
//! - κ² = c2/a³ is a polynomial ratio and needs no extension, so a straight
//!   rod keeps the exact anisotropic quadratic bending energy;
//! - on a curved rest shape that extension starts below ½ the rest |C⁰|
//!   (δ_b = min(δ, ½|C⁰|)), so any rest curvature, however small, is kept
//!   exactly: the rest shape has zero energy and zero force. The Huber
//!   Hessian B/δ_b stays bounded because B ∝ κ⁰.
use super::invariants::{curvature_squared, Curvature2, LocalState, Mat5, Vec5, QA, QC2, QP, QTH, QTH1};
use super::{ActiveSlots, EnergyTerms, FrameKinematics, FrameState, HoldCrossSection, MaterialAngle, MaterialFrame, SampleConsts, Strains};
use crate::error::{Error, Result};
use nalgebra::Vector3;
use std::f64::consts::PI;

/// The Frenet + roll model (SPEC §2.2): no per-sample state.
pub struct Frenet;

impl FrameKinematics for Frenet {
    /// Frenet bending F(a, c2, θ) uses r″ and θ (c2 = |r′×r″|²); Frenet
    /// twist F(a, c2, p, θ′) adds r‴ (p = (r′×r″)·r‴) and θ′.
    fn active_slots(terms: EnergyTerms) -> ActiveSlots {
        ActiveSlots {
            positions: if terms.twist {
                3
            } else if terms.bend {
                2
            } else {
                0
            },
            theta: terms.bend,
            theta1: terms.twist,
        }
    }
    #[inline(always)]
    fn add_bend_twist(q: &Vec5, c: &SampleConsts, _state: &FrameState, terms: EnergyTerms, fq: &mut Vec5, fqq: &mut Mat5) -> f64 {
        let mut w = 0.0;
        if terms.bend {
            w += add_bend(q, c, fq, fqq);
        }
        if terms.twist {
            w += add_twist(q, c, fq, fqq);
        }
        w
    }
    fn strains(_s: &LocalState, q: &Vec5, c: &SampleConsts, _state: &FrameState) -> Strains {
        strains(q, c)
    }
    fn rest_values(s0: &LocalState, _state: &FrameState, delta: f64) -> (f64, f64, f64) {
        rest_values(&s0.invariants(), delta)
    }
    fn initial_states(_samples: &[(LocalState, f64)], _closed: bool) -> Result<Vec<FrameState>> {
        Ok(Vec::new())
    }
    fn transport(_state: &mut FrameState, _s: &LocalState) {}
    /// d1 is at angle θ + φ_n about t, φ_n the angle of the Frenet normal
    /// n = b × t from e1 (the reference projected ⟂ t), i.e. φ_b − π/2 with
    /// φ_b = atan2(C·e2, C·e1), C = r' × r''; wrapped to (−π, π]. The
    /// derivative includes the turning of (e1, e2) with the tangent:
    /// ∂ψ/∂r' gains (t·r)/(|P r| |r'|) e2 (P = I − t tᵀ).
    fn material_angle(s: &LocalState, _at_sample: &LocalState, _state: &FrameState, reference: &Vector3<f64>, delta: f64) -> Result<MaterialAngle> {
        let speed = s.r1.norm();
        let t = s.r1 / speed;
        let e1p = reference - t * reference.dot(&t);
        let pr = e1p.norm();
        if pr < 1e-6 {
            return Err(Error::invalid("material roll reference", format!("{:?}", reference.as_slice()), "a direction not parallel to the tangent"));
        }
        let e1 = e1p / pr;
        let e2 = t.cross(&e1);
        let c = s.cross();
        let (c1, c2) = (c.dot(&e1), c.dot(&e2));
        let cc = c1 * c1 + c2 * c2;
        if !(cc.sqrt() > 1e-9 * delta) || cc == 0.0 {
            return Err(Error::singular(
                "material roll: the rod is straight there, so the Frenet frame (and the absolute roll) is undefined",
            ));
        }
        let g_c = (e2 * c1 - e1 * c2) / cc;
        let d_r1 = s.r2.cross(&g_c) + e2 * (t.dot(reference) / (pr * speed));
        let d_r2 = g_c.cross(&s.r1);
        Ok(MaterialAngle { angle: s.th + c2.atan2(c1) - 0.5 * PI, d_r1, d_r2, d_th: 1.0, ..Default::default() })
    }
    /// Where the rod is curved above the regularisation threshold the roll
    /// coordinate is measured from a Frenet normal that turns with the rod,
    /// so only the material angle holds the section; on a (nearly)
    /// straight stretch the regularised frame makes θ the section's angle.
    fn hold_cross_section(s: &LocalState, delta: f64) -> HoldCrossSection {
        if s.cross().norm() >= delta {
            HoldCrossSection::MaterialAngle
        } else {
            HoldCrossSection::RollCoordinate
        }
    }
    /// The Frenet frame (t, n, b) rotated by θ about t: d1 = cos θ n +
    /// sin θ b, d2 = t × d1, so that κ1 = κ b·d1 = κ sin θ and κ2 = κ b·d2 =
    /// κ cos θ as in the energy (II.57). Undefined where C = r'×r'' = 0 (the
    /// same test as [`Self::material_angle`]).
    fn material_frame(s: &LocalState, _state: &FrameState, delta: f64) -> Result<MaterialFrame> {
        let t = s.r1.normalize();
        let c = s.cross();
        let cn = c.norm();
        if !(cn > 1e-9 * delta) || cn == 0.0 || !t.iter().all(|x| x.is_finite()) {
            return Err(Error::singular(
                "material frame: the rod is straight there, so the Frenet frame (and the material frame of the Frenet model) is undefined",
            ));
        }
        let b = c / cn;
        let n = b.cross(&t);
        let (sn, cs) = s.th.sin_cos();
        let d1 = n * cs + b * sn;
        Ok(MaterialFrame { d1, d2: t.cross(&d1), d3: t })
    }
}

/// Huber extension of √c2 below δ²: value, first and second derivative in c2.
#[inline(always)]
fn huber_sqrt(c2: f64, delta: f64) -> (f64, f64, f64) {
    if c2 >= delta * delta {
        let s = c2.sqrt();
        (s, 0.5 / s, -0.25 / (s * c2))
    } else {
        (c2 / (2.0 * delta) + 0.5 * delta, 0.5 / delta, 0.0)
    }
}

#[inline(always)]
fn add_bend(q: &Vec5, c: &SampleConsts, fq: &mut Vec5, fqq: &mut Mat5) -> f64 {
    let (a, c2, th) = (q[QA], q[QC2], q[QTH]);
    let curved = c.kappa1 != 0.0 || c.kappa2 != 0.0;
    // An isotropic section on a straight rest shape does not depend on θ
    // (A = ½ EI, B = 0): the sine and cosine, a fifth of a sample's energy
    // evaluation, are skipped.
    let (sn, cs) = if curved || c.ei1 != c.ei2 { th.sin_cos() } else { (0.0, 1.0) };
    let d_ei = c.ei1 - c.ei2;
    let aa = 0.5 * (c.ei1 * sn * sn + c.ei2 * cs * cs);
    let aa1 = d_ei * sn * cs;
    let aa2 = d_ei * (cs * cs - sn * sn);
    let Curvature2 { v: qv, a: q_a, c: q_c, aa: q_aa, ac: q_ac } = curvature_squared(q);
    let ia = 1.0 / a;
    let mut w = aa * qv;
    fq[QA] += aa * q_a;
    fq[QC2] += aa * q_c;
    fq[QTH] += aa1 * qv;
    fqq[(QA, QA)] += aa * q_aa;
    sym_add(fqq, QA, QC2, aa * q_ac);
    sym_add(fqq, QA, QTH, aa1 * q_a);
    sym_add(fqq, QC2, QTH, aa1 * q_c);
    fqq[(QTH, QTH)] += aa2 * qv;
    if curved {
        let b = c.ei1 * c.kappa1 * sn + c.ei2 * c.kappa2 * cs;
        let b1 = c.ei1 * c.kappa1 * cs - c.ei2 * c.kappa2 * sn;
        let b2 = -b;
        // K = h(c2) a^(-3/2) ≈ κ
        let (h, h1, h2) = huber_sqrt(c2, c.delta_bend);
        let ia15 = ia * ia.sqrt();
        let kv = h * ia15;
        let (k_a, k_c) = (-1.5 * kv * ia, h1 * ia15);
        let (k_aa, k_ac, k_cc) = (3.75 * kv * ia * ia, -1.5 * h1 * ia15 * ia, h2 * ia15);
        w += -b * kv + 0.5 * (c.ei1 * c.kappa1 * c.kappa1 + c.ei2 * c.kappa2 * c.kappa2);
        fq[QA] -= b * k_a;
        fq[QC2] -= b * k_c;
        fq[QTH] -= b1 * kv;
        fqq[(QA, QA)] -= b * k_aa;
        sym_add(fqq, QA, QC2, -b * k_ac);
        fqq[(QC2, QC2)] -= b * k_cc;
        sym_add(fqq, QA, QTH, -b1 * k_a);
        sym_add(fqq, QC2, QTH, -b1 * k_c);
        fqq[(QTH, QTH)] -= b2 * kv;
    }
    w
}

/// Material twist ω with its gradient and Hessian in the invariants:
/// ω = p c2 / (c2 + δ²)² + θ' a^(−1/2) (the regularised Frenet torsion of
/// the module doc, whose slope vanishes at κ = 0).
#[inline(always)]
fn omega(q: &Vec5, delta: f64) -> (f64, Vec5, Mat5) {
    let (a, c2, p, th1) = (q[QA], q[QC2], q[QP], q[QTH1]);
    let d2 = delta * delta;
    let id = 1.0 / (c2 + d2);
    let id2 = id * id;
    let isa = 1.0 / a.sqrt();
    let ia = isa * isa;
    let w = p * c2 * id2 + th1 * isa;
    let mut g = Vec5::zeros();
    g[QP] = c2 * id2;
    g[QC2] = p * (d2 - c2) * id2 * id;
    g[QA] = -0.5 * th1 * isa * ia;
    g[QTH1] = isa;
    let mut h = Mat5::zeros();
    sym_add(&mut h, QP, QC2, (d2 - c2) * id2 * id);
    h[(QC2, QC2)] = p * (2.0 * c2 - 4.0 * d2) * id2 * id2;
    h[(QA, QA)] = 0.75 * th1 * isa * ia * ia;
    sym_add(&mut h, QA, QTH1, -0.5 * isa * ia);
    (w, g, h)
}

#[inline(always)]
fn add_twist(q: &Vec5, c: &SampleConsts, fq: &mut Vec5, fqq: &mut Mat5) -> f64 {
    let (om, g, h) = omega(q, c.delta);
    let e = om - c.omega;
    // ∂ω/∂θ is zero: only the other four rows and columns are touched
    // (GJ (g gᵀ + e ∇²ω), entry by entry; this runs at every sample).
    const IDX: [usize; 4] = [QA, QC2, QP, QTH1];
    for &i in &IDX {
        fq[i] += c.gj * e * g[i];
        for &j in &IDX {
            fqq[(i, j)] += c.gj * (g[i] * g[j] + e * h[(i, j)]);
        }
    }
    0.5 * c.gj * e * e
}

fn sym_add(m: &mut Mat5, i: usize, j: usize, v: f64) {
    m[(i, j)] += v;
    m[(j, i)] += v;
}

/// Curvature κ = |C|/|r'|³ (exact, no extension).
fn kappa(q: &Vec5) -> f64 {
    q[QC2].sqrt() / (q[QA] * q[QA].sqrt())
}

/// (κ1, κ2, ω); ε is left to the stretch model.
fn strains(q: &Vec5, c: &SampleConsts) -> Strains {
    let k = kappa(q);
    let (sn, cs) = q[QTH].sin_cos();
    Strains {
        eps: 0.0,
        kappa1: k * sn,
        kappa2: k * cs,
        omega: omega(q, c.delta).0,
    }
}

/// (κ1⁰, κ2⁰, ω⁰) from the rest invariants (rest curvatures below the
/// threshold δ are rounded to zero, see the module doc).
fn rest_values(q: &Vec5, delta: f64) -> (f64, f64, f64) {
    let om = omega(q, delta).0;
    if q[QC2].sqrt() <= 1e-8 * delta {
        return (0.0, 0.0, om); // round-off of a straight rest shape (see δ_b in rod::samples)
    }
    let k = kappa(q);
    let (sn, cs) = q[QTH].sin_cos();
    (k * sn, k * cs, om)
}
