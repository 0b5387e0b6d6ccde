//! Clips (thesis III.A.5.a, algorithms 4–5): a sphere with an exit axis.
//! A rod whose centreline enters the sphere is captured by a position
//! constraint at its closest abscissa, pulled to the clip's centre; the clip
//! releases it when the pull-out force along the exit axis (minus the force
//! the clip exerts on the rod, projected on the axis) exceeds the clip's
//! resistance. A released clip re-arms once no rod is inside it.
use crate::handles::{ConstraintHandle, RodHandle};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Clip {
    /// Centre and radius of the capture sphere (length unit).
    pub center: [f64; 3],
    pub radius: f64,
    /// Unit exit axis: the rod leaves the clip when pulled along it.
    pub axis: [f64; 3],
    /// Pull-out force that releases the rod (force unit).
    pub resistance: f64,
    /// The rod held and the constraint holding it.
    pub held: Option<(RodHandle, ConstraintHandle)>,
    /// Released and not re-armed yet (a rod is still inside).
    pub disarmed: bool,
}

impl Clip {
    /// Capture sphere (centre, radius > 0), exit axis (non-zero, normalised)
    /// and pull-out resistance (> 0, force unit).
    pub fn new(center: [f64; 3], radius: f64, axis: [f64; 3], resistance: f64) -> crate::error::Result<Clip> {
        let a = crate::constraint::unit(&axis, "clip exit axis")?;
        let c = Clip { center, radius, axis: a.into(), resistance, held: None, disarmed: false };
        c.validate()?;
        Ok(c)
    }
    pub(crate) fn validate(&self) -> crate::error::Result<()> {
        crate::constraint::finite3(&self.center, "clip centre")?;
        crate::error::positive("clip radius", self.radius)?;
        let a = crate::constraint::unit(&self.axis, "clip exit axis")?;
        if (a.norm() - nalgebra::Vector3::from(self.axis).norm()).abs() > 1e-9 {
            return Err(crate::error::Error::invalid("clip exit axis", format!("{:?}", self.axis), "a unit vector"));
        }
        crate::error::positive("clip resistance", self.resistance).map(|_| ())
    }
}
