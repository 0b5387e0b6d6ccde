//! strandkit-core: geometrically exact dynamic splines (SPEC §1–§5).
//!
//! A [`World`] owns rods (cubic B-spline centreline + roll), constraints and
//! loads by handle; [`World::step`] advances it with linearised implicit
//! Euler and [`World::relax`] solves for static equilibrium, both through one
//! banded KKT system whose multipliers are reported as forces and torques.
pub mod bead;
pub mod clip;
pub mod constraint;
pub mod energy;
pub mod error;
pub mod frames;
pub mod handles;
pub mod integrator;
pub mod io;
pub mod linalg;
pub mod load;
pub mod material;
pub mod quadrature;
pub mod rod;
mod rupture;
pub mod section;
pub mod spline;
pub mod system;
pub mod world;

pub use constraint::{ConstraintKind, Reaction};
pub use error::{Error, Result};
pub use bead::Bead;
pub use clip::Clip;
pub use handles::{BeadHandle, ClipHandle, ConstraintHandle, LoadHandle, RodHandle};
pub use integrator::quasi_dynamic::{Clock, FrameReport, Mode, QuasiDynamic, QuasiDynamicParameters, WallClock};
pub use integrator::{IntegrationParameters, RelaxReport, StepReport};
pub use load::Load;
pub use material::Material;
pub use rod::{Cut, Rod, RodBuilder, RodOptions, StrainMode};
pub use section::Section;
pub use system::LinearSolver;
pub use world::{Breaking, Constraint, Event, World};
