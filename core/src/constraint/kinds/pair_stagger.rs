//! Pair stagger (a base pair's shear, SPEC §9.1): the two points of a
//! base pair — one on strand a, one on strand b — read along the local
//! helix axis, (r_b − r_a)·ẑ = rest. ẑ is [`stagger_free_axis`]: the
//! difference of two neighbouring pairs' rung midpoints turned, in the
//! plane it spans with their rungs, by the rest angle that makes it ⟂ the
//! pair's rung — a plane and midpoints that no pair's stagger moves, so
//! the row reads the pair's stagger exactly on a helix (however large)
//! and its neighbours' only at second order; the duplex turning or
//! bending carries the axis along, stretching or twisting it leans the
//! axis slightly (the rest angle is fixed: see [`stagger_free_axis`]). With a distance rung and stagger-free stacking
//! ([`super::BasePairStep::stagger_free`]) it makes the hydrogen bonds a
//! relative position in the pair's own frame: the rung of de Gennes'
//! ladder, whose stiffness R (1 / compliance) against the backbone's Q sets
//! the shear load's decay length κ⁻¹ = √(Q/2R).
use super::base_pair_step::{axis_mu, control_points, point_rows, select, stagger_free_axis_jacobian, strand_a_resultant, unit, J3};
#[cfg(test)]
use super::base_pair_step::stagger_free_axis;
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{ConstraintLaw, Reaction, Row, Side, MAX_ENTRIES};
use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// (r_b(ub) − r_a(ua))·ẑ = `rest`, ẑ the stagger-free helix axis from the
/// rung midpoints and rungs of the pairs `first` and `last` (the pair's
/// neighbours, or at a duplex's end the pair itself and its neighbour)
/// with the rule's `axis_mu`. Multiplier: the stagger force (its resultant
/// on strand a is along ẑ, spread over the three pairs' points).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairStagger {
    pub ua: f64,
    pub ub: f64,
    pub ua_first: f64,
    pub ub_first: f64,
    pub ua_last: f64,
    pub ub_last: f64,
    /// μ of [`stagger_free_axis`] (set at rest by [`PairStagger::at_rest`]).
    pub axis_mu: f64,
    /// The stagger at rest (length).
    #[serde(default)]
    pub rest: f64,
}

/// The row's value, its gradient over the six points' coordinates and the
/// points.
type Eval = (f64, [f64; 24], [Vector3<f64>; 6]);

/// c₀ (the midpoints' difference, last − first) and p (the two pairs'
/// rungs summed) of [`stagger_free_axis`], from the six points.
fn axis_inputs<T: nalgebra::RealField + Copy>(p: &[Vector3<T>; 6]) -> (Vector3<T>, Vector3<T>) {
    ((p[4] + p[5] - p[2] - p[3]) * T::from_subset(&0.5), p[3] - p[2] + p[5] - p[4])
}

impl PairStagger {
    /// The six abscissae with their side: the pair, first, last.
    fn points(&self) -> [(usize, f64); 6] {
        [(0, self.ua), (1, self.ub), (0, self.ua_first), (1, self.ub_first), (0, self.ua_last), (1, self.ub_last)]
    }

    fn inputs(&self, rods: &[&Rod]) -> Result<[Vector3<f64>; 6]> {
        let mut p = [Vector3::zeros(); 6];
        for (k, (side, u)) in self.points().into_iter().enumerate() {
            p[k] = rods[side].position(u)?;
        }
        let (c0, plane) = axis_inputs(&p);
        if !(c0.cross(&plane).norm() > 1e-9 * c0.norm() * plane.norm()) || !((p[1] - p[0]).norm() > 0.0) {
            return Err(Error::singular("pair stagger: the neighbours' midpoints run along the rung, or the pair's points coincide (no helix axis)"));
        }
        Ok(p)
    }

    fn eval(&self, rods: &[&Rod]) -> Result<Eval> {
        let p = self.inputs(rods)?;
        let (c0, plane) = axis_inputs(&p);
        let jc0 = select(4, 0.5) + select(5, 0.5) - select(2, 0.5) - select(3, 0.5);
        let jp = select(3, 1.0) - select(2, 1.0) + select(5, 1.0) - select(4, 1.0);
        let (r, jr): (Vector3<f64>, J3) = (p[1] - p[0], select(1, 1.0) - select(0, 1.0));
        let (c, jc) = stagger_free_axis_jacobian(&c0, &jc0, &plane, &jp, self.axis_mu);
        let (z, jz) = unit(&c, &jc);
        let g = z.transpose() * jr + r.transpose() * jz;
        let mut grad = [0.0; 24];
        grad.copy_from_slice(g.as_slice());
        Ok((r.dot(&z) - self.rest, grad, p))
    }

    /// The stagger of pair `pair` = (ua, ub) at rest in the rods' current
    /// shape, its axis read from the pairs `first` and `last`.
    pub fn at_rest(rods: &[&Rod], pair: (f64, f64), first: (f64, f64), last: (f64, f64)) -> Result<PairStagger> {
        let mut s = PairStagger { ua: pair.0, ub: pair.1, ua_first: first.0, ub_first: first.1, ua_last: last.0, ub_last: last.1, axis_mu: 0.0, rest: 0.0 };
        let p = s.inputs(rods)?;
        let (c0, plane) = axis_inputs(&p);
        s.axis_mu = axis_mu(&c0, &plane, &(p[1] - p[0]).normalize())?;
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
        doc: "Stagger of a base pair (ua on strand a, ub on strand b): (r_b − r_a)·ẑ = `rest`, ẑ the helix axis from \
              the rung midpoints of the pairs first and last, turned in the plane of the rung by the rest angle `axis_mu` \
              encodes (blind to the pair's own stagger). One row (length). Multiplier: the force along ẑ on strand a.",
        fields: &[
            FieldInfo::new("ua", Abscissa, "u", "the pair on strand a"),
            FieldInfo::new("ub", Abscissa, "u", "the pair on strand b"),
            FieldInfo::new("ua_first", Abscissa, "u", "the pair before (or the pair itself at the start) on strand a"),
            FieldInfo::new("ub_first", Abscissa, "u", "the same on strand b"),
            FieldInfo::new("ua_last", Abscissa, "u", "the pair after (or the pair itself at the end) on strand a"),
            FieldInfo::new("ub_last", Abscissa, "u", "the same on strand b"),
            FieldInfo::new("axis_mu", Scalar, "", "μ of the stagger-free axis rule (makes ẑ ⟂ the rung at rest)"),
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
        f(0, &mut self.ua_last);
        f(1, &mut self.ub_last);
    }
    fn validate(&self, rods: &[&Rod]) -> Result<()> {
        crate::error::finite("pair stagger axis_mu", self.axis_mu)?;
        crate::error::finite("pair stagger rest", self.rest)?;
        if self.ua_first == self.ua_last && self.ub_first == self.ub_last {
            return Err(Error::invalid("pair stagger axis pairs", format!("first = last ({}, {})", self.ua_first, self.ub_first), "two different pairs"));
        }
        let (_, len) = control_points(rods, &self.points(), &[[0.0; 24]])?;
        if 3 * (len[0] + len[1]) > MAX_ENTRIES {
            return Err(Error::invalid("pair stagger abscissae", "pairs far apart along a strand", format!("neighbouring pairs (at most {} control points moved on both strands)", MAX_ENTRIES / 3)));
        }
        Ok(())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let (g, grad, _) = self.eval(rods)?;
        point_rows(rods, &self.points(), &[grad], &[g], rows)
    }
    /// Resultant on strand a through its three points, reduced to the
    /// pair's point `ua`.
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        let (_, grad, p) = self.eval(rods)?;
        Ok(strand_a_resultant(&p, &[grad], lambda))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A B-DNA-like helix point k of strand `side`, slightly perturbed.
    fn point(k: usize, side: usize) -> Vector3<f64> {
        let t = 2.0 * std::f64::consts::PI * k as f64 / 10.5 + side as f64 * 2.23;
        let q = (k * 2 + side) as f64;
        Vector3::new(t.cos() + 0.05 * (1.7 * q).sin(), t.sin() + 0.05 * (2.3 * q).cos(), 0.34 * k as f64 + 0.03 * (0.7 * q).sin())
    }

    fn row(p: &[Vector3<f64>; 6], mu: f64) -> f64 {
        let (c0, plane) = axis_inputs(p);
        (p[1] - p[0]).dot(&stagger_free_axis(&c0, &plane, mu).normalize())
    }

    /// The chain-rule gradient against central differences of the row.
    #[test]
    fn gradient_matches_finite_differences() {
        for (pair, first, last) in [(1, 0, 2), (0, 0, 2), (2, 1, 2)] {
            let p = [point(pair, 0), point(pair, 1), point(first, 0), point(first, 1), point(last, 0), point(last, 1)];
            let jc0 = select(4, 0.5) + select(5, 0.5) - select(2, 0.5) - select(3, 0.5);
            let jp = select(3, 1.0) - select(2, 1.0) + select(5, 1.0) - select(4, 1.0);
            let (r, jr) = (p[1] - p[0], select(1, 1.0) - select(0, 1.0));
            let (c0, plane) = axis_inputs(&p);
            let (c, jc) = stagger_free_axis_jacobian(&c0, &jc0, &plane, &jp, -0.8);
            let (z, jz) = unit(&c, &jc);
            let g = z.transpose() * jr + r.transpose() * jz;
            for i in 0..18 {
                let h = 1e-6;
                let (mut pp, mut pm) = (p, p);
                pp[i / 3][i % 3] += h;
                pm[i / 3][i % 3] -= h;
                let fd = (row(&pp, -0.8) - row(&pm, -0.8)) / (2.0 * h);
                assert!((g[i] - fd).abs() < 1e-7, "∂/∂input {i} (pair {pair}): {} vs {fd}", g[i]);
            }
        }
    }

    /// On an exact helix the axis at rest is the helix axis, inside and at
    /// either end; sliding the pair's two points by ±d/2 along it reads d
    /// exactly, however large (no snap-through), and a neighbour's stagger
    /// does not move the row to first order.
    #[test]
    fn reads_the_stagger_along_the_helix_axis() {
        let helix = |k: usize, side: usize| {
            let t = 2.0 * std::f64::consts::PI * k as f64 / 10.5 + side as f64 * 2.2176;
            Vector3::new(t.cos(), t.sin(), 0.34 * k as f64)
        };
        for (pair, first, last) in [(5, 4, 6), (0, 0, 1), (9, 8, 9)] {
            let p0 = [helix(pair, 0), helix(pair, 1), helix(first, 0), helix(first, 1), helix(last, 0), helix(last, 1)];
            let (c0, plane) = axis_inputs(&p0);
            let mu = axis_mu(&c0, &plane, &(p0[1] - p0[0]).normalize()).unwrap(); // an exact helix: never singular
            let z = stagger_free_axis(&c0, &plane, mu).normalize();
            assert!((z - Vector3::z()).norm() < 1e-12, "pair {pair}: axis {z:?}");
            let rest = row(&p0, mu);
            // The pair's own stagger (its points appear again among the
            // axis pairs at an end: moved there too).
            for d in [0.01, 1.0, -1.0] {
                let mut p = p0;
                for k in 0..6 {
                    let same = (p0[k] - p0[k % 2]).norm() == 0.0;
                    if k < 2 || same {
                        p[k].z += if k % 2 == 0 { d / 2.0 } else { -d / 2.0 };
                    }
                }
                let got = row(&p, mu) - rest;
                assert!((got + d).abs() < 1e-9 * d.abs(), "pair {pair}: stagger {got} for {d}");
            }
            // A neighbour's stagger: second order only.
            if first != pair {
                let d = 1e-3;
                let mut p = p0;
                p[2].z += d / 2.0;
                p[3].z -= d / 2.0;
                let got = row(&p, mu) - rest;
                assert!(got.abs() < 1e-3 * d, "pair {pair}: a neighbour's stagger {d} read as {got}");
            }
        }
    }
}
