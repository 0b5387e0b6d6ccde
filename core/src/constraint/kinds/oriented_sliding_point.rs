//! Oriented sliding point (III.43–III.49): the sliding point's rows plus
//! two rows e_i · t(u) = 0 (e_i ⟂ `direction`) at the same moving u; the
//! Δu column of the tangent rows is e_i · P r''(u) / |r'(u)|.
use super::sliding_point::{slide, slider_blocks, slider_rows};
use super::tangent::{tangent_reaction, tangent_rows};
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{finite3, perpendicular_pair, tangent_of, unit, Anchoring, ConstraintLaw, Reaction, Row, Side, SlidingBlocks};
use crate::error::Result;
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// A sliding point whose tangent is also held parallel to `direction` at
/// the same moving abscissa: a rod through a tube or a clip. Multipliers:
/// force (3), moment (2).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OrientedSlidingPoint {
    pub u: f64,
    pub point: [f64; 3],
    pub direction: [f64; 3],
    pub friction: f64,
}

impl ConstraintLaw for OrientedSlidingPoint {
    const INFO: KindInfo = KindInfo {
        name: "OrientedSlidingPoint",
        helper: "oriented_sliding_point",
        rods: 1,
        doc: "A sliding point that also holds the tangent along `direction` (a guide tube; III.43–III.49). \
              Multipliers: force (3), moment (2).",
        fields: &[
            FieldInfo::new("u", Abscissa, "u", "starting abscissa"),
            FieldInfo::new("point", Vec3, "length", "the fixed point"),
            FieldInfo::new("direction", Direction, "", "tangent direction held"),
            FieldInfo::new("friction", Scalar, "force·time/length", "viscous friction coefficient (>= 0)").default("0.0"),
        ],
    };
    fn n_rows(&self) -> usize {
        5
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
        unit(&self.direction, "oriented slider direction")?;
        crate::error::non_negative("sliding friction", self.friction).map(|_| ())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let rod = rods[0];
        slider_rows(rod, self.u, &self.point, &mut rows[..3])?;
        tangent_rows(rod, self.u, &self.direction, &mut rows[3..5])?;
        let d2 = rod.eval(self.u, 2)?;
        let r2 = Vector3::new(d2[0], d2[1], d2[2]);
        let (t, speed) = tangent_of(rod, self.u)?;
        let (e1, e2) = perpendicular_pair(&unit(&self.direction, "oriented slider direction")?);
        for (row, e) in rows[3..5].iter_mut().zip([e1, e2]) {
            let g = (e - t * e.dot(&t)) / speed;
            row.push_on(2, 0, g.dot(&r2));
        }
        Ok(())
    }
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        let m = tangent_reaction(rods[0], self.u, &self.direction, &lambda[3..5])?;
        Ok(Reaction { force: [lambda[0], lambda[1], lambda[2]], torque: m.torque })
    }
    fn anchoring(&self) -> Anchoring {
        Anchoring::Orientation
    }
    fn sliding_blocks(&self, rods: &[&Rod], lambda: &[f64], friction_coeff: f64, out: &mut SlidingBlocks) -> Result<()> {
        slider_blocks(rods[0], self.u, self.friction, &lambda[..3], friction_coeff, out)
    }
    fn advance(&mut self, rods: &[&Rod], du: &[f64]) -> bool {
        slide(&mut self.u, rods[0], du[0])
    }
}
