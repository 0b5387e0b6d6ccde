//! Hanging-cable shapes parametrised by arc length (the initial shapes of
//! ropes, and the closed forms the tests compare with).
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

/// The funicular polygon of N equal loads at equal horizontal spacing
/// Δ = S/(N+1): nodes on the parabola y = −4d x(S−x)/S² (y up).
#[derive(Clone, Debug)]
pub struct LoadedCable {
    pub nodes: Vec<Vector3<f64>>,
    /// Arc length at each node.
    pub at: Vec<f64>,
}

impl LoadedCable {
    pub fn new(span: f64, sag: f64, n_loads: usize) -> LoadedCable {
        let dx = span / (n_loads + 1) as f64;
        let nodes: Vec<Vector3<f64>> = (0..n_loads + 2).map(|k| {
            let x = k as f64 * dx;
            Vector3::new(x, -4.0 * sag * x * (span - x) / (span * span), 0.0)
        }).collect();
        let mut at = vec![0.0];
        for w in nodes.windows(2) {
            at.push(at.last().copied().unwrap_or(0.0) + (w[1] - w[0]).norm());
        }
        LoadedCable { nodes, at }
    }
    pub fn length(&self) -> f64 {
        self.at.last().copied().unwrap_or(0.0)
    }
    /// The point at arc length s along the polygon.
    pub fn at_arc_length(&self, s: f64) -> Vector3<f64> {
        let k = self.at.partition_point(|&a| a <= s).clamp(1, self.at.len() - 1);
        let (s0, s1) = (self.at[k - 1], self.at[k]);
        let t = ((s - s0) / (s1 - s0)).clamp(0.0, 1.0);
        self.nodes[k - 1] + (self.nodes[k] - self.nodes[k - 1]) * t
    }
}
