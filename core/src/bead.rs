//! Beads: particles sliding along a rod (sliding-abscissa particles,
//! III.50–III.54, SPEC §4). In a dynamic step a sliding bead's abscissa u
//! is an unknown of the same implicit system as its rod's coordinates: its
//! position r(q, u) carries its whole mass, its load and its momentum, and
//! viscous friction c acts on its sliding speed |r′| u̇ (force per unit
//! sliding speed). Where it arrives on a bend or on a part of the rod
//! moving differently it meets it inelastically (its velocity is the
//! step's linearised displacement over h), which never adds energy; the
//! thesis' explicit centripetal and Coriolis forces did. In statics u is an
//! unknown of the Newton system (the bead sits where its load is normal to
//! the rod).
//! Beads on one rod do not pass each other: they are spheres threaded on
//! the string, which touch when their centres are r_a + r_b apart (the
//! chord, shorter than the arc between them on a bend), kept so by a
//! unilateral row on that chord in the step's system (with an active set):
//! its force pushes them apart along their line of centres and the string
//! bears the part across it, so a train pressed round a bend leans on the
//! string and the pair's forces do no work ([`crate::pipeline::beads`]).
//! A `fixed` bead (knotted on the string) keeps its abscissa: a point mass
//! riding with the rod, whole load and mass, never an unknown.
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
    /// Held at its abscissa (knotted): it does not slide.
    #[serde(default)]
    pub fixed: bool,
    /// This step's abscissa increment Δu (dynamics) and the force the bead
    /// puts on the rod besides its point mass (force unit).
    #[serde(default)]
    pub(crate) step_du: f64,
    #[serde(default)]
    pub(crate) rod_force: [f64; 3],
    /// Abscissa at which `rod_force` was last assembled (statics).
    #[serde(default)]
    pub(crate) u_assembled: f64,
    /// The bead's own velocity (length/time) after a dynamic step, the
    /// step's linearised displacement J [Δq; Δu] over h: a bead carries its
    /// momentum into the next. None: the rod's velocity at u plus `velocity` along the
    /// tangent.
    #[serde(default)]
    pub(crate) carried: Option<[f64; 3]>,
    /// It pressed on its next neighbour along the rod at the end of the
    /// last step (where the next step's active set of gap rows starts).
    #[serde(default)]
    pub(crate) pressed: bool,
}

impl Bead {
    /// A bead at rest at abscissa `u`: mass (> 0), viscous friction (force
    /// per unit sliding speed, ≥ 0), radius (length, ≥ 0).
    pub fn new(rod: RodHandle, u: f64, mass: f64, friction: f64, radius: f64) -> crate::error::Result<Bead> {
        let b = Bead { rod, u, velocity: 0.0, mass, friction, radius, force: [0.0; 3], fixed: false, step_du: 0.0, rod_force: [0.0; 3], u_assembled: u, carried: None, pressed: false };
        b.check_values()?;
        Ok(b)
    }
    fn check_values(&self) -> crate::error::Result<()> {
        crate::error::finite("bead abscissa u", self.u)?;
        crate::error::positive("bead mass", self.mass)?;
        crate::error::non_negative("bead friction", self.friction)?;
        crate::error::non_negative("bead radius", self.radius)?;
        crate::error::finite("bead velocity", self.velocity)?;
        crate::constraint::finite3(&self.force, "bead force")
    }
    /// The bead's velocity (length/time) on `rod` (its rod).
    pub fn absolute_velocity(&self, rod: &crate::rod::Rod) -> crate::error::Result<nalgebra::Vector3<f64>> {
        Ok(self.velocity_from(rod.eval_velocity(self.u)?, rod.tangent(self.u)?))
    }
    /// [`Self::absolute_velocity`] from the rod's velocity and unit tangent
    /// at the bead: the carried velocity, or the rod's plus the sliding speed.
    pub(crate) fn velocity_from(&self, rod_velocity: nalgebra::Vector3<f64>, tangent: nalgebra::Vector3<f64>) -> nalgebra::Vector3<f64> {
        match self.carried {
            Some(v) if !self.fixed => v.into(),
            _ => rod_velocity + tangent * self.velocity,
        }
    }
    /// All values valid and the abscissa on `rod`.
    pub(crate) fn validate(&self, rod: &crate::rod::Rod) -> crate::error::Result<()> {
        self.check_values()?;
        rod.knots().locate(self.u).map(|_| ())
    }
}
