//! Beads: particles sliding along a rod (sliding-abscissa particles,
//! III.50–III.54 in arc-length form, SPEC §4). Loosely coupled to the rod:
//!
//!   (c/h + m/h²) Δs_{n+1} = t·F_p + m Δs_n / h²
//!
//! (t the unit tangent at the bead, F_p its weight plus user force, c the
//! viscous friction); the force applied back to the rod at the bead is
//! F_p − m a_t t with a_t = (Δs_{n+1} − Δs_n)/h² (momentum-consistent: a
//! free bead loads the string with the normal part of its weight only, a
//! stuck one with all of it), and the bead's mass is added to the rod's mass
//! matrix at its abscissa (transverse inertia). In statics the bead's
//! abscissa is an unknown of the Newton system (it minimises −F·r(u): the
//! bead sits where its load is normal to the rod). Beads on one rod do not pass each
//! other: |s_a − s_b| ≥ r_a + r_b, enforced by an inelastic contact.
use crate::handles::RodHandle;
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Bead {
    pub rod: RodHandle,
    /// Spline abscissa of the bead.
    pub u: f64,
    /// Speed along the rod (length/time, positive towards increasing u).
    pub velocity: f64,
    /// Mass (mass unit), friction coefficient (force per speed), radius (length).
    pub mass: f64,
    pub friction: f64,
    pub radius: f64,
    /// External force besides gravity (force unit).
    pub force: [f64; 3],
    /// This step's arc-length increment and the force it puts on the rod.
    #[serde(default)]
    pub(crate) step_ds: f64,
    #[serde(default)]
    pub(crate) rod_force: [f64; 3],
    /// Abscissa at which `rod_force` was last assembled (statics).
    #[serde(default)]
    pub(crate) u_assembled: f64,
}
