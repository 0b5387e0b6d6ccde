//! Relative plane: r_a(ua) − r_b(ub) − offset stays in the plane ⟂ a unit
//! normal, one row (a prismatic link free in two directions). A slipping
//! contact adds it across its slip direction (SPEC §7): the linearised
//! Coulomb force's stiffness there, which makes the slip direction
//! implicit. Λ is the force on rod a along the normal; rod b receives the
//! opposite.
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{finite3, point_rows, unit, ConstraintLaw, Reaction, Row, Side};
use crate::error::Result;
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// (r_a(ua) − r_b(ub) − `offset`)·`normal` = 0 (length; one row).
/// Multiplier: the force on rod a along the normal.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RelativePlane {
    pub ua: f64,
    pub ub: f64,
    pub offset: [f64; 3],
    pub normal: [f64; 3],
}

impl ConstraintLaw for RelativePlane {
    const INFO: KindInfo = KindInfo {
        name: "RelativePlane",
        helper: "relative_plane",
        rods: 2,
        doc: "Two points (rods a and b of World.add_link) move relative to each other only in the plane ⟂ \
              `normal`: (r_a(ua) − r_b(ub) − `offset`)·normal = 0 (length; one row). Multiplier: the force on \
              rod a along the normal (rod b gets the opposite).",
        fields: &[
            FieldInfo::new("ua", Abscissa, "u", "abscissa on rod a"),
            FieldInfo::new("ub", Abscissa, "u", "abscissa on rod b"),
            FieldInfo::new("offset", Vec3, "length", "r_a − r_b allowed besides motion in the plane").default("[0, 0, 0]"),
            FieldInfo::new("normal", Direction, "", "the direction of no relative motion"),
        ],
    };
    fn n_rows(&self) -> usize {
        1
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
        finite3(&self.offset, "relative plane offset")?;
        unit(&self.normal, "relative plane normal").map(|_| ())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let n = unit(&self.normal, "relative plane normal")?;
        let v = rods[0].position(self.ua)? - rods[1].position(self.ub)? - Vector3::from(self.offset);
        point_rows(rods[0], 0, self.ua, 1.0, &[n], rows)?;
        point_rows(rods[1], 1, self.ub, -1.0, &[n], rows)?;
        rows[0].rhs = -v.dot(&n);
        Ok(())
    }
    fn reaction(&self, _rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        Ok(Reaction::force(unit(&self.normal, "relative plane normal")? * lambda[0]))
    }
}
