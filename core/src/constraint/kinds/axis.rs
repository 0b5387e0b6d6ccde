//! Axis constraint (III.34): r(u) on the line through p0 along a direction,
//! as two planes through it (normals n1, n2 ⟂ the direction).
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{finite3, perpendicular_pair, point_rows, unit, ConstraintLaw, Reaction, Row, Side};
use crate::error::Result;
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// r(u) stays on the line through `origin` along `direction` (two rows).
/// Multipliers: the force components along two normals of the line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    pub u: f64,
    pub origin: [f64; 3],
    pub direction: [f64; 3],
}

impl ConstraintLaw for Axis {
    const INFO: KindInfo = KindInfo {
        name: "Axis",
        helper: "axis",
        rods: 1,
        doc: "r(u) stays on the line through `origin` (length) along `direction` (two rows). \
              Multipliers: the force ⟂ the line.",
        fields: &[
            FieldInfo::new("u", Abscissa, "u", "abscissa (spline parameter)"),
            FieldInfo::new("origin", Vec3, "length", "a point of the line"),
            FieldInfo::new("direction", Direction, "", "line direction"),
        ],
    };
    fn n_rows(&self) -> usize {
        2
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        f(0, self.u)
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.u)
    }
    fn validate(&self, _rods: &[&Rod]) -> Result<()> {
        finite3(&self.origin, "axis origin")?;
        unit(&self.direction, "axis direction").map(|_| ())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let (n1, n2) = perpendicular_pair(&unit(&self.direction, "axis direction")?);
        let v = rods[0].position(self.u)? - Vector3::from(self.origin);
        point_rows(rods[0], 0, self.u, 1.0, &[n1, n2], rows)?;
        rows[0].rhs = -v.dot(&n1);
        rows[1].rhs = -v.dot(&n2);
        Ok(())
    }
    fn reaction(&self, _rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        let (n1, n2) = perpendicular_pair(&unit(&self.direction, "axis direction")?);
        Ok(Reaction::force(n1 * lambda[0] + n2 * lambda[1]))
    }
}
