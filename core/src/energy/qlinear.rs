//! The reference-frame model's bending strains with exact first and second
//! derivatives, exploiting their structure: in the old frame's basis, with
//! p = r′ and q = r″, each is F(p) + Σ_j q_j G_j(p) — linear in q (SPEC
//! §2.3; the formulas are in [`super::reference`]). So only functions of the
//! three components of p need second-order jets ([`J3`]: value, gradient,
//! packed 3×3 Hessian); the q rows follow: ∂S/∂q_j = G_j, ∂²S/∂p∂q_j =
//! ∇G_j, ∂²S/∂q² = 0. A third of the work of six-variable jets, checked
//! against them in the tests below.

/// A function of p = (p0, p1, p2) with its gradient and Hessian (packed:
/// 00, 01, 02, 11, 12, 22).
#[derive(Clone, Copy, Debug, Default)]
pub struct J3 {
    pub v: f64,
    pub g: [f64; 3],
    pub h: [f64; 6],
}

/// Packed index of Hessian entry (a, b).
#[inline(always)]
pub const fn hp(a: usize, b: usize) -> usize {
    const IDX: [[usize; 3]; 3] = [[0, 1, 2], [1, 3, 4], [2, 4, 5]];
    IDX[a][b]
}

impl J3 {
    /// Variable p_i at value v.
    #[inline(always)]
    pub fn var(i: usize, v: f64) -> J3 {
        let mut j = J3 { v, ..Default::default() };
        j.g[i] = 1.0;
        j
    }
    /// f(self) from f, f′, f″ at self.v.
    #[inline(always)]
    fn compose(self, f: f64, f1: f64, f2: f64) -> J3 {
        let g = self.g;
        let mut h = [0.0; 6];
        for a in 0..3 {
            for b in a..3 {
                h[hp(a, b)] = f1 * self.h[hp(a, b)] + f2 * g[a] * g[b];
            }
        }
        J3 { v: f, g: [f1 * g[0], f1 * g[1], f1 * g[2]], h }
    }
    #[inline(always)]
    pub fn recip(self) -> J3 {
        let r = 1.0 / self.v;
        self.compose(r, -r * r, 2.0 * r * r * r)
    }
    #[inline(always)]
    pub fn sqrt(self) -> J3 {
        let s = self.v.sqrt();
        self.compose(s, 0.5 / s, -0.25 / (s * self.v))
    }
    #[inline(always)]
    pub fn mul(self, o: J3) -> J3 {
        let mut h = [0.0; 6];
        for a in 0..3 {
            for b in a..3 {
                let k = hp(a, b);
                h[k] = self.v * o.h[k] + o.v * self.h[k] + self.g[a] * o.g[b] + o.g[a] * self.g[b];
            }
        }
        // Written out (not `array::from_fn`): these run per sample, and
        // whether from_fn's closure got inlined moved with unrelated code
        // (a 6 % `try_from_fn` in the reference-model spring).
        let g = [self.v * o.g[0] + o.v * self.g[0], self.v * o.g[1] + o.v * self.g[1], self.v * o.g[2] + o.v * self.g[2]];
        J3 { v: self.v * o.v, g, h }
    }
    /// self × p_i (a variable: gradient e_i, no Hessian).
    #[inline(always)]
    pub fn mul_var(self, i: usize, pi: f64) -> J3 {
        let mut out = J3 { v: self.v * pi, g: self.g.map(|x| x * pi), h: self.h.map(|x| x * pi) };
        out.g[i] += self.v;
        for a in 0..3 {
            out.h[hp(a, i)] += self.g[a];
        }
        // (a, i) with a = i got g[i] once above; the symmetric term adds it again.
        out.h[hp(i, i)] += self.g[i];
        out
    }
    #[inline(always)]
    pub fn scale(self, k: f64) -> J3 {
        J3 { v: self.v * k, g: self.g.map(|x| x * k), h: self.h.map(|x| x * k) }
    }
    #[inline(always)]
    pub fn add(self, o: J3) -> J3 {
        let mut h = self.h;
        for (x, y) in h.iter_mut().zip(&o.h) {
            *x += y;
        }
        J3 { v: self.v + o.v, g: [self.g[0] + o.g[0], self.g[1] + o.g[1], self.g[2] + o.g[2]], h }
    }
}

/// A strain S = F(p) + Σ_j q_j G_j(p).
#[derive(Clone, Copy, Debug, Default)]
pub struct QLinear {
    pub f: J3,
    pub gq: [J3; 3],
}

impl QLinear {
    /// Value and gradient in (p, q).
    #[inline(always)]
    pub fn value_grad(&self, q: &[f64; 3]) -> (f64, [f64; 6]) {
        let mut v = self.f.v;
        let mut g = [0.0; 6];
        g[..3].copy_from_slice(&self.f.g);
        for j in 0..3 {
            let gj = &self.gq[j];
            v += q[j] * gj.v;
            g[3 + j] = gj.v;
            for a in 0..3 {
                g[a] += q[j] * gj.g[a];
            }
        }
        (v, g)
    }
    /// The Hessian blocks of α S + β T (pp packed, pq with `pq[a][j]` =
    /// ∂²/∂p_a∂q_j; qq is zero), without forming either strain's own.
    #[inline(always)]
    pub fn combined_hessian(s: &QLinear, alpha: f64, t: &QLinear, beta: f64, q: &[f64; 3]) -> ([f64; 6], [[f64; 3]; 3]) {
        let mut hpp = [0.0f64; 6];
        for (k, x) in hpp.iter_mut().enumerate() {
            *x = alpha * s.f.h[k] + beta * t.f.h[k];
        }
        let mut hpq = [[0.0; 3]; 3];
        for j in 0..3 {
            let (sa, tb) = (alpha * q[j], beta * q[j]);
            for k in 0..6 {
                hpp[k] += sa * s.gq[j].h[k] + tb * t.gq[j].h[k];
            }
            for a in 0..3 {
                hpq[a][j] = alpha * s.gq[j].g[a] + beta * t.gq[j].g[a];
            }
        }
        (hpp, hpq)
    }
}

/// The bending strains' building blocks at p (old-frame basis):
/// curvature-binormal components x = κb·d1, y = κb·d2. (The twist, whose
/// strain has a simpler structure, is written in world components in
/// [`super::reference`].)
pub struct Kinematics {
    pub x: QLinear,
    pub y: QLinear,
}

/// x = (c1 − p0 c3/(s + p2))/s³, y = (c2 − p1 c3/(s + p2))/s³, with
/// c = p × q, s = |p| (their F parts are zero).
pub fn kinematics(p: [f64; 3]) -> Kinematics {
    let pv: [J3; 3] = std::array::from_fn(|i| J3::var(i, p[i]));
    let a = pv[0].mul_var(0, p[0]).add(pv[1].mul_var(1, p[1])).add(pv[2].mul_var(2, p[2]));
    let s = a.sqrt();
    let inv = s.recip();
    let id = s.add(pv[2]).recip();
    let (mut x, mut y) = (QLinear::default(), QLinear::default());
    let is3 = inv.mul(inv).mul(inv);
    // ∂c/∂q_j: c1 = p1 q2 − p2 q1, c2 = p2 q0 − p0 q2, c3 = p0 q1 − p1 q0.
    let pc = is3.mul(id); // multiplies p_i c3 in x and y
    let px = pc.mul_var(0, p[0]);
    let py = pc.mul_var(1, p[1]);
    x.gq = [px.mul_var(1, p[1]), is3.mul_var(2, p[2]).add(px.mul_var(0, p[0])).scale(-1.0), is3.mul_var(1, p[1])];
    y.gq = [is3.mul_var(2, p[2]).add(py.mul_var(1, p[1])), py.mul_var(0, p[0]).scale(-1.0), is3.mul_var(0, p[0]).scale(-1.0)];
    Kinematics { x, y }
}

#[cfg(test)]
mod tests {
    use super::super::jet::{Jet, N};
    use super::*;

    /// The same strains on six-variable jets (the generic formulas).
    fn reference(p: [f64; 3], q: [f64; 3]) -> [Jet; 2] {
        let pj: [Jet; 3] = std::array::from_fn(|i| Jet::var(i, p[i]));
        let qj: [Jet; 3] = std::array::from_fn(|i| Jet::var(3 + i, q[i]));
        let a = pj[0] * pj[0] + pj[1] * pj[1] + pj[2] * pj[2];
        let s = a.sqrt();
        let inv = s.recip();
        let id = (s + pj[2]).recip();
        let c1 = pj[1] * qj[2] - pj[2] * qj[1];
        let c2 = pj[2] * qj[0] - pj[0] * qj[2];
        let c3 = pj[0] * qj[1] - pj[1] * qj[0];
        let is3 = inv * inv * inv;
        let x = (c1 - pj[0] * c3 * id) * is3;
        let y = (c2 - pj[1] * c3 * id) * is3;
        [x, y]
    }

    #[test]
    fn q_linear_kinematics_match_six_variable_jets() {
        let cases = [
            ([0.3, -0.2, 1.1], [0.5, 0.7, -0.4]),
            ([-0.9, 0.4, 0.2], [-1.5, 0.1, 0.6]),
            ([0.01, 0.02, -0.7], [0.3, 0.3, 0.3]),
            ([1.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
        ];
        for (p, q) in cases {
            let kin = kinematics(p);
            let jets = reference(p, q);
            // Each strain alone (α = 1, β = 0, and the other way round) and
            // one combination.
            for (alpha, beta) in [(1.0, 0.0), (0.0, 1.0), (0.7, -1.3)] {
                let (hpp, hpq) = QLinear::combined_hessian(&kin.x, alpha, &kin.y, beta, &q);
                let want = |a: usize, b: usize| alpha * jets[0].hess(a, b) + beta * jets[1].hess(a, b);
                for a in 0..3 {
                    for b in 0..3 {
                        let (pp, pq) = (want(a, b), want(a, 3 + b));
                        assert!((hpp[hp(a, b)] - pp).abs() < (1.0 + pp.abs()) * 1e-11, "pp ({a},{b}): {} vs {pp}", hpp[hp(a, b)]);
                        assert!((hpq[a][b] - pq).abs() < (1.0 + pq.abs()) * 1e-11, "pq ({a},{b}): {} vs {pq}", hpq[a][b]);
                        assert!(want(3 + a, 3 + b).abs() < 1e-14, "qq ({a},{b}) should vanish");
                    }
                }
            }
            for (s, jet) in [kin.x, kin.y].iter().zip(jets) {
                let (v, g) = s.value_grad(&q);
                let scale = 1.0 + jet.v.abs() + jet.g.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                assert!((v - jet.v).abs() < 1e-12 * scale, "value {v} vs {}", jet.v);
                for i in 0..N {
                    assert!((g[i] - jet.g[i]).abs() < 1e-12 * scale, "gradient {i}: {} vs {}", g[i], jet.g[i]);
                }
            }
        }
    }
}
