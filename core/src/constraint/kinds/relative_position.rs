//! Relative position (III.55): q_a(ua) − q_b(ub) = offset on the selected
//! axes [x, y, z, θ], between two rods or two points of one rod. Linear in
//! q; entries on rod a are side 0, on rod b side 1. Λ is the force (and
//! roll torque) on rod a; rod b receives the opposite.
use super::position::axes_reaction;
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{finite3, Anchoring, ConstraintLaw, Reaction, Row, Side};
use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// q_a(ua) − q_b(ub) = `offset` (length; roll in rad) on the selected
/// `axes`. Multiplier: the force (and roll torque) on rod a.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RelativePosition {
    pub ua: f64,
    pub ub: f64,
    pub axes: [bool; 4],
    pub offset: [f64; 4],
}

impl ConstraintLaw for RelativePosition {
    const INFO: KindInfo = KindInfo {
        name: "RelativePosition",
        helper: "relative_position",
        rods: 2,
        doc: "Two points (rods a and b of World.add_link): q_a(ua) − q_b(ub) = `offset` (length) on the selected \
              `axes` (\"r\": roll). Multiplier: force on rod a (rod b gets the opposite). Breaks in tension along \
              r_b − r_a when the offset is non-zero.",
        fields: &[
            FieldInfo::new("ua", Abscissa, "u", "abscissa on rod a"),
            FieldInfo::new("ub", Abscissa, "u", "abscissa on rod b"),
            FieldInfo::new("offset", Vec4, "length, rad", "q_a − q_b to keep (x, y, z, roll)").default("[0, 0, 0, 0]").roll_keyword("roll_offset"),
            FieldInfo::new("axes", Axes, "", "constrained axes").default("[true, true, true, false]"),
        ],
    };
    fn n_rows(&self) -> usize {
        self.axes.iter().filter(|a| **a).count()
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        f(0, self.ua);
        f(1, self.ub);
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.ua);
        f(1, &mut self.ub);
    }
    fn validate(&self, rods: &[&Rod]) -> Result<()> {
        if !self.axes.iter().any(|a| *a) {
            return Err(Error::invalid("relative position axes", "none selected", "at least one of x, y, z, roll"));
        }
        if self.axes[3] && (rods[0].dofs() == 3 || rods[1].dofs() == 3) {
            return Err(Error::invalid("relative position axes", "roll", "x, y, z only (a rod has no roll coordinate)"));
        }
        finite3(&[self.offset[0], self.offset[1], self.offset[2]], "relative position offset")?;
        crate::error::finite("relative roll offset", self.offset[3]).map(|_| ())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let (pa, pb) = (rods[0].eval(self.ua, 0)?, rods[1].eval(self.ub, 0)?);
        let (ca, ba) = rods[0].basis_at(self.ua)?;
        let (cb, bb) = rods[1].basis_at(self.ub)?;
        let mut r = 0;
        for a in 0..4 {
            if !self.axes[a] {
                continue;
            }
            for j in 0..4 {
                rows[r].push_on(0, ca[j] * rods[0].dofs() + a, ba[0][j]);
                rows[r].push_on(1, cb[j] * rods[1].dofs() + a, -bb[0][j]);
            }
            rows[r].rhs = self.offset[a] - (pa[a] - pb[a]);
            r += 1;
        }
        Ok(())
    }
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        axes_reaction(rods[0], self.ua, &self.axes, lambda)
    }
    /// Along d = r_b − r_a (or −offset while the two points coincide).
    fn tension(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Option<f64>> {
        let d = rods[1].position(self.ub)? - rods[0].position(self.ua)?;
        let scale = rods[0].rest_length().max(rods[1].rest_length());
        let o = -Vector3::new(self.offset[0], self.offset[1], self.offset[2]);
        let dir = if d.norm() > 1e-12 * scale {
            d.normalize()
        } else if o.norm() > 0.0 {
            o.normalize()
        } else {
            return Ok(None);
        };
        let f = Vector3::from(self.reaction(rods, lambda)?.force);
        Ok(Some(f.dot(&dir)))
    }
    fn anchoring(&self) -> Anchoring {
        if self.axes[..3].iter().all(|a| *a) {
            Anchoring::PointViaPeer
        } else {
            Anchoring::None
        }
    }
    fn duplicates(&self, other: &Self) -> bool {
        let same = |x: f64, y: f64| (x - y).abs() <= 1e-12 * (1.0 + x.abs());
        same(self.ua, other.ua) && same(self.ub, other.ub) && self.axes.iter().zip(&other.axes).any(|(p, q)| *p && *q)
    }
}
