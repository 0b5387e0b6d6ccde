//! Distance to a fixed point (III.28): |r(u) − p| = d. One row along the
//! unit vector n = (r − p)/|r − p|, so Λ is the force along n (negative:
//! the link pulls the rod towards p, i.e. tension).
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{finite3, point_rows, ConstraintLaw, Reaction, Row, Side};
use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// |r(u) − point| = distance (length, > 0). Multiplier: force along
/// (r − point)/|r − point|, negative when the link is in tension.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Distance {
    pub u: f64,
    pub point: [f64; 3],
    pub distance: f64,
}

impl Distance {
    fn direction(&self, rod: &Rod) -> Result<(Vector3<f64>, f64)> {
        let v = rod.position(self.u)? - Vector3::from(self.point);
        let len = v.norm();
        if !(len > 1e-12 * rod.rest_length()) {
            return Err(Error::singular(format!(
                "distance constraint at u = {}: the point coincides with the anchor, direction undefined",
                self.u
            )));
        }
        Ok((v / len, len))
    }
}

impl ConstraintLaw for Distance {
    const INFO: KindInfo = KindInfo {
        name: "Distance",
        helper: "distance",
        rods: 1,
        doc: "|r(u) − point| = `distance` (length, > 0). Multiplier: force along (r − point)/|r − point|, \
              negative in tension.",
        fields: &[
            FieldInfo::new("u", Abscissa, "u", "abscissa (spline parameter)"),
            FieldInfo::new("point", Vec3, "length", "anchor point"),
            FieldInfo::new("distance", Scalar, "length", "distance to keep (> 0)"),
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
        finite3(&self.point, "distance anchor point")?;
        crate::error::positive("constraint distance (use a Position constraint for zero)", self.distance).map(|_| ())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let (n, len) = self.direction(rods[0])?;
        point_rows(rods[0], 0, self.u, 1.0, &[n], rows)?;
        rows[0].rhs = self.distance - len;
        Ok(())
    }
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        Ok(Reaction::force(self.direction(rods[0])?.0 * lambda[0]))
    }
    fn tension(&self, _rods: &[&Rod], lambda: &[f64]) -> Result<Option<f64>> {
        Ok(Some(-lambda[0]))
    }
    /// Two of them at one abscissa can be legitimate (two planes make an
    /// axis); only the dependence check rejects repeated rows.
    fn duplicates(&self, _other: &Self) -> bool {
        false
    }
}
