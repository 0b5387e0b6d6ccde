//! Second-order jets in six variables (test only): a value with its exact
//! gradient and Hessian, carried through +, −, ×, 1/x and √x by the chain
//! rule — the plain evaluation of the reference-frame strains in (r′, r″)
//! that [`super::qlinear`]'s structured one is checked against.
use std::ops::{Add, Mul, Neg, Sub};

/// Number of variables.
pub const N: usize = 6;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jet {
    pub v: f64,
    pub g: [f64; N],
    /// Hessian, upper half only: `h[i][k]` for k ≥ i (the rest stays 0;
    /// read with [`Jet::hess`]). Half the work of every operation.
    pub h: [[f64; N]; N],
}

impl Jet {
    pub fn constant(v: f64) -> Jet {
        Jet { v, g: [0.0; N], h: [[0.0; N]; N] }
    }
    /// Variable `i` at value `v`.
    pub fn var(i: usize, v: f64) -> Jet {
        let mut j = Jet::constant(v);
        j.g[i] = 1.0;
        j
    }
    /// Hessian entry (i, k) of either half.
    #[inline(always)]
    pub fn hess(&self, i: usize, k: usize) -> f64 {
        if k >= i {
            self.h[i][k]
        } else {
            self.h[k][i]
        }
    }
    /// f(self) given f, f′, f″ at self.v.
    #[inline(always)]
    fn compose(self, f: f64, f1: f64, f2: f64) -> Jet {
        let mut out = Jet::constant(f);
        for i in 0..N {
            out.g[i] = f1 * self.g[i];
            for k in i..N {
                out.h[i][k] = f1 * self.h[i][k] + f2 * self.g[i] * self.g[k];
            }
        }
        out
    }
    pub fn recip(self) -> Jet {
        let r = 1.0 / self.v;
        self.compose(r, -r * r, 2.0 * r * r * r)
    }
    pub fn sqrt(self) -> Jet {
        let s = self.v.sqrt();
        self.compose(s, 0.5 / s, -0.25 / (s * self.v))
    }
}

impl Add for Jet {
    type Output = Jet;
    #[inline(always)]
    fn add(mut self, o: Jet) -> Jet {
        self.v += o.v;
        for i in 0..N {
            self.g[i] += o.g[i];
            for k in i..N {
                self.h[i][k] += o.h[i][k];
            }
        }
        self
    }
}

impl Sub for Jet {
    type Output = Jet;
    #[inline(always)]
    fn sub(self, o: Jet) -> Jet {
        self + (-o)
    }
}

impl Neg for Jet {
    type Output = Jet;
    #[inline(always)]
    fn neg(self) -> Jet {
        self * -1.0
    }
}

impl Mul<f64> for Jet {
    type Output = Jet;
    #[inline(always)]
    fn mul(mut self, k: f64) -> Jet {
        self.v *= k;
        for i in 0..N {
            self.g[i] *= k;
            for x in &mut self.h[i][i..] {
                *x *= k;
            }
        }
        self
    }
}

impl Add<f64> for Jet {
    type Output = Jet;
    #[inline(always)]
    fn add(mut self, k: f64) -> Jet {
        self.v += k;
        self
    }
}

impl Mul for Jet {
    type Output = Jet;
    /// (ab)″ = a b″ + b a″ + a′ b′ᵀ + b′ a′ᵀ.
    #[inline(always)]
    fn mul(self, o: Jet) -> Jet {
        let mut out = Jet::constant(self.v * o.v);
        for i in 0..N {
            out.g[i] = self.v * o.g[i] + o.v * self.g[i];
            for k in i..N {
                out.h[i][k] = self.v * o.h[i][k] + o.v * self.h[i][k] + self.g[i] * o.g[k] + o.g[i] * self.g[k];
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f(x) = √(x0² + x1 x2) / (1 + x3 x4 − x5) against central differences
    /// of the value (gradient) and of the jet's own gradient (Hessian).
    fn f(x: &[Jet; N]) -> Jet {
        (x[0] * x[0] + x[1] * x[2]).sqrt() * (x[3] * x[4] - x[5] + 1.0).recip()
    }

    fn at(p: &[f64; N]) -> Jet {
        let x: [Jet; N] = std::array::from_fn(|i| Jet::var(i, p[i]));
        f(&x)
    }

    #[test]
    fn jet_derivatives_match_central_differences() {
        let p = [0.7, 0.4, 1.3, 0.2, -0.5, 0.3];
        let j = at(&p);
        let h = 1e-6;
        for i in 0..N {
            let (mut a, mut b) = (p, p);
            a[i] += h;
            b[i] -= h;
            let (ja, jb) = (at(&a), at(&b));
            let g = (ja.v - jb.v) / (2.0 * h);
            assert!((g - j.g[i]).abs() < 1e-8, "gradient {i}: {g} vs {}", j.g[i]);
            for k in 0..N {
                let hk = (ja.g[k] - jb.g[k]) / (2.0 * h);
                assert!((hk - j.hess(i, k)).abs() < 1e-7, "hessian {i},{k}: {hk} vs {}", j.hess(i, k));
            }
        }
    }
}
