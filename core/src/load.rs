//! External loads (III.1–III.10): point forces and torques at an abscissa,
//! distributed forces; gravity lives in the integration parameters.
use crate::handles::RodHandle;
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Load {
    /// Force (force unit) applied at r(u): generalised force f b_i(u).
    PointForce { rod: RodHandle, u: f64, force: [f64; 3] },
    /// Torque (force × length) about the tangent at u, on the roll: T b_i(u).
    PointTorque { rod: RodHandle, u: f64, torque: f64 },
    /// Force per unit rest length, uniform along the rod: ∫ f b_i ds0.
    Distributed { rod: RodHandle, force_per_length: [f64; 3] },
}

impl Load {
    pub fn rod(&self) -> RodHandle {
        match self {
            Load::PointForce { rod, .. } | Load::PointTorque { rod, .. } | Load::Distributed { rod, .. } => *rod,
        }
    }
}
