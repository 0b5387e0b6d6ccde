//! The reference-frame model (SPEC §2.3, issue 14): its closed-form
//! gradient and Hessian against forward-mode AD (num-dual) of the SPEC
//! formulas written in world components (transported director, curvature
//! binormal, twist of the transported field) and against central
//! differences; the transport leaves the energy unchanged; a twisted
//! straight rod stores ½ GJ (Φ/L)² L.
use nalgebra::{SVector, Vector3};
use num_dual::{hessian, DualNum};
use proptest::prelude::*;
use strandkit_core::energy::invariants::{LocalState, Vec11};
use strandkit_core::energy::reference::RefFrame;
use strandkit_core::energy::{density, EnergyTerms, FrameModel, FrameState, SampleConsts};

type V3<D> = [D; 3];

fn dot<D: DualNum<Primitive = f64> + Copy>(a: V3<D>, b: V3<D>) -> D {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross<D: DualNum<Primitive = f64> + Copy>(a: V3<D>, b: V3<D>) -> V3<D> {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
fn lin<D: DualNum<Primitive = f64> + Copy>(a: V3<D>, x: D, b: V3<D>, y: D) -> V3<D> {
    [a[0] * x + b[0] * y, a[1] * x + b[1] * y, a[2] * x + b[2] * y]
}
fn cst<D: DualNum<Primitive = f64> + Copy>(v: [f64; 3]) -> V3<D> {
    [D::from(v[0]), D::from(v[1]), D::from(v[2])]
}

/// W(d) from SPEC §2.3 in world components (no local basis): t = r′/|r′|,
/// t_s = (r″ − (t·r″) t)/|r′|², κb = t × t_s, d1 = d1° − (d1°·t)/(1 + t°·t)
/// (t° + t), m1 = cos θ d1 + sin θ (t × d1), m2 = t × m1, κ_i = κb·m_i,
/// ω = (θ′ + ω°_u + (t × t°)·(t°_u + t_u)/(1 + t°·t))/|r′| with the state's
/// rates per unit u (t_u = |r′| t_s).
fn w_spec<D: DualNum<Primitive = f64> + Copy>(x: &[D], c: &SampleConsts, f: &RefFrame, terms: EnergyTerms) -> D {
    let r1 = [x[0], x[1], x[2]];
    let r2 = [x[3], x[4], x[5]];
    let (th, th1) = (x[9], x[10]);
    let one = D::from(1.0);
    let speed = dot(r1, r1).sqrt();
    let t = lin(r1, speed.recip(), r1, D::from(0.0));
    let a = dot(r1, r1);
    let ts = lin(r2, a.recip(), t, -dot(t, r2) / a);
    let (d1o, to) = (cst::<D>(f.d1), cst::<D>(f.t));
    let d2o = cross(to, d1o);
    let tos = lin(d1o, D::from(f.k[0]), d2o, D::from(f.k[1]));
    let den = one + dot(to, t);
    let d1 = lin(d1o, one, lin(to, one, t, one), -dot(d1o, t) / den);
    let d2 = cross(t, d1);
    let m1 = lin(d1, th.cos(), d2, th.sin());
    let m2 = cross(t, m1);
    let kb = cross(t, ts);
    let mut w = D::from(0.0);
    if terms.stretch {
        let e = speed / c.speed0 - 1.0 - c.eps_p;
        w += e * e * (0.5 * c.ea);
    }
    if terms.bend {
        let e1 = dot(kb, m1) - c.kappa1;
        let e2 = dot(kb, m2) - c.kappa2;
        w += e1 * e1 * (0.5 * c.ei1) + e2 * e2 * (0.5 * c.ei2);
    }
    if terms.twist {
        let wref_u = dot(cross(t, to), lin(tos, one, ts, speed)) / den + f.omega;
        let e = (th1 + wref_u) / speed - c.omega;
        w += e * e * (0.5 * c.gj);
    }
    w
}

fn closed(d: &Vec11, c: &SampleConsts, f: &RefFrame, t: EnergyTerms) -> strandkit_core::energy::LocalEnergy {
    density(&LocalState::from_vec(d), c, &FrameState::Reference(*f), t, FrameModel::Reference, true)
}

/// Largest difference relative to the largest entry, or to 1e-3 where all
/// are smaller (a straight rod at a straight rest has a round-off gradient,
/// 1e-16 against stiffnesses and states of order one).
fn rel_err(a: &[f64], b: &[f64]) -> f64 {
    let scale = a.iter().chain(b).fold(1e-3_f64, |m, x| m.max(x.abs()));
    a.iter().zip(b).fold(0.0_f64, |m, (x, y)| m.max((x - y).abs())) / scale
}

const TERMS: [EnergyTerms; 4] = [
    EnergyTerms { stretch: false, bend: true, twist: false },
    EnergyTerms { stretch: false, bend: false, twist: true },
    EnergyTerms { stretch: true, bend: true, twist: true },
    EnergyTerms { stretch: true, bend: false, twist: false },
];

fn vec3() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64).prop_map(|(a, b, c)| Vector3::new(a, b, c))
}

/// A reference frame whose tangent is within ~35° of `r1`'s direction
/// (a step's worth of turning, and more).
fn frame_near(r1: &Vector3<f64>, tilt: Vector3<f64>, spin: f64, k: [f64; 2], omega: f64) -> RefFrame {
    let t = (r1.normalize() + 0.6 * tilt).normalize();
    let e = if t[0].abs() < 0.9 { Vector3::x() } else { Vector3::y() };
    let b1 = (e - t * e.dot(&t)).normalize();
    let b2 = t.cross(&b1);
    let d1 = b1 * spin.cos() + b2 * spin.sin();
    RefFrame { d1: d1.into(), t: t.into(), k, omega }
}

fn consts(ea: f64, ei1: f64, ei2: f64, gj: f64, k1: f64, k2: f64, om: f64) -> SampleConsts {
    SampleConsts { ea, ei1, ei2, gj, speed0: 1.1, kappa1: k1, kappa2: k2, omega: om, delta: 1e-3, delta_bend: 1e-3, ..Default::default() }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x2e5f_0a14),
        ..ProptestConfig::default()
    })]

    /// Generic states, including straight ones (r″ ∥ r′ or 0 is no
    /// special case in this model), anisotropic sections, curved rest, and
    /// isotropic sections on a straight rest shape.
    #[test]
    fn reference_closed_form_matches_ad_and_differences(
        r1 in vec3(), r2 in vec3(), straight in 0..3u8, tilt in vec3(), spin in -3.0..3.0f64,
        k0 in -1.0..1.0f64, k1 in -1.0..1.0f64, om0 in -1.0..1.0f64, th in -3.0..3.0f64, th1 in -2.0..2.0f64,
        stiff in (0.5..2.0f64, 0.5..3.0f64, 0.5..3.0f64, 0.3..2.0f64), rest in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
        iso in 0..3u8,
    ) {
        let r1 = r1 + Vector3::new(0.9, 0.0, 0.0);
        // A third of the cases straight: r″ zero or along r′.
        let r2 = match straight { 0 => Vector3::zeros(), 1 => 0.4 * r1, _ => r2 };
        let f = frame_near(&r1, tilt, spin, [k0, k1], om0);
        // A third of the cases an isotropic section on a straight rest shape
        // (bending then written in the invariants, as ½ EI |κb|²).
        let c = if iso == 0 {
            consts(stiff.0, stiff.1, stiff.1, stiff.3, 0.0, 0.0, rest.2)
        } else {
            consts(stiff.0, stiff.1, stiff.2, stiff.3, rest.0, rest.1, rest.2)
        };
        let d = LocalState { r1, r2, r3: Vector3::new(0.3, -0.2, 0.5), th, th1 }.to_vec();
        for t in TERMS {
            let (w, g, h) = hessian(|x: SVector<_, 11>| w_spec(x.as_slice(), &c, &f, t), &d);
            let e = closed(&d, &c, &f, t);
            prop_assert!((w - e.w).abs() <= 1e-12 * w.abs().max(1.0), "W {w} vs {} for {t:?}", e.w);
            prop_assert!(rel_err(g.as_slice(), e.grad.as_slice()) < 1e-10, "grad {t:?}: {g} vs {}", e.grad);
            prop_assert!(rel_err(h.as_slice(), e.hess.as_slice()) < 1e-10, "hess {t:?}: {h} vs {}", e.hess);
            // Carrying the state to this local state (as after a step)
            // leaves the energy unchanged: the same formulas (module doc).
            let mut st = FrameState::Reference(f);
            FrameModel::Reference.transport(&mut st, &LocalState::from_vec(&d));
            let moved = density(&LocalState::from_vec(&d), &c, &st, t, FrameModel::Reference, false).w;
            prop_assert!((moved - e.w).abs() <= 1e-12 * e.w.abs().max(1.0), "transport changed W {} → {moved} for {t:?}", e.w);
            // Central differences of the closed-form gradient and energy.
            let step = 1e-6;
            for k in 0..11 {
                let (mut dp, mut dm) = (d, d);
                dp[k] += step;
                dm[k] -= step;
                let (ep, em) = (closed(&dp, &c, &f, t), closed(&dm, &c, &f, t));
                let fd = (ep.grad - em.grad) / (2.0 * step);
                prop_assert!(rel_err(fd.as_slice(), e.hess.column(k).as_slice()) < 1e-6 + 1e-6 * e.grad.amax() / e.hess.amax().max(1e-300),
                    "FD hessian column {k} {t:?}");
                prop_assert!(((ep.w - em.w) / (2.0 * step) - e.grad[k]).abs() < 1e-7 * e.grad.amax().max(1.0), "FD gradient {k} {t:?}");
            }
        }
    }
}
