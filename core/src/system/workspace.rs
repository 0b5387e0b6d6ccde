//! Scratch space of the pipeline, owned by the world but not part of its
//! data: the KKT system and its factorisations, the layout and what it was
//! built for, and buffers recycled across steps so that a step allocates
//! nothing once warmed up.
use super::kkt::{ConstraintRef, KktSystem};
use super::layout::{ConstraintSlot, Layout};
use crate::handles::{Index, RodHandle};

#[derive(Debug, Default)]
pub struct Workspace {
    pub(crate) sys: KktSystem,
    pub(crate) layout: Layout,
    /// What `layout` was built for: rods (id, control points, dofs,
    /// segment fingerprint), constraint slots, interleaved groups.
    pub(crate) layout_rods: Vec<(Index, usize, usize, usize)>,
    pub(crate) layout_slots: Vec<ConstraintSlot>,
    pub(crate) layout_groups: Vec<Vec<RodHandle>>,
    /// The order of the control points the layout was built on and the
    /// two-rod links that order came from: while rods, groups and links
    /// stay, a slot that moves rebuilds the layout on the same order.
    pub(crate) layout_order: Vec<(usize, usize)>,
    pub(crate) layout_links: Vec<crate::system::ordering::Link>,
    pub(crate) links: Vec<crate::system::ordering::Link>,
    pub(crate) layout_scratch: super::layout::LayoutScratch,
    pub(crate) slots: Vec<ConstraintSlot>,
    /// Allocations kept for the per-step vectors of references (always
    /// empty between steps, see [`recycle`]).
    pub(crate) rod_refs: Vec<&'static crate::rod::Rod>,
    pub(crate) rod_list: Vec<(crate::handles::RodHandle, &'static crate::rod::Rod)>,
    pub(crate) con_refs: Vec<ConstraintRef<'static>>,
    pub(crate) masses: Vec<crate::system::kkt::PointMass>,
    pub(crate) field_k: Vec<(usize, usize, usize, f64)>,
    pub(crate) ext: Vec<Vec<f64>>,
    /// Each rod's drag in the last assembly (layout order).
    pub(crate) drags: Vec<crate::rod::drag::Drag>,
    /// The thermal noise of the step under way: its h (0: none), kT and
    /// standard normals per rod (layout order).
    pub(crate) thermal_h: f64,
    pub(crate) thermal_kt: f64,
    pub(crate) thermal_normals: Vec<Vec<f64>>,
    /// Whether this try of the step drew normals, and the normals of the
    /// step's first try; the Brownian bridge of a retried step.
    pub(crate) thermal_drawn: bool,
    pub(crate) thermal_first: Vec<Vec<f64>>,
    pub(crate) bridge: Option<crate::pipeline::thermal::Bridge>,
    pub(crate) rod_ids: Vec<Index>,
    pub(crate) con_ids: Vec<Index>,
    /// Slot index → position of each rod in iteration order.
    pub(crate) rod_pos: Vec<Option<(u32, usize)>>,
    /// Rows of one constraint (the trapezoidal rule's velocity projection).
    pub(crate) rows: Vec<crate::constraint::Row>,
    /// Contact pairs in the system (indices into the contact set), after
    /// the constraints.
    pub(crate) contact_ids: Vec<usize>,
    /// Pairs with friction rows (indices into the contact set): two for a
    /// sticking pair, one across the slip direction for a slipping one;
    /// they follow the contacts' normal rows.
    pub(crate) stick_ids: Vec<usize>,
    /// Contact pairs whose row the factorisation found dependent on the
    /// others (a point an anchor already holds against an obstacle): kept
    /// out of the active set for the rest of the solve.
    pub(crate) blocked: Vec<crate::contact::ContactPair>,
    /// Contact pairs that left the active set in the held rounds of the
    /// current solve (their multiplier pulled): kept out for the rest of it.
    pub(crate) pulled: Vec<crate::contact::ContactPair>,
    /// The last assembly let contact rows hold a slight penetration
    /// (`assemble::CONTACT_SLACK`: implicit Euler steps).
    pub(crate) contact_slack: bool,
    /// Largest bounding radius of each rod, in layout order (per assembly).
    pub(crate) radii: Vec<f64>,
    /// The previous assembly's contact pairs (what the carry-over reads),
    /// kept so that the next detection fills this allocation.
    pub(crate) previous_pairs: Vec<crate::contact::ContactPair>,
    /// The contact carry-over's buffer (`pipeline::assemble::Carry`).
    pub(crate) carry: Vec<(crate::handles::RodHandle, crate::handles::RodHandle, f64, usize)>,
    /// Detected pairs kept across the active-set rounds of one
    /// [`crate::pipeline::solve::assemble_and_solve`] (see [`Detected`]).
    pub(crate) detected: Detected,
    /// The contact detectors' buffers.
    pub(crate) detect: crate::contact::Scratch,
    /// Each rod's stick compliance this assembly, by arena slot (NaN: not
    /// yet computed; it scans the rod's sections).
    pub(crate) stick: Vec<f64>,
    /// Sliders that left their rod in the last solve.
    pub(crate) left: Vec<Index>,
    /// Averaged break measures of this step, written back after the
    /// breaking pass (kept to recycle its allocation).
    pub(crate) break_measures: Vec<(Index, f64)>,
    /// What the last `apply` overwrote (coordinates, velocities,
    /// multipliers, slider abscissae), to undo a step refused after it.
    pub(crate) undo: Vec<f64>,
    /// Kinetic energy of each rod before the step being committed (the
    /// guard's, naming the rod whose energy grew).
    pub(crate) energy_before: Vec<f64>,
    /// Each rod's elastic + kinetic energy after the step (the guard's).
    pub(crate) energy_after: Vec<f64>,
    /// Buffers of the bead passes.
    pub(crate) beads: crate::pipeline::beads::Scratch,
    /// The trapezoidal step's per-rod vectors.
    pub(crate) trapezoidal: crate::pipeline::trapezoidal::State,
    /// The active-set update's row of each contact pair (and of its
    /// friction rows), by pair.
    pub(crate) row_of: Vec<usize>,
    pub(crate) stick_of: Vec<usize>,
    /// The contact set at the start of a step, put back if it is refused.
    pub(crate) contacts_before: crate::contact::ContactSet,
    /// With `contact_recheck`: pairs found past contact where a step ended,
    /// added to its pairs when it is solved again (`pipeline/recheck.rs`),
    /// and the detection that found them.
    pub(crate) recheck_pairs: Vec<crate::contact::ContactPair>,
    pub(crate) recheck_found: crate::contact::ContactSet,
    /// The clips walked after a solve.
    pub(crate) clip_ids: Vec<Index>,
}

/// Empties a vector and reuses its allocation for another element type of
/// the same size and alignment — here references of another lifetime — so
/// per-step vectors of borrows keep their buffer between steps (the
/// in-place `collect` of `vec::IntoIter` keeps the allocation).
pub(crate) fn recycle<T, U>(mut v: Vec<T>) -> Vec<U> {
    v.clear();
    // The vector is empty, so the closure never runs.
    v.into_iter().filter_map(|_| None).collect()
}

/// The workspace is scratch space: a cloned world starts with empty buffers
/// (and rebuilds its layout on its first solve).
impl Clone for Workspace {
    fn clone(&self) -> Self {
        Workspace::default()
    }
}

/// The contact pairs as the detectors found them, before the active set's
/// carry-over. Between the rounds of one assemble-and-solve the rods do not
/// move, so detection would find the same pairs again: its first round
/// detects and keeps them (`valid`), the others reuse them
/// (`pipeline::assemble::assemble_with`); any other assembly detects.
#[derive(Debug, Default)]
pub(crate) struct Detected {
    pub(crate) valid: bool,
    pub(crate) pairs: Vec<crate::contact::ContactPair>,
}
