//! The world's mechanical energy, beads included: what a conservative
//! scene keeps and implicit damping can only lower.
use super::World;
use crate::error::Result;
use crate::force::ForceField;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Energy parts (energy unit).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Energy {
    /// ½ VᵀMV of the rods plus ½ m |v|² of the beads, whose velocity is the
    /// rod's at their abscissa plus their sliding speed along the tangent.
    pub kinetic: f64,
    /// Elastic energy of the rods.
    pub elastic: f64,
    /// Potential of gravity (rods and beads), of the loads and of the
    /// beads' user forces: −Σ F·r.
    pub external: f64,
}

impl Energy {
    pub fn total(&self) -> f64 {
        self.kinetic + self.elastic + self.external
    }
}

impl World {
    /// Mechanical energy now (see [`Energy`]); constraints do no work
    /// and add nothing.
    pub fn energy(&self) -> Result<Energy> {
        let t = self.time;
        let g = Vector3::from(self.params.gravity);
        let gravity = crate::force::gravity::Gravity(self.params.gravity);
        let mut e = Energy::default();
        for (_, rod) in self.rods.iter() {
            e.kinetic += rod.kinetic_energy();
            e.elastic += rod.elastic_energy();
            e.external += gravity.potential(rod, t)?;
        }
        for (_, l) in self.loads.iter() {
            e.external += l.potential(self.rod(l.rod())?, t)?;
        }
        for (_, b) in self.beads.iter() {
            let rod = self.rod(b.rod)?;
            let v = b.absolute_velocity(rod)?;
            e.kinetic += 0.5 * b.mass * v.norm_squared();
            e.external -= (g * b.mass + Vector3::from(b.force)).dot(&rod.position(b.u)?);
        }
        Ok(e)
    }
}
