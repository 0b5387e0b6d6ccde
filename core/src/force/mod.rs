//! External forces (SPEC §3, III.1–III.10) behind one seam, [`ForceField`]:
//! anything that adds generalised forces, and optionally their stiffness
//! −∂F/∂q, to the rods before assembly. Gravity is a world-wide field
//! ([`gravity::Gravity`]); the per-rod fields a user adds by handle are the
//! [`Load`] kinds, one file each, registered by one line of the
//! `force_kinds!` table below (the same recipe as constraint kinds):
//! point force, point torque, distributed force, harmonic trap.
//!
//! Viscous drag is not a field here: it is the rod's dissipation matrix D
//! (`RodOptions::drag`, D_ij = ∫ c_d b_i b_j ds0), assembled with the mass
//! matrix as c_d D in the same pass, because implicit Euler takes it wholly
//! on the left-hand side and the thermal forces of SPEC §3 need the same D
//! (their covariance is 2kT D/h).
pub mod distributed;
pub mod gravity;
pub mod point_force;
pub mod point_torque;
pub mod thermal;
pub mod trap;

use crate::constraint::catalogue::FieldInfo;
use crate::error::Result;
use crate::handles::RodHandle;
use crate::rod::Rod;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

/// Where stiffness entries go: `(i, j, value)` on the rod's local
/// coordinates (i = control point × dofs + axis), full symmetric entries.
pub type StiffnessSink<'a> = dyn FnMut(usize, usize, f64) + 'a;

/// The force seam. `time` is the time the force is evaluated at (the end of
/// a dynamic step, the current time in statics).
pub trait ForceField {
    /// Adds the generalised force on `rod` to `f` (rod-local coordinates).
    fn add_force(&self, rod: &Rod, time: f64, f: &mut [f64]) -> Result<()>;
    /// The potential V of the force at the rod's current configuration
    /// (F = −∂V/∂q; energy unit), for the statics' energy test.
    fn potential(&self, rod: &Rod, time: f64) -> Result<f64>;
    /// Adds −∂F/∂q (force per length) through `k`; nothing for loads that
    /// do not depend on the configuration.
    fn add_stiffness(&self, _rod: &Rod, _time: f64, _k: &mut StiffnessSink<'_>) -> Result<()> {
        Ok(())
    }
}

/// What happens to a load when its rod ruptures (SPEC §6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OnRupture {
    /// It follows the piece holding its abscissa.
    Follow,
    /// It applies to both pieces (distributed along the rod).
    Copy,
}

/// Catalogue entry of a load kind (as [`crate::constraint::KindInfo`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct LoadInfo {
    pub name: &'static str,
    pub helper: &'static str,
    pub doc: &'static str,
    pub fields: &'static [FieldInfo],
}

/// A per-rod load kind (one file, one registration line).
pub trait LoadLaw: ForceField + Clone + std::fmt::Debug + PartialEq + Serialize + DeserializeOwned {
    const INFO: LoadInfo;
    fn rod(&self) -> RodHandle;
    fn rod_mut(&mut self) -> &mut RodHandle;
    /// The abscissa it acts at (None: the whole rod).
    fn abscissa_mut(&mut self) -> Option<&mut f64> {
        None
    }
    fn on_rupture(&self) -> OnRupture {
        OnRupture::Follow
    }
    /// Checks values and abscissa against the rod.
    fn validate(&self, rod: &Rod) -> Result<()>;
}

macro_rules! load_kinds {
    ($($module:ident :: $ty:ident),* $(,)?) => {
        $(pub use $module::$ty;)*

        /// A load on one rod; one variant per kind (serde form
        /// `{"PointForce": {"rod": …, "u": …, "force": […]}}`).
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        pub enum Load {
            $($ty($ty),)*
        }

        $(impl From<$ty> for Load {
            fn from(l: $ty) -> Self {
                Load::$ty(l)
            }
        })*

        impl Load {
            pub const CATALOGUE: &'static [LoadInfo] = &[$(<$ty as LoadLaw>::INFO,)*];
            pub fn info(&self) -> &'static LoadInfo {
                match self { $(Load::$ty(_) => &<$ty as LoadLaw>::INFO,)* }
            }
            pub fn rod(&self) -> RodHandle {
                match self { $(Load::$ty(l) => l.rod(),)* }
            }
            pub fn rod_mut(&mut self) -> &mut RodHandle {
                match self { $(Load::$ty(l) => l.rod_mut(),)* }
            }
            pub fn abscissa_mut(&mut self) -> Option<&mut f64> {
                match self { $(Load::$ty(l) => l.abscissa_mut(),)* }
            }
            pub fn on_rupture(&self) -> OnRupture {
                match self { $(Load::$ty(l) => l.on_rupture(),)* }
            }
            pub fn validate(&self, rod: &Rod) -> Result<()> {
                match self { $(Load::$ty(l) => l.validate(rod),)* }
            }
        }

        impl ForceField for Load {
            fn add_force(&self, rod: &Rod, time: f64, f: &mut [f64]) -> Result<()> {
                match self { $(Load::$ty(l) => l.add_force(rod, time, f),)* }
            }
            fn add_stiffness(&self, rod: &Rod, time: f64, k: &mut StiffnessSink<'_>) -> Result<()> {
                match self { $(Load::$ty(l) => l.add_stiffness(rod, time, k),)* }
            }
            fn potential(&self, rod: &Rod, time: f64) -> Result<f64> {
                match self { $(Load::$ty(l) => l.potential(rod, time),)* }
            }
        }
    };
}

load_kinds! {
    point_force::PointForce,
    point_torque::PointTorque,
    distributed::Distributed,
    trap::Trap,
}

/// Adds `w_k v` on the position coordinates of control points `ctrl`.
pub(crate) fn spread(f: &mut [f64], dofs: usize, ctrl: &[usize; 4], w: &[f64; 4], v: &[f64; 3]) {
    for k in 0..4 {
        for a in 0..3 {
            f[ctrl[k] * dofs + a] += w[k] * v[a];
        }
    }
}

pub(crate) fn finite_all(what: &str, v: &[f64]) -> Result<()> {
    for x in v {
        crate::error::finite(what, *x)?;
    }
    Ok(())
}

/// −F·q for a force that does not depend on the configuration.
pub(crate) fn linear_potential(field: &impl ForceField, rod: &Rod, time: f64) -> Result<f64> {
    let mut f = vec![0.0; rod.coords().len()];
    field.add_force(rod, time, &mut f)?;
    Ok(-f.iter().zip(rod.coords()).map(|(a, b)| a * b).sum::<f64>())
}
