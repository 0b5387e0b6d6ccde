//! Sliding contact between two rods (III.42 remark): a relative distance
//! whose two abscissae are moved to the closest points before every
//! linearisation, so the force is normal to both rods and yarns slide
//! freely. By the envelope theorem the rows at the closest points are the
//! exact Jacobian of the distance between the two curves.
use super::relative_distance::{link, link_rows};
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{ConstraintLaw, Reaction, Row, Side};
use crate::error::Result;
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// |r_a(ua) − r_b(ub)| = `distance` with both abscissae at the closest
/// points. Multiplier: force on rod a along (r_a − r_b), negative in tension.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Contact {
    pub ua: f64,
    pub ub: f64,
    pub distance: f64,
}

impl ConstraintLaw for Contact {
    const INFO: KindInfo = KindInfo {
        name: "Contact",
        helper: "contact",
        rods: 2,
        doc: "Sliding contact between rods a and b of World.add_link: |r_a(ua) − r_b(ub)| = `distance` (length) \
              with both abscissae moved to the closest points. Multiplier: force on rod a, negative in tension.",
        fields: &[
            FieldInfo::new("ua", Abscissa, "u", "starting abscissa on rod a"),
            FieldInfo::new("ub", Abscissa, "u", "starting abscissa on rod b"),
            FieldInfo::new("distance", Scalar, "length", "distance between the centrelines (> 0)"),
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
        crate::error::positive("contact distance", self.distance).map(|_| ())
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
    fn project(&mut self, rods: &[&Rod]) -> Result<()> {
        let (a, b) = closest_points(rods[0], rods[1], self.ua, self.ub)?;
        self.ua = a;
        self.ub = b;
        Ok(())
    }
}

/// Closest points between rod a near `ua` and rod b near `ub`: alternating
/// one-dimensional Newton steps on |r_a(ua) − r_b(ub)|², each abscissa kept
/// in its domain (an end point is a valid closest point).
pub fn closest_points(a: &Rod, b: &Rod, ua: f64, ub: f64) -> Result<(f64, f64)> {
    closest_points_within(a, b, ua, ub, a.domain(), b.domain())
}

/// [`closest_points`] with each abscissa kept in a window (a ring's window
/// may run past its period end: the abscissae are wrapped to evaluate).
/// Detection bounds the search to the capsules that found the pair: along
/// strands lying side by side the distance is nearly flat, and an unbounded
/// search slid every row to the few places where the strands sag most,
/// leaving them to sag into each other between (SPEC §7).
pub fn closest_points_within(a: &Rod, b: &Rod, ua: f64, ub: f64, wa: (f64, f64), wb: (f64, f64)) -> Result<(f64, f64)> {
    closest_points_and_positions_within(a, b, ua, ub, wa, wb).map(|(ua, ub, _, _)| (ua, ub))
}

/// [`closest_points_within`] with the two points' positions: each
/// evaluation of a rod serves both its own Newton step and the other
/// rod's target.
pub fn closest_points_and_positions_within(a: &Rod, b: &Rod, mut ua: f64, mut ub: f64, wa: (f64, f64), wb: (f64, f64)) -> Result<(f64, f64, Vector3<f64>, Vector3<f64>)> {
    let v3 = |d: [f64; 4]| Vector3::new(d[0], d[1], d[2]);
    let at = |rod: &Rod, u: f64| if rod.is_closed() { rod.knots().wrap(u) } else { u };
    // One Newton step of `u` towards `target`, from the rod's position and
    // first two derivatives `e` at u.
    let newton = |e: &[[f64; 4]; 3], u: f64, w: (f64, f64), target: Vector3<f64>| {
        let (d, r1, r2) = (v3(e[0]) - target, v3(e[1]), v3(e[2]));
        let h = r1.dot(&r1) + d.dot(&r2);
        if h > 0.0 { (u - d.dot(&r1) / h).clamp(w.0, w.1) } else { u }
    };
    ua = ua.clamp(wa.0, wa.1);
    ub = ub.clamp(wb.0, wb.1);
    let mut ea = a.eval_012(at(a, ua))?;
    let mut eb = b.eval_012(at(b, ub))?;
    for _ in 0..30 {
        let (oa, ob) = (ua, ub);
        ua = newton(&ea, ua, wa, v3(eb[0]));
        ea = a.eval_012(at(a, ua))?;
        ub = newton(&eb, ub, wb, v3(ea[0]));
        eb = b.eval_012(at(b, ub))?;
        if (ua - oa).abs() + (ub - ob).abs() < 1e-14 * (1.0 + ua.abs() + ub.abs()) {
            break;
        }
    }
    Ok((at(a, ua), at(b, ub), v3(ea[0]), v3(eb[0])))
}
