//! Knot vectors, segment lookup and cubic B-spline basis functions with
//! derivatives (SPEC §1.1; thesis II.10–II.15).
//!
//! Conventions (knots `t_0 ..`, `n` = number of control points):
//! * Open kinds (Uniform, Clamped, General) store `n + 4` knots; the domain
//!   is `[t_3, t_n]`; control point `i` is supported on `[t_i, t_{i+4}]`.
//! * Periodic stores the `n + 7` knots `-3, -2, .., n + 3` of its unwrapped
//!   open form (`n + 3` control points, the first three repeated); the domain
//!   is `[0, n]`, segment `s = [s, s+1]` uses control points `s..s+3 mod n`,
//!   and abscissae outside the domain wrap with period `n`.
//! * Segment `s` is the `s`-th non-empty knot span inside the domain.

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

use super::ORDER;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum KnotKind {
    /// Knots `0, 1, .., n+3`; domain `[3, n]` (the thesis' choice, II.12).
    Uniform,
    /// Knots `0,0,0,0,1,..,n-4,n-3,n-3,n-3,n-3`; the curve interpolates its end control points.
    Clamped,
    /// Closed curve with `n` unit segments.
    Periodic,
    /// Any valid open knot vector (e.g. after knot insertion).
    General,
}

/// A validated cubic knot vector. Deserialisation re-validates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "KnotVectorData", into = "KnotVectorData")]
pub struct KnotVector {
    kind: KnotKind,
    knots: Vec<f64>,
    n_ctrl: usize,
    /// Derived: knot index `i` of each segment `[t_i, t_{i+1})`.
    spans: Vec<usize>,
}

/// Serialised form of [`KnotVector`] (the derived span table is rebuilt).
#[derive(Clone, Serialize, Deserialize)]
pub struct KnotVectorData {
    pub kind: KnotKind,
    pub knots: Vec<f64>,
    pub n_ctrl: usize,
}

impl From<KnotVector> for KnotVectorData {
    fn from(k: KnotVector) -> Self {
        Self {
            kind: k.kind,
            knots: k.knots,
            n_ctrl: k.n_ctrl,
        }
    }
}

impl TryFrom<KnotVectorData> for KnotVector {
    type Error = Error;
    fn try_from(d: KnotVectorData) -> Result<Self> {
        let built = match d.kind {
            KnotKind::Uniform => Self::uniform(d.n_ctrl)?,
            KnotKind::Clamped => Self::clamped(d.n_ctrl)?,
            KnotKind::Periodic => Self::periodic(d.n_ctrl)?,
            KnotKind::General => return Self::from_knots(d.knots, d.n_ctrl),
        };
        if built.knots != d.knots {
            return Err(Error::input(format!(
                "the knots do not match a {:?} knot vector with {} control points",
                d.kind, d.n_ctrl
            )));
        }
        Ok(built)
    }
}

/// Most control points one spline may have (checked before allocating:
/// a rod of 10⁷ control points already needs several GiB).
pub const MAX_CONTROL_POINTS: usize = 10_000_000;

fn check_count(n_ctrl: usize) -> Result<()> {
    crate::error::size("number of control points", n_ctrl, MAX_CONTROL_POINTS)?;
    if n_ctrl < ORDER {
        return Err(Error::input(format!(
            "a cubic B-spline needs at least 4 control points, got {n_ctrl}"
        )));
    }
    Ok(())
}

impl KnotVector {
    /// Uniform knots `0, 1, .., n+3`; domain `[3, n]`, `n - 3` unit segments.
    pub fn uniform(n_ctrl: usize) -> Result<Self> {
        check_count(n_ctrl)?;
        let knots = (0..n_ctrl + 4).map(|i| i as f64).collect();
        Ok(Self {
            kind: KnotKind::Uniform,
            knots,
            n_ctrl,
            spans: (3..n_ctrl).collect(),
        })
    }

    /// Open-uniform knots `0,0,0,0,1,..,n-4,n-3,n-3,n-3,n-3`; domain `[0, n-3]`.
    pub fn clamped(n_ctrl: usize) -> Result<Self> {
        check_count(n_ctrl)?;
        let last = (n_ctrl - 3) as f64;
        let knots = (0..n_ctrl + 4)
            .map(|i| (i.saturating_sub(3) as f64).min(last))
            .collect();
        Ok(Self {
            kind: KnotKind::Clamped,
            knots,
            n_ctrl,
            spans: (3..n_ctrl).collect(),
        })
    }

    /// Closed curve: domain `[0, n]`, segment `s` uses control points `s..s+3 mod n`.
    pub fn periodic(n_ctrl: usize) -> Result<Self> {
        check_count(n_ctrl)?;
        let knots = (0..n_ctrl + 7).map(|i| i as f64 - 3.0).collect();
        Ok(Self {
            kind: KnotKind::Periodic,
            knots,
            n_ctrl,
            spans: (3..n_ctrl + 3).collect(),
        })
    }

    /// A General open knot vector: `n + 4` finite, non-decreasing knots, no
    /// knot repeated more than 4 times, non-empty domain `[t_3, t_n]`, and
    /// every control point influencing the domain (`t_3 < t_4`, `t_{n-1} < t_n`).
    pub fn from_knots(knots: Vec<f64>, n_ctrl: usize) -> Result<Self> {
        check_count(n_ctrl)?;
        if knots.len() != n_ctrl + 4 {
            return Err(Error::input(format!(
                "{n_ctrl} control points need {} knots, got {}",
                n_ctrl + 4,
                knots.len()
            )));
        }
        if let Some(i) = knots.iter().position(|t| !t.is_finite()) {
            return Err(Error::input(format!("knot {i} is {}", knots[i])));
        }
        if let Some(i) = knots.windows(2).position(|w| w[1] < w[0]) {
            return Err(Error::input(format!(
                "knots must be non-decreasing, but t_{} = {} > t_{} = {}",
                i,
                knots[i],
                i + 1,
                knots[i + 1]
            )));
        }
        if let Some(i) = knots.windows(ORDER + 1).position(|w| w[0] == w[ORDER]) {
            return Err(Error::input(format!(
                "knot {} has multiplicity > 4 (a cubic B-spline allows at most 4)",
                knots[i]
            )));
        }
        let n = n_ctrl;
        if knots[3] >= knots[n] {
            return Err(Error::input(format!(
                "empty parameter domain [t_3, t_n] = [{}, {}]",
                knots[3], knots[n]
            )));
        }
        if knots[3] == knots[4] || knots[n - 1] == knots[n] {
            return Err(Error::input(
                "an end control point has no influence on the domain (t_3 = t_4 or t_(n-1) = t_n); use 4 equal end knots to clamp",
            ));
        }
        let spans = (3..n).filter(|&i| knots[i] < knots[i + 1]).collect();
        Ok(Self {
            kind: KnotKind::General,
            knots,
            n_ctrl,
            spans,
        })
    }

    pub fn kind(&self) -> KnotKind {
        self.kind
    }
    pub fn n_ctrl(&self) -> usize {
        self.n_ctrl
    }
    /// All knots (for Periodic, the `n + 7` knots of the unwrapped form).
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// Parameter domain `[a, b]` (`[t_3, t_{len-4}]` for every kind).
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[3], self.knots[self.knots.len() - 4])
    }

    /// Number of non-empty knot spans inside the domain.
    pub fn n_segments(&self) -> usize {
        self.spans.len()
    }

    /// Knot index `i` of segment `seg` (`[t_i, t_{i+1})`). Panics if `seg >= n_segments()`.
    #[inline]
    pub(crate) fn span(&self, seg: usize) -> usize {
        self.spans[seg]
    }

    /// `[start, end]` of segment `seg`. Panics if `seg >= n_segments()`.
    pub fn segment_interval(&self, seg: usize) -> (f64, f64) {
        let i = self.spans[seg];
        (self.knots[i], self.knots[i + 1])
    }

    /// Global indices of the 4 control points segment `seg` touches, in local
    /// order 0..4 (wrapped modulo `n` for Periodic). Panics if `seg >= n_segments()`.
    #[inline]
    pub fn segment_ctrl(&self, seg: usize) -> [usize; 4] {
        let first = self.spans[seg] - 3;
        let mut idx = [first, first + 1, first + 2, first + 3];
        if self.kind == KnotKind::Periodic {
            for i in &mut idx {
                if *i >= self.n_ctrl {
                    *i -= self.n_ctrl;
                }
            }
        }
        idx
    }

    /// Tolerance for "on the domain boundary" / "equal to a knot".
    pub(crate) fn tol(&self) -> f64 {
        let (a, b) = self.domain();
        1e-12 * (b - a)
    }

    /// Periodic only: `u` wrapped into `[0, n)`.
    pub(crate) fn wrap(&self, u: f64) -> f64 {
        let p = self.n_ctrl as f64;
        let w = u - p * (u / p).floor();
        // Rounding can give exactly p (u slightly negative) or -0.0.
        if w >= p || w <= 0.0 {
            0.0
        } else {
            w
        }
    }

    fn outside(&self, u: f64) -> Error {
        let (a, b) = self.domain();
        Error::input(format!(
            "abscissa u = {u} is outside the rod's parameter domain [{a}, {b}]"
        ))
    }

    /// Segment containing `u` (`u == b` gives the last segment). Abscissae
    /// within `1e-12 (b - a)` outside the domain are accepted; Periodic wraps.
    pub fn locate(&self, u: f64) -> Result<usize> {
        let last = self.spans.len() - 1;
        if self.kind == KnotKind::Periodic {
            if !u.is_finite() {
                return Err(self.outside(u));
            }
            return Ok((self.wrap(u).floor() as usize).min(last));
        }
        let (a, b) = self.domain();
        let tol = self.tol();
        // Written so that NaN fails too.
        if !(u >= a - tol && u <= b + tol) {
            return Err(self.outside(u));
        }
        let u = u.clamp(a, b);
        Ok(match self.kind {
            // Unit spans starting at a: O(1). u − a ≥ 0 here, where the
            // cast's truncation is the floor (no libm call on baseline x86-64).
            KnotKind::Uniform | KnotKind::Clamped => ((u - a) as usize).min(last),
            _ => self
                .spans
                .partition_point(|&i| self.knots[i] <= u)
                .saturating_sub(1)
                .min(last),
        })
    }

    /// Basis functions of segment `seg` at `u`: `[derivative 0..=3][local 0..4]`,
    /// derivatives with respect to `u`. `u` may be anywhere (the segment's
    /// polynomial is extended); for Periodic, `u` may be off by whole periods.
    /// Panics if `seg >= n_segments()`. No allocation.
    #[inline]
    pub fn basis(&self, seg: usize, u: f64) -> [[f64; 4]; 4] {
        let i = self.spans[seg];
        match self.kind {
            KnotKind::Uniform => uniform_basis(u - self.knots[i]),
            KnotKind::Periodic => {
                let p = self.n_ctrl as f64;
                let t = u - self.knots[i];
                uniform_basis(t - p * (t / p).round())
            }
            // Clamped spans whose knots t_{i-2}..t_{i+3} are all unit-spaced
            // (2 <= seg <= n_segments - 3) have the uniform basis.
            KnotKind::Clamped if seg >= 2 && seg + 3 <= self.spans.len() => {
                uniform_basis(u - self.knots[i])
            }
            // The two first and two last segments, once the ends are apart
            // (≥ 7 control points: 4 segments or more), have fixed shapes.
            KnotKind::Clamped if self.spans.len() >= 4 => {
                let tables = clamped_end_tables();
                let x = u - self.knots[i];
                // 3: the last segment, 2: the one before; the first two
                // give less (saturating: a plain subtraction overflows
                // there, a panic in debug builds).
                match (seg + 4).saturating_sub(self.spans.len()) {
                    // The last segment from whichever end is nearer, so
                    // that both the knot it starts at and the domain's end
                    // get exact zeros (a position held at the far end
                    // touches only the last point with weight).
                    3 if x > 0.5 => taylor_basis(&tables[4], x - 1.0),
                    3 => taylor_basis(&tables[3], x),
                    2 => taylor_basis(&tables[2], x),
                    _ => taylor_basis(&tables[seg], x),
                }
            }
            KnotKind::Clamped | KnotKind::General => ders_basis(&self.knots, i, u),
        }
    }

    /// Greville abscissae `(t_{i+1} + t_{i+2} + t_{i+3}) / 3` (wrapped into
    /// `[0, n)` for Periodic). For Uniform the first/last lie outside the domain.
    pub fn greville(&self) -> Vec<f64> {
        (0..self.n_ctrl)
            .map(|i| {
                let g = (self.knots[i + 1] + self.knots[i + 2] + self.knots[i + 3]) / 3.0;
                if self.kind == KnotKind::Periodic {
                    self.wrap(g)
                } else {
                    g
                }
            })
            .collect()
    }

    /// Number of knots within `1e-12 (b - a)` of `u` (Periodic: of `u` wrapped, per period).
    pub fn multiplicity(&self, u: f64) -> usize {
        let tol = self.tol();
        if self.kind == KnotKind::Periodic {
            if !u.is_finite() {
                return 0;
            }
            let w = self.wrap(u);
            let near = (w - w.round()).abs() <= tol || (self.n_ctrl as f64 - w).abs() <= tol;
            return usize::from(near);
        }
        self.knots.iter().filter(|&&t| (t - u).abs() <= tol).count()
    }
}

/// Uniform cubic B-spline basis on a unit span, local parameter `t ∈ [0, 1]`
/// (thesis II.12–II.15) and its first three derivatives.
#[inline]
fn uniform_basis(t: f64) -> [[f64; 4]; 4] {
    let s = 1.0 - t;
    let t2 = t * t;
    let t3 = t2 * t;
    [
        [
            s * s * s / 6.0,
            (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0,
            (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0,
            t3 / 6.0,
        ],
        [
            -0.5 * s * s,
            1.5 * t2 - 2.0 * t,
            -1.5 * t2 + t + 0.5,
            0.5 * t2,
        ],
        [s, 3.0 * t - 2.0, 1.0 - 3.0 * t, t],
        [-1.0, 3.0, -3.0, 1.0],
    ]
}

/// The clamped knot vector's end segments (first, second, second-to-last,
/// last at its start, last at its end), each as its basis and derivatives
/// at that point: the same for every clamped vector of ≥ 7 control points
/// (their knots, from the segment's start, are 0,0,0,0,1,2,3 and its
/// mirror), so their Cox–de Boor recursion runs once, not at every
/// evaluation. Each is exact at its point (zeros where a basis vanishes).
fn clamped_end_tables() -> &'static [[[f64; 4]; 4]; 5] {
    static TABLES: std::sync::OnceLock<[[[f64; 4]; 4]; 5]> = std::sync::OnceLock::new();
    TABLES.get_or_init(|| {
        // 8 control points: 5 segments, the two ends apart.
        let n_ctrl = 8usize;
        let last = (n_ctrl - 3) as f64;
        let knots: Vec<f64> = (0..n_ctrl + 4).map(|i: usize| (i.saturating_sub(3) as f64).min(last)).collect();
        [(3usize, 0.0), (4, 1.0), (6, 3.0), (7, 4.0), (7, 5.0)].map(|(i, u)| ders_basis(&knots, i, u))
    })
}

/// A cubic segment's basis at `x` past its start, from its basis and
/// derivatives `t` there (Taylor, exact for cubics).
#[inline]
fn taylor_basis(t: &[[f64; 4]; 4], x: f64) -> [[f64; 4]; 4] {
    let mut out = [[0.0; 4]; 4];
    for k in 0..4 {
        let (d0, d1, d2, d3) = (t[0][k], t[1][k], t[2][k], t[3][k]);
        out[0][k] = d0 + x * (d1 + x * (0.5 * d2 + x * d3 / 6.0));
        out[1][k] = d1 + x * (d2 + 0.5 * x * d3);
        out[2][k] = d2 + x * d3;
        out[3][k] = d3;
    }
    out
}

/// Cox–de Boor basis functions and derivatives on span `i` (`t_i < t_{i+1}`),
/// Piegl & Tiller, *The NURBS Book*, algorithm A2.3, with p = n = 3.
/// Every divisor is a knot difference `t_{i+a} - t_{i-b}` with a >= 1, b >= 0,
/// so it is >= t_{i+1} - t_i > 0 on a non-empty span.
fn ders_basis(t: &[f64], i: usize, u: f64) -> [[f64; 4]; 4] {
    const P: usize = 3;
    let mut ndu = [[0.0f64; 4]; 4];
    let mut left = [0.0f64; 4];
    let mut right = [0.0f64; 4];
    ndu[0][0] = 1.0;
    for j in 1..=P {
        left[j] = u - t[i + 1 - j];
        right[j] = t[i + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r]; // knot differences (lower triangle)
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    let mut ders = [[0.0f64; 4]; 4];
    for j in 0..=P {
        ders[0][j] = ndu[j][P];
    }
    let mut a = [[0.0f64; 4]; 2];
    for r in 0..=P {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0][0] = 1.0;
        for k in 1..=P {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = P - k;
            if r >= k {
                let rk = rk as usize;
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                d = a[s2][0] * ndu[rk][pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if r as isize - 1 <= pk as isize {
                k - 1
            } else {
                P - r
            };
            for j in j1..=j2 {
                let c = (rk + j as isize) as usize;
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][c];
                d += a[s2][j] * ndu[c][pk];
            }
            if r <= pk {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    // Multiply by p! / (p - k)!.
    let mut fac = P as f64;
    for (k, row) in ders.iter_mut().enumerate().skip(1) {
        for v in row.iter_mut() {
            *v *= fac;
        }
        fac *= (P - k) as f64;
    }
    ders
}

/// Derivative of order `deriv` (0..=3) of the curve `Σ b_i(u) ctrl_i` at `u`.
pub fn eval<const D: usize>(
    knots: &KnotVector,
    ctrl: &[[f64; D]],
    u: f64,
    deriv: usize,
) -> Result<[f64; D]> {
    check_ctrl(knots, ctrl)?;
    if deriv > 3 {
        return Err(Error::input(format!(
            "derivative order {deriv} > 3 (cubic B-spline)"
        )));
    }
    let seg = knots.locate(u)?;
    let b = knots.basis(seg, u)[deriv];
    let idx = knots.segment_ctrl(seg);
    let mut out = [0.0; D];
    for (w, &i) in b.iter().zip(&idx) {
        for (o, c) in out.iter_mut().zip(&ctrl[i]) {
            *o += w * c;
        }
    }
    Ok(out)
}

pub(crate) fn check_ctrl<const D: usize>(knots: &KnotVector, ctrl: &[[f64; D]]) -> Result<()> {
    if ctrl.len() != knots.n_ctrl() {
        return Err(Error::input(format!(
            "the knot vector has {} control points, got {}",
            knots.n_ctrl(),
            ctrl.len()
        )));
    }
    Ok(())
}

#[cfg(test)]
#[allow(clippy::needless_range_loop, clippy::too_many_arguments)] // index-heavy checks
mod tests {
    use super::*;

    /// The clamped end segments' tables give the Cox–de Boor basis and its
    /// three derivatives (7–12 control points, 11 abscissae per segment),
    /// with exact zeros at the domain's ends and the knots the segments
    /// start at.
    #[test]
    fn clamped_end_tables_match_cox_de_boor() {
        for n in 7..=12 {
            let k = KnotVector::clamped(n).unwrap();
            let ns = k.n_segments();
            for seg in [0, 1, ns - 2, ns - 1] {
                let (a, b) = k.segment_interval(seg);
                for j in 0..=10 {
                    let u = a + (b - a) * j as f64 / 10.0;
                    let (fast, exact) = (k.basis(seg, u), ders_basis(&k.knots, k.spans[seg], u));
                    for d in 0..4 {
                        for l in 0..4 {
                            assert!((fast[d][l] - exact[d][l]).abs() < 1e-13, "n {n} seg {seg} u {u} d {d} l {l}: {} vs {}", fast[d][l], exact[d][l]);
                        }
                    }
                    if j == 0 || (seg == ns - 1 && j == 10) {
                        for l in 0..4 {
                            assert_eq!(fast[0][l] == 0.0, exact[0][l] == 0.0, "n {n} seg {seg} u {u}: zero pattern {:?} vs {:?}", fast[0], exact[0]);
                        }
                    }
                }
            }
        }
    }

    fn general() -> KnotVector {
        super::super::test_fixtures::general()
    }

    fn all_kinds() -> Vec<KnotVector> {
        vec![
            KnotVector::uniform(7).unwrap(),
            KnotVector::clamped(8).unwrap(),
            KnotVector::clamped(4).unwrap(),
            KnotVector::periodic(6).unwrap(),
            general(),
        ]
    }

    /// Abscissae spread over each segment, ends included.
    fn samples(k: &KnotVector) -> Vec<(usize, f64)> {
        let mut v = Vec::new();
        for s in 0..k.n_segments() {
            let (a, b) = k.segment_interval(s);
            for j in 0..=8 {
                v.push((s, a + (b - a) * j as f64 / 8.0));
            }
        }
        v
    }

    #[test]
    fn constructors_and_domains() {
        let u = KnotVector::uniform(7).unwrap();
        assert_eq!(
            (u.domain(), u.n_segments(), u.knots().len()),
            ((3.0, 7.0), 4, 11)
        );
        let c = KnotVector::clamped(7).unwrap();
        assert_eq!(c.knots(), &[0., 0., 0., 0., 1., 2., 3., 4., 4., 4., 4.]);
        assert_eq!((c.domain(), c.n_segments()), ((0.0, 4.0), 4));
        let p = KnotVector::periodic(5).unwrap();
        assert_eq!((p.domain(), p.n_segments()), ((0.0, 5.0), 5));
        assert_eq!(p.segment_ctrl(3), [3, 4, 0, 1]);
        assert_eq!(p.segment_interval(4), (4.0, 5.0));
        let g = general();
        assert_eq!((g.domain(), g.n_segments()), ((1.0, 5.0), 6));
        assert_eq!(g.segment_interval(1), (1.7, 2.0));
        assert_eq!(g.segment_ctrl(2), [3, 4, 5, 6]); // span [2, 3.5) starts at knot 6
        assert_eq!(g.multiplicity(3.5), 3);
        assert_eq!(g.multiplicity(5.0), 4);
        assert_eq!(g.multiplicity(4.1), 0);
        assert_eq!(p.multiplicity(7.0), 1);
        assert_eq!(p.multiplicity(2.5), 0);
        assert_eq!(
            c.greville(),
            vec![0.0, 1.0 / 3.0, 1.0, 2.0, 3.0, 11.0 / 3.0, 4.0]
        );
        assert_eq!(p.greville(), vec![4.0, 0.0, 1.0, 2.0, 3.0]);
    }

    #[test]
    fn too_few_control_points_and_bad_knots() {
        for r in [
            KnotVector::uniform(3),
            KnotVector::clamped(0),
            KnotVector::periodic(2),
        ] {
            match r {
                Err(e @ Error::InvalidInput { .. }) => { let m = e.to_string();
                    assert!(m.contains("at least 4 control points"), "{m}")
                }
                other => panic!("{other:?}"),
            }
        }
        let bad = [
            (vec![0., 1., 2., 3., 4., 5., 6.], 4),           // wrong length
            (vec![0., 1., 2., 3., 2., 5., 6., 7.], 4),       // decreasing
            (vec![0., 1., 2., 3., f64::NAN, 5., 6., 7.], 4), // NaN
            (vec![0., 0., 0., 0., 0., 1., 1., 1., 1.], 5),   // multiplicity 5
            (vec![0., 1., 2., 3., 3., 4., 5., 6.], 4),       // t_3 = t_4
        ];
        for (k, n) in bad {
            assert!(matches!(
                KnotVector::from_knots(k, n),
                Err(Error::InvalidInput { .. })
            ));
        }
    }

    #[test]
    fn partition_of_unity_and_derivative_sums() {
        for k in all_kinds() {
            for (s, u) in samples(&k) {
                let b = k.basis(s, u);
                let sums: Vec<f64> = b.iter().map(|r| r.iter().sum()).collect();
                assert!(
                    (sums[0] - 1.0).abs() < 1e-14,
                    "{:?} u={u}: {sums:?}",
                    k.kind()
                );
                for d in 1..4 {
                    assert!(sums[d].abs() < 1e-11, "{:?} u={u}: {sums:?}", k.kind());
                }
                assert!(b[0].iter().all(|&v| v >= -1e-15));
            }
        }
    }

    #[test]
    fn basis_derivatives_match_finite_differences() {
        let h = 1e-5;
        for k in all_kinds() {
            for (s, u) in samples(&k) {
                let (bp, bm) = (k.basis(s, u + h), k.basis(s, u - h));
                let b = k.basis(s, u);
                for d in 0..3 {
                    for l in 0..4 {
                        let fd = (bp[d][l] - bm[d][l]) / (2.0 * h);
                        assert!(
                            (fd - b[d + 1][l]).abs() < 1e-6 * (1.0 + b[d + 1][l].abs()),
                            "{:?} d={d} l={l} u={u}",
                            k.kind()
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn clamped_matches_cox_de_boor_and_uniform_closed_form() {
        // The closed form used for Uniform (and interior Clamped spans) equals the general recursion.
        for k in [
            KnotVector::uniform(6).unwrap(),
            KnotVector::clamped(12).unwrap(),
            KnotVector::clamped(6).unwrap(),
        ] {
            for (s, x) in samples(&k) {
                let a = k.basis(s, x);
                let b = ders_basis(k.knots(), k.span(s), x);
                for d in 0..4 {
                    for l in 0..4 {
                        assert!(
                            (a[d][l] - b[d][l]).abs() < 1e-13,
                            "{:?} seg {s} u {x}",
                            k.kind()
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn clamped_interpolates_end_points_and_tangents() {
        let k = KnotVector::clamped(6).unwrap();
        let ctrl: Vec<[f64; 2]> = (0..6).map(|i| [i as f64, (i * i) as f64]).collect();
        let (a, b) = k.domain();
        assert_eq!(eval(&k, &ctrl, a, 0).unwrap(), ctrl[0]);
        assert_eq!(eval(&k, &ctrl, b, 0).unwrap(), ctrl[5]);
        // Tangent at the start is 3 (P1 - P0) / (t_4 - t_1).
        let d = eval(&k, &ctrl, a, 1).unwrap();
        assert!((d[0] - 3.0).abs() < 1e-14 && (d[1] - 3.0).abs() < 1e-14);
    }

    #[test]
    fn periodic_closes_with_c2_seam_and_wraps() {
        let k = KnotVector::periodic(5).unwrap();
        let ctrl: Vec<[f64; 3]> = (0..5)
            .map(|i| [(i as f64).cos(), (i as f64).sin(), (i * i) as f64])
            .collect();
        let n = k.n_segments();
        let idx_end = k.segment_ctrl(n - 1);
        let idx_0 = k.segment_ctrl(0);
        let (be, b0) = (k.basis(n - 1, 5.0), k.basis(0, 0.0));
        for d in 0..3 {
            for c in 0..3 {
                let ve: f64 = (0..4).map(|l| be[d][l] * ctrl[idx_end[l]][c]).sum();
                let v0: f64 = (0..4).map(|l| b0[d][l] * ctrl[idx_0[l]][c]).sum();
                assert!((ve - v0).abs() < 1e-13, "derivative {d} jumps at the seam");
            }
        }
        for u in [0.3, 2.7, 4.99] {
            for d in 0..4 {
                let a = eval(&k, &ctrl, u, d).unwrap();
                for m in [-2.0, 1.0, 3.0] {
                    let b = eval(&k, &ctrl, u + m * 5.0, d).unwrap();
                    for c in 0..3 {
                        assert!((a[c] - b[c]).abs() < 1e-12);
                    }
                }
            }
        }
        assert_eq!(k.locate(-0.5).unwrap(), 4);
        assert_eq!(k.locate(5.0).unwrap(), 0);
        assert!(k.locate(f64::NAN).is_err() && k.locate(f64::INFINITY).is_err());
    }

    #[test]
    fn locate_finds_segments_and_rejects_outside() {
        let g = general();
        for (s, u) in samples(&g) {
            let (a, b) = g.segment_interval(s);
            let found = g.locate(u).unwrap();
            if u > a && u < b {
                assert_eq!(found, s);
            }
        }
        assert_eq!(g.locate(5.0).unwrap(), g.n_segments() - 1);
        assert_eq!(g.locate(3.5).unwrap(), 3);
        assert_eq!(g.locate(1.0 - 1e-13).unwrap(), 0);
        let u = KnotVector::uniform(6).unwrap();
        assert_eq!(u.locate(6.0).unwrap(), 2);
        assert_eq!(u.locate(4.5).unwrap(), 1);
        for bad in [f64::NAN, 2.9, 6.1, f64::NEG_INFINITY] {
            match u.locate(bad) {
                Err(e @ Error::InvalidInput { .. }) => {
                    let m = e.to_string();
                    assert!(m.contains("outside the rod's parameter domain [3, 6]"), "{m}")
                }
                other => panic!("{other:?}"),
            }
        }
        let ctrl = vec![[0.0; 2]; 6];
        assert!(eval(&u, &ctrl, f64::NAN, 0).is_err());
        assert!(eval(&u, &ctrl, 4.0, 4).is_err());
        assert!(eval(&u, &ctrl[..5], 4.0, 0).is_err());
    }

    #[test]
    fn serde_round_trip_and_validation() {
        for k in all_kinds() {
            let s = serde_json::to_string(&k).unwrap();
            let back: KnotVector = serde_json::from_str(&s).unwrap();
            assert_eq!(back, k);
        }
        let bad = r#"{"kind":"Uniform","knots":[0,1,2,3,4,5,6,8],"n_ctrl":4}"#;
        assert!(serde_json::from_str::<KnotVector>(bad).is_err());
        let bad = r#"{"kind":"General","knots":[0,1,2,3,2,5,6,7],"n_ctrl":4}"#;
        assert!(serde_json::from_str::<KnotVector>(bad).is_err());
    }
}
