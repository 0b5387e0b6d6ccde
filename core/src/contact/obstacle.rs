//! A fixed plane obstacle (SPEC §7): the rods' points closer to it than
//! their radius plus `margin` become unilateral [`ConstraintKind::Plane`]
//! rows on the plane lifted by the radius (its normal points out of the
//! obstacle), so the rods' surfaces rest on it. Along a rod only the
//! lowest point of each run of candidates and points at least a segment
//! apart are kept: a rod lying on the plane gets about one row per
//! segment (its n + 3 control points meet at most that many heights
//! independently).
use super::{ContactDetector, ContactPair, ContactSet};
use crate::constraint::kinds::Plane;
use crate::constraint::ConstraintKind;
use crate::error::{Error, Result};
use crate::handles::RodHandle;
use crate::rod::Rod;
use nalgebra::Vector3;

/// The plane through `origin` (length) with unit `normal` (pointing out of
/// the obstacle), detected `margin` (length) ahead of contact.
#[derive(Clone, Debug, PartialEq)]
pub struct PlaneObstacle {
    origin: Vector3<f64>,
    normal: Vector3<f64>,
    margin: f64,
}

impl PlaneObstacle {
    pub fn new(origin: [f64; 3], normal: [f64; 3], margin: f64) -> Result<PlaneObstacle> {
        crate::constraint::finite3(&origin, "plane obstacle origin")?;
        let n = Vector3::from(normal);
        if !n.iter().all(|x| x.is_finite()) || !(n.norm() > 0.0) {
            return Err(Error::invalid("plane obstacle normal", format!("{normal:?}"), "a finite, non-zero direction"));
        }
        if !(margin >= 0.0) || !margin.is_finite() {
            return Err(Error::invalid("contact margin", margin, "a finite length ≥ 0"));
        }
        Ok(PlaneObstacle { origin: Vector3::from(origin), normal: n.normalize(), margin })
    }
}

impl ContactDetector for PlaneObstacle {
    fn detect(&self, rods: &[(RodHandle, &Rod)], out: &mut ContactSet) -> Result<()> {
        for (h, rod) in rods {
            let (us, radius) = super::probe_points(rod);
            let (u0, u1) = rod.domain();
            let height: Vec<f64> = us.iter().map(|&u| Ok((rod.position(u)? - self.origin).dot(&self.normal) - radius)).collect::<Result<_>>()?;
            // One segment, in the parameter.
            let span = (u1 - u0) / rod.n_segments().max(1) as f64;
            let mut last: Option<f64> = None;
            let n = us.len();
            for k in 0..n {
                if height[k] >= self.margin {
                    continue;
                }
                let lower = |j: usize| height[j] < height[k];
                let minimum = !(k > 0 && lower(k - 1)) && !(k + 1 < n && lower(k + 1));
                if !minimum && last.is_some_and(|l| (us[k] - l).abs() < span) {
                    continue;
                }
                if last.is_some_and(|l| (us[k] - l).abs() < 0.5 * span) {
                    continue; // a minimum right next to a kept row: the same touching point
                }
                last = Some(us[k]);
                let lifted = self.origin + self.normal * radius;
                let kind = ConstraintKind::Plane(Plane { u: us[k], origin: lifted.into(), normal: self.normal.into() });
                out.pairs.push(ContactPair::new([*h, *h], kind)?);
            }
        }
        Ok(())
    }
}
