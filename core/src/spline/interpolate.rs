//! Collocation: control points of a curve through given points (SPEC §1.1,
//! "Schoenberg / global interpolation, banded solve").
//!
//! Row `k` of the collocation matrix holds the 4 basis values `b_j(p_k)`.
//! Open knots: with sorted parameters the matrix is banded as is. Periodic:
//! the matrix is cyclic-banded; the "folding" permutation `0, n-1, 1, n-2, ..`
//! on rows and columns turns cyclic distance `d` into band distance `<= 2d`,
//! so the same band LU with pivoting solves it in O(n).

use super::knots::{KnotKind, KnotVector};
use crate::error::{Error, Result};
use crate::linalg::{solve_refined, BandLu, BandMatrix};

/// Default collocation parameters: for open kinds (Uniform, Clamped,
/// General) the Greville abscissae of the knots with the end knots clamped
/// into the domain (exactly Greville for Clamped; both domain ends included);
/// for Periodic the `n` segment starts `0, 1, .., n-1`. All satisfy the
/// Schoenberg–Whitney condition for knots without interior multiplicity 4.
///
/// Uniform does not use `n` equally spaced points: they satisfy
/// Schoenberg–Whitney but sit up to one knot span away from the basis
/// functions' peaks, and the collocation matrix becomes exponentially
/// ill-conditioned (pivot ~1e-138 at n = 2000).
pub fn default_params(knots: &KnotVector) -> Vec<f64> {
    let n = knots.n_ctrl();
    let (a, b) = knots.domain();
    match knots.kind() {
        KnotKind::Periodic => (0..n).map(|i| i as f64).collect(),
        KnotKind::Uniform | KnotKind::Clamped | KnotKind::General => {
            // Unclamped end knots would put the first/last Greville abscissae outside the domain.
            let t = knots.knots();
            let c = |i: usize| t[i].clamp(a, b);
            (0..n)
                .map(|i| (c(i + 1) + c(i + 2) + c(i + 3)) / 3.0)
                .collect()
        }
    }
}

/// Folding permutation position of index `j` among `n`: `0, n-1, 1, n-2, ..`
/// become positions `0, 1, 2, 3, ..`; cyclic neighbours end up <= 2 apart.
fn fold(j: usize, n: usize) -> usize {
    let h = n.div_ceil(2);
    if j < h {
        2 * j
    } else {
        2 * (n - 1 - j) + 1
    }
}

/// Control points such that the curve passes through `values[k]` at
/// `params[k]` (`n_ctrl` of each). Errors: wrong lengths, non-finite data,
/// parameters outside the domain, `Singular` when the parameters violate the
/// Schoenberg–Whitney condition.
pub fn interpolate<const D: usize>(
    knots: &KnotVector,
    params: &[f64],
    values: &[[f64; D]],
) -> Result<Vec<[f64; D]>> {
    let n = knots.n_ctrl();
    if params.len() != n || values.len() != n {
        return Err(Error::input(format!(
            "interpolation with {n} control points needs {n} parameters and {n} values, got {} and {}",
            params.len(),
            values.len()
        )));
    }
    if let Some(k) = values.iter().position(|v| v.iter().any(|x| !x.is_finite())) {
        return Err(Error::input(format!(
            "interpolation value {k} = {:?} is not finite",
            values[k]
        )));
    }
    let mut rows = Vec::with_capacity(n);
    for (k, &p) in params.iter().enumerate() {
        let seg = knots.locate(p).map_err(|e| e.context(format_args!("collocation parameter {k}")))?;
        rows.push((knots.segment_ctrl(seg), knots.basis(seg, p)[0]));
    }

    let periodic = knots.kind() == KnotKind::Periodic;
    // Pair row k with column k + shift (periodic: the column the first row
    // weighs most, which keeps sorted cyclic parameters near the diagonal).
    let shift = if periodic { rows[0].0[1] } else { 0 };
    let col_pos = |j: usize| if periodic { fold(j, n) } else { j };
    let row_pos = |k: usize| {
        if periodic {
            fold((k + shift) % n, n)
        } else {
            k
        }
    };

    let (mut kl, mut ku) = (0usize, 0usize);
    for (k, (cols, w)) in rows.iter().enumerate() {
        let r = row_pos(k);
        for (&j, &v) in cols.iter().zip(w) {
            if v != 0.0 {
                let c = col_pos(j);
                kl = kl.max(r.saturating_sub(c));
                ku = ku.max(c.saturating_sub(r));
            }
        }
    }
    let mut m = BandMatrix::new(n, kl, ku);
    for (k, (cols, w)) in rows.iter().enumerate() {
        for (&j, &v) in cols.iter().zip(w) {
            if v != 0.0 {
                m.add(row_pos(k), col_pos(j), v);
            }
        }
    }
    let mut lu = BandLu::new();
    lu.factor(&m).map_err(|e| match e {
        Error::Singular { detail, .. } => Error::singular(format!(
            "collocation matrix is singular ({detail}): the parameters must satisfy the Schoenberg-Whitney condition \
             t_i < p_i < t_(i+4) (distinct, sorted, spread over the domain)"
        )),
        other => other,
    })?;

    let mut out = vec![[0.0; D]; n];
    let (mut rhs, mut x, mut work) = (vec![0.0; n], vec![0.0; n], Vec::new());
    for d in 0..D {
        for (k, v) in values.iter().enumerate() {
            rhs[row_pos(k)] = v[d];
        }
        solve_refined(&m, &lu, &rhs, &mut x, &mut work, 1)?;
        for (j, o) in out.iter_mut().enumerate() {
            o[d] = x[col_pos(j)];
        }
    }
    Ok(out)
}

/// Fit a curve given as a function of `u`: `interpolate(knots, default_params(knots), f(u))`.
pub fn fit<const D: usize>(
    knots: &KnotVector,
    f: impl Fn(f64) -> [f64; D],
) -> Result<Vec<[f64; D]>> {
    let params = default_params(knots);
    let values: Vec<[f64; D]> = params.iter().map(|&u| f(u)).collect();
    interpolate(knots, &params, &values)
}

#[cfg(test)]
#[allow(clippy::needless_range_loop, clippy::too_many_arguments)] // index-heavy checks
mod tests {
    use super::super::knots::eval;
    use super::*;

    fn general() -> KnotVector {
        super::super::test_fixtures::general()
    }

    fn kinds() -> Vec<KnotVector> {
        vec![
            KnotVector::uniform(4).unwrap(),
            KnotVector::uniform(11).unwrap(),
            KnotVector::clamped(4).unwrap(),
            KnotVector::clamped(9).unwrap(),
            KnotVector::periodic(4).unwrap(),
            KnotVector::periodic(5).unwrap(),
            KnotVector::periodic(10).unwrap(),
            general(),
        ]
    }

    fn data(n: usize) -> Vec<[f64; 2]> {
        (0..n)
            .map(|i| [((i * 7) % 5) as f64 - 2.0, (i as f64).sqrt()])
            .collect()
    }

    #[test]
    fn fold_is_a_permutation_with_close_neighbours() {
        for n in 1..12 {
            let mut seen = vec![false; n];
            for j in 0..n {
                seen[fold(j, n)] = true;
                let d = fold(j, n).abs_diff(fold((j + 1) % n, n));
                assert!(n == 1 || d <= 2);
            }
            assert!(seen.iter().all(|&s| s));
        }
    }

    #[test]
    fn passes_through_data_with_default_params() {
        for k in kinds() {
            let p = default_params(&k);
            let v = data(k.n_ctrl());
            let c = interpolate(&k, &p, &v).unwrap();
            for (pk, vk) in p.iter().zip(&v) {
                let y = eval(&k, &c, *pk, 0).unwrap();
                assert!(
                    (y[0] - vk[0]).abs() < 1e-12 && (y[1] - vk[1]).abs() < 1e-12,
                    "{:?}",
                    k.kind()
                );
            }
        }
    }

    #[test]
    fn recovers_control_points_with_other_params() {
        // Interpolating the curve's own values at `params` gives its control points back.
        let recovers = |k: &KnotVector, ctrl: &[[f64; 2]], params: &[f64]| {
            let v: Vec<[f64; 2]> = params.iter().map(|&u| eval(k, ctrl, u, 0).unwrap()).collect();
            let c = interpolate(k, params, &v).unwrap();
            for (a, b) in c.iter().zip(ctrl) {
                assert!((a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12);
            }
        };
        // Periodic parameters at segment midpoints, shifted by whole periods and rotated.
        let params: Vec<f64> = (0..9).map(|i| ((i + 4) % 9) as f64 + 0.5 + 9.0).collect();
        recovers(&KnotVector::periodic(9).unwrap(), &data(9), &params);
        // Open, unsorted parameters (the band widens but the answer is the same).
        let k = KnotVector::clamped(8).unwrap();
        let mut params = default_params(&k);
        params.reverse();
        params.swap(2, 5);
        recovers(&k, &data(8), &params);
    }

    #[test]
    fn reproduces_cubic_polynomials_exactly() {
        let f = |u: f64| [1.0 - 2.0 * u + 0.5 * u * u - 0.25 * u * u * u, 3.0 + u * u];
        for k in [
            KnotVector::uniform(9).unwrap(),
            KnotVector::clamped(7).unwrap(),
            general(),
        ] {
            let c = fit(&k, f).unwrap();
            let (a, b) = k.domain();
            for j in 0..=50 {
                let u = a + (b - a) * j as f64 / 50.0;
                let y = eval(&k, &c, u, 0).unwrap();
                let e = f(u);
                assert!(
                    (y[0] - e[0]).abs() < 1e-10 && (y[1] - e[1]).abs() < 1e-10,
                    "{:?} u={u}",
                    k.kind()
                );
                // Third derivative of the cubic is the constant -1.5.
                let d3 = eval(&k, &c, u, 3).unwrap();
                assert!((d3[0] + 1.5).abs() < 1e-8 && d3[1].abs() < 1e-8);
            }
        }
    }

    #[test]
    fn periodic_fit_of_a_circle_converges() {
        let n = 64;
        let k = KnotVector::periodic(n).unwrap();
        let w = std::f64::consts::TAU / n as f64;
        let c = fit(&k, |u| [(w * u).cos(), (w * u).sin()]).unwrap();
        for j in 0..200 {
            let u = n as f64 * j as f64 / 200.0;
            let y = eval(&k, &c, u, 0).unwrap();
            assert!(((y[0] * y[0] + y[1] * y[1]).sqrt() - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn large_rings_and_rods_are_banded() {
        for k in [
            KnotVector::periodic(2000).unwrap(),
            KnotVector::uniform(2000).unwrap(),
        ] {
            let ctrl: Vec<[f64; 1]> = (0..2000).map(|i| [(i as f64 * 0.37).sin()]).collect();
            let p = default_params(&k);
            let v: Vec<[f64; 1]> = p.iter().map(|&u| eval(&k, &ctrl, u, 0).unwrap()).collect();
            let c = interpolate(&k, &p, &v).unwrap();
            assert!(c
                .iter()
                .zip(&ctrl)
                .all(|(a, b)| (a[0] - b[0]).abs() < 1e-10));
        }
    }

    #[test]
    fn errors() {
        let k = KnotVector::clamped(6).unwrap();
        let p = default_params(&k);
        let v = data(6);
        assert!(matches!(
            interpolate(&k, &p[..5], &v),
            Err(Error::InvalidInput { .. })
        ));
        assert!(matches!(
            interpolate(&k, &p, &v[..5]),
            Err(Error::InvalidInput { .. })
        ));
        let mut bad = v.clone();
        bad[3][1] = f64::NAN;
        assert!(matches!(
            interpolate(&k, &p, &bad),
            Err(Error::InvalidInput { .. })
        ));
        let mut q = p.clone();
        q[2] = f64::NAN;
        assert!(matches!(
            interpolate(&k, &q, &v),
            Err(Error::InvalidInput { .. })
        ));
        q[2] = 7.0;
        match interpolate(&k, &q, &v) {
            Err(e @ Error::InvalidInput { .. }) => { let m = e.to_string();
                assert!(m.contains("parameter 2") && m.contains("outside"), "{m}")
            }
            other => panic!("{other:?}"),
        }
        // Duplicate parameters and Schoenberg-Whitney violation (all in the first span).
        let mut q = p.clone();
        q[3] = q[2];
        assert!(matches!(interpolate(&k, &q, &v), Err(Error::Singular { .. })));
        let q: Vec<f64> = (0..6).map(|i| 0.1 * i as f64).collect();
        match interpolate(&k, &q, &v) {
            Err(e @ Error::Singular { .. }) => { let m = e.to_string(); assert!(m.contains("Schoenberg-Whitney"), "{m}") }
            other => panic!("{other:?}"),
        }
        let kp = KnotVector::periodic(6).unwrap();
        let q = vec![0.5; 6];
        assert!(matches!(interpolate(&kp, &q, &v), Err(Error::Singular { .. })));
        assert!(fit(&k, |u| [u, f64::INFINITY]).is_err());
    }
}
