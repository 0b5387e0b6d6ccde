//! Sliding point (III.37–III.42): the rod passes through a fixed point p at
//! an abscissa u that is itself an unknown. Rows r(u) − p = 0 linearised in
//! both the coordinates and Δu (column r'(u), side 2); the Δu unknown
//! carries the viscous friction c (tangential force −c v_s, v_s = |r'| u̇)
//! and the second-order terms of the Lagrangian −Λ·∂²g (III.40: −Λ·r''(u)
//! on the diagonal, −Λ_α b'_k(u) coupling Δu with the coordinates), with Λ
//! from the previous solve.
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{finite3, ConstraintLaw, Reaction, Row, Side, SlidingBlocks};
use crate::error::Result;
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// The rod passes through `point` (length); `u` is an unknown updated every
/// solve. `friction`: viscous coefficient c (force per unit sliding speed).
/// Multiplier: the force on the rod (⟂ tangent when frictionless). A slider
/// that leaves the rod is removed with a `SliderLeft` event.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SlidingPoint {
    pub u: f64,
    pub point: [f64; 3],
    pub friction: f64,
}

impl ConstraintLaw for SlidingPoint {
    const INFO: KindInfo = KindInfo {
        name: "SlidingPoint",
        helper: "sliding_point",
        rods: 1,
        doc: "The rod passes through `point` (length) at a free abscissa that starts at `u` and slides (a ring; \
              III.37–III.42); `friction` is viscous (force per sliding speed). A slider that leaves the rod is \
              removed with a SliderLeft event. Multiplier: the ring force.",
        fields: &[
            FieldInfo::new("u", Abscissa, "u", "starting abscissa"),
            FieldInfo::new("point", Vec3, "length", "the fixed point"),
            FieldInfo::new("friction", Scalar, "force·time/length", "viscous friction coefficient (>= 0)").default("0.0"),
        ],
    };
    fn n_rows(&self) -> usize {
        3
    }
    fn n_extra(&self) -> usize {
        1
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        f(0, self.u)
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.u)
    }
    fn validate(&self, _rods: &[&Rod]) -> Result<()> {
        finite3(&self.point, "sliding point")?;
        crate::error::non_negative("sliding friction", self.friction).map(|_| ())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        slider_rows(rods[0], self.u, &self.point, rows)
    }
    fn reaction(&self, _rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        Ok(Reaction::force(Vector3::new(lambda[0], lambda[1], lambda[2])))
    }
    fn sliding_blocks(&self, rods: &[&Rod], lambda: &[f64], friction_coeff: f64, out: &mut SlidingBlocks) -> Result<()> {
        slider_blocks(rods[0], self.u, self.friction, &lambda[..3], friction_coeff, out)
    }
    fn advance(&mut self, rods: &[&Rod], du: &[f64]) -> bool {
        slide(&mut self.u, rods[0], du[0])
    }
}

/// The three rows r(u) − p with their Δu column.
pub(crate) fn slider_rows(rod: &Rod, u: f64, point: &[f64; 3], rows: &mut [Row]) -> Result<()> {
    let (ctrl, b) = rod.basis_at(u)?;
    let (p, d1) = (rod.eval(u, 0)?, rod.eval(u, 1)?);
    for (a, row) in rows.iter_mut().enumerate().take(3) {
        for k in 0..4 {
            row.push(ctrl[k] * rod.dofs() + a, b[0][k]);
        }
        row.push_on(2, 0, d1[a]);
        row.rhs = point[a] - p[a];
    }
    Ok(())
}

pub(crate) fn slider_blocks(rod: &Rod, u: f64, friction: f64, lambda: &[f64], friction_coeff: f64, out: &mut SlidingBlocks) -> Result<()> {
    let (ctrl, b) = rod.basis_at(u)?;
    let (d1, d2) = (rod.eval(u, 1)?, rod.eval(u, 2)?);
    let lam = Vector3::new(lambda[0], lambda[1], lambda[2]);
    let speed2 = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2];
    out.diag[0] = friction_coeff * friction * speed2 - lam.dot(&Vector3::new(d2[0], d2[1], d2[2]));
    for k in 0..4 {
        for a in 0..3 {
            out.coupling.push_on(0, ctrl[k] * rod.dofs() + a, -lam[a] * b[1][k]);
        }
    }
    Ok(())
}

/// u += Δu; false when u left an open rod's domain (on a closed rod it
/// wraps round and never leaves).
pub(crate) fn slide(u: &mut f64, rod: &Rod, du: f64) -> bool {
    *u += du;
    let (a, b) = rod.domain();
    if rod.knots().kind() == crate::spline::KnotKind::Periodic {
        *u = a + (*u - a).rem_euclid(b - a);
        return true;
    }
    *u >= a && *u <= b
}
