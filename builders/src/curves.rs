//! Shapes parametrised by arc length: hanging cables, polylines, circles
//! (the initial shapes of ropes and cables, and the closed forms the tests
//! compare with).
use nalgebra::Vector3;
use strandkit_core::{Error, Result};

/// The catenary through (0, 0) and (span, 0) with mid-span sag `sag`
/// (y up): y = a cosh((x − S/2)/a) − a cosh(S/2a), d = a (cosh(S/2a) − 1).
#[derive(Clone, Copy, Debug)]
pub struct Catenary {
    pub span: f64,
    /// Catenary parameter a = H / w (m).
    pub a: f64,
}

impl Catenary {
    /// The catenary of the given sag (bisection on a: d(a) decreases).
    pub fn with_sag(span: f64, sag: f64) -> Result<Catenary> {
        Self::solve(span, |a| a * ((span / (2.0 * a)).cosh() - 1.0) - sag)
    }
    /// The catenary of the given length (> span).
    pub fn with_length(span: f64, length: f64) -> Result<Catenary> {
        if !(length > span) {
            return Err(Error::invalid("catenary length", length, format!("> the span {span}")));
        }
        Self::solve(span, |a| 2.0 * a * (span / (2.0 * a)).sinh() - length)
    }
    /// f(a) decreasing in a, positive for small a: its root by bisection in
    /// log a (to round-off).
    fn solve(span: f64, f: impl Fn(f64) -> f64) -> Result<Catenary> {
        let (mut lo, mut hi) = (span * 1e-3, span * 1e6);
        if !(f(lo) > 0.0 && f(hi) < 0.0) {
            return Err(Error::invalid("catenary", "sag or length", "a sag between 1e-6 and 100 spans"));
        }
        for _ in 0..200 {
            let mid = (lo * hi).sqrt();
            if f(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Ok(Catenary { span, a: (lo * hi).sqrt() })
    }
    pub fn sag(&self) -> f64 {
        self.a * ((self.span / (2.0 * self.a)).cosh() - 1.0)
    }
    pub fn length(&self) -> f64 {
        2.0 * self.a * (self.span / (2.0 * self.a)).sinh()
    }
    pub fn y(&self, x: f64) -> f64 {
        self.a * (((x - 0.5 * self.span) / self.a).cosh() - (0.5 * self.span / self.a).cosh())
    }
    /// The point at arc length s from (0, 0).
    pub fn at_arc_length(&self, s: f64) -> Vector3<f64> {
        let h = 0.5 * self.span / self.a;
        let x = 0.5 * self.span + self.a * (s / self.a - h.sinh()).asinh();
        Vector3::new(x, self.y(x), 0.0)
    }
}

/// A polyline parametrised by arc length: the funicular polygon of a
/// loaded cable, or a cable's route given as points.
#[derive(Clone, Debug)]
pub struct Polyline {
    pub nodes: Vec<Vector3<f64>>,
    /// Arc length at each node.
    pub at: Vec<f64>,
}

impl Polyline {
    /// Through `nodes` (at least 2, finite, no two consecutive equal);
    /// `what` names the argument in errors.
    pub fn new(nodes: Vec<Vector3<f64>>, what: &str) -> Result<Polyline> {
        if nodes.len() < 2 {
            return Err(Error::invalid(what, format!("{} points", nodes.len()), "at least 2 points"));
        }
        for (k, x) in nodes.iter().enumerate() {
            strandkit_core::constraint::finite3(&[x.x, x.y, x.z], &format!("{what}[{k}]"))?;
        }
        if let Some(k) = nodes.windows(2).position(|w| (w[1] - w[0]).norm() == 0.0) {
            return Err(Error::invalid(format!("{what}[{}]", k + 1), format!("{:?}", nodes[k + 1].as_slice()), "a point distinct from the one before it"));
        }
        Ok(Self::through(nodes))
    }
    fn through(nodes: Vec<Vector3<f64>>) -> Polyline {
        let mut at = vec![0.0];
        for w in nodes.windows(2) {
            at.push(at.last().copied().unwrap_or(0.0) + (w[1] - w[0]).norm());
        }
        Polyline { nodes, at }
    }
    /// The funicular polygon of N equal loads at equal horizontal spacing
    /// Δ = S/(N+1): nodes on the parabola y = −4d x(S−x)/S² (y up).
    pub fn funicular(span: f64, sag: f64, n_loads: usize) -> Polyline {
        let dx = span / (n_loads + 1) as f64;
        Self::through((0..n_loads + 2).map(|k| {
            let x = k as f64 * dx;
            Vector3::new(x, -4.0 * sag * x * (span - x) / (span * span), 0.0)
        }).collect())
    }
    /// The same route with every corner rounded by a circular arc of
    /// radius `radius` (m; smaller where the neighbouring segments are
    /// too short: the arc takes at most half of each), drawn as 24 chords
    /// per arc. A cable laid along it bends as a cable can.
    pub fn rounded(&self, radius: f64) -> Polyline {
        let n = self.nodes.len();
        let mut out = vec![self.nodes[0]];
        for k in 1..n - 1 {
            let (a, p, b) = (self.nodes[k - 1], self.nodes[k], self.nodes[k + 1]);
            let (d1, d2) = ((p - a).normalize(), (b - p).normalize());
            let phi = d1.dot(&d2).clamp(-1.0, 1.0).acos();
            if phi < 1e-9 || phi > std::f64::consts::PI - 1e-9 {
                out.push(p); // straight on, or a U-turn (kept as a corner)
                continue;
            }
            let t = (radius * (0.5 * phi).tan()).min(0.5 * (p - a).norm()).min(0.5 * (b - p).norm());
            let rho = t / (0.5 * phi).tan();
            let inward = (d2 - d1 * d1.dot(&d2)).normalize();
            let centre = p - d1 * t + inward * rho;
            for j in 0..=24 {
                let alpha = phi * j as f64 / 24.0;
                out.push(centre + (-inward * alpha.cos() + d1 * alpha.sin()) * rho);
            }
        }
        out.push(self.nodes[n - 1]);
        out.dedup_by(|x, y| (*x - *y).norm() == 0.0);
        Self::through(out)
    }
    pub fn length(&self) -> f64 {
        self.at.last().copied().unwrap_or(0.0)
    }
    /// The point at arc length s along the polyline (clamped to its ends).
    pub fn at_arc_length(&self, s: f64) -> Vector3<f64> {
        let k = self.at.partition_point(|&a| a <= s).clamp(1, self.at.len() - 1);
        let (s0, s1) = (self.at[k - 1], self.at[k]);
        let t = ((s - s0) / (s1 - s0)).clamp(0.0, 1.0);
        self.nodes[k - 1] + (self.nodes[k] - self.nodes[k - 1]) * t
    }
}

/// A circular arc (or whole circle) in a vertical plane, parametrised by
/// arc length from `start`, turning downwards first (y up).
#[derive(Clone, Copy, Debug)]
pub struct CircleArc {
    pub center: Vector3<f64>,
    pub radius: f64,
    /// Unit vectors of the circle's plane: p(φ) = c + R (cos φ e1 + sin φ e2).
    e1: Vector3<f64>,
    e2: Vector3<f64>,
}

/// The in-plane "down" direction of a chord: −y without its part along
/// the chord (x when the chord is vertical).
fn down_across(chord: Vector3<f64>) -> Vector3<f64> {
    let e = chord.normalize();
    let d = -Vector3::y() + e * e.y;
    if d.norm() < 1e-9 {
        Vector3::x()
    } else {
        d.normalize()
    }
}

impl CircleArc {
    /// The arc of length `length` from `a` to `b` hanging below the chord
    /// (sin α / α = |ab| / length, α the half angle); needs |ab| < length.
    pub fn hanging(a: Vector3<f64>, b: Vector3<f64>, length: f64) -> Result<CircleArc> {
        let c = (b - a).norm();
        if !(c > 0.0 && c < length) {
            return Err(Error::invalid("support distance", c, format!("in (0, the string length {length}) m")));
        }
        // sin α/α decreases from 1 to 0 on (0, π): bisection.
        let (mut lo, mut hi) = (0.0f64, std::f64::consts::PI);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid.sin() / mid > c / length {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let alpha = 0.5 * (lo + hi);
        let radius = length / (2.0 * alpha);
        let d = down_across(b - a);
        let center = 0.5 * (a + b) - d * (radius * alpha.cos());
        Ok(Self::through(center, radius, a, d))
    }

    /// The circle of circumference `length` through `a` and `b`, both on its
    /// upper part (chord |ab| ≤ length/π), starting at `a` downwards; the
    /// arc from `a` to `b` the long way round is [`CircleArc::long_arc`].
    pub fn loop_through(a: Vector3<f64>, b: Vector3<f64>, length: f64) -> Result<CircleArc> {
        let radius = length / (2.0 * std::f64::consts::PI);
        let c = (b - a).norm();
        if !(c > 0.0 && c <= 2.0 * radius) {
            return Err(Error::invalid("support distance", c, format!("in (0, length/π = {}] m for a closed necklace", 2.0 * radius)));
        }
        let d = down_across(b - a);
        let center = 0.5 * (a + b) + d * (radius * radius - 0.25 * c * c).max(0.0).sqrt();
        Ok(Self::through(center, radius, a, d))
    }

    /// The circle of circumference `length` hanging from its top point `top`.
    pub fn hanging_loop(top: Vector3<f64>, length: f64) -> CircleArc {
        let radius = length / (2.0 * std::f64::consts::PI);
        Self::through(top - Vector3::y() * radius, radius, top, Vector3::x())
    }

    /// Circle of centre `center` through `a`, heading from `a` towards `down`.
    fn through(center: Vector3<f64>, radius: f64, a: Vector3<f64>, down: Vector3<f64>) -> CircleArc {
        let e1 = (a - center) / radius;
        let mut e2 = down - e1 * e1.dot(&down);
        if e2.norm() < 1e-12 {
            e2 = Vector3::y().cross(&e1);
        }
        CircleArc { center, radius, e1, e2: e2.normalize() }
    }

    /// Arc length from the start to `b` going round the long way (for
    /// `loop_through`).
    pub fn long_arc(&self, b: Vector3<f64>) -> f64 {
        let v = (b - self.center) / self.radius;
        let phi = v.dot(&self.e2).atan2(v.dot(&self.e1));
        self.radius * phi.rem_euclid(2.0 * std::f64::consts::PI)
    }

    pub fn at_arc_length(&self, s: f64) -> Vector3<f64> {
        let phi = s / self.radius;
        self.center + (self.e1 * phi.cos() + self.e2 * phi.sin()) * self.radius
    }
}
