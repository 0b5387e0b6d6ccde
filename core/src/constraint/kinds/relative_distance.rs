//! Relative distance (III.66): |r_a(ua) − r_b(ub)| = d, one row along
//! n = (r_a − r_b)/|r_a − r_b|; Λ is the force on rod a along n (negative
//! in tension).
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{point_rows, ConstraintLaw, Reaction, Row, Side};
use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// |r_a(ua) − r_b(ub)| = `distance` (length, > 0). Multiplier: force on
/// rod a along (r_a − r_b)/|r_a − r_b|, negative in tension.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RelativeDistance {
    pub ua: f64,
    pub ub: f64,
    pub distance: f64,
}

/// Unit vector from r_b(ub) to r_a(ua) and the distance.
pub(crate) fn link(rods: &[&Rod], ua: f64, ub: f64) -> Result<(Vector3<f64>, f64)> {
    let v = rods[0].position(ua)? - rods[1].position(ub)?;
    let len = v.norm();
    if !(len > 1e-12 * rods[0].rest_length()) {
        return Err(Error::singular("relative distance: the two points coincide, direction undefined"));
    }
    Ok((v / len, len))
}

/// The row of a distance link between two rods (shared with contacts).
pub(crate) fn link_rows(rods: &[&Rod], ua: f64, ub: f64, distance: f64, rows: &mut [Row]) -> Result<()> {
    let (n, len) = link(rods, ua, ub)?;
    point_rows(rods[0], 0, ua, 1.0, &[n], rows)?;
    point_rows(rods[1], 1, ub, -1.0, &[n], rows)?;
    rows[0].rhs = distance - len;
    Ok(())
}

impl ConstraintLaw for RelativeDistance {
    const INFO: KindInfo = KindInfo {
        name: "RelativeDistance",
        helper: "relative_distance",
        rods: 2,
        doc: "|r_a(ua) − r_b(ub)| = `distance` (length, > 0). Multiplier: force on rod a, negative in tension.",
        fields: &[
            FieldInfo::new("ua", Abscissa, "u", "abscissa on rod a"),
            FieldInfo::new("ub", Abscissa, "u", "abscissa on rod b"),
            FieldInfo::new("distance", Scalar, "length", "distance to keep (> 0)"),
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
        crate::error::positive("relative distance (use RelativePosition for zero)", self.distance).map(|_| ())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        link_rows(rods, self.ua, self.ub, self.distance, rows)
    }
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        Ok(Reaction::force(link(rods, self.ua, self.ub)?.0 * lambda[0]))
    }
    fn tension(&self, _rods: &[&Rod], lambda: &[f64]) -> Result<Option<f64>> {
        Ok(Some(-lambda[0]))
    }
}
