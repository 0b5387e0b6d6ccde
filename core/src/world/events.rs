//! What happened during a solve, reported in the order it happened.
use crate::constraint::{BreakPolicy, ConstraintKind};
use crate::handles::{BeadHandle, ClipHandle, ConstraintHandle, RodHandle};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Event {
    /// A constraint exceeded its break force and was removed (or, force 0:
    /// a constraint straddling a rupture could no longer hold, or one that
    /// `breaks_with` a constraint that broke went with it).
    ConstraintBroken {
        constraint: ConstraintHandle,
        /// Its label in the world's groups, e.g. "hbond[17]".
        label: Option<String>,
        time: f64,
        /// The measure that broke it (force unit, see `policy`).
        force: f64,
        policy: BreakPolicy,
        kind: ConstraintKind,
    },
    /// A sliding constraint's abscissa left its rod; the constraint was removed.
    SliderLeft { constraint: ConstraintHandle, label: Option<String>, time: f64, kind: ConstraintKind },
    /// A bead slid off the end of its rod and was removed.
    BeadLeft { bead: BeadHandle, time: f64 },
    /// A clip captured a rod (position constraint `constraint` at abscissa u).
    ClipCaptured { clip: ClipHandle, rod: RodHandle, constraint: ConstraintHandle, u: f64, time: f64 },
    /// A clip released its rod: the pull-out force exceeded its resistance.
    ClipReleased { clip: ClipHandle, rod: RodHandle, force: f64, time: f64 },
    /// Material rupture (SPEC §6): `rod` was cut at abscissa `u` where its
    /// relative strain in `mode` passed `limit`. An open rod keeps the piece
    /// on [start, u] under its handle and the piece on [u, end] becomes
    /// `new_rod`; a ring is opened into one rod (new_rod None) whose abscissa
    /// s is the ring's u + s.
    RodRuptured {
        rod: RodHandle,
        new_rod: Option<RodHandle>,
        u: f64,
        time: f64,
        mode: crate::rod::StrainMode,
        strain: f64,
        limit: f64,
    },
    /// A rupture cut off a free piece (held by no constraint) shorter than
    /// its own thickness (the equivalent diameter of its section): no
    /// longer slender, it left the world with its attachments (loads on it
    /// included). This bounds a
    /// rupture cascade — a load beyond the breaking strength tears the
    /// loaded end off instead of cutting it ever smaller.
    FragmentRemoved {
        rod: RodHandle,
        rest_length: f64,
        time: f64,
    },
}
