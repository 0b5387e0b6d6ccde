//! The constraint set of a world: adding (checked: abscissae, targets,
//! duplicates, linear dependence on what the rods already carry), moving
//! targets, break thresholds, reactions.
use super::{bad_con, World};
use crate::constraint::{BreakPolicy, Breaking, ConstraintKind, Reaction};
use crate::error::{Error, Result};
use crate::handles::{ConstraintHandle, RodHandle};
use crate::rod::Rod;
use serde::{Deserialize, Serialize};

/// A constraint on one rod (or two, for relative kinds) with its
/// compliance (0 = hard; > 0: a spring of stiffness 1/C), the multipliers
/// of the last solve (force/torque units), its break threshold and label.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Constraint {
    pub rod: RodHandle,
    /// Second rod of a relative constraint (None: the constraint is on `rod` only).
    pub other: Option<RodHandle>,
    pub kind: ConstraintKind,
    pub compliance: f64,
    pub multipliers: Vec<f64>,
    /// Force-threshold rupture (III.C.3, algorithm 5); None = unbreakable.
    pub breaking: Option<Breaking>,
    /// Group label, e.g. "hbond[17]".
    #[serde(default)]
    pub label: Option<String>,
    /// Labels of constraints this one goes with: when one of them breaks
    /// (or is cut by a rupture), this one is removed too, reported as
    /// broken with force 0 (stacking that needs both of its base pairs).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub breaks_with: Vec<String>,
    /// Labels of constraints whose breaking under their own load removes
    /// this one too, but not their removal with a third one (a base pair's
    /// bond fails with its stagger; the stagger goes with its neighbours'
    /// bonds, which must not take this pair along).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fails_with: Vec<String>,
    /// The averaged break measure so far ([`Breaking::averaging_time`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub break_measure: Option<f64>,
    /// A compliant constraint held at the step's end under the trapezoidal
    /// rule, as implicit Euler holds it, instead of averaged over the step
    /// like an elastic energy ([`Constraint::is_elastic`]): its stiff modes
    /// are then damped (and cooled under thermal noise) but the Newton
    /// iterations stay robust where averaged rows are stiff and strongly
    /// nonlinear (a duplex's stacking at steps of picoseconds).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub held_at_end: bool,
}

impl Constraint {
    /// A constraint with zero multipliers, not breakable, unlabelled.
    pub fn new(rod: RodHandle, other: Option<RodHandle>, kind: ConstraintKind, compliance: f64) -> Constraint {
        let n = kind.n_rows();
        Constraint { rod, other, kind, compliance, multipliers: vec![0.0; n], breaking: None, label: None, breaks_with: Vec::new(), fails_with: Vec::new(), break_measure: None, held_at_end: false }
    }
    /// A compliant constraint without sliders, not `held_at_end`: an
    /// elastic energy ½ g²/α that a trapezoidal step averages like the
    /// rods' elastic forces ([`crate::system::kkt::ConstraintRef::elastic`]).
    pub fn is_elastic(&self) -> bool {
        self.compliance > 0.0 && self.kind.n_extra() == 0 && !self.held_at_end
    }

    /// Everything about the constraint that can be checked against its rods.
    pub(crate) fn check(&self, rods: &[&Rod]) -> Result<()> {
        let arity = 1 + usize::from(self.other.is_some());
        if arity != self.kind.n_rods() {
            let use_ = if self.kind.n_rods() == 2 { "a relative kind: use add_link" } else { "a one-rod kind: use add_constraint" };
            return Err(Error::invalid(format!("{} constraint", self.kind.name()), format!("{arity} rod(s)"), use_));
        }
        self.kind.validate(rods)?;
        if self.other == Some(self.rod) {
            let mut first: Option<f64> = None;
            let mut all_same = true;
            self.kind.visit_abscissae(&mut |_, u| match first {
                None => first = Some(u),
                Some(f) => all_same &= (u - f).abs() <= 1e-12 * (1.0 + f.abs()),
            });
            if all_same {
                return Err(Error::invalid(
                    format!("{} link", self.kind.name()),
                    format!("one point of rod {} linked to itself", self.rod.index),
                    "two distinct points (or two rods)",
                ));
            }
        }
        crate::error::non_negative("compliance", self.compliance)?;
        if self.multipliers.len() != self.kind.n_rows() {
            return Err(Error::invalid("constraint multipliers", self.multipliers.len(), format!("{} values (one per row)", self.kind.n_rows())));
        }
        for m in &self.multipliers {
            crate::error::finite("constraint multiplier", *m)?;
        }
        if let Some(m) = self.break_measure {
            crate::error::finite("constraint break measure", m)?;
        }
        if let Some(b) = self.breaking {
            check_breaking(&self.kind, rods, b)?;
        }
        if let Some(l) = &self.label {
            super::groups::check_label(l)?;
        }
        Ok(())
    }
}

/// A break threshold must be positive, and tension/compression need a line
/// of action.
pub(crate) fn check_breaking(kind: &ConstraintKind, rods: &[&Rod], b: Breaking) -> Result<()> {
    crate::error::positive("break force", b.force)?;
    crate::error::non_negative("break averaging time", b.averaging_time)?;
    if b.averaging_time > 0.0 && b.policy == BreakPolicy::Magnitude {
        // |F| of a zero-mean noisy force averages to the noise's size, not to 0.
        return Err(Error::invalid(
            "break averaging with policy magnitude",
            b.averaging_time,
            "policy tension or compression (a signed measure: the magnitude of a noisy force does not average down)",
        ));
    }
    if b.policy != BreakPolicy::Magnitude && kind.tension(rods, &vec![0.0; kind.n_rows()])?.is_none() {
        return Err(Error::invalid(
            format!("break policy of a {} constraint", kind.name()),
            format!("{:?}", b.policy).to_lowercase(),
            "magnitude (this kind has no line of action; tension/compression apply to distance links, contacts and relative positions with an offset)",
        ));
    }
    Ok(())
}

impl World {
    /// Adds a hard (compliance 0) or compliant one-rod constraint. Errors:
    /// removed rod, abscissa outside the rod, non-finite target, duplicate,
    /// linearly dependent on the rod's other constraints.
    pub fn add_constraint(&mut self, rod: RodHandle, kind: impl Into<ConstraintKind>, compliance: f64) -> Result<ConstraintHandle> {
        self.insert_constraint(Constraint::new(rod, None, kind.into(), compliance))
    }

    /// Adds a relative constraint between rod `a` (abscissa ua) and rod `b`
    /// (ub); `a` and `b` may be the same rod.
    pub fn add_link(&mut self, a: RodHandle, b: RodHandle, kind: impl Into<ConstraintKind>, compliance: f64) -> Result<ConstraintHandle> {
        self.insert_constraint(Constraint::new(a, Some(b), kind.into(), compliance))
    }

    /// Adds a fully described constraint (breaking and label included), with
    /// the same checks as `add_constraint`.
    pub fn insert_constraint(&mut self, c: Constraint) -> Result<ConstraintHandle> {
        let mut hs = self.insert_constraints(vec![c])?;
        hs.pop().ok_or_else(|| Error::input("insert_constraint: nothing inserted"))
    }

    /// Adds a batch of constraints at once: every one is checked, then the
    /// batch's rows (with those already on the rods it touches) are checked
    /// for linear dependence once, on the sparse structure. On any error
    /// nothing is added.
    pub fn insert_constraints(&mut self, batch: Vec<Constraint>) -> Result<Vec<ConstraintHandle>> {
        for (k, c) in batch.iter().enumerate() {
            let rods = self.rods_of(c)?;
            c.check(&rods).map_err(|e| if batch.len() > 1 { e.context(format_args!("constraint {k} of the batch")) } else { e })?;
        }
        self.check_duplicates(&batch)?;
        super::independence::check(self, &batch)?;
        self.add_checked_constraints(batch)
    }

    /// Adds constraints that passed every check (labels were checked too).
    pub(crate) fn add_checked_constraints(&mut self, batch: Vec<Constraint>) -> Result<Vec<ConstraintHandle>> {
        let mut out = Vec::with_capacity(batch.len());
        for c in batch {
            let label = c.label.clone();
            let h: ConstraintHandle = self.constraints.insert(c).into();
            if let Some(l) = label {
                self.groups.add(&l, super::Item::Constraint(h))?;
            }
            out.push(h);
        }
        Ok(out)
    }

    /// Rejects a constraint that repeats one already on the same rods (or
    /// earlier in the batch) at the same place. Duplicates share their first
    /// abscissa, so candidates are found by sorting on it: O(k log k).
    pub(crate) fn check_duplicates(&self, batch: &[Constraint]) -> Result<()> {
        use std::collections::HashSet;
        let pairs: HashSet<(RodHandle, Option<RodHandle>)> = batch.iter().map(|c| (c.rod, c.other)).collect();
        // (rod pair, first abscissa, who: Err(existing handle index) / Ok(batch index), kind)
        let mut all: Vec<((RodHandle, Option<RodHandle>), f64, std::result::Result<usize, u32>, &ConstraintKind)> = Vec::new();
        for (h, c) in self.constraints.iter() {
            if pairs.contains(&(c.rod, c.other)) {
                all.push(((c.rod, c.other), c.kind.u(), Err(h.0), &c.kind));
            }
        }
        for (k, c) in batch.iter().enumerate() {
            all.push(((c.rod, c.other), c.kind.u(), Ok(k), &c.kind));
        }
        all.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let tol = |u: f64| 1e-12 * (1.0 + u.abs());
        let mut worst: Option<(usize, String, &ConstraintKind)> = None;
        for (i, x) in all.iter().enumerate() {
            let Ok(k) = x.2 else { continue };
            // Neighbours with the same rods within the abscissa tolerance.
            let near = all[..i].iter().rev().take_while(|y| y.0 == x.0 && x.1 - y.1 <= tol(x.1));
            let after = all[i + 1..].iter().take_while(|y| y.0 == x.0 && y.1 - x.1 <= tol(x.1));
            for y in near.chain(after) {
                let earlier = match y.2 {
                    Err(h) => Some(format!("constraint {h}")),
                    Ok(j) if j < k => Some(format!("constraint {j} of the batch")),
                    Ok(_) => None,
                };
                if let Some(who) = earlier {
                    if y.3.duplicates(x.3) && worst.as_ref().is_none_or(|w| k < w.0) {
                        worst = Some((k, who, x.3));
                    }
                }
            }
        }
        match worst {
            Some((_, who, kind)) => Err(Error::input(format!(
                "duplicate constraint: {} repeats {who} on the same rods at the same abscissa",
                kind.name()
            ))),
            None => Ok(()),
        }
    }

    /// Coplanar relative clamp between rod a at ua and rod b at ub (III.61):
    /// α0, α1 are solved from the current geometry, r_a − r_b = α0 r_a' +
    /// α1 r_b'. Errors when the tangents are parallel or the link is not in
    /// their plane (the thesis' restriction).
    pub fn add_coplanar_clamp(&mut self, a: RodHandle, ua: f64, b: RodHandle, ub: f64, compliance: f64) -> Result<ConstraintHandle> {
        let v3 = |d: [f64; 4]| nalgebra::Vector3::new(d[0], d[1], d[2]);
        let (ra, rb) = (self.rod(a)?, self.rod(b)?);
        let d = v3(ra.eval(ua, 0)?) - v3(rb.eval(ub, 0)?);
        let (ta, tb) = (v3(ra.eval(ua, 1)?), v3(rb.eval(ub, 1)?));
        let m = nalgebra::Matrix3x2::from_columns(&[ta, tb]);
        let mtm = m.transpose() * m;
        let inv = mtm.try_inverse().filter(|_| ta.cross(&tb).norm() > 1e-9 * ta.norm() * tb.norm()).ok_or_else(|| {
            Error::invalid("coplanar clamp tangents", "parallel", "two non-parallel tangents (for parallel ones use RelativePosition + RelativeOrientation)")
        })?;
        let alpha = inv * (m.transpose() * d);
        if (m * alpha - d).norm() > 1e-9 * d.norm().max(1e-300) {
            return Err(Error::invalid("coplanar clamp link", "out of the plane of the two tangents", "a link in the plane of the two tangents"));
        }
        let kind = crate::constraint::kinds::CoplanarClamp { ua, ub, alpha: [alpha[0], alpha[1]] };
        self.add_link(a, b, kind, compliance)
    }

    /// Clamps `rod` at `u`: position (x, y, z) and tangent at their current
    /// values, and the cross-section held as the rod's frame model says
    /// (`Rod::hold_cross_section`): the roll coordinate where θ is the
    /// section's angle, else an absolute `MaterialRoll` (Frenet model on a
    /// curved stretch). Rods without roll get position and tangent only.
    /// Returns the handles [position, tangent, (material roll)].
    pub fn clamp(&mut self, rod: RodHandle, u: f64, compliance: f64) -> Result<Vec<ConstraintHandle>> {
        let kinds = crate::constraint::clamp_kinds(self.rod(rod)?, u)?;
        self.insert_constraints(kinds.into_iter().map(|k| Constraint::new(rod, None, k, compliance)).collect())
    }

    pub fn remove_constraint(&mut self, h: ConstraintHandle) -> Result<Constraint> {
        self.constraints.remove(h.into()).ok_or_else(|| bad_con(h))
    }
    pub fn constraint(&self, h: ConstraintHandle) -> Result<&Constraint> {
        self.constraints.get(h.into()).ok_or_else(|| bad_con(h))
    }
    /// Replaces a constraint's kind (moving targets: how a user drags,
    /// rotates or pulls). The new kind must be of the same kind and rows.
    pub fn set_constraint(&mut self, h: ConstraintHandle, kind: impl Into<ConstraintKind>) -> Result<()> {
        let kind = kind.into();
        let probe = Constraint { kind, ..self.constraint(h)?.clone() };
        let old = &self.constraint(h)?.kind;
        if probe.kind.n_rows() != old.n_rows() || probe.kind.name() != old.name() {
            return Err(Error::invalid("set_constraint kind", probe.kind.name(), format!("a {} with {} rows (the constraint's kind)", old.name(), old.n_rows())));
        }
        probe.check(&self.rods_of(&probe)?)?;
        if let Some(c) = self.constraints.get_mut(h.into()) {
            c.kind = probe.kind;
        }
        Ok(())
    }
    /// Makes a constraint breakable (None: unbreakable again).
    pub fn set_breaking(&mut self, h: ConstraintHandle, breaking: Option<Breaking>) -> Result<()> {
        let c = self.constraint(h)?;
        if let Some(b) = breaking {
            check_breaking(&c.kind, &self.rods_of(c)?, b)?;
        }
        if let Some(c) = self.constraints.get_mut(h.into()) {
            c.breaking = breaking;
            // A new rule averages from 0 again.
            c.break_measure = None;
        }
        Ok(())
    }

    /// Force and torque the constraint exerted on its (first) rod in the last solve.
    pub fn reaction(&self, h: ConstraintHandle) -> Result<Reaction> {
        let c = self.constraint(h)?;
        c.kind.reaction(&self.rods_of(c)?, &c.multipliers)
    }
    /// Tension along the constraint's line of action in the last solve
    /// (force unit; None for kinds without one).
    pub fn tension(&self, h: ConstraintHandle) -> Result<Option<f64>> {
        let c = self.constraint(h)?;
        c.kind.tension(&self.rods_of(c)?, &c.multipliers)
    }

    /// The rods a constraint acts on (the first twice for one-rod kinds).
    pub(crate) fn rods_of(&self, c: &Constraint) -> Result<[&Rod; 2]> {
        let a = self.rod(c.rod)?;
        Ok([a, c.other.map_or(Ok(a), |b| self.rod(b))?])
    }
}
