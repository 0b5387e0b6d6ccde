//! Beads: particles sliding along a rod (sliding-abscissa particles,
//! III.50–III.54 in arc-length form, SPEC §4). Loosely coupled to the rod:
//! the bead's motion along the tangent t is its own unknown, its absolute
//! tangential speed w = t·v_b (v_b its own velocity) following
//!
//!   (m/h + c) w_{n+1} = m w_n / h + t·F_p + c t·v_rod
//!
//! (F_p its weight plus user force, c the viscous friction on the sliding
//! speed ṡ), while the rod carries its transverse inertia m (I − t tᵀ) and
//! the force F_p⊥ + c ṡ t + m (v_b − v_rod)⊥ / h. The bead carries its
//! momentum from step to step: where it arrives on a bend or on a part of
//! the rod moving differently, the difference reaches the rod as an
//! inelastic impulse (the centripetal and Coriolis forces
//! −m (ṡ² κn + 2ṡ ∂v_rod/∂s⊥) of x = r(s(t), t) in the limit, without
//! ever adding energy, which their explicit form did).
//! A free bead thus loads a resting string with the normal part of its
//! weight only, a stuck one with all of it; the thesis' form, which moved
//! the bead relative to the string and gave the rod its whole mass, let a
//! string that moves along itself drag its beads and created energy.
//! In statics the bead's abscissa is an unknown of the Newton system (it
//! minimises −F·r(u): the bead sits where its load is normal to the rod).
//! Beads on one rod do not pass each other: they are spheres threaded on
//! the string, which touch when their centres are r_a + r_b apart (the
//! chord, shorter than the arc between them on a bend), kept so by an
//! inelastic projection of the step's increments (and after the step, of
//! the positions, for what the rod's deformation changed). Touching
//! beads push each other along their line of centres: the part of that
//! push across the string goes to the string, so a train pressed round a
//! bend leans on it and the pair's forces do no work.
//! A `fixed` bead (knotted on the string) keeps its abscissa: a point mass
//! riding with the rod, whole load and mass, never an unknown of the statics.
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
    /// This step's arc-length increment and the force it puts on the rod.
    #[serde(default)]
    pub(crate) step_ds: f64,
    #[serde(default)]
    pub(crate) rod_force: [f64; 3],
    /// This step's absolute speed along the tangent (length/time).
    #[serde(default)]
    pub(crate) step_w: f64,
    /// Abscissa at which `rod_force` was last assembled (statics).
    #[serde(default)]
    pub(crate) u_assembled: f64,
    /// The bead's own velocity (length/time) after a dynamic step. A bead
    /// carries its momentum: arriving where the rod moves differently, or
    /// round a bend, it meets the rod with the difference, which the next
    /// step hands to the rod as an inelastic impulse. None: the rod's
    /// velocity at u plus `velocity` along the tangent.
    #[serde(default)]
    pub(crate) carried: Option<[f64; 3]>,
    /// The unit tangent at the bead when this step's tangential motion was
    /// predicted (the direction of `step_w`).
    #[serde(default)]
    pub(crate) step_t: [f64; 3],
}

impl Bead {
    /// A bead at rest at abscissa `u`: mass (> 0), viscous friction (force
    /// per unit sliding speed, ≥ 0), radius (length, ≥ 0).
    pub fn new(rod: RodHandle, u: f64, mass: f64, friction: f64, radius: f64) -> crate::error::Result<Bead> {
        let b = Bead { rod, u, velocity: 0.0, mass, friction, radius, force: [0.0; 3], fixed: false, step_ds: 0.0, rod_force: [0.0; 3], step_w: 0.0, u_assembled: u, carried: None, step_t: [0.0; 3] };
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
