//! Bending and twist in the reference-frame model (SPEC §2.3): each sample
//! keeps a reference director d1° ⟂ t°, the tangent t° it belongs to, the
//! old tangent's derivative t°_u in the spline parameter u (as
//! k = (t°_u·d1°, t°_u·d2°)) and the reference field's twist per unit u,
//! ω°_u. Rates per u, not per arc length: transport is a rotation at fixed
//! u, so per-u rates add exactly when the rod stretches (per arc length
//! they would mix the old and the new |r′|, and ∮ ω ds would drift from
//! Lk − Wr by the strain). In a step the director is the smallest rotation
//! of d1° onto the current tangent t (time-parallel transport, as Discrete
//! Elastic Rods and Meier–Popp–Wall 2014 carry it), so everything is
//! defined where the curvature vanishes:
//!
//!   κb = t × t_s = r′×r″/|r′|³     (curvature binormal)
//!   d1 = d1° − (d1°·t)/(1 + t°·t) (t° + t),  d2 = t × d1
//!   κ1 = κb·m1, κ2 = κb·m2,  m1 = cos θ d1 + sin θ d2,  m2 = t × m1
//!   ω  = (θ′ + ω_u)/|r′|,  ω_u = ω°_u + (t × t°)·(t°_u + t_u)/(1 + t°·t)
//!
//! The last line is the twist per u of the transported field (the smallest
//! rotation's angular rate along u, projected on t); its first variation at
//! t = t° is (t° × t°_s)·δt per arc length, the local formula of SPEC §2.3,
//! so the energy of a sample depends on that sample's (r′, r″, θ, θ′) only
//! and the band is unchanged. In the old frame's basis (d1°, d2°, t°), with
//! p = r′ and q = r″ in that basis, C = p × q and s = |p|:
//!
//!   κb·d1 = (C1 − p1 C3/(s + p3)) / s³,   κb·d2 = (C2 − p2 C3/(s + p3)) / s³
//!   ω_u − ω°_u = (p2 k1 − p1 k2 − C3/s) / (s + p3)
//!
//! rational in six variables and linear in q. The bending strains' exact
//! gradient and Hessian come from [`super::qlinear`] (second-order jets in
//! p only, checked against six-variable jets); the twist's are written in
//! world components ([`add_twist`]), with no rotation back.
//! W_b = ½ EI1 (κ1 − κ1⁰)² + ½ EI2 (κ2 − κ2⁰)², W_t = ½ GJ (ω − ω⁰)² per
//! unit rest length, as in the Frenet model (the same EI1 ↔ d1 convention:
//! κ1 = κ b·d1). For an isotropic section on a straight rest shape W_b =
//! ½ EI |κb|² does not depend on the frame and is written in the
//! invariants, like the Frenet model's ([`bend_is_invariant`]).
use super::invariants::{curvature_squared, LocalState, Mat5, Vec5, QA, QC2, R1, R2, TH, TH1};
use super::qlinear;

/// Number of local variables (p, q).
const N: usize = 6;
use super::{ActiveSlots, EnergyTerms, FrameKinematics, FrameState, HoldCrossSection, LocalEnergy, MaterialAngle, MaterialFrame, SampleConsts, Strains};
use crate::error::{Error, Result};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// The reference-frame model (SPEC §2.3).
pub struct Reference;

/// cos 150°, negated: neighbouring samples' tangents must stay within 150°.
const KINK_COS: f64 = 0.866;

/// What a sample carries in time in the reference-frame model.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RefFrame {
    /// Reference director d1° (unit, ⟂ `t`).
    pub d1: [f64; 3],
    /// The unit tangent d1° belongs to.
    pub t: [f64; 3],
    /// That tangent's derivative in the parameter u, in (d1°, d2°)
    /// components (1/u).
    pub k: [f64; 2],
    /// Twist of the reference field at the sample per unit u (rad/u; per
    /// unit length it is this over |r′|).
    pub omega: f64,
}

impl RefFrame {
    /// Finite, with unit and orthogonal d1° and t° (a snapshot's check).
    pub fn is_valid(&self) -> bool {
        let (d1, t) = (Vector3::from(self.d1), Vector3::from(self.t));
        self.d1.iter().chain(&self.t).chain(&self.k).chain([&self.omega]).all(|x| x.is_finite())
            && (d1.norm() - 1.0).abs() < 1e-9
            && (t.norm() - 1.0).abs() < 1e-9
            && d1.dot(&t).abs() < 1e-9
    }
    fn basis(&self) -> [Vector3<f64>; 3] {
        let (d1, t) = (Vector3::from(self.d1), Vector3::from(self.t));
        [d1, t.cross(&d1), t]
    }
}

/// κb·d1, κb·d2 from p = r′, q = r″ in the old frame's basis (module
/// doc). Values only: the derivatives come from [`qlinear::kinematics`].
#[inline(always)]
fn bend_values(p: [f64; 3], q: [f64; 3]) -> (f64, f64) {
    let a = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    let s = a.sqrt();
    let c1 = p[1] * q[2] - p[2] * q[1];
    let c2 = p[2] * q[0] - p[0] * q[2];
    let c3 = p[0] * q[1] - p[1] * q[0];
    // 1 + t°·t = (s + p3)/s: zero only if the tangent turned half a turn
    // since the last transport (refused beyond 150°: `transportable`).
    let t1 = c3 / (s + p[2]);
    let is3 = (a * s).recip();
    ((c1 - p[0] * t1) * is3, (c2 - p[1] * t1) * is3)
}

/// The reference field's twist increment w = ω_u − ω°_u (module doc) in
/// world components, with the parts its derivatives reuse ([`add_twist`]):
/// with r = r′, v = r″, s = |r|, the old tangent T = t° and m = t° × t°_u =
/// k0 d2° − k1 d1°,
///
///   w = N/D,  N = r·m − c3/s,  c3 = T·(r × v) = r·(v × T),  D = s + T·r.
///
/// D = s (1 + t°·t) vanishes only if the tangent turned half a turn since
/// the last transport (refused beyond 150°: `transportable`).
struct Twist {
    /// 1/s, t = r/s, n = v × T, o = T × r, m, T.
    is: f64,
    t: Vector3<f64>,
    n: Vector3<f64>,
    o: Vector3<f64>,
    m: Vector3<f64>,
    tt: Vector3<f64>,
    c3: f64,
    /// 1/D and w.
    id: f64,
    w: f64,
}

#[inline(always)]
fn twist_increment(r: &Vector3<f64>, v: &Vector3<f64>, f: &RefFrame) -> Twist {
    let (d1o, tt) = (Vector3::from(f.d1), Vector3::from(f.t));
    let m = tt.cross(&d1o) * f.k[0] - d1o * f.k[1];
    let sp = r.norm();
    let is = sp.recip();
    let n = v.cross(&tt);
    let c3 = r.dot(&n);
    let id = (sp + tt.dot(r)).recip();
    let w = (r.dot(&m) - c3 * is) * id;
    Twist { is, t: r * is, n, o: tt.cross(r), m, tt, c3, id, w }
}

/// Ω = (θ′ + ω°_u + w)/|r′|, the material twist per length.
#[inline(always)]
fn twist_value(s: &LocalState, f: &RefFrame) -> f64 {
    let tw = twist_increment(&s.r1, &s.r2, f);
    (s.th1 + f.omega + tw.w) * tw.is
}

/// Whether bending is ½ EI |κb|² — an isotropic section (EI1 = EI2) on a
/// straight rest shape (κ⁰ = 0): κ1² + κ2² = |κb|² in any frame ⟂ t, so
/// it is written in the invariants like the Frenet model's (exactly the
/// same energy; the frame's derivatives are then needed for twist only).
#[inline(always)]
fn bend_is_invariant(c: &SampleConsts) -> bool {
    c.ei1 == c.ei2 && c.kappa1 == 0.0 && c.kappa2 == 0.0
}

/// p, q of a local state in the old frame's basis.
fn local(s: &LocalState, f: &RefFrame) -> ([f64; 3], [f64; 3], [Vector3<f64>; 3]) {
    let e = f.basis();
    (
        [e[0].dot(&s.r1), e[1].dot(&s.r1), e[2].dot(&s.r1)],
        [e[0].dot(&s.r2), e[1].dot(&s.r2), e[2].dot(&s.r2)],
        e,
    )
}

fn frame_of(state: &FrameState) -> &RefFrame {
    match state {
        FrameState::Reference(f) => f,
        // A rod's frame states are built by its own model (Rod::new,
        // Cache::build); a missing state is a programming error.
        FrameState::None => panic!("reference-frame model evaluated without its per-sample state"),
    }
}

/// Values (κ1, κ2, ω) at a local state.
fn strain_values(s: &LocalState, f: &RefFrame) -> (f64, f64, f64) {
    let (p, q, _) = local(s, f);
    let (x, y) = bend_values(p, q);
    let (sn, cs) = s.th.sin_cos();
    (cs * x + sn * y, cs * y - sn * x, twist_value(s, f))
}

/// The transported director d1 at tangent t.
fn transported_d1(f: &RefFrame, t: &Vector3<f64>) -> Vector3<f64> {
    let (d1o, to) = (Vector3::from(f.d1), Vector3::from(f.t));
    let d1 = d1o - (to + t) * (d1o.dot(t) / (1.0 + to.dot(t)));
    // Re-orthonormalised: round-off would otherwise accumulate step by step.
    (d1 - t * d1.dot(t)).normalize()
}

/// Unit tangent and its u-derivative t_u = (r″ − (t·r″) t)/|r′|.
fn tangent_and_rate(s: &LocalState) -> (Vector3<f64>, Vector3<f64>) {
    let speed = s.r1.norm();
    let t = s.r1 / speed;
    (t, (s.r2 - t * t.dot(&s.r2)) / speed)
}

/// The state of a sample with unit tangent t, its rate t_u, director `d1`
/// (⟂ t) and reference twist `omega` per unit u.
fn frame_at(t: Vector3<f64>, ts: Vector3<f64>, d1: Vector3<f64>, omega: f64) -> RefFrame {
    let d2 = t.cross(&d1);
    RefFrame { d1: d1.into(), t: t.into(), k: [ts.dot(&d1), ts.dot(&d2)], omega }
}

/// Rotation of v about the unit axis n by angle φ (v ⟂ n).
fn rotate_perp(v: &Vector3<f64>, n: &Vector3<f64>, phi: f64) -> Vector3<f64> {
    let (sn, cs) = phi.sin_cos();
    v * cs + n.cross(v) * sn
}

impl FrameKinematics for Reference {
    /// Rest states along a rod: the first director ⟂ t, each next one the
    /// previous carried to its tangent by the smallest rotation (a discrete
    /// Bishop frame, twist ω° = 0). On a closed rod the loop's holonomy
    /// (the angle the carried director misses the first one by) is spread
    /// as a uniform reference twist, so that the field closes up.
    /// A tangent that is undefined or turns by more than 150° between
    /// neighbouring samples (a kink: coincident control points) is refused —
    /// the smallest rotation is ill-conditioned there.
    fn initial_states(samples: &[(LocalState, f64)], closed: bool) -> Result<Vec<FrameState>> {
        let mut d1s: Vec<Vector3<f64>> = Vec::with_capacity(samples.len());
        for (i, (s, _)) in samples.iter().enumerate() {
            let t = s.r1.normalize();
            let kinked = i > 0 && !(samples[i - 1].0.r1.normalize().dot(&t) > -KINK_COS);
            if !t.iter().all(|x| x.is_finite()) || kinked {
                return Err(Error::input(format!(
                    "reference-frame model: the rod's tangent {} at sample {i} (a kink: coincident control points?); the reference directors cannot be carried across it",
                    if kinked { "turns by more than 150° between neighbouring samples" } else { "is undefined" }
                )));
            }
            let d1 = if i == 0 {
                crate::frames::perpendicular(&t)
            } else {
                let prev = &samples[i - 1].0;
                let f = RefFrame { d1: d1s[i - 1].into(), t: prev.r1.normalize().into(), k: [0.0; 2], omega: 0.0 };
                transported_d1(&f, &t)
            };
            d1s.push(d1);
        }
        let mut omega = 0.0;
        if closed && samples.len() > 1 {
            // Carry the last director once more, to the first tangent, and
            // measure the angle from the first director to it about t.
            let (s0, sl) = (&samples[0].0, &samples[samples.len() - 1].0);
            let t0 = s0.r1.normalize();
            let f = RefFrame { d1: d1s[samples.len() - 1].into(), t: sl.r1.normalize().into(), k: [0.0; 2], omega: 0.0 };
            let back = transported_d1(&f, &t0);
            let miss = t0.cross(&d1s[0]).dot(&back).atan2(d1s[0].dot(&back));
            // The field rotated by −miss·(s/L) about t closes; its twist is
            // −miss/L per length (the rest weights sum to the rest length L).
            let length: f64 = samples.iter().map(|(_, w)| w).sum();
            omega = -miss / length;
            let mut arc = 0.0;
            for (d1, (s, w)) in d1s.iter_mut().zip(samples) {
                arc += 0.5 * w;
                *d1 = rotate_perp(d1, &s.r1.normalize(), omega * arc);
                arc += 0.5 * w;
            }
        }
        Ok(samples.iter().zip(d1s).map(|((s, _), d1)| {
            let (t, ts) = tangent_and_rate(s);
            FrameState::Reference(frame_at(t, ts, d1, omega * s.r1.norm()))
        }).collect())
    }

    /// Energy density of bending and twist with its derivatives in d,
    /// added to `out` (which holds the invariant part: stretch, and the
    /// bending where [`bend_is_invariant`]). Returns W.
    fn add_direct(s: &LocalState, c: &SampleConsts, state: &FrameState, terms: EnergyTerms, derivs: bool, out: &mut LocalEnergy) -> f64 {
        let (bend, twist) = (terms.bend && !bend_is_invariant(c), terms.twist);
        if !bend && !twist {
            return 0.0;
        }
        let f = frame_of(state);
        let mut w = 0.0;
        if bend {
            let (p, q, e) = local(s, f);
            w += if derivs {
                add_frame_bend(s, c, p, q, &e, out)
            } else {
                let (x, y) = bend_values(p, q);
                let (sn, cs) = s.th.sin_cos();
                let (e1, e2) = (cs * x + sn * y - c.kappa1, cs * y - sn * x - c.kappa2);
                0.5 * (c.ei1 * e1 * e1 + c.ei2 * e2 * e2)
            };
        }
        if twist && !derivs {
            return w + 0.5 * c.gj * (twist_value(s, f) - c.omega).powi(2);
        }
        if twist {
            w += add_twist(s, c, f, out);
        }
        w
    }

    /// Bending and twist use r′, r″ (never r‴), θ and θ′.
    fn active_slots(terms: EnergyTerms) -> ActiveSlots {
        let any = terms.bend || terms.twist;
        ActiveSlots { positions: if any { 2 } else { 0 }, theta: terms.bend, theta1: terms.twist }
    }
    /// The bending of an isotropic section on a straight rest shape, which
    /// does not depend on the frame (see [`bend_is_invariant`]); the rest
    /// is [`Reference::add_direct`].
    fn add_bend_twist(q: &Vec5, c: &SampleConsts, _state: &FrameState, terms: EnergyTerms, fq: &mut Vec5, fqq: &mut Mat5) -> f64 {
        if !(terms.bend && bend_is_invariant(c)) {
            return 0.0;
        }
        // ½ EI (κ1² + κ2²) = ½ EI |κb|² = ½ EI c2 a⁻³.
        let k = curvature_squared(q);
        let half = 0.5 * c.ei1;
        fq[QA] += half * k.a;
        fq[QC2] += half * k.c;
        fqq[(QA, QA)] += half * k.aa;
        fqq[(QA, QC2)] += half * k.ac;
        fqq[(QC2, QA)] += half * k.ac;
        half * k.v
    }
    fn strains(s: &LocalState, _q: &Vec5, _c: &SampleConsts, state: &FrameState) -> Strains {
        let (kappa1, kappa2, omega) = strain_values(s, frame_of(state));
        Strains { eps: 0.0, kappa1, kappa2, omega }
    }
    /// A rest |r′ × r″| below 1e-8 δ is a straight rest shape's round-off
    /// (as in the Frenet model): its curvature is rounded to zero.
    fn rest_values(s0: &LocalState, state: &FrameState, delta: f64) -> (f64, f64, f64) {
        let (k1, k2, om) = strain_values(s0, frame_of(state));
        if s0.cross().norm() <= 1e-8 * delta {
            return (0.0, 0.0, om);
        }
        (k1, k2, om)
    }
    /// The transported director, its tangent's rate and the reference
    /// twist of the transported field (the same formula as the energy, so
    /// the energy is continuous across a transport).
    fn transport(state: &mut FrameState, s: &LocalState) {
        let FrameState::Reference(f) = state else { return };
        let (t, ts) = tangent_and_rate(s);
        if !t.iter().all(|x| x.is_finite()) {
            return; // a degenerate tangent: keep the last good state
        }
        let dw = twist_increment(&s.r1, &s.r2, f).w;
        let d1 = transported_d1(f, &t);
        *f = frame_at(t, ts, d1, f.omega + dw);
    }
    /// The angle ψ of the material director m1 about t from `reference`
    /// (projected ⟂ t): ψ = θ + α, α the angle of the director carried from
    /// the sample's state to the sample's current tangent t_s (in time) and
    /// on to t at u (along the rod), both by smallest rotations. Going via
    /// t_s makes ψ independent of when the sample was last transported.
    /// With δt = (I − t tᵀ) δr′/|r′|: the outer rotation turns the director
    /// about t by (t × t_s)·δt/(1 + t_s·t), the projected reference by
    /// −(t·ref)/|ref⊥| e2·δt; a change of t_s turns it by the change of the
    /// spherical triangle (t°, t_s, t)'s area A, tan(A/2) = t°·(t_s × t) /
    /// (1 + t°·t_s + t_s·t + t·t°). ψ does not depend on r″. Defined
    /// wherever the reference is not along the tangent, straight or bent.
    /// The smallest rotation from t° to t is ill-conditioned as t → −t°:
    /// refused beyond 150° (a step that far is not resolved anyway).
    fn transportable(state: &FrameState, s: &LocalState) -> bool {
        let FrameState::Reference(f) = state else { return true };
        let t = s.r1.normalize();
        t.iter().all(|x| x.is_finite()) && Vector3::from(f.t).dot(&t) > -KINK_COS
    }
    fn material_angle(s: &LocalState, at_sample: &LocalState, state: &FrameState, reference: &Vector3<f64>, _delta: f64) -> Result<MaterialAngle> {
        let f = frame_of(state);
        let (speed, speed_s) = (s.r1.norm(), at_sample.r1.norm());
        let (t, ts) = (s.r1 / speed, at_sample.r1 / speed_s);
        let e1p = reference - t * reference.dot(&t);
        let pr = e1p.norm();
        if !(pr >= 1e-6 * reference.norm()) || !t.iter().chain(ts.iter()).all(|x| x.is_finite()) {
            return Err(Error::invalid("material roll reference", format!("{:?}", reference.as_slice()), "a direction not parallel to the tangent"));
        }
        let (e1, to) = (e1p / pr, Vector3::from(f.t));
        let e2 = t.cross(&e1);
        let at_ts = RefFrame { d1: transported_d1(f, &ts).into(), t: ts.into(), k: [0.0; 2], omega: 0.0 };
        let d1 = transported_d1(&at_ts, &t);
        let alpha = d1.dot(&e2).atan2(d1.dot(&e1));
        let d_r1 = (t.cross(&ts) / (1.0 + ts.dot(&t)) + e2 * (t.dot(reference) / pr)) / speed;
        let (n, d) = (to.dot(&ts.cross(&t)), 1.0 + to.dot(&ts) + ts.dot(&t) + t.dot(&to));
        let da = (t.cross(&to) * d - (to + t) * n) * (2.0 / (n * n + d * d));
        let d_r1_sample = (da - ts * ts.dot(&da)) / speed_s;
        Ok(MaterialAngle { angle: s.th + alpha, d_r1, d_r2: Vector3::zeros(), d_th: 1.0, d_r1_sample, sample_b1: [0.0; 4] })
    }
    /// θ is the section's angle from the transported director, which does
    /// not turn while the tangent is held: fixing θ holds the section.
    fn hold_cross_section(_s: &LocalState, _delta: f64) -> HoldCrossSection {
        HoldCrossSection::RollCoordinate
    }
    fn material_frame(s: &LocalState, state: &FrameState, _delta: f64) -> Result<MaterialFrame> {
        let f = frame_of(state);
        let (t, _) = tangent_and_rate(s);
        if !t.iter().all(|x| x.is_finite()) {
            return Err(Error::singular("material frame: the tangent is undefined there (zero speed)"));
        }
        let d1 = transported_d1(f, &t);
        let (sn, cs) = s.th.sin_cos();
        let m1 = d1 * cs + t.cross(&d1) * sn;
        Ok(MaterialFrame { d1: m1, d2: t.cross(&m1), d3: t })
    }
}

/// The bending of an anisotropic section or a curved rest shape (where
/// [`bend_is_invariant`] does not hold) with its gradient and Hessian,
/// added to `out`. With κ1 = cos θ x + sin θ y, κ2 = cos θ y − sin θ x
/// (∂κ1/∂θ = κ2, ∂κ2/∂θ = −κ1), W_b's Hessian in (r′, r″) is
/// EI1 ∇κ1∇κ1ᵀ + EI2 ∇κ2∇κ2ᵀ + α ∇²x + β ∇²y with α = EI1 e1 cos θ −
/// EI2 e2 sin θ, β = EI1 e1 sin θ + EI2 e2 cos θ (e_i = κ_i − κ_i⁰): the
/// gradients are rotated to world components and their outer products
/// formed there; of the second derivatives (jets in p from [`qlinear`])
/// only the one combination α ∇²x + β ∇²y is formed and rotated.
fn add_frame_bend(s: &LocalState, c: &SampleConsts, p: [f64; 3], q: [f64; 3], e: &[Vector3<f64>; 3], out: &mut LocalEnergy) -> f64 {
    let kin = qlinear::kinematics(p);
    let (sn, cs) = s.th.sin_cos();
    let ((xv, xg), (yv, yg)) = (kin.x.value_grad(&q), kin.y.value_grad(&q));
    let (k1, k2) = (cs * xv + sn * yv, cs * yv - sn * xv);
    let (e1, e2) = (k1 - c.kappa1, k2 - c.kappa2);
    let (a1, a2) = (c.ei1, c.ei2);
    // ∇κ1, ∇κ2 in world components: r′ = Σ_b p_b e_b, so ∂/∂r′ = Σ_b e_b ∂/∂p_b.
    // Loops written out rather than `array::from_fn` (per sample; whether
    // its closures were inlined moved with unrelated code).
    let rot = |v: &[f64]| -> [f64; 3] {
        let mut out = [0.0; 3];
        for (a, o) in out.iter_mut().enumerate() {
            *o = e[0][a] * v[0] + e[1][a] * v[1] + e[2][a] * v[2];
        }
        out
    };
    let world = |g: [f64; N]| -> [f64; N] {
        let (lo, hi) = (rot(&g[..3]), rot(&g[3..]));
        [lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]]
    };
    let (mut g1, mut g2) = ([0.0; N], [0.0; N]);
    for i in 0..N {
        g1[i] = cs * xg[i] + sn * yg[i];
        g2[i] = cs * yg[i] - sn * xg[i];
    }
    let (g1, g2) = (world(g1), world(g2));
    let grad = out.grad.as_mut_slice();
    for i in 0..N {
        grad[R1 + i] += a1 * e1 * g1[i] + a2 * e2 * g2[i];
    }
    grad[TH] += a1 * e1 * k2 - a2 * e2 * k1;
    let h = out.hess.as_mut_slice();
    let at = |i: usize, j: usize| 11 * j + i; // column-major
    for i in 0..N {
        for j in 0..N {
            h[at(R1 + i, R1 + j)] += a1 * g1[i] * g1[j] + a2 * g2[i] * g2[j];
        }
        let x = a1 * (k2 * g1[i] + e1 * g2[i]) - a2 * (k1 * g2[i] + e2 * g1[i]);
        h[at(R1 + i, TH)] += x;
        h[at(TH, R1 + i)] += x;
    }
    h[at(TH, TH)] += a1 * (k2 * k2 - e1 * k1) + a2 * (k1 * k1 - e2 * k2);
    // α ∇²x + β ∇²y: its pp (symmetric) and pq blocks, each X to Eᵀ X E.
    let (alpha, beta) = (a1 * e1 * cs - a2 * e2 * sn, a1 * e1 * sn + a2 * e2 * cs);
    let (hpp, hpq) = qlinear::QLinear::combined_hessian(&kin.x, alpha, &kin.y, beta, &q);
    let to_world = |x: &[[f64; 3]; 3]| -> [[f64; 3]; 3] {
        let (mut t, mut w) = ([[0.0; 3]; 3], [[0.0; 3]; 3]);
        for r in 0..3 {
            for c in 0..3 {
                t[r][c] = x[r][0] * e[0][c] + x[r][1] * e[1][c] + x[r][2] * e[2][c];
            }
        }
        for a in 0..3 {
            for c in 0..3 {
                w[a][c] = e[0][a] * t[0][c] + e[1][a] * t[1][c] + e[2][a] * t[2][c];
            }
        }
        w
    };
    let mut pp = [[0.0; 3]; 3];
    for (r, row) in pp.iter_mut().enumerate() {
        for (c, x) in row.iter_mut().enumerate() {
            *x = hpp[qlinear::hp(r, c)];
        }
    }
    let wpp = to_world(&pp);
    let wpq = to_world(&hpq);
    for a in 0..3 {
        for b in 0..3 {
            h[at(R1 + a, R1 + b)] += wpp[a][b];
            h[at(R1 + a, R2 + b)] += wpq[a][b];
            h[at(R2 + b, R1 + a)] += wpq[a][b];
        }
    }
    0.5 * (a1 * e1 * e1 + a2 * e2 * e2)
}

/// Twist W_t = ½ GJ (Ω − ω⁰)², Ω = (θ′ + ω°_u + w)/|r′|, with its
/// gradient and Hessian in (r′, r″, θ′), added to `out`. Written in world
/// components (no rotation back), with w = N/D of [`twist_increment`], so
/// each factor's derivatives are a few outer products: ∇_r c3 = v × T,
/// ∇_v c3 = T × r, ∂²c3/∂r∂v = −[T]×; ∇s = t, ∇²s = (I − t tᵀ)/s; and a
/// quotient a = b/c has ∇a = (∇b − a∇c)/c, ∇²a = (∇²b − a∇²c − ∇a∇cᵀ −
/// ∇c∇aᵀ)/c. Checked against AD of the SPEC formulas
/// (`core/tests/reference_frame.rs`).
fn add_twist(s: &LocalState, c: &SampleConsts, f: &RefFrame, out: &mut LocalEnergy) -> f64 {
    let Twist { is, t, n, o, m, tt, c3, id, w } = twist_increment(&s.r1, &s.r2, f);
    let om = (s.th1 + f.omega + w) * is;
    let is2 = is * is;
    // N's derivatives.
    let gn_r = m - n * is + t * (c3 * is2);
    let gn_v = o * (-is);
    // ∇²_rr N = c3 (I − 3 t tᵀ)/s³ + (n tᵀ + t nᵀ)/s²; ∇²_rv N = [T]×/s + t oᵀ/s².
    let c3s3 = c3 * is2 * is;
    let mut hn_rr = [[0.0f64; 3]; 3];
    let mut hn_rv = [[0.0f64; 3]; 3];
    let tx = [[0.0, -tt[2], tt[1]], [tt[2], 0.0, -tt[0]], [-tt[1], tt[0], 0.0]];
    for a in 0..3 {
        for b in 0..3 {
            let i = if a == b { 1.0 } else { 0.0 };
            hn_rr[a][b] = c3s3 * (i - 3.0 * t[a] * t[b]) + is2 * (n[a] * t[b] + t[a] * n[b]);
            hn_rv[a][b] = tx[a][b] * is + t[a] * o[b] * is2;
        }
    }
    // w = N/D: ∇D = t + T, ∇²D = (I − t tᵀ)/s (r only).
    let gd = t + tt;
    let gw_r = (gn_r - gd * w) * id;
    let gw_v = gn_v * id;
    // Ω = U/s, U = θ′ + ω°_u + w.
    let go_r = (gw_r - t * om) * is;
    let go_v = gw_v * is;
    let go_th1 = is;
    let (gj, e3) = (c.gj, om - c.omega);
    let grad = out.grad.as_mut_slice();
    for a in 0..3 {
        grad[R1 + a] += gj * e3 * go_r[a];
        grad[R2 + a] += gj * e3 * go_v[a];
    }
    grad[TH1] += gj * e3 * go_th1;
    // Hessian: GJ (∇Ω∇Ωᵀ + e ∇²Ω), written to both halves.
    let h = out.hess.as_mut_slice();
    let at = |i: usize, j: usize| 11 * j + i; // column-major
    let ge = gj * e3;
    for a in 0..3 {
        for b in 0..3 {
            let i = if a == b { 1.0 } else { 0.0 };
            let p = i - t[a] * t[b];
            // ∇²w, then ∇²Ω (rr).
            let hw_rr = (hn_rr[a][b] - w * p * is - gw_r[a] * gd[b] - gd[a] * gw_r[b]) * id;
            let ho_rr = (hw_rr - om * p * is - go_r[a] * t[b] - t[a] * go_r[b]) * is;
            h[at(R1 + a, R1 + b)] += gj * go_r[a] * go_r[b] + ge * ho_rr;
            // rv: ∇²_rv w = (∇²_rv N − ∇D ∇_v wᵀ)/D, ∇²_rv Ω = (∇²_rv w − t ∇_v Ωᵀ)/s.
            let ho_rv = ((hn_rv[a][b] - gd[a] * gw_v[b]) * id - t[a] * go_v[b]) * is;
            let x = gj * go_r[a] * go_v[b] + ge * ho_rv;
            h[at(R1 + a, R2 + b)] += x;
            h[at(R2 + b, R1 + a)] += x;
            h[at(R2 + a, R2 + b)] += gj * go_v[a] * go_v[b];
        }
        // ∂²Ω/∂r∂θ′ = −t/s² (∂²Ω/∂v∂θ′ = 0).
        let x = gj * go_r[a] * go_th1 - ge * t[a] * is2;
        h[at(R1 + a, TH1)] += x;
        h[at(TH1, R1 + a)] += x;
        let y = gj * go_v[a] * go_th1;
        h[at(R2 + a, TH1)] += y;
        h[at(TH1, R2 + a)] += y;
    }
    h[at(TH1, TH1)] += gj * go_th1 * go_th1;
    0.5 * gj * e3 * e3
}
