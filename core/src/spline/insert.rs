//! Boehm knot insertion and splitting (SPEC §1.1, §6; thesis II.C rupture).
//!
//! Periodic curves are first unwrapped to an equivalent General open curve:
//! `n + 3` control points (the first three repeated) on knots
//! `s-3, .., s+n+3`, domain `[s, s+n]`, with `s = 0` unless the abscissa is at
//! the seam `u ≡ 0 (mod n)`, in which case `s = -floor(n/2)` so that `u = 0`
//! is strictly inside. Every open result has kind General.

use super::knots::{check_ctrl, KnotKind, KnotVector};
use crate::error::{Error, Result};

type Piece<const D: usize> = (KnotVector, Vec<[f64; D]>);

/// Boehm insertion of one knot at `u`; the new curve is the same curve
/// (one more control point). `u` must be strictly inside the domain (a
/// periodic `u` wraps) and have multiplicity < 4.
pub fn insert_knot<const D: usize>(
    knots: &KnotVector,
    ctrl: &[[f64; D]],
    u: f64,
) -> Result<Piece<D>> {
    check_ctrl(knots, ctrl)?;
    if knots.kind() == KnotKind::Periodic {
        let (k, c, u) = unwrap_for(knots, ctrl, u)?;
        return insert_open(&k, &c, u);
    }
    insert_open(knots, ctrl, u)
}

/// Insert `u` up to multiplicity 4 and cut: `[left, right]` open pieces with
/// clamped ends at the cut, left on `[a, u]` and right on `[u, b]`, each
/// reproducing the curve exactly there (values and the derivatives that are
/// continuous at `u`). Periodic input is unwrapped first (see the module
/// docs), so a ring gives two arcs; use [`open_ring_at`] to open a ring into
/// one rod.
pub fn split_at<const D: usize>(
    knots: &KnotVector,
    ctrl: &[[f64; D]],
    u: f64,
) -> Result<[Piece<D>; 2]> {
    check_ctrl(knots, ctrl)?;
    if knots.kind() == KnotKind::Periodic {
        let (k, c, u) = unwrap_for(knots, ctrl, u)?;
        return split_open(&k, &c, u);
    }
    split_open(knots, ctrl, u)
}

/// Open a periodic curve (ring) at `u`: one open rod, clamped at both ends,
/// with domain `[0, ≈n]` and `rod(s) = ring(u + s)` (thesis II.C rupture of
/// a closed loop). Error unless `knots` is Periodic.
pub fn open_ring_at<const D: usize>(
    knots: &KnotVector,
    ctrl: &[[f64; D]],
    u: f64,
) -> Result<Piece<D>> {
    check_ctrl(knots, ctrl)?;
    if knots.kind() != KnotKind::Periodic {
        return Err(Error::input(
            "open_ring_at needs a periodic knot vector; use split_at for an open rod",
        ));
    }
    if !u.is_finite() {
        return Err(Error::input(format!(
            "abscissa u = {u} must be finite"
        )));
    }
    let n = knots.n_ctrl();
    // Three periods [0, 3n]; the cut points n + w and 2n + w are strictly inside.
    let (k3, c3) = unwrap_periodic(knots, ctrl, 0, 3)?;
    let c1 = snap(&k3, n as f64 + knots.wrap(u));
    let c2 = c1 + n as f64;
    let [_, (kr, cr)] = split_open(&k3, &c3, c1)?;
    let [(km, cm), _] = split_open(&kr, &cr, c2)?;
    let shifted = km.knots().iter().map(|t| t - c1).collect();
    Ok((KnotVector::from_knots(shifted, cm.len())?, cm))
}

/// Equivalent General open form of a periodic curve over `periods` periods,
/// starting at integer `start`: knots `start-3 ..= start + periods n + 3`,
/// control points `ctrl[(start + i) mod n]`, `i < periods n + 3`.
pub(crate) fn unwrap_periodic<const D: usize>(
    knots: &KnotVector,
    ctrl: &[[f64; D]],
    start: i64,
    periods: usize,
) -> Result<Piece<D>> {
    let n = knots.n_ctrl();
    let m = periods * n + 3;
    let t: Vec<f64> = (0..m + 4).map(|i| (start - 3 + i as i64) as f64).collect();
    let c: Vec<[f64; D]> = (0..m)
        .map(|i| ctrl[(start + i as i64).rem_euclid(n as i64) as usize])
        .collect();
    Ok((KnotVector::from_knots(t, m)?, c))
}

/// Unwrap a periodic curve so that `u` (wrapped) is strictly inside the domain.
fn unwrap_for<const D: usize>(
    knots: &KnotVector,
    ctrl: &[[f64; D]],
    u: f64,
) -> Result<(KnotVector, Vec<[f64; D]>, f64)> {
    if !u.is_finite() {
        return Err(Error::input(format!(
            "abscissa u = {u} must be finite"
        )));
    }
    let n = knots.n_ctrl() as f64;
    let w = knots.wrap(u);
    if w <= knots.tol() || n - w <= knots.tol() {
        // At the seam: unwrap around it instead.
        let (k, c) = unwrap_periodic(knots, ctrl, -((knots.n_ctrl() / 2) as i64), 1)?;
        Ok((k, c, 0.0))
    } else {
        let (k, c) = unwrap_periodic(knots, ctrl, 0, 1)?;
        Ok((k, c, w))
    }
}

/// `u` replaced by a knot within the tolerance, if any (so near-duplicate
/// knots never create near-empty spans).
fn snap(knots: &KnotVector, u: f64) -> f64 {
    let t = knots.knots();
    let tol = knots.tol();
    let p = t.partition_point(|&x| x < u);
    let mut best = u;
    let mut dist = tol;
    for q in [p.wrapping_sub(1), p] {
        if let Some(&x) = t.get(q) {
            if (x - u).abs() <= dist {
                dist = (x - u).abs();
                best = x;
            }
        }
    }
    best
}

/// Domain check, then snap; `u` must end up strictly inside `(a, b)`.
fn interior_abscissa(knots: &KnotVector, u: f64, what: &str) -> Result<f64> {
    knots.locate(u)?; // NaN / outside-domain message
    let u = snap(knots, u);
    let (a, b) = knots.domain();
    if u <= a + knots.tol() || u >= b - knots.tol() {
        return Err(Error::input(format!(
            "{what} at u = {u}: it must be strictly inside the domain ({a}, {b})"
        )));
    }
    Ok(u)
}

fn insert_open<const D: usize>(knots: &KnotVector, ctrl: &[[f64; D]], u: f64) -> Result<Piece<D>> {
    let u = interior_abscissa(knots, u, "cannot insert a knot")?;
    if knots.multiplicity(u) >= 4 {
        return Err(Error::input(format!(
            "cannot insert a knot at u = {u}: it already has multiplicity 4"
        )));
    }
    let t = knots.knots();
    let n = knots.n_ctrl();
    // Span k with t_k <= u < t_{k+1} (a < u < b, so 3 <= k <= n-1).
    let k = knots.span(knots.locate(u)?);
    let mut q = Vec::with_capacity(n + 1);
    q.extend_from_slice(&ctrl[..=k - 3]);
    for i in k - 2..=k {
        // Boehm: Q_i = (1 - α) P_{i-1} + α P_i, α = (u - t_i) / (t_{i+3} - t_i);
        // t_i <= t_k < t_{k+1} <= t_{i+3}, so the divisor is > 0.
        let alpha = (u - t[i]) / (t[i + 3] - t[i]);
        let mut p = [0.0; D];
        for ((o, a), b) in p.iter_mut().zip(&ctrl[i - 1]).zip(&ctrl[i]) {
            *o = (1.0 - alpha) * a + alpha * b;
        }
        q.push(p);
    }
    q.extend_from_slice(&ctrl[k..]);
    let mut nt = Vec::with_capacity(t.len() + 1);
    nt.extend_from_slice(&t[..=k]);
    nt.push(u);
    nt.extend_from_slice(&t[k + 1..]);
    Ok((KnotVector::from_knots(nt, n + 1)?, q))
}

fn split_open<const D: usize>(
    knots: &KnotVector,
    ctrl: &[[f64; D]],
    u: f64,
) -> Result<[Piece<D>; 2]> {
    let u = interior_abscissa(knots, u, "cannot split")?;
    let count = |k: &KnotVector| k.knots().iter().filter(|&&x| x == u).count();
    let mut cur = (knots.clone(), ctrl.to_vec());
    while count(&cur.0) < 4 {
        cur = insert_open(&cur.0, &cur.1, u)?;
    }
    let (k, c) = cur;
    let t = k.knots();
    let total = k.n_ctrl();
    // t_r ..= t_{r+3} == u; left uses P_0..P_{r-1}, right P_r.. (their supports end/start at u).
    let r = t.partition_point(|&x| x < u);
    for m in [r, total - r] {
        if m < 4 {
            return Err(Error::input(format!("splitting at u = {u} would leave a piece with {m} control points (a cubic needs 4)")));
        }
    }
    let mut lt = t[..r].to_vec();
    lt.extend_from_slice(&[u; 4]);
    let mut rt = vec![u; 4];
    rt.extend_from_slice(&t[r + 4..]);
    Ok([
        (KnotVector::from_knots(lt, r)?, c[..r].to_vec()),
        (KnotVector::from_knots(rt, total - r)?, c[r..].to_vec()),
    ])
}

#[cfg(test)]
#[allow(clippy::needless_range_loop, clippy::too_many_arguments)] // index-heavy checks
mod tests {
    use super::super::knots::eval;
    use super::*;

    fn ctrl_for(n: usize) -> Vec<[f64; 3]> {
        (0..n)
            .map(|i| {
                let x = i as f64;
                [x.sin() * 2.0, (1.3 * x).cos(), 0.1 * x * x - x]
            })
            .collect()
    }

    fn general() -> KnotVector {
        super::super::test_fixtures::general()
    }

    /// Both curves agree on [lo, hi]: values and derivatives up to `max_d`
    /// inside, up to `end_d` at lo and hi (where a derivative may jump and the
    /// two curves may take different one-sided limits). Tolerance 1e-12
    /// relative to the scale Σ|b_l^(d)| |P_l| of the first curve's sum.
    fn same_curve(
        k1: &KnotVector,
        c1: &[[f64; 3]],
        k2: &KnotVector,
        c2: &[[f64; 3]],
        lo: f64,
        hi: f64,
        max_d: usize,
        end_d: usize,
    ) {
        for j in 0..=200 {
            let u = lo + (hi - lo) * j as f64 / 200.0;
            let seg = k1.locate(u).unwrap();
            let (b, idx) = (k1.basis(seg, u), k1.segment_ctrl(seg));
            let top = if j == 0 || j == 200 { end_d } else { max_d };
            for d in 0..=top {
                let a = eval(k1, c1, u, d).unwrap();
                let e = eval(k2, c2, u, d).unwrap();
                for c in 0..3 {
                    let scale: f64 = (0..4).map(|l| (b[d][l] * c1[idx[l]][c]).abs()).sum();
                    assert!(
                        (a[c] - e[c]).abs() <= 1e-12 * scale.max(1.0),
                        "u={u} d={d}: {a:?} vs {e:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn insertion_reproduces_open_curves() {
        let kinds = [
            KnotVector::uniform(8).unwrap(),
            KnotVector::clamped(7).unwrap(),
            general(),
        ];
        for k in kinds {
            let c = ctrl_for(k.n_ctrl());
            let (a, b) = k.domain();
            let mut us: Vec<f64> = (1..10).map(|j| a + (b - a) * j as f64 / 10.0).collect();
            us.extend(
                k.knots()
                    .iter()
                    .copied()
                    .filter(|&t| t > a && t < b && k.multiplicity(t) < 4),
            );
            for u in us {
                let (k2, c2) = insert_knot(&k, &c, u).unwrap();
                assert_eq!(
                    (k2.kind(), k2.n_ctrl(), k2.domain()),
                    (KnotKind::General, k.n_ctrl() + 1, k.domain())
                );
                assert_eq!(k2.multiplicity(u), k.multiplicity(u) + 1);
                same_curve(&k, &c, &k2, &c2, a, b, 3, 3);
            }
        }
    }

    #[test]
    fn insertion_up_to_multiplicity_four_then_error() {
        let k = KnotVector::uniform(6).unwrap();
        let c = ctrl_for(6);
        let (mut kk, mut cc) = (k.clone(), c.clone());
        for _ in 0..4 {
            (kk, cc) = insert_knot(&kk, &cc, 4.25).unwrap();
        }
        same_curve(&k, &c, &kk, &cc, 3.0, 6.0, 2, 2);
        assert!(matches!(
            insert_knot(&kk, &cc, 4.25),
            Err(Error::InvalidInput { .. })
        ));
        // The curve passes through the control point at a multiplicity-3 knot.
        let (k3, c3) = insert_knot(&k, &c, 5.0)
            .and_then(|(k, c)| insert_knot(&k, &c, 5.0))
            .unwrap();
        let p = eval(&k3, &c3, 5.0, 0).unwrap();
        assert!(c3
            .iter()
            .any(|q| (0..3).all(|i| (q[i] - p[i]).abs() < 1e-13)));
    }

    #[test]
    fn insertion_errors() {
        let k = KnotVector::clamped(6).unwrap();
        let c = ctrl_for(6);
        for u in [f64::NAN, -0.5, 3.5, 0.0, 3.0] {
            assert!(
                matches!(insert_knot(&k, &c, u), Err(Error::InvalidInput { .. })),
                "u = {u}"
            );
        }
        assert!(insert_knot(&k, &c[..5], 1.0).is_err());
        assert!(insert_knot(&KnotVector::periodic(5).unwrap(), &c[..5], f64::INFINITY).is_err());
    }

    #[test]
    fn insertion_reproduces_periodic_curve() {
        let k = KnotVector::periodic(6).unwrap();
        let c = ctrl_for(6);
        for u in [0.4, 2.0, 3.75, 5.9, -1.5, 0.0, 6.0, 12.0] {
            let (k2, c2) = insert_knot(&k, &c, u).unwrap();
            assert_eq!((k2.kind(), k2.n_ctrl()), (KnotKind::General, 10));
            let (a, b) = k2.domain();
            assert!(b - a == 6.0 && a <= k.wrap(u) && (k.wrap(u) < b || a < 0.0));
            same_curve(&k, &c, &k2, &c2, a, b, 3, 2);
        }
        // Four insertions: a break (multiplicity 4) in the unwrapped rod.
        let (mut kk, mut cc) = (k.clone(), c.clone());
        for _ in 0..4 {
            (kk, cc) = insert_knot(&kk, &cc, 2.5).unwrap();
        }
        assert_eq!(kk.multiplicity(2.5), 4);
        same_curve(&k, &c, &kk, &cc, 0.0, 6.0, 2, 2);
    }

    /// `cut_d`: highest derivative continuous at `u` in the original curve.
    fn check_split(k: &KnotVector, c: &[[f64; 3]], u: f64, cut_d: usize) {
        let [(kl, cl), (kr, cr)] = split_at(k, c, u).unwrap();
        let (a, b) = if k.kind() == KnotKind::Periodic {
            (0.0, k.n_ctrl() as f64)
        } else {
            k.domain()
        };
        assert_eq!((kl.domain(), kr.domain()), ((a, u), (u, b)));
        // The original takes right limits at u, like the right piece.
        let end_d = if k.kind() == KnotKind::Periodic { 2 } else { 3 };
        same_curve(k, c, &kl, &cl, a, u, 3, cut_d.min(end_d));
        same_curve(k, c, &kr, &cr, u, b, 3, end_d);
        // Clamped at the cut: the end control points are the curve point.
        let p = eval(k, c, u, 0).unwrap();
        for q in [cl[cl.len() - 1], cr[0]] {
            assert!((0..3).all(|i| (q[i] - p[i]).abs() < 1e-12));
        }
    }

    #[test]
    fn split_pieces_reproduce_each_half() {
        check_split(&KnotVector::uniform(9).unwrap(), &ctrl_for(9), 5.3, 3);
        check_split(&KnotVector::uniform(9).unwrap(), &ctrl_for(9), 6.0, 2);
        check_split(&KnotVector::uniform(4).unwrap(), &ctrl_for(4), 3.5, 3);
        check_split(&KnotVector::clamped(6).unwrap(), &ctrl_for(6), 0.2, 3);
        check_split(&general(), &ctrl_for(12), 3.5, 0); // existing triple knot: C0 there
        check_split(&general(), &ctrl_for(12), 1.2, 3);
        check_split(&KnotVector::periodic(7).unwrap(), &ctrl_for(7), 2.6, 3);
    }

    #[test]
    fn split_errors() {
        let k = KnotVector::uniform(6).unwrap();
        let c = ctrl_for(6);
        for u in [3.0, 6.0, 2.0, 7.0, f64::NAN, 3.0 + 1e-14] {
            assert!(
                matches!(split_at(&k, &c, u), Err(Error::InvalidInput { .. })),
                "u = {u}"
            );
        }
    }

    #[test]
    fn open_ring_gives_one_clamped_rod() {
        let k = KnotVector::periodic(6).unwrap();
        let c = ctrl_for(6);
        for u in [0.0, 2.3, 4.0, -0.7] {
            let (kr, cr) = open_ring_at(&k, &c, u).unwrap();
            let (a, b) = kr.domain();
            assert!(a == 0.0 && (b - 6.0).abs() < 1e-12);
            for j in 0..=120 {
                let s = b * j as f64 / 120.0;
                for d in 0..=2 {
                    let x = eval(&k, &c, u + s, d).unwrap();
                    let y = eval(&kr, &cr, s, d).unwrap();
                    assert!(
                        (0..3).all(|i| (x[i] - y[i]).abs() < 1e-11),
                        "u={u} s={s} d={d}"
                    );
                }
            }
            let p = eval(&k, &c, u, 0).unwrap();
            for q in [cr[0], cr[cr.len() - 1]] {
                assert!((0..3).all(|i| (q[i] - p[i]).abs() < 1e-12));
            }
        }
        assert!(open_ring_at(&KnotVector::uniform(6).unwrap(), &c, 4.0).is_err());
    }
}
