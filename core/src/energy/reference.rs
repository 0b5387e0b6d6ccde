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
//! rational in six variables and linear in q; their exact gradient and
//! Hessian come from [`super::qlinear`] (second-order jets in p only,
//! checked against six-variable jets).
//! W_b = ½ EI1 (κ1 − κ1⁰)² + ½ EI2 (κ2 − κ2⁰)², W_t = ½ GJ (ω − ω⁰)² per
//! unit rest length, as in the Frenet model (the same EI1 ↔ d1 convention:
//! κ1 = κ b·d1).
use super::invariants::{LocalState, Mat5, Vec5, R1, TH, TH1};
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

/// κb·d1, κb·d2, ω_ref − ω° and 1/|r′| from p = r′, q = r″ in the old
/// frame's basis (module doc).
/// Values only: the derivatives come from [`qlinear::kinematics`].
struct Kin {
    x: f64,
    y: f64,
    dw: f64,
    inv_speed: f64,
}

#[inline(always)]
fn kinematics(p: [f64; 3], q: [f64; 3], k: [f64; 2], bend: bool, twist: bool) -> Kin {
    let a = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    let s = a.sqrt();
    let inv_speed = s.recip();
    let c3 = p[0] * q[1] - p[1] * q[0];
    // 1 + t°·t = (s + p3)/s: zero only if the tangent turned half a turn
    // since the last transport (refused beyond 150°: `transportable`).
    let id = (s + p[2]).recip();
    let ia = inv_speed * inv_speed;
    let (mut x, mut y, mut dw) = (0.0, 0.0, 0.0);
    if bend {
        let c1 = p[1] * q[2] - p[2] * q[1];
        let c2 = p[2] * q[0] - p[0] * q[2];
        let t1 = c3 * id;
        let is3 = ia * inv_speed;
        x = (c1 - p[0] * t1) * is3;
        y = (c2 - p[1] * t1) * is3;
    }
    if twist {
        dw = (p[1] * k[0] - p[0] * k[1] - c3 * inv_speed) * id;
    }
    Kin { x, y, dw, inv_speed }
}

/// A strain's value, gradient in (p, q) and Hessian blocks (pp packed, pq;
/// qq = 0: every strain is linear in q, see [`qlinear`]).
struct Strain6 {
    v: f64,
    g: [f64; N],
    hpp: [f64; 6],
    hpq: [[f64; 3]; 3],
}

impl Strain6 {
    #[inline(always)]
    fn of(s: &qlinear::QLinear, q: &[f64; 3]) -> Strain6 {
        let (v, g, hpp, hpq) = s.eval(q);
        Strain6 { v, g, hpp, hpq }
    }
    /// a·self + b·o.
    #[inline(always)]
    fn combine(&self, a: f64, o: &Strain6, b: f64) -> Strain6 {
        Strain6 {
            v: a * self.v + b * o.v,
            g: std::array::from_fn(|i| a * self.g[i] + b * o.g[i]),
            hpp: std::array::from_fn(|k| a * self.hpp[k] + b * o.hpp[k]),
            hpq: std::array::from_fn(|i| std::array::from_fn(|j| a * self.hpq[i][j] + b * o.hpq[i][j])),
        }
    }
    /// h += k (∇S ∇Sᵀ + e ∇²S) on the upper half, for ½ k e² with e = S − S⁰.
    #[inline(always)]
    fn add_hessian(&self, k: f64, e: f64, h: &mut [[f64; N]; N]) {
        let ke = k * e;
        for i in 0..N {
            let kg = k * self.g[i];
            for j in i..N {
                h[i][j] += kg * self.g[j];
            }
        }
        for a in 0..3 {
            for b in a..3 {
                h[a][b] += ke * self.hpp[qlinear::hp(a, b)];
            }
            for j in 0..3 {
                h[a][3 + j] += ke * self.hpq[a][j];
            }
        }
    }
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
    let kin = kinematics(p, q, f.k, true, true);
    let (sn, cs) = s.th.sin_cos();
    (cs * kin.x + sn * kin.y, cs * kin.y - sn * kin.x, (s.th1 + f.omega + kin.dw) * kin.inv_speed)
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

/// The state of a sample with director `d1` (⟂ t) and reference twist
/// `omega` per unit u.
fn frame_at(s: &LocalState, d1: Vector3<f64>, omega: f64) -> RefFrame {
    let (t, ts) = tangent_and_rate(s);
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
        Ok(samples.iter().zip(d1s).map(|((s, _), d1)| FrameState::Reference(frame_at(s, d1, omega * s.r1.norm()))).collect())
    }

    /// Energy density of bending and twist with its derivatives in d,
    /// added to `out` (which holds the stretch part). Returns W.
    fn add_direct(s: &LocalState, c: &SampleConsts, state: &FrameState, terms: EnergyTerms, derivs: bool, out: &mut LocalEnergy) -> f64 {
        let (bend, twist) = (terms.bend, terms.twist);
        if !bend && !twist {
            return 0.0;
        }
        let f = frame_of(state);
        let (p, q, e) = local(s, f);
        if !derivs {
            let (k1, k2, om) = strain_values(s, f);
            let mut w = 0.0;
            if bend {
                let (e1, e2) = (k1 - c.kappa1, k2 - c.kappa2);
                w += 0.5 * (c.ei1 * e1 * e1 + c.ei2 * e2 * e2);
            }
            if twist {
                w += 0.5 * c.gj * (om - c.omega).powi(2);
            }
            return w;
        }
        let kin = qlinear::kinematics(p, f.k, bend, twist);
        // Derivatives in (p, q) (6), θ and θ′, then rotated to (r′, r″).
        let mut g6 = [0.0f64; N];
        let mut h66 = [[0.0f64; N]; N];
        let (mut g_th, mut g_th1) = (0.0, 0.0);
        let mut h6_th = [0.0f64; N];
        let mut h6_th1 = [0.0f64; N];
        let (mut h_thth, mut h_th1th1) = (0.0, 0.0);
        let mut w = 0.0;
        if bend {
            let (sn, cs) = s.th.sin_cos();
            // κ1 = cos θ x + sin θ y, κ2 = cos θ y − sin θ x; ∂κ1/∂θ = κ2, ∂κ2/∂θ = −κ1.
            let (x, y) = (Strain6::of(&kin.x, &q), Strain6::of(&kin.y, &q));
            let k1 = x.combine(cs, &y, sn);
            let k2 = y.combine(cs, &x, -sn);
            let (e1, e2) = (k1.v - c.kappa1, k2.v - c.kappa2);
            let (a1, a2) = (c.ei1, c.ei2);
            w += 0.5 * (a1 * e1 * e1 + a2 * e2 * e2);
            g_th += a1 * e1 * k2.v - a2 * e2 * k1.v;
            h_thth += a1 * (k2.v * k2.v - e1 * k1.v) + a2 * (k1.v * k1.v - e2 * k2.v);
            for i in 0..N {
                g6[i] += a1 * e1 * k1.g[i] + a2 * e2 * k2.g[i];
                h6_th[i] += a1 * (k2.v * k1.g[i] + e1 * k2.g[i]) - a2 * (k1.v * k2.g[i] + e2 * k1.g[i]);
            }
            k1.add_hessian(a1, e1, &mut h66);
            k2.add_hessian(a2, e2, &mut h66);
        }
        if twist {
            // Ω = (θ′ + ω°_u + w)/|p|: its f and G_j times 1/|p|.
            let is = kin.inv_speed;
            let om = qlinear::QLinear { f: is.scale(s.th1 + f.omega).add(kin.w.f.mul(is)), gq: kin.w.gq.map(|g| g.mul(is)) };
            let om = Strain6::of(&om, &q);
            let e3 = om.v - c.omega;
            w += 0.5 * c.gj * e3 * e3;
            g_th1 += c.gj * e3 * is.v;
            h_th1th1 += c.gj * is.v * is.v;
            for i in 0..N {
                g6[i] += c.gj * e3 * om.g[i];
                // ∂Ω/∂θ′ = 1/|p|, a function of p only.
                h6_th1[i] += c.gj * (is.v * om.g[i] + e3 * if i < 3 { is.g[i] } else { 0.0 });
            }
            om.add_hessian(c.gj, e3, &mut h66);
        }
        // Back to world components: r′ = Σ_b p_b e_b, so ∂/∂r′ = Σ_b e_b ∂/∂p_b,
        // and each 3×3 Hessian block X becomes Eᵀ X E (E's rows e_b).
        let rot = |v: &[f64]| -> [f64; 3] { std::array::from_fn(|a| e[0][a] * v[0] + e[1][a] * v[1] + e[2][a] * v[2]) };
        let grad = out.grad.as_mut_slice();
        for blk in 0..2 {
            let gw = rot(&g6[3 * blk..3 * blk + 3]);
            for a in 0..3 {
                grad[R1 + 3 * blk + a] += gw[a];
            }
        }
        grad[TH] += g_th;
        grad[TH1] += g_th1;
        let h = &mut out.hess;
        for (bi, bj) in [(0, 0), (0, 1), (1, 1)] {
            // X = h66 block (bi, bj), the upper half stored for diagonal blocks.
            let x = |r: usize, c: usize| if bi == bj && c < r { h66[3 * bi + c][3 * bj + r] } else { h66[3 * bi + r][3 * bj + c] };
            // T = X E, then W = Eᵀ T.
            let mut t = [[0.0f64; 3]; 3];
            for r in 0..3 {
                for c in 0..3 {
                    t[r][c] = x(r, 0) * e[0][c] + x(r, 1) * e[1][c] + x(r, 2) * e[2][c];
                }
            }
            for a in 0..3 {
                for c in 0..3 {
                    let wv = e[0][a] * t[0][c] + e[1][a] * t[1][c] + e[2][a] * t[2][c];
                    h[(R1 + 3 * bi + a, R1 + 3 * bj + c)] += wv;
                    if bi != bj {
                        h[(R1 + 3 * bj + c, R1 + 3 * bi + a)] += wv;
                    }
                }
            }
        }
        for blk in 0..2 {
            let (ht, ht1) = (rot(&h6_th[3 * blk..3 * blk + 3]), rot(&h6_th1[3 * blk..3 * blk + 3]));
            for a in 0..3 {
                let i = R1 + 3 * blk + a;
                h[(i, TH)] += ht[a];
                h[(TH, i)] += ht[a];
                h[(i, TH1)] += ht1[a];
                h[(TH1, i)] += ht1[a];
            }
        }
        h[(TH, TH)] += h_thth;
        h[(TH1, TH1)] += h_th1th1;
        w
    }

    /// Bending and twist use r′, r″ (never r‴), θ and θ′.
    fn active_slots(terms: EnergyTerms) -> ActiveSlots {
        let any = terms.bend || terms.twist;
        ActiveSlots { positions: if any { 2 } else { 0 }, theta: terms.bend, theta1: terms.twist }
    }
    /// Nothing in the invariants: the whole bending and twist energy is
    /// [`Reference::add_direct`].
    fn add_bend_twist(_q: &Vec5, _c: &SampleConsts, _state: &FrameState, _terms: EnergyTerms, _fq: &mut Vec5, _fqq: &mut Mat5) -> f64 {
        0.0
    }
    fn strains(s: &LocalState, _q: &Vec5, _c: &SampleConsts, state: &FrameState) -> Strains {
        let (kappa1, kappa2, omega) = strain_values(s, frame_of(state));
        Strains { eps: 0.0, kappa1, kappa2, omega }
    }
    fn rest_values(s0: &LocalState, state: &FrameState, _delta: f64) -> (f64, f64, f64) {
        strain_values(s0, frame_of(state))
    }
    /// The transported director, its tangent's rate and the reference
    /// twist of the transported field (the same formula as the energy, so
    /// the energy is continuous across a transport).
    fn transport(state: &mut FrameState, s: &LocalState) {
        let FrameState::Reference(f) = state else { return };
        let (t, _) = tangent_and_rate(s);
        if !t.iter().all(|x| x.is_finite()) {
            return; // a degenerate tangent: keep the last good state
        }
        let (p, q, _) = local(s, f);
        let dw = kinematics(p, q, f.k, false, true).dw;
        let d1 = transported_d1(f, &t);
        *f = frame_at(s, d1, f.omega + dw);
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
