//! strandkit-core: geometrically exact dynamic splines (SPEC §1–§5).
//!
//! A [`World`] holds rods (cubic B-spline centreline + roll), constraints,
//! loads, beads and clips by handle; the [`pipeline`] steps it —
//! [`World::step`] with linearised implicit Euler, [`World::relax`] to static
//! equilibrium, [`QuasiDynamic`] frame by frame — through one banded KKT
//! system whose multipliers are reported as forces and torques. Structures
//! are built as an [`Assembly`] and inserted in one batch. See
//! `ARCHITECTURE.md` for the modules, the data flow of a step and the seams.
pub mod assembly;
pub mod bead;
pub mod clip;
pub mod constraint;
pub mod contact;
pub mod energy;
pub mod error;
pub mod force;
pub mod frames;
pub mod handles;
pub mod io;
pub mod linalg;
pub mod material;
pub mod pipeline;
pub mod quadrature;
pub mod rod;
pub mod section;
pub mod spline;
pub mod system;
pub mod world;

pub use assembly::{Assembly, AssemblyConstraint, Inserted};
pub use bead::Bead;
pub use clip::Clip;
pub use constraint::{BreakPolicy, Breaking, ConstraintKind, ConstraintLaw, Reaction};
pub use contact::{mesh::TriMesh, obstacle::Obstacle, rods::RodContacts, ContactPair, ContactSet, Detector};
pub use energy::{FrameModel, MaterialFrame};
pub use error::{Error, Result, Unknown};
pub use force::{ForceField, Load};
pub use handles::{BeadHandle, ClipHandle, ConstraintHandle, LoadHandle, RodHandle};
pub use material::Material;
pub use pipeline::quasi_dynamic::{Clock, FrameReport, Mode, QuasiDynamic, QuasiDynamicParameters, WallClock};
pub use pipeline::{RelaxReport, StepReport};
pub use rod::{Cut, Jet, Rod, RodBuilder, RodOptions, StrainMode};
pub use section::Section;
pub use system::{Factorisation, LinearSolver};
pub use world::{Constraint, Energy, Event, IntegrationParameters, Item, Scheme, Units, World};

/// Everything a scene script needs, in one import: the world and its
/// objects, every constraint kind and load kind by name.
pub mod prelude {
    pub use crate::assembly::Assembly;
    pub use crate::constraint::kinds::*;
    pub use crate::constraint::{BreakPolicy, Breaking, ConstraintKind, Reaction};
    pub use crate::force::{Distributed, Load, PointForce, PointTorque, Trap};
    pub use crate::{
        BeadHandle, ClipHandle, ConstraintHandle, Error, FrameModel, IntegrationParameters, LoadHandle, Material, Result, Rod, RodBuilder,
        RodHandle, RodOptions, Section, World,
    };
}
