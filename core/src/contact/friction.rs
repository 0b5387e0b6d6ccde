//! Coulomb friction on contact pairs (SPEC §7), as an active set on the
//! tangential motion beside the one on the normal force:
//! - **stick**: two rows keep the pair's relative position, in the plane ⟂
//!   the normal, where it was at the start of the step (an
//!   [`Axis`] against an obstacle, a [`RelativeAxis`] between rods); their
//!   multipliers are the friction force;
//! - **slip**: the force −μ N ŝ (ŝ the direction of the relative
//!   tangential motion, N the normal force) acts on rod a, its opposite on
//!   rod b; between two rods one compliant row across ŝ
//!   ([`RelativePlane`]) stands for the Coulomb force's stiffness there,
//!   μ N / (the slide over the step): the direction is then solved with
//!   the motion instead of lagging a solve behind.
//!
//! After each solve a sticking pair whose friction force leaves the cone
//! |F_t| ≤ μ N starts slipping (ŝ opposite that force); a slipping pair
//! whose motion over the step turned against ŝ sticks again; a slipping
//! pair whose direction or normal force moved is solved again with them,
//! so that the friction of a slipping pair is μ N of the same solve.
//!
//! A penalty row (distributed rows, `ContactPair::is_penalty`) takes no
//! rounds: its friction is a tangential spring of the row's compliance,
//! trimmed to μ N at the start of each step ([`Friction::prepare_spring`]).
//! At rest it keeps |F_t| ≤ μ N; sliding, it passes μ N by what the pair
//! slides in the step over the compliance — against a drag ζ per length,
//! μ q + (t − μ q) k dt/(ζ + k dt) per length (`tests/contact_line.rs`).
use crate::constraint::kinds::{Axis, RelativeAxis, RelativePlane};
use crate::constraint::ConstraintKind;
use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Relative change of the normal force, or angle of the slip direction
/// (rad), above which a slipping pair is solved again.
const SLIP_TOLERANCE: f64 = 1e-3;

/// Active-set rounds of one solve (an implicit Euler step, a Newton
/// iterate) in which friction may change state; after them it is held as
/// it is (see [`Friction::update`]).
pub(crate) const FREE_ROUNDS: usize = 10;

/// A contact pair's friction state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Friction {
    /// Coulomb coefficient μ (dimensionless, ≥ 0).
    pub mu: f64,
    /// While slipping: the unit direction of rod a's relative tangential
    /// motion; `None` while sticking.
    pub slip: Option<[f64; 3]>,
    /// While sticking: the relative position held (length: r_a − r_b, or
    /// r_a against an obstacle) and the abscissae (ua, ub) it was taken at;
    /// kept from step to step, moved with the rod when the pair is found
    /// again at neighbouring abscissae (ub is 0 against an obstacle).
    pub anchor: Option<([f64; 3], [f64; 2])>,
    /// The relative position at the start of the step `n_steps`, and the
    /// abscissae it was taken at (for the slip check over the whole step,
    /// and the anchor of a pair that sticks again).
    #[serde(default)]
    pub start: Option<([f64; 3], u64, [f64; 2])>,
    /// Tangential force on rod a of the last solve (force unit).
    pub force: [f64; 3],
    /// The normal force the slip force was computed from (force unit).
    pub normal: f64,
    /// The friction rows of the current assembly and their compliance
    /// (length/force): a sticking pair's two ([`stick_compliance`]), or a
    /// slipping pair's one across its slip direction (see
    /// [`Friction::prepare`]).
    pub rows: Option<ConstraintKind>,
    pub compliance: f64,
    /// While slipping: the length the pair slid over the step in the last
    /// solve (length unit; 0 before its first), which sets the compliance
    /// of its row across the slip direction (see [`Friction::prepare`]).
    #[serde(default)]
    pub slip_length: f64,
    /// While slipping: the slip force −μ N ŝ the current assembly applies
    /// to rod a (force unit).
    #[serde(default)]
    pub slip_applied: [f64; 3],
    /// A penalty row's spring ([`Friction::prepare_spring`]) was trimmed to
    /// the Coulomb cone at the start of this step: the pair is sliding.
    #[serde(default)]
    pub at_limit: bool,
}

impl Friction {
    pub fn new(mu: f64) -> Result<Friction> {
        check_mu(mu)?;
        Ok(Friction { mu, slip: None, anchor: None, start: None, force: [0.0; 3], normal: 0.0, rows: None, compliance: 0.0, slip_length: 0.0, slip_applied: [0.0; 3], at_limit: false })
    }
    /// Forgets the motion state (the pair left the active set).
    pub fn reset(&mut self) {
        *self = Friction { mu: self.mu, ..Friction::new(0.0).expect("0 is a valid coefficient") };
    }
    /// Takes the motion state of the same pair found again.
    pub fn carry(&mut self, old: &Friction) {
        let mu = self.mu;
        *self = Friction { mu, rows: None, ..old.clone() };
    }
}

/// Compliance of the stick rows (length/force): a sticking point may give
/// tangentially by 1e-3 of what one segment of its rod stretches under
/// the same force. Hard stick rows at one pair per segment, three rows a
/// point, would pin every point of a wrapped stretch of rod, and any more
/// rows there make the system singular; this much give keeps it regular
/// and is invisible beside the rod's own compliance.
pub(crate) fn stick_compliance(rod: &Rod) -> Result<f64> {
    let mut area = f64::INFINITY;
    for s in rod.sections() {
        area = area.min(s.props()?.area);
    }
    Ok(1e-3 * rod.rest_length() / rod.n_segments().max(1) as f64 / (rod.material().young * area))
}

pub(crate) fn check_mu(mu: f64) -> Result<()> {
    if !(mu >= 0.0) || !mu.is_finite() {
        return Err(Error::invalid("friction coefficient", mu, "a finite number ≥ 0"));
    }
    Ok(())
}

/// A pair's contact geometry: rod a's point and abscissa, rod b's (none
/// against an obstacle), and the unit normal pushing rod a out.
pub(crate) struct Geometry {
    pub ua: f64,
    pub ub: Option<f64>,
    pub relative: Vector3<f64>,
    pub normal: Vector3<f64>,
}

pub(crate) fn geometry(kind: &ConstraintKind, rods: [&Rod; 2]) -> Result<Geometry> {
    match kind {
        ConstraintKind::Contact(c) => {
            let d = rods[0].position(c.ua)? - rods[1].position(c.ub)?;
            let n = d.norm();
            if !(n > 0.0) {
                return Err(Error::singular(format!("contact with coincident centrelines at ua = {}, ub = {}", c.ua, c.ub)));
            }
            Ok(Geometry { ua: c.ua, ub: Some(c.ub), relative: d, normal: d / n })
        }
        ConstraintKind::Plane(p) => Ok(Geometry { ua: p.u, ub: None, relative: rods[0].position(p.u)?, normal: Vector3::from(p.normal) }),
        k => Err(Error::invalid("contact pair kind", k.name(), "Contact or Plane")),
    }
}

impl Friction {
    /// Before an assembly: the step's starting position; while sticking
    /// the stick rows about the anchor (taken now if there is none, moved
    /// along the rods if the pair moved to other abscissae), while slipping
    /// the slip force −μ N ŝ from the pair's last normal force `normal`;
    /// `compliance`: the stick rows' ([`stick_compliance`] of the pair's rods).
    pub(crate) fn prepare(&mut self, g: &Geometry, rods: [&Rod; 2], step: u64, normal: f64, compliance: f64) -> Result<()> {
        self.mark_start(g, step);
        if let Some(s) = self.slip {
            let s = Vector3::from(s);
            self.anchor = None;
            self.normal = normal.max(0.0);
            let limit = self.mu * self.normal;
            self.force = (-limit * s).into();
            self.slip_applied = self.force;
            // Across the slip direction ŝ the Coulomb force −μN v/|v|
            // linearised is a stiffness μN/|Δx| (Δx the slide over the
            // step): one compliant row there, so that the direction is
            // solved with the motion. Taken from the last solve, ŝ
            // overshoots the true direction by a factor 1/ε when the drive
            // exceeds μN by ε, and the rounds never settle. Between rods
            // only: against an obstacle the row made the dependent rows of
            // a rope and a plank tied together on a wall be found on the
            // tie instead of on a contact (examples/bridge_fall.py).
            let across = g.normal.cross(&s);
            self.rows = match g.ub {
                Some(ub) if limit > 0.0 && across.norm() > 0.5 => {
                    Some(RelativePlane { ua: g.ua, ub, offset: g.relative.into(), normal: across.normalize().into() }.into())
                }
                _ => None,
            };
            // Never stiffer than the stick rows: a point held by another
            // constraint slides by nothing, and a row that rigid would
            // repeat the other's.
            self.compliance = if self.rows.is_some() { compliance.max(self.slip_length / limit) } else { compliance };
            return Ok(());
        }
        let anchor = self.moved_anchor(g, rods)?;
        self.hold(g, anchor, compliance);
        Ok(())
    }
    /// The relative position at the start of step `step`, once per step.
    fn mark_start(&mut self, g: &Geometry, step: u64) {
        if self.start.is_none_or(|a| a.1 != step) {
            self.start = Some((g.relative.into(), step, [g.ua, g.ub.unwrap_or(0.0)]));
        }
    }
    /// The anchor where the pair is now: none yet, where it is; found
    /// again at neighbouring abscissae, moved by what separates the
    /// points on the rods now.
    fn moved_anchor(&self, g: &Geometry, rods: [&Rod; 2]) -> Result<Vector3<f64>> {
        Ok(match self.anchor {
            None => g.relative,
            Some((a, [ua, ub_old])) => {
                // anchor + [r_a(ua') − r_a(ua)] − [r_b(ub') − r_b(ub)], the
                // relative position (g.relative) carrying the primed terms.
                let mut a = Vector3::from(a) + g.relative - rods[0].position(ua)?;
                if g.ub.is_some() {
                    a += rods[1].position(ub_old)?;
                }
                a
            }
        })
    }
    /// Stick rows of compliance `compliance` about `anchor`.
    fn hold(&mut self, g: &Geometry, anchor: Vector3<f64>, compliance: f64) {
        self.anchor = Some((anchor.into(), [g.ua, g.ub.unwrap_or(0.0)]));
        self.compliance = compliance;
        self.rows = Some(match g.ub {
            Some(ub) => RelativeAxis { ua: g.ua, ub, offset: anchor.into(), direction: g.normal.into() }.into(),
            None => Axis { u: g.ua, origin: anchor.into(), direction: g.normal.into() }.into(),
        });
    }
    /// A penalty row's friction (`ContactPair::is_penalty`, normal force
    /// `normal` = −g/C at the start of the step, `compliance` its C): a
    /// tangential spring of the same compliance about the anchor, its
    /// stretch trimmed at the start of each step to the Coulomb cone,
    /// |d_t| ≤ μ N C — the linear spring–slider of granular codes
    /// (Cundall & Strack 1979), slipping between steps instead of in
    /// active-set rounds (each a solve; thousands of rows at the cone's
    /// edge used them all). Within a step the spring may pass μ N by what
    /// the pair slides in it over C; a pair at rest keeps |F_t| ≤ μ N.
    pub(crate) fn prepare_spring(&mut self, g: &Geometry, rods: [&Rod; 2], step: u64, normal: f64, compliance: f64) -> Result<()> {
        self.mark_start(g, step);
        self.slip = None;
        self.normal = normal.max(0.0);
        let mut anchor = self.moved_anchor(g, rods)?;
        let d = g.relative - anchor;
        let dt = d - g.normal * g.normal.dot(&d);
        let reach = self.mu * self.normal * compliance;
        self.at_limit = dt.norm() > reach;
        if self.at_limit {
            anchor = g.relative - dt * (reach / dt.norm());
        }
        self.hold(g, anchor, compliance);
        Ok(())
    }
    /// The slip force on rod a (force unit) of the current assembly.
    pub(crate) fn slip_force(&self) -> Option<[f64; 3]> {
        self.slip.map(|_| self.force)
    }
    /// After a solve: `stick` the friction rows' force on rod a (a
    /// slipping pair's row across ŝ: not used), `moved` rod
    /// a's relative displacement since the anchor (this solve's included),
    /// `normal` the normal force. Returns whether the state changed enough
    /// to solve again.
    ///
    /// `frozen` (the active set has gone round [`FREE_ROUNDS`] times in one
    /// solve): nothing changes state — a sticking pair records its force,
    /// a slipping one keeps its direction (its slip force still follows
    /// the normal force at the next assembly, but a change of it no longer
    /// asks for another solve) — so that the rounds left settle the normal
    /// active set alone. Pairs chattering between stick and slip at the
    /// cone's edge would otherwise use up the rounds and leave a contact
    /// pulling or a point inside an obstacle. The price: a pair held
    /// sticking may end the step with a friction force past μ N (reported
    /// as it is, not slipping). Letting held pairs still start slipping
    /// was tried: a slipping pair whose motion then turned back either
    /// pushed the rod along (the capstan's step diverged) or chattered.
    pub(crate) fn update(&mut self, g: &Geometry, stick: Option<Vector3<f64>>, moved: Vector3<f64>, normal: f64, frozen: bool) -> bool {
        let n = g.normal;
        if frozen {
            if let (None, Some(f)) = (self.slip, stick) {
                self.force = (f - n * n.dot(&f)).into();
            }
            return false;
        }
        let normal = normal.max(0.0);
        let limit = self.mu * normal;
        match (self.slip, stick) {
            (None, Some(f)) => {
                let ft = f - n * n.dot(&f);
                self.force = ft.into();
                if ft.norm() > limit * (1.0 + 1e-9) {
                    self.slip = Some((-ft / ft.norm()).into());
                    self.slip_length = 0.0;
                    return true;
                }
                false
            }
            (Some(s), _) => {
                let s = Vector3::from(s);
                let mt = moved - n * n.dot(&moved);
                if mt.dot(&s) <= 0.0 {
                    // The friction turned the motion back: it holds (from
                    // where the step started).
                    self.slip = None;
                    self.slip_length = 0.0;
                    self.anchor = self.start.map(|(a, _, at)| (a, at));
                    return true;
                }
                let dir = mt / mt.norm();
                let turned = (dir - s).norm() > SLIP_TOLERANCE;
                self.slip = Some(dir.into());
                self.slip_length = mt.norm();
                turned || (normal - self.normal).abs() > SLIP_TOLERANCE * self.normal.max(f64::MIN_POSITIVE)
            }
            (None, None) => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A slipping pair between two rods gets one row across its slip
    /// direction (⟂ the normal and ŝ), of compliance slide/(μN), never
    /// below the stick rows'; with no normal force, no row and a finite
    /// compliance (it is saved in snapshots).
    #[test]
    fn a_slipping_pair_holds_a_row_across_its_slip_direction() {
        let (a, b) = (super::super::test_rod(), super::super::test_rod());
        let g = Geometry { ua: 3.5, ub: Some(4.0), relative: Vector3::new(0.0, 0.0, 0.02), normal: Vector3::z() };
        let stick = 1e-9;
        let mut f = Friction { slip: Some([1.0, 0.0, 0.0]), slip_length: 2e-4, ..Friction::new(0.5).unwrap() };
        f.prepare(&g, [&a, &b], 1, 4.0, stick).unwrap();
        assert_eq!(f.slip_force(), Some([-2.0, 0.0, 0.0]));
        assert_eq!(f.compliance, 2e-4 / 2.0);
        match &f.rows {
            Some(ConstraintKind::RelativePlane(r)) => {
                assert_eq!((r.ua, r.ub, r.offset), (3.5, 4.0, [0.0, 0.0, 0.02]));
                assert!((Vector3::from(r.normal).abs() - Vector3::y()).norm() < 1e-15, "{:?}", r.normal);
            }
            other => panic!("expected a RelativePlane row, got {other:?}"),
        }
        // A slide too short to give: the stick rows' compliance.
        f.slip_length = 1e-15;
        f.prepare(&g, [&a, &b], 1, 4.0, stick).unwrap();
        assert_eq!(f.compliance, stick);
        // No normal force: no row, and nothing infinite.
        f.slip_length = 2e-4;
        f.prepare(&g, [&a, &b], 1, 0.0, stick).unwrap();
        assert!(f.rows.is_none() && f.compliance == stick);
    }

    /// A pair against a floor (normal +z) with μ = 0.5 and N = 2: a stick
    /// force of 1.5 (past μ N = 1) makes it slip against that force; held
    /// (`frozen`), it stays sticking and records the force; a slipping pair
    /// whose motion turned back sticks again, held it keeps slipping.
    #[test]
    fn held_friction_changes_no_state() {
        let g = Geometry { ua: 0.0, ub: None, relative: Vector3::zeros(), normal: Vector3::z() };
        let past = Some(Vector3::new(1.5, 0.0, 0.3));
        let mut f = Friction::new(0.5).unwrap();
        assert!(f.update(&g, past, Vector3::zeros(), 2.0, false));
        assert_eq!(f.slip, Some([-1.0, 0.0, 0.0]));
        let mut held = Friction::new(0.5).unwrap();
        assert!(!held.update(&g, past, Vector3::zeros(), 2.0, true));
        assert_eq!((held.slip, held.force), (None, [1.5, 0.0, 0.0]));
        // Slipping along +x, the step moved it along −x.
        let back = Vector3::new(-1e-6, 0.0, 0.0);
        let mut s = Friction { slip: Some([1.0, 0.0, 0.0]), ..Friction::new(0.5).unwrap() };
        assert!(s.update(&g, None, back, 2.0, false));
        assert_eq!(s.slip, None);
        let mut s = Friction { slip: Some([1.0, 0.0, 0.0]), ..Friction::new(0.5).unwrap() };
        assert!(!s.update(&g, None, back, 2.0, true));
        assert_eq!(s.slip, Some([1.0, 0.0, 0.0]));
    }
}
