//! Plane constraint (III.31): (r(u) − p0)·n = 0, one row along the unit
//! normal, so Λ is the normal force.
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{finite3, point_rows, unit, ConstraintLaw, Reaction, Row, Side};
use crate::error::Result;
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// r(u) stays on the plane through `origin` with `normal`. Multiplier:
/// normal force (force unit, along the unit normal).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plane {
    pub u: f64,
    pub origin: [f64; 3],
    pub normal: [f64; 3],
}

impl ConstraintLaw for Plane {
    const INFO: KindInfo = KindInfo {
        name: "Plane",
        helper: "plane",
        rods: 1,
        doc: "r(u) stays on the plane through `origin` (length) with `normal`. Multiplier: normal force.",
        fields: &[
            FieldInfo::new("u", Abscissa, "u", "abscissa (spline parameter)"),
            FieldInfo::new("origin", Vec3, "length", "a point of the plane"),
            FieldInfo::new("normal", Direction, "", "plane normal"),
        ],
    };
    fn n_rows(&self) -> usize {
        1
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        f(0, self.u)
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.u)
    }
    fn validate(&self, _rods: &[&Rod]) -> Result<()> {
        finite3(&self.origin, "plane origin")?;
        unit(&self.normal, "plane normal").map(|_| ())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let n = unit(&self.normal, "plane normal")?;
        let g = (rods[0].position(self.u)? - Vector3::from(self.origin)).dot(&n);
        point_rows(rods[0], 0, self.u, 1.0, &[n], rows)?;
        rows[0].rhs = -g;
        Ok(())
    }
    fn reaction(&self, _rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        Ok(Reaction::force(unit(&self.normal, "plane normal")? * lambda[0]))
    }
    /// Two of them at one abscissa can be legitimate (two planes make an
    /// axis); only the dependence check rejects repeated rows.
    fn duplicates(&self, _other: &Self) -> bool {
        false
    }
}
