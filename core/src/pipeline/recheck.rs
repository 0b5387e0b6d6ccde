//! Contacts missed by a step (SPEC §7): rows are found where the rods are
//! at the start of the step, one at each place where two strands come
//! closest. Where one strand wraps round another, the place moves as the
//! strands move, and a step held at the start's place may press the
//! strands into each other a segment on, where no row was: a knit cell's
//! yarns flipped between two sets of rows from step to step, a third of
//! their radius into each other where the row was not, and never settled.
//! With `contact_recheck` a step looks again where it ended: pairs that
//! went through each other by more than [`DEPTH`] of their contact
//! distance, at places the step had no row, join the step's pairs and the
//! step is solved again from its start.
use crate::constraint::{ConstraintKind, Row};
use crate::contact::ContactPair;
use crate::error::Result;
use crate::world::World;

/// Depth past contact (fraction of the pair's contact distance) of a pair
/// found at the end of a step that makes it solve again.
pub(crate) const DEPTH: f64 = 0.01;

/// Solves of one step again at most (each adds the pairs it finds).
pub(crate) const MAX_AGAIN: usize = 3;

/// After a step's solution is applied: detects at the rods' new places
/// and adds to `ws.recheck_pairs` every rod–rod pair deeper than [`DEPTH`]
/// at a place where the step had no pair. Returns whether it added any.
pub(crate) fn missed(world: &mut World) -> Result<bool> {
    if world.detectors.is_empty() {
        return Ok(false);
    }
    let World { rods, detectors, contacts, ws, .. } = world;
    // The buffer goes back to the workspace whatever fails.
    let mut found = std::mem::take(&mut ws.recheck_found);
    found.pairs.clear();
    let added = super::assemble::detect_all(rods, detectors, ws, &mut found).and_then(|()| {
        let mut added = false;
        let mut rows = [Row::default(); 1];
        for p in found.pairs.drain(..) {
            let ConstraintKind::Contact(c) = &p.kind else { continue };
            // A penalty row sinks by design, and the next step takes it.
            if p.is_penalty() {
                continue;
            }
            let (Some(a), Some(b)) = (rods.get(p.rods[0].into()), rods.get(p.rods[1].into())) else { continue };
            p.kind.linearize(&[a, b], &mut rows)?;
            // rhs = target − g: the gap is −rhs.
            if -rows[0].rhs >= -DEPTH * c.distance {
                continue;
            }
            let had = |q: &ContactPair| q.rods == p.rods && super::assemble::same_place(rods, q, &p);
            if contacts.pairs.iter().any(had) || ws.recheck_pairs.iter().any(had) {
                continue;
            }
            ws.recheck_pairs.push(ContactPair { active: false, force: 0.0, ..p });
            added = true;
        }
        Ok(added)
    });
    ws.recheck_found = found;
    added
}
