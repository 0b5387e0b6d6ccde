//! The contact seam (SPEC §7; rapier keeps contacts apart from joints the
//! same way): a [`ContactSet`] of unilateral pairs, produced each step by
//! the world's [`ContactDetector`]s ([`rods::RodContacts`]: rod–rod and
//! self-contact between capsules), entering the same KKT system as the
//! constraints, with an active set — a pair whose multiplier would pull is
//! dropped and the system solved again; a candidate that the solution
//! would push through its gap is taken in.
//!
//! A pair's row is a constraint kind oriented so that a positive multiplier
//! pushes the rods apart: [`ConstraintKind::Contact`] between two rods
//! (g = |r_a − r_b| − distance), or [`ConstraintKind::Plane`] for a rod
//! against a fixed plane whose normal points out of the obstacle.
pub mod capsule;
pub mod obstacle;
pub mod rods;

use crate::constraint::ConstraintKind;
use crate::error::{Error, Result};
use crate::handles::RodHandle;
use serde::{Deserialize, Serialize};

/// The abscissae a detector probes along a rod (its samples, plus its two
/// ends when open) and the rod's largest section radius.
pub(crate) fn probe_points(rod: &crate::rod::Rod) -> (Vec<f64>, f64) {
    let mut us = rod.sample_params();
    if !rod.is_closed() {
        let (u0, u1) = rod.domain();
        us.insert(0, u0);
        us.push(u1);
    }
    (us, rod.sections().iter().map(|s| s.bounding_radius()).fold(0.0, f64::max))
}

/// One unilateral contact: g(q) ≥ 0 with a non-negative multiplier.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactPair {
    /// The rods (the same twice for a rod against the environment or itself).
    pub rods: [RodHandle; 2],
    pub kind: ConstraintKind,
    /// Normal force of the last solve (force unit, ≥ 0 while active).
    #[serde(default)]
    pub force: f64,
    /// In the active set of the last solve.
    #[serde(default)]
    pub active: bool,
}

impl ContactPair {
    pub fn new(rods: [RodHandle; 2], kind: ConstraintKind) -> Result<ContactPair> {
        match &kind {
            ConstraintKind::Contact(_) | ConstraintKind::Plane(_) => Ok(ContactPair { rods, kind, force: 0.0, active: false }),
            k => Err(Error::invalid("contact pair kind", k.name(), "Contact (rod–rod) or Plane (rod–obstacle)")),
        }
    }
}

/// The unilateral pairs of the current step.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactSet {
    pub pairs: Vec<ContactPair>,
}

impl ContactSet {
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }
    pub fn len(&self) -> usize {
        self.pairs.len()
    }
    /// The pairs in the active set.
    pub fn active(&self) -> impl Iterator<Item = (usize, &ContactPair)> {
        self.pairs.iter().enumerate().filter(|(_, p)| p.active)
    }
}

/// Fills the contact set from the rods before each solve
/// ([`rods::RodContacts`]); without a detector, pairs put in the set by
/// hand stay as given.
pub trait ContactDetector: Send + Sync + std::fmt::Debug {
    fn detect(&self, rods: &[(RodHandle, &crate::rod::Rod)], out: &mut ContactSet) -> Result<()>;
}
