//! Pair stagger (a base pair's shear, SPEC §9.1): the two points of a
//! base pair — one on strand a, one on strand b — read along the local
//! helix axis, (r_b − r_a)·ẑ = rest. ẑ comes from three consecutive pairs'
//! rung midpoints ([`helix_axis`]), which do not move when the pair's two
//! points slide past each other: the row is the pair's stagger and nothing
//! else to first order (the duplex turning, twisting or stretching leaves
//! it). With a distance rung and stagger-free stacking
//! ([`super::BasePairStep::stagger_free`]) it makes the hydrogen bonds a
//! relative position in the pair's own frame: the rung of de Gennes'
//! ladder, whose stiffness R (1 / compliance) against the backbone's Q sets
//! the shear load's decay length κ⁻¹ = √(Q/2R).
use super::base_pair_step::{axis_lambda, control_points, helix_axis, helix_axis_jacobian, select, unit, J3};
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{ConstraintLaw, Reaction, Row, Side, MAX_ENTRIES};
use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// (r_b(ub) − r_a(ua))·ẑ = `rest`, ẑ the helix axis through the rung
/// midpoints of three consecutive pairs (first, middle, last; the pair
/// itself among them) with the rule's `axis_lambda`. Multiplier: the
/// force along ẑ on strand a's point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairStagger {
    pub ua: f64,
    pub ub: f64,
    pub ua_first: f64,
    pub ub_first: f64,
    pub ua_middle: f64,
    pub ub_middle: f64,
    pub ua_last: f64,
    pub ub_last: f64,
    /// λ of [`helix_axis`] (set at rest by [`PairStagger::at_rest`]).
    pub axis_lambda: f64,
    /// The stagger at rest (length).
    pub rest: f64,
}

impl PairStagger {
    /// The eight abscissae with their side: the pair, then the axis triple.
    fn points(&self) -> [(usize, f64); 8] {
        [(0, self.ua), (1, self.ub), (0, self.ua_first), (1, self.ub_first), (0, self.ua_middle), (1, self.ub_middle), (0, self.ua_last), (1, self.ub_last)]
    }

    fn inputs(&self, rods: &[&Rod]) -> Result<[Vector3<f64>; 8]> {
        let mut p = [Vector3::zeros(); 8];
        for (k, (side, u)) in self.points().into_iter().enumerate() {
            p[k] = rods[side].position(u)?;
        }
        let m = [1, 2, 3].map(|j| (p[2 * j] + p[2 * j + 1]) * 0.5);
        let (t, w) = (m[2] - m[0], (m[2] - m[1]) - (m[1] - m[0]));
        if !(w.norm() > 1e-12 * t.norm()) || !(helix_axis(&m, self.axis_lambda).norm() > 1e-12 * t.norm()) {
            return Err(Error::singular("pair stagger: the three rung midpoints give no helix axis (on a line)"));
        }
        Ok(p)
    }

    /// The row's value and gradient over the eight points' coordinates.
    fn eval(&self, rods: &[&Rod]) -> Result<(f64, [f64; 24], [Vector3<f64>; 8])> {
        let p = self.inputs(rods)?;
        let jm = [1, 2, 3].map(|j| select(2 * j, 0.5) + select(2 * j + 1, 0.5));
        let m = [1, 2, 3].map(|j| (p[2 * j] + p[2 * j + 1]) * 0.5);
        let (c, jc) = helix_axis_jacobian(&m, &jm, self.axis_lambda);
        let (z, jz) = unit(&c, &jc);
        let (r, jr): (Vector3<f64>, J3) = (p[1] - p[0], select(1, 1.0) - select(0, 1.0));
        let g = z.transpose() * jr + r.transpose() * jz;
        let mut grad = [0.0; 24];
        grad.copy_from_slice(g.as_slice());
        Ok((r.dot(&z) - self.rest, grad, p))
    }

    /// The stagger of pair (ua, ub) at rest in the rods' current shape,
    /// its axis read from the pairs `first`, `middle`, `last` ((ua, ub) on
    /// strands a and b, consecutive along the duplex; the pair among them).
    pub fn at_rest(rods: &[&Rod], pair: (f64, f64), first: (f64, f64), middle: (f64, f64), last: (f64, f64)) -> Result<PairStagger> {
        let mut s = PairStagger { ua: pair.0, ub: pair.1, ua_first: first.0, ub_first: first.1, ua_middle: middle.0, ub_middle: middle.1, ua_last: last.0, ub_last: last.1, axis_lambda: 0.0, rest: 0.0 };
        let mut p = [Vector3::zeros(); 8];
        for (k, (side, u)) in s.points().into_iter().enumerate() {
            p[k] = rods[side].position(u)?;
        }
        let r = p[1] - p[0];
        if !(r.norm() > 0.0) {
            return Err(Error::singular("pair stagger: the pair's two points coincide"));
        }
        s.axis_lambda = axis_lambda(&[1, 2, 3].map(|j| (p[2 * j] + p[2 * j + 1]) * 0.5), &r.normalize())?;
        s.rest = s.eval(rods)?.0;
        Ok(s)
    }

    /// The stagger now (length), from rest.
    pub fn stagger(&self, rods: &[&Rod]) -> Result<f64> {
        Ok(self.eval(rods)?.0)
    }
}

impl ConstraintLaw for PairStagger {
    const INFO: KindInfo = KindInfo {
        name: "PairStagger",
        helper: "pair_stagger",
        rods: 2,
        doc: "Stagger of a base pair (ua on strand a, ub on strand b): (r_b − r_a)·ẑ = `rest`, ẑ the helix axis \
              through the rung midpoints of three consecutive pairs (first, middle, last), blind to the pair's own \
              stagger, with the axis rule's `axis_lambda`. One row (length). Multiplier: the force along ẑ on strand a.",
        fields: &[
            FieldInfo::new("ua", Abscissa, "u", "the pair on strand a"),
            FieldInfo::new("ub", Abscissa, "u", "the pair on strand b"),
            FieldInfo::new("ua_first", Abscissa, "u", "first pair of the axis triple on strand a"),
            FieldInfo::new("ub_first", Abscissa, "u", "first pair of the axis triple on strand b"),
            FieldInfo::new("ua_middle", Abscissa, "u", "middle pair on strand a"),
            FieldInfo::new("ub_middle", Abscissa, "u", "middle pair on strand b"),
            FieldInfo::new("ua_last", Abscissa, "u", "last pair on strand a"),
            FieldInfo::new("ub_last", Abscissa, "u", "last pair on strand b"),
            FieldInfo::new("axis_lambda", Scalar, "", "λ of the helix-axis rule (t + λ ŵ × t; makes ẑ ⟂ the rung at rest)"),
            FieldInfo::new("rest", Scalar, "length", "stagger at rest").default("0.0"),
        ],
    };
    fn n_rows(&self) -> usize {
        1
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        for (side, u) in self.points() {
            f(side as Side, u);
        }
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.ua);
        f(1, &mut self.ub);
        f(0, &mut self.ua_first);
        f(1, &mut self.ub_first);
        f(0, &mut self.ua_middle);
        f(1, &mut self.ub_middle);
        f(0, &mut self.ua_last);
        f(1, &mut self.ub_last);
    }
    fn validate(&self, rods: &[&Rod]) -> Result<()> {
        crate::error::finite("pair stagger axis_lambda", self.axis_lambda)?;
        crate::error::finite("pair stagger rest", self.rest)?;
        if self.ua_first == self.ua_middle || self.ua_middle == self.ua_last || self.ua_first == self.ua_last {
            return Err(Error::invalid("pair stagger axis pairs", format!("{}, {}, {} on strand a", self.ua_first, self.ua_middle, self.ua_last), "three different pairs"));
        }
        let (_, len) = control_points(rods, &self.points(), &[[0.0; 24]])?;
        if 3 * (len[0] + len[1]) > MAX_ENTRIES {
            return Err(Error::invalid("pair stagger abscissae", "pairs far apart along a strand", format!("consecutive pairs (at most {} control points moved on both strands)", MAX_ENTRIES / 3)));
        }
        Ok(())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let (g, grad, _) = self.eval(rods)?;
        let (cps, len) = control_points(rods, &self.points(), &[grad])?;
        for side in 0..2 {
            let dofs = rods[side].dofs();
            for (cp, c) in &cps[side][..len[side]] {
                for a in 0..3 {
                    rows[0].push_on(side as Side, cp * dofs + a, c[0][a]);
                }
            }
        }
        rows[0].rhs = -g;
        Ok(())
    }
    /// Resultant on strand a through its four points, reduced to the
    /// pair's point `ua`.
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        let (_, grad, p) = self.eval(rods)?;
        let (mut f, mut m) = (Vector3::zeros(), Vector3::zeros());
        for k in [0, 2, 4, 6] {
            let g = Vector3::new(grad[3 * k], grad[3 * k + 1], grad[3 * k + 2]) * lambda[0];
            f += g;
            m += (p[k] - p[0]).cross(&g);
        }
        Ok(Reaction { force: f.into(), torque: m.into() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The chain-rule gradient against central differences of the row.
    #[test]
    fn gradient_matches_finite_differences() {
        let point = |k: usize, side: usize| {
            let t = 2.0 * std::f64::consts::PI * k as f64 / 10.5 + side as f64 * 2.23;
            let q = (k * 2 + side) as f64;
            Vector3::new(t.cos() + 0.05 * (1.7 * q).sin(), t.sin() + 0.05 * (2.3 * q).cos(), 0.34 * k as f64 + 0.03 * (0.7 * q).sin())
        };
        let row = |p: &[Vector3<f64>; 8]| -> f64 {
            let m = [1, 2, 3].map(|j| (p[2 * j] + p[2 * j + 1]) * 0.5);
            (p[1] - p[0]).dot(&helix_axis(&m, -0.74).normalize())
        };
        for pair in 0..3 {
            let mut p = [Vector3::zeros(); 8];
            p[0] = point(pair, 0);
            p[1] = point(pair, 1);
            for j in 0..3 {
                p[2 + 2 * j] = point(j, 0);
                p[3 + 2 * j] = point(j, 1);
            }
            let jm = [1, 2, 3].map(|j| select(2 * j, 0.5) + select(2 * j + 1, 0.5));
            let m = [1, 2, 3].map(|j| (p[2 * j] + p[2 * j + 1]) * 0.5);
            let (c, jc) = helix_axis_jacobian(&m, &jm, -0.74);
            let (z, jz) = unit(&c, &jc);
            let g = z.transpose() * (select(1, 1.0) - select(0, 1.0)) + (p[1] - p[0]).transpose() * jz;
            for i in 0..24 {
                let h = 1e-6;
                let (mut pp, mut pm) = (p, p);
                pp[i / 3][i % 3] += h;
                pm[i / 3][i % 3] -= h;
                let fd = (row(&pp) - row(&pm)) / (2.0 * h);
                assert!((g[i] - fd).abs() < 1e-7, "∂/∂input {i} (pair slot {pair}): {} vs {fd}", g[i]);
            }
        }
    }
}
