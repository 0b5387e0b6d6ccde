//! Constraints (SPEC §4, thesis III.A): each kind linearises its g(q) into
//! rows L (the Jacobian, normalised so that the multiplier Λ is a force or a
//! torque) and a right-hand side E = target − g(q^n), which carries the
//! drift correction and moving targets.
//!
//! A kind is one file in [`kinds`]: a struct implementing [`ConstraintLaw`]
//! (rows, Jacobian, unknowns touched, reported force, break test, serde
//! form, catalogue entry), registered by one line of the
//! `constraint_kinds!` table in `kinds/mod.rs`, which generates the
//! [`ConstraintKind`] enum and its exhaustive dispatch.
//!
//! # Adding a kind
//! 1. Write `kinds/my_kind.rs`: `#[derive(Clone, Debug, PartialEq,
//!    Serialize, Deserialize)] pub struct MyKind { … }` with documented,
//!    unit-carrying public fields, and `impl ConstraintLaw for MyKind`. The
//!    required methods are `INFO`, `n_rows`, `visit_abscissae(_mut)`,
//!    `linearize` and `reaction`; the policies (`validate`, `tension`,
//!    `anchoring`, sliding unknowns, `project`, `advance`, `duplicates`)
//!    have defaults.
//! 2. Add `MyKind => my_kind::MyKind,` to the `constraint_kinds!` table.
//! 3. Add one example instance to `tests/constraint_contract.rs`: that test
//!    fails for a registered kind without one, and then checks the new
//!    kind's Jacobian against central differences, its reported force
//!    against the multipliers mapped through the Jacobian, its serde round
//!    trip, and that bad input is a clean error. The Python helper
//!    (`strandkit.my_kind(...)`) and its stub come from `INFO`.
pub mod catalogue;
pub mod kinds;

pub use catalogue::{FieldInfo, FieldType, KindInfo};
pub use kinds::ConstraintKind;

use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

/// Which of a constraint's rods an abscissa or a Jacobian entry belongs to:
/// 0 = the first rod, 1 = the second (relative kinds; one-rod kinds may use 1
/// to separate a point from the others, on the same rod), 2 = the
/// constraint's own abscissa unknown (sliders).
pub type Side = u8;

/// The law of one constraint kind. See the module documentation for the
/// recipe. `rods` is always two rods (the same one twice for one-rod kinds).
pub trait ConstraintLaw: Clone + std::fmt::Debug + PartialEq + Serialize + DeserializeOwned {
    /// Catalogue entry (name, Python helper, rods, documentation, fields).
    const INFO: KindInfo;
    /// Number of rows (= multipliers).
    fn n_rows(&self) -> usize;
    /// Abscissa unknowns the constraint adds to the system (sliders).
    fn n_extra(&self) -> usize {
        0
    }
    /// Calls `f(side, u)` for every abscissa, first the one the reaction is
    /// reported at (see [`ConstraintLaw::reaction`]).
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64));
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64));
    /// Kind-specific checks (targets finite, directions non-zero, roll only
    /// on rods with roll, …); abscissae are checked before this is called.
    fn validate(&self, _rods: &[&Rod]) -> Result<()> {
        Ok(())
    }
    /// Writes `n_rows()` rows linearised at the rods' current coordinates.
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()>;
    /// The force and torque the constraint exerts on the side of its first
    /// abscissa, reduced to that point, from the multipliers Λ: the resultant
    /// of the generalised force LᵀΛ on that side's rigid motions (the moment
    /// about the tangent measured on the roll coordinate where the rows
    /// touch it). Checked against LᵀΛ by the contract test.
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction>;
    /// Tension along the link's line of action (force unit, > 0 when the
    /// link pulls its two ends together), for [`BreakPolicy::Tension`] and
    /// `Compression`; None for kinds without a line of action.
    fn tension(&self, _rods: &[&Rod], _lambda: &[f64]) -> Result<Option<f64>> {
        Ok(None)
    }
    /// How the constraint holds its rod(s) for the quasi-static rule (IV.B).
    fn anchoring(&self) -> Anchoring {
        Anchoring::None
    }
    /// A_uu, rhs and A_(q,u) of the abscissa unknowns (sliders), given the
    /// previous multipliers and the friction factor (1/h in dynamics, 0 in statics).
    fn sliding_blocks(&self, _rods: &[&Rod], _lambda: &[f64], _friction_coeff: f64, _out: &mut SlidingBlocks) -> Result<()> {
        Ok(())
    }
    /// Moves abscissae that follow the geometry (contacts: closest points)
    /// before every linearisation.
    fn project(&mut self, _rods: &[&Rod]) -> Result<()> {
        Ok(())
    }
    /// Moves the abscissae by the solved increments; false when a slider
    /// left its rod's domain.
    fn advance(&mut self, _rods: &[&Rod], _du: &[f64]) -> bool {
        true
    }
    /// True when `other` (same kind, same rods) imposes the same thing at the
    /// same place: adding it would duplicate rows. Default: same abscissae.
    fn duplicates(&self, other: &Self) -> bool {
        same_abscissae(self, other)
    }
}

/// How a constraint holds its rod for the thesis' quasi-static rule (IV.B):
/// a rod is held at ≥ 2 points or one point with an orientation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchoring {
    None,
    /// A fixed point (x, y and z) at the first abscissa.
    Point,
    /// A fixed tangent direction.
    Orientation,
    /// A point, once the other rod is held.
    PointViaPeer,
    /// An orientation, once the other rod is held.
    OrientationViaPeer,
}

/// What the force that breaks a constraint is measured on (III.C.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BreakPolicy {
    /// |reaction force| (|torque| for kinds that exert a moment only).
    #[default]
    Magnitude,
    /// The tension along the line of action (kinds with one: distance links,
    /// contacts, relative positions with an offset): compression never breaks it.
    Tension,
    /// The compression along the line of action: tension never breaks it.
    Compression,
}

/// A constraint breaks after a solve whose measure (see [`BreakPolicy`])
/// exceeds `force` (force unit; torque unit for moment-only kinds) — or,
/// with an `averaging_time` τ > 0, whose measure averaged over the last τ
/// of dynamics does: an exponential moving average m ← m + (1 − e^(−h/τ))
/// (f − m) from m = 0, updated after every accepted step of length h. With
/// thermal noise the multipliers of hard constraints fluctuate by ~√(kT ζ/h)
/// per step (tens of pN for a DNA base pair at h = 1 ps) and a threshold on
/// them breaks everything at once; averaged over τ the noise falls as
/// √(h/2τ) while a sustained load still reaches the threshold, τ later.
/// Only signed measures average (policies tension and compression: the
/// magnitude of a noisy force would average to the noise's size).
/// Statics and quasi-static frames compare the measure itself.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Breaking {
    pub force: f64,
    #[serde(default)]
    pub policy: BreakPolicy,
    /// τ (time unit); 0: the measure of each solve (not written then).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub averaging_time: f64,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

impl Breaking {
    /// Breaks when the measure by `policy` exceeds `force`.
    pub fn new(force: f64, policy: BreakPolicy) -> Breaking {
        Breaking { force, policy, averaging_time: 0.0 }
    }
    /// The same, with the measure averaged over `tau` (time unit).
    pub fn averaged(self, tau: f64) -> Breaking {
        Breaking { averaging_time: tau, ..self }
    }
}

/// Extra blocks of a constraint that owns abscissa unknowns (sliders):
/// the diagonal A_uu and right-hand side per unknown, and the coupling
/// entries A_(q,u) with the coordinates (one unknown for now).
#[derive(Clone, Copy, Debug, Default)]
pub struct SlidingBlocks {
    pub diag: [f64; 2],
    pub rhs: [f64; 2],
    pub coupling: Row,
}

/// Most coordinates one row can touch (two rods × 4 control points × 4,
/// with room for sliding abscissae).
pub const MAX_ENTRIES: usize = 40;

/// Most rows one constraint has (oriented slider: 5).
pub const MAX_ROWS: usize = 6;

/// Most abscissae one constraint has (base-pair step: 4 pairs × 2 strands).
pub const MAX_ABSCISSAE: usize = 8;

/// One linearised constraint row; entries are (side, rod-local coordinate,
/// value), see [`Side`].
#[derive(Clone, Copy, Debug)]
pub struct Row {
    pub entries: [(Side, usize, f64); MAX_ENTRIES],
    pub len: usize,
    pub rhs: f64,
}

impl Default for Row {
    fn default() -> Self {
        Row { entries: [(0, 0, 0.0); MAX_ENTRIES], len: 0, rhs: 0.0 }
    }
}

impl Row {
    pub(crate) fn push(&mut self, i: usize, v: f64) {
        self.push_on(0, i, v);
    }
    pub(crate) fn push_on(&mut self, side: Side, i: usize, v: f64) {
        self.entries[self.len] = (side, i, v);
        self.len += 1;
    }
    pub fn entries(&self) -> &[(Side, usize, f64)] {
        &self.entries[..self.len]
    }
}

/// Control points a constraint touches: (side, control point), and
/// whether the curve passes through them with weight (`held`: a nonzero
/// basis value at the abscissa — at a clamped end only the end point).
#[derive(Clone, Copy, Debug)]
pub struct Touched {
    pub items: [(Side, usize); MAX_TOUCHED],
    pub held: [bool; MAX_TOUCHED],
    pub len: usize,
}

/// Most control points one constraint touches (barycentric: 5 points × 4).
pub const MAX_TOUCHED: usize = 4 * MAX_ABSCISSAE;

impl Touched {
    pub fn as_slice(&self) -> &[(Side, usize)] {
        &self.items[..self.len]
    }
}

/// The force and torque a constraint exerts on its rod (force unit,
/// force × length unit), from its multipliers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Reaction {
    pub force: [f64; 3],
    pub torque: [f64; 3],
}

impl Reaction {
    pub fn force(f: Vector3<f64>) -> Reaction {
        Reaction { force: f.into(), torque: [0.0; 3] }
    }
    pub fn torque(m: Vector3<f64>) -> Reaction {
        Reaction { force: [0.0; 3], torque: m.into() }
    }
    /// The measure of [`BreakPolicy::Magnitude`]: |force|, or |torque| for a
    /// constraint that exerts a moment only.
    pub fn magnitude(&self) -> f64 {
        let f = Vector3::from(self.force).norm();
        if f > 0.0 {
            f
        } else {
            Vector3::from(self.torque).norm()
        }
    }
}

/// The abscissae of a constraint as a fixed array (side, u).
pub fn abscissae_of<K: ConstraintLaw>(k: &K) -> ([(Side, f64); MAX_ABSCISSAE], usize) {
    let mut out = [(0u8, 0.0); MAX_ABSCISSAE];
    let mut n = 0;
    k.visit_abscissae(&mut |s, u| {
        if n < MAX_ABSCISSAE {
            out[n] = (s, u);
            n += 1;
        }
    });
    (out, n)
}

pub(crate) fn same_abscissae<K: ConstraintLaw>(a: &K, b: &K) -> bool {
    let ((x, n), (y, m)) = (abscissae_of(a), abscissae_of(b));
    n == m && x[..n].iter().zip(&y[..m]).all(|(p, q)| p.0 == q.0 && (p.1 - q.1).abs() <= 1e-12 * (1.0 + p.1.abs()))
}

/// Checks every abscissa (finite, inside its rod's domain), then the kind.
pub(crate) fn validate_law<K: ConstraintLaw>(k: &K, rods: &[&Rod]) -> Result<()> {
    let mut bad = Ok(());
    k.visit_abscissae(&mut |side, u| {
        if bad.is_ok() {
            let name = if K::INFO.rods == 2 { ["ua", "ub"][side.min(1) as usize] } else { "u" };
            bad = crate::error::finite(&format!("{} abscissa {name}", K::INFO.name), u)
                .and_then(|u| rods[side.min(1) as usize].knots().locate(u).map(|_| ()));
        }
    });
    bad?;
    k.validate(rods)
}

/// Control points the rows touch (for ordering, IV.3–IV.4): the four of
/// every abscissa.
pub(crate) fn touched_by<K: ConstraintLaw>(k: &K, rods: &[&Rod]) -> Result<Touched> {
    let mut t = Touched { items: [(0, 0); MAX_TOUCHED], held: [true; MAX_TOUCHED], len: 0 };
    let mut res = Ok(());
    k.visit_abscissae(&mut |side, u| {
        if res.is_err() || t.len + 4 > MAX_TOUCHED {
            return;
        }
        match rods[side.min(1) as usize].basis_at(u) {
            Ok((ctrl, b)) => {
                for (c, v) in ctrl.into_iter().zip(b[0]) {
                    t.items[t.len] = (side.min(1), c);
                    t.held[t.len] = v != 0.0;
                    t.len += 1;
                }
            }
            Err(e) => res = Err(e),
        }
    });
    res.map(|_| t)
}

/// Normalised copy of a direction; error on zero / non-finite.
pub fn unit(v: &[f64; 3], what: &str) -> Result<Vector3<f64>> {
    let x = Vector3::from(*v);
    let n = x.norm();
    if !n.is_finite() || n == 0.0 {
        return Err(Error::invalid(what, format!("{v:?}"), "a finite non-zero vector"));
    }
    Ok(x / n)
}

/// Error naming `what` unless all three values are finite.
pub fn finite3(v: &[f64; 3], what: &str) -> Result<()> {
    for x in v {
        crate::error::finite(what, *x)?;
    }
    Ok(())
}

/// The constraints clamping `rod` at `u` where it now is: position
/// (x, y, z) and tangent at their current values, and the cross-section
/// held as the rod's frame model says (`Rod::hold_cross_section`): the
/// roll coordinate where θ is the section's angle, else an absolute
/// `MaterialRoll` (Frenet model on a curved stretch). A rod without roll
/// gets position and tangent only. Used by `World::clamp` and
/// `Assembly::clamp`.
pub fn clamp_kinds(rod: &Rod, u: f64) -> Result<Vec<ConstraintKind>> {
    use crate::energy::HoldCrossSection;
    use kinds::{MaterialRoll, Position, Tangent};
    let p = rod.eval(u, 0)?;
    let t = rod.tangent(u)?;
    let hold = if rod.dofs() == 4 { Some(rod.hold_cross_section(u)?) } else { None };
    let axes = [true, true, true, hold == Some(HoldCrossSection::RollCoordinate)];
    let mut kinds = vec![Position { u, axes, target: p }.into(), Tangent { u, direction: t.into() }.into()];
    if hold == Some(HoldCrossSection::MaterialAngle) {
        // Measure the angle from a fixed axis ⟂ t: the current d1 is at 0.
        let (e1, _) = perpendicular_pair(&t);
        let angle = rod.material_angle(u, &e1)?.angle;
        kinds.push(MaterialRoll { u, reference: e1.into(), angle }.into());
    }
    Ok(kinds)
}

/// Two unit vectors completing `t` to an orthonormal frame, and the helper
/// axis they were built from (needed to differentiate them).
pub(crate) fn perpendicular_frame(t: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let helper = if t.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
    let e1 = (helper - t * t.dot(&helper)).normalize();
    (e1, t.cross(&e1), helper)
}

/// Two unit vectors completing `t` to an orthonormal frame.
pub(crate) fn perpendicular_pair(t: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let (e1, e2, _) = perpendicular_frame(t);
    (e1, e2)
}

/// Rows n_i · r(u) of one rod point (side `side`), each with its right-hand side.
pub(crate) fn point_rows(rod: &Rod, side: Side, u: f64, sign: f64, normals: &[Vector3<f64>], rows: &mut [Row]) -> Result<()> {
    let (ctrl, b) = rod.basis_at(u)?;
    for (row, n) in rows.iter_mut().zip(normals) {
        for k in 0..4 {
            for a in 0..3 {
                row.push_on(side, ctrl[k] * rod.dofs() + a, sign * b[0][k] * n[a]);
            }
        }
    }
    Ok(())
}

/// r'(u) as a vector and its length (error where it vanishes).
pub(crate) fn tangent_of(rod: &Rod, u: f64) -> Result<(Vector3<f64>, f64)> {
    let d = rod.eval(u, 1)?;
    let v = Vector3::new(d[0], d[1], d[2]);
    let n = v.norm();
    if !(n > 0.0) {
        return Err(Error::singular(format!("zero tangent at u = {u}")));
    }
    Ok((v / n, n))
}
