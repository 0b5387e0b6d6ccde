//! SPEC §2 / issue "Show 1": the closed-form gradient and Hessian of each
//! energy density equal forward-mode AD (num-dual) of the SPEC formulas
//! written directly (not through the invariants), and central differences.
use nalgebra::{Const, SVector, Vector3};
use num_dual::{hessian, DualNum};
use proptest::prelude::*;
use strandkit_core::energy::invariants::{LocalState, Vec11};
use strandkit_core::energy::{density, EnergyTerms, FrameModel, SampleConsts};

/// W(d) straight from SPEC §2.1–2.2: ε, κ = |r'×r''|/|r'|³, κ1 = κ sinθ,
/// κ2 = κ cosθ, τ = (C·r''') |C|²/(|C|²+δ²)², ω = τ + θ'/|r'|. Valid where |C| ≥ δ
/// or the rest is straight (then the Huber branch is not used).
fn w_ref<D: DualNum<Primitive = f64> + Copy>(x: &[D], c: &SampleConsts, t: EnergyTerms) -> D {
    let v = |i: usize| [x[i], x[i + 1], x[i + 2]];
    let (r1, r2, r3) = (v(0), v(3), v(6));
    let (th, th1) = (x[9], x[10]);
    let dot = |a: [D; 3], b: [D; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let cr = [r1[1] * r2[2] - r1[2] * r2[1], r1[2] * r2[0] - r1[0] * r2[2], r1[0] * r2[1] - r1[1] * r2[0]];
    let speed = dot(r1, r1).sqrt();
    let mut w = D::from(0.0);
    if t.stretch {
        let e = speed / c.speed0 - 1.0 - c.eps_p;
        w += e * e * (0.5 * c.ea);
    }
    let c2 = dot(cr, cr);
    if t.bend {
        let k1 = c2 / (speed * speed * speed * speed * speed * speed);
        if c.kappa1 == 0.0 && c.kappa2 == 0.0 {
            // κ² sin²θ etc. (no square root needed for a straight rest)
            w += k1 * (th.sin() * th.sin() * (0.5 * c.ei1) + th.cos() * th.cos() * (0.5 * c.ei2));
        } else {
            let kappa = c2.sqrt() / (speed * speed * speed);
            let e1 = kappa * th.sin() - c.kappa1;
            let e2 = kappa * th.cos() - c.kappa2;
            w += e1 * e1 * (0.5 * c.ei1) + e2 * e2 * (0.5 * c.ei2);
        }
    }
    if t.twist {
        let dd = c2 + c.delta * c.delta;
        let tau = dot(cr, r3) * c2 / (dd * dd);
        let e = tau + th1 / speed - c.omega;
        w += e * e * (0.5 * c.gj);
    }
    w
}

fn ad(d: &Vec11, c: &SampleConsts, t: EnergyTerms) -> (f64, Vec11, nalgebra::SMatrix<f64, 11, 11>) {
    hessian(|x: SVector<_, 11>| w_ref(x.as_slice(), c, t), d)
}

fn closed(d: &Vec11, c: &SampleConsts, t: EnergyTerms) -> strandkit_core::energy::LocalEnergy {
    density(&LocalState::from_vec(d), c, &strandkit_core::energy::FrameState::None, t, FrameModel::Frenet, true)
}

fn rel_err_vec(a: &[f64], b: &[f64]) -> f64 {
    let scale = a.iter().chain(b).fold(1e-300_f64, |m, x| m.max(x.abs()));
    a.iter().zip(b).fold(0.0_f64, |m, (x, y)| m.max((x - y).abs())) / scale
}

const TERMS: [EnergyTerms; 4] = [
    EnergyTerms { stretch: true, bend: false, twist: false },
    EnergyTerms { stretch: false, bend: true, twist: false },
    EnergyTerms { stretch: false, bend: false, twist: true },
    EnergyTerms { stretch: true, bend: true, twist: true },
];

fn vec3() -> impl Strategy<Value = Vector3<f64>> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64).prop_map(|(a, b, c)| Vector3::new(a, b, c))
}

fn consts(curved: bool) -> impl Strategy<Value = SampleConsts> {
    (0.5..2.0f64, 0.5..3.0f64, 0.5..3.0f64, 0.3..2.0f64, 0.5..2.0f64, -1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
        .prop_map(move |(ea, ei1, ei2, gj, speed0, k1, k2, om)| SampleConsts {
            ea,
            ei1,
            ei2,
            gj,
            speed0,
            kappa1: if curved { k1 } else { 0.0 },
            kappa2: if curved { k2 } else { 0.0 },
            omega: om,
            eps_p: 0.01,
            delta: 1e-3, delta_bend: 1e-3,
        })
}

/// `fd`: also compare with central differences (skipped where |C| ~ δ: the
/// regularised torsion varies on the scale δ, below any usable FD step).
fn check(d: Vec11, c: SampleConsts, tol: f64, fd: bool) -> Result<(), TestCaseError> {
    for t in TERMS {
        let (w, g, h) = ad(&d, &c, t);
        let e = closed(&d, &c, t);
        prop_assert!((w - e.w).abs() <= 1e-12 * w.abs().max(1.0), "W {w} vs {} for {t:?}", e.w);
        prop_assert!(rel_err_vec(g.as_slice(), e.grad.as_slice()) < tol, "grad for {t:?}: {g} vs {}", e.grad);
        prop_assert!(rel_err_vec(h.as_slice(), e.hess.as_slice()) < tol, "hess for {t:?}");
        if !fd {
            continue;
        }
        // Central differences of the closed-form gradient reproduce its Hessian.
        // Step 1e-5: with |C| ~ 0.05 the twist gradient reaches ~1e3, and a
        // 1e-6 step leaves round-off eps |g| / h ~ 4e-7 (the second seed of
        // the regressions file), while truncation at 1e-5 stays ~1e-10.
        let step = 1e-5;
        for k in 0..11 {
            let (mut dp, mut dm) = (d, d);
            dp[k] += step;
            dm[k] -= step;
            let fd = (closed(&dp, &c, t).grad - closed(&dm, &c, t).grad) / (2.0 * step);
            let col = e.hess.column(k).into_owned();
            // Tolerance: truncation (≤ 1e-5 at |C| ≥ 0.05) plus the round-off
            // of differencing a gradient of size |g|: 10 ε |g| / h relative to
            // the column's own size, so nearly parallel r′, r″ (large |g|,
            // small Hessian entries) are judged at what doubles can resolve.
            let roundoff = 10.0 * f64::EPSILON * e.grad.amax() / (step * col.amax().max(1e-300));
            prop_assert!(rel_err_vec(fd.as_slice(), col.as_slice()) < 1e-5 + roundoff, "FD hess col {k} {t:?}: d {d:?}");
            let fdw = (closed(&dp, &c, t).w - closed(&dm, &c, t).w) / (2.0 * step);
            prop_assert!((fdw - e.grad[k]).abs() < 1e-6 * e.grad.amax().max(1.0), "FD grad {k} {t:?}");
        }
    }
    Ok(())
}

fn state(r1: Vector3<f64>, r2: Vector3<f64>, r3: Vector3<f64>, th: f64, th1: f64) -> Vec11 {
    LocalState { r1, r2, r3, th, th1 }.to_vec()
}

proptest! {
    // A fixed seed: the suite must give the same verdict on every run (the
    // regressions file still replays the seeds that once failed).
    #![proptest_config(ProptestConfig {
        cases: 64,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x5712_a4d1),
        ..ProptestConfig::default()
    })]

    /// Generic configurations, curved rest shape (|C| well above δ).
    #[test]
    fn closed_form_matches_ad_generic(r1 in vec3(), r2 in vec3(), r3 in vec3(), th in -3.0..3.0f64,
                                       th1 in -2.0..2.0f64, c in consts(true)) {
        let r1 = r1 + Vector3::new(0.8, 0.0, 0.0);
        prop_assume!(r1.cross(&r2).norm() > 0.05);
        check(state(r1, r2, r3, th, th1), c, 1e-9, true)?;
    }

    /// Nearly straight configurations (|C| ~ 1e-4 … 1e-2, down to δ),
    /// straight rest: the Frenet torsion is regularised there.
    #[test]
    fn closed_form_matches_ad_nearly_straight(dir in vec3(), tiny in vec3(), r3 in vec3(), scale in -4.0..-2.0f64,
                                              th in -3.0..3.0f64, th1 in -2.0..2.0f64, c in consts(false)) {
        let r1 = (dir + Vector3::new(1.0, 0.3, 0.0)).normalize() * 1.2;
        let r2 = 0.3 * r1 + tiny * 10f64.powf(scale);
        check(state(r1, r2, r3, th, th1), c, 1e-8, false)?;
    }
}

/// Exactly straight (C = 0): finite values and derivatives, no NaN.
#[test]
fn exactly_straight_is_finite() {
    let d = state(Vector3::new(1.0, 0.0, 0.0), Vector3::zeros(), Vector3::new(0.0, 0.3, 0.1), 0.4, 0.2);
    let c = SampleConsts { ea: 1.0, ei1: 1.0, ei2: 2.0, gj: 1.0, speed0: 1.0, delta: 1e-3, delta_bend: 1e-3, ..Default::default() };
    for t in TERMS {
        let e = closed(&d, &c, t);
        assert!(e.w.is_finite() && e.grad.iter().all(|x| x.is_finite()) && e.hess.iter().all(|x| x.is_finite()));
        let (_, g, h) = ad(&d, &c, t);
        assert!(rel_err_vec(g.as_slice(), e.grad.as_slice()) < 1e-12);
        assert!(rel_err_vec(h.as_slice(), e.hess.as_slice()) < 1e-12);
    }
}

/// The Huber branch (curved rest, |C| < δ) is C¹: value and gradient are
/// continuous across |C| = δ.
#[test]
fn huber_branch_is_c1() {
    let c = SampleConsts { ea: 1.0, ei1: 1.0, ei2: 1.5, gj: 1.0, speed0: 1.0, kappa1: 0.2, kappa2: 0.4, delta: 1e-3, delta_bend: 1e-3, ..Default::default() };
    let t = EnergyTerms { stretch: false, bend: true, twist: false };
    let r1 = Vector3::new(1.0, 0.0, 0.0);
    let at = |m: f64| closed(&state(r1, Vector3::new(0.0, m, 0.0), Vector3::zeros(), 0.3, 0.0), &c, t);
    let (lo, hi) = (at(1e-3 * (1.0 - 1e-9)), at(1e-3 * (1.0 + 1e-9)));
    assert!((lo.w - hi.w).abs() < 1e-9);
    assert!(rel_err_vec(lo.grad.as_slice(), hi.grad.as_slice()) < 1e-6);
}

#[allow(dead_code)]
fn _type_check(_: Const<11>) {}
