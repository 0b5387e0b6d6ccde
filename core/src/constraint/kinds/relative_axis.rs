//! Relative axis (a prismatic link between two points, III.55 restricted
//! to two directions): r_a(ua) − r_b(ub) − offset stays along a direction,
//! as two rows on normals n1, n2 ⟂ it. The two points may separate or
//! approach along the direction but not move across it relative to each
//! other: the rows a sticking contact adds (SPEC §7). Λ is the force on
//! rod a across the direction; rod b receives the opposite.
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{finite3, perpendicular_pair, point_rows, unit, ConstraintLaw, Reaction, Row, Side};
use crate::error::Result;
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// r_a(ua) − r_b(ub) − `offset` (length) stays along `direction` (two
/// rows). Multipliers: the force on rod a ⟂ the direction.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RelativeAxis {
    pub ua: f64,
    pub ub: f64,
    pub offset: [f64; 3],
    pub direction: [f64; 3],
}

impl ConstraintLaw for RelativeAxis {
    const INFO: KindInfo = KindInfo {
        name: "RelativeAxis",
        helper: "relative_axis",
        rods: 2,
        doc: "Two points (rods a and b of World.add_link) move relative to each other only along `direction`: \
              r_a(ua) − r_b(ub) − `offset` (length) stays parallel to it (two rows; a prismatic link, or a \
              sticking contact). Multipliers: the force on rod a ⟂ the direction (rod b gets the opposite).",
        fields: &[
            FieldInfo::new("ua", Abscissa, "u", "abscissa on rod a"),
            FieldInfo::new("ub", Abscissa, "u", "abscissa on rod b"),
            FieldInfo::new("offset", Vec3, "length", "r_a − r_b allowed besides motion along the direction").default("[0, 0, 0]"),
            FieldInfo::new("direction", Direction, "", "the direction of free relative motion"),
        ],
    };
    fn n_rows(&self) -> usize {
        2
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        f(0, self.ua);
        f(1, self.ub);
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.ua);
        f(1, &mut self.ub);
    }
    fn validate(&self, _rods: &[&Rod]) -> Result<()> {
        finite3(&self.offset, "relative axis offset")?;
        unit(&self.direction, "relative axis direction").map(|_| ())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let (n1, n2) = perpendicular_pair(&unit(&self.direction, "relative axis direction")?);
        let v = rods[0].position(self.ua)? - rods[1].position(self.ub)? - Vector3::from(self.offset);
        point_rows(rods[0], 0, self.ua, 1.0, &[n1, n2], rows)?;
        point_rows(rods[1], 1, self.ub, -1.0, &[n1, n2], rows)?;
        rows[0].rhs = -v.dot(&n1);
        rows[1].rhs = -v.dot(&n2);
        Ok(())
    }
    fn reaction(&self, _rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        let (n1, n2) = perpendicular_pair(&unit(&self.direction, "relative axis direction")?);
        Ok(Reaction::force(n1 * lambda[0] + n2 * lambda[1]))
    }
}
