//! The contact seam (SPEC §7; rapier keeps contacts apart from joints the
//! same way): a [`ContactSet`] of unilateral pairs, produced each step by
//! the world's [`ContactDetector`]s ([`rods::RodContacts`]: rod–rod and
//! self-contact between capsules; [`obstacle::Obstacle`]: plane, sphere,
//! capsule, triangle mesh), entering the same KKT system as the
//! constraints, with an active set — a pair whose multiplier would pull is
//! dropped and the system solved again; a candidate that the solution
//! would push through its gap is taken in.
//!
//! A pair's row is a constraint kind oriented so that a positive multiplier
//! pushes the rods apart: [`ConstraintKind::Contact`] between two rods
//! (g = |r_a − r_b| − distance), or [`ConstraintKind::Plane`] for a rod
//! against an obstacle's tangent plane, its normal pointing out of the
//! obstacle. Coulomb friction ([`friction`]) adds stick rows or a slip
//! force (with, between rods, a row across the slip direction) to active
//! pairs.
//!
//! Why the queries are our own rather than parry3d-f64's (SPEC §7): the
//! pairs need the segment parameters (s, t) to map back to spline
//! abscissae, with our convention for parallel segments (the middle of
//! the overlap); the self-contact exclusion along the rod, the
//! nearest-partner filter and the per-rod-pair thinning would sit on top
//! of any library anyway; parry from 0.26 works on glam types (a
//! conversion at every call) and up to 0.25 on a nalgebra release of its
//! own choosing, not necessarily ours (0.35); and the closed forms —
//! segment–segment (`capsule.rs`), point–triangle and a median-split BVH
//! (`mesh.rs`) — are short and tested against brute force.
pub mod capsule;
pub mod friction;
pub mod mesh;
pub mod obstacle;
pub(crate) mod broad;
pub(crate) mod nearest;
pub mod rods;

/// A straight steel rod from the origin along x, 1 m long, 1 cm radius, 6
/// control points: the unit tests' rod.
#[cfg(test)]
pub(crate) fn test_rod() -> crate::rod::Rod {
    crate::RodBuilder::straight(nalgebra::Vector3::zeros(), nalgebra::Vector3::x())
        .control_points(6)
        .section(crate::Section::circle(0.01).unwrap())
        .material(crate::Material::new("steel", 2e11, 0.3, 7800.0).unwrap())
        .build()
        .unwrap()
}

use crate::constraint::ConstraintKind;
use crate::error::{Error, Result};
use crate::handles::RodHandle;
use serde::{Deserialize, Serialize};

/// The abscissae a detector probes along a rod (its samples, plus its two
/// ends when open) into `us`, and the rod's largest section radius.
pub(crate) fn probe_points(rod: &crate::rod::Rod, us: &mut Vec<f64>) -> f64 {
    us.clear();
    let (u0, u1) = rod.domain();
    let open = !rod.is_closed();
    if open {
        us.push(u0);
    }
    us.extend(rod.sample_params_iter());
    if open {
        us.push(u1);
    }
    capsule_radius(rod)
}

/// A rod's capsule radius: its largest section's bounding radius (length unit).
pub(crate) fn capsule_radius(rod: &crate::rod::Rod) -> f64 {
    rod.sections().iter().map(|s| s.bounding_radius()).fold(0.0, f64::max)
}

/// A block's buffer for [`fill_blocks`]: emptied before its block fills it.
pub(crate) trait BlockBuffer: Send + Default {
    fn clear(&mut self);
}

impl<T: Send> BlockBuffer for Vec<T> {
    fn clear(&mut self) {
        Vec::clear(self)
    }
}

/// `f` over `0..n` in contiguous blocks, each filling its own buffer of
/// `bufs` (cleared first; kept between calls, so that a warmed-up caller
/// reuses their memory; buffers past the blocks are left empty, so a
/// reader may take them all): on rayon's pool when `parallel` (a few blocks per
/// thread, for balance), else one block on this thread. The buffers read
/// one after the other never depend on the blocking, so both ways give
/// the same answer; so does the error, the first block's that failed.
/// Allocation-free once `bufs` has grown (the blocks' outcomes are reduced,
/// not collected).
pub(crate) fn fill_blocks<B: BlockBuffer>(parallel: bool, n: usize, bufs: &mut Vec<B>, f: impl Fn(std::ops::Range<usize>, &mut B) -> Result<()> + Sync) -> Result<()> {
    let k = if parallel { (4 * rayon::current_num_threads()).min(n).max(1) } else { 1 };
    // Grown, never shrunk (a short last chunk would drop buffers that the
    // next call builds again); the ones past `k` are left empty.
    if bufs.len() < k {
        bufs.resize_with(k, B::default);
    }
    bufs[k..].iter_mut().for_each(B::clear);
    let run = |(b, out): (usize, &mut B)| {
        out.clear();
        f(b * n / k..(b + 1) * n / k, out)
    };
    if k > 1 {
        use rayon::prelude::*;
        bufs[..k].par_iter_mut().enumerate().map(|(b, out)| run((b, out)).map_err(|e| (b, e))).reduce(|| Ok(()), first_error).map_err(|(_, e)| e)
    } else {
        bufs[..1].iter_mut().enumerate().try_for_each(run)
    }
}

/// Of two parallel outcomes tagged with their item's index, the error of
/// the lowest index (what a serial pass would have stopped at).
pub(crate) fn first_error<E>(x: std::result::Result<(), (usize, E)>, y: std::result::Result<(), (usize, E)>) -> std::result::Result<(), (usize, E)> {
    match (x, y) {
        (Err(a), Err(b)) => Err(if a.0 <= b.0 { a } else { b }),
        (Err(a), _) | (_, Err(a)) => Err(a),
        _ => Ok(()),
    }
}

/// A detector's `margin` (a finite length ≥ 0) and Coulomb coefficient.
pub(crate) fn check_margin_and_friction(margin: f64, mu: f64) -> Result<()> {
    if !(margin >= 0.0) || !margin.is_finite() {
        return Err(Error::invalid("contact margin", margin, "a finite length ≥ 0"));
    }
    friction::check_mu(mu)
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
    /// Coulomb friction, when the pair has a coefficient.
    #[serde(default)]
    pub friction: Option<friction::Friction>,
    /// Compliance of the normal row (length/force): 0 for a rigid row, a
    /// distributed row's share of its line stiffness otherwise
    /// ([`rods::RodContacts::line_stiffness`]).
    #[serde(default)]
    pub compliance: f64,
}

impl ContactPair {
    pub fn new(rods: [RodHandle; 2], kind: ConstraintKind) -> Result<ContactPair> {
        match &kind {
            ConstraintKind::Contact(_) | ConstraintKind::Plane(_) => Ok(ContactPair { rods, kind, force: 0.0, active: false, friction: None, compliance: 0.0 }),
            k => Err(Error::invalid("contact pair kind", k.name(), "Contact (rod–rod) or Plane (rod–obstacle)")),
        }
    }
    /// With Coulomb friction of coefficient `mu` (none when 0).
    pub fn with_friction(mut self, mu: f64) -> Result<ContactPair> {
        friction::check_mu(mu)?;
        self.friction = if mu > 0.0 { Some(friction::Friction::new(mu)?) } else { None };
        Ok(self)
    }
    /// With a compliant normal row (`c`: length/force, finite ≥ 0).
    pub fn with_compliance(mut self, c: f64) -> Result<ContactPair> {
        self.compliance = crate::error::non_negative("contact compliance", c)?;
        Ok(self)
    }
    /// A penalty row (compliance > 0): acting where the strands are into
    /// each other at the start of the step, never pulling, outside the
    /// active-set rounds (see `pipeline::assemble::assemble_with`).
    pub fn is_penalty(&self) -> bool {
        self.compliance > 0.0
    }
    /// The tangential (friction) force on rod a of the last solve (force unit).
    pub fn friction_force(&self) -> [f64; 3] {
        self.friction.as_ref().filter(|_| self.active).map_or([0.0; 3], |f| f.force)
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

/// One active contact as a user reads it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactInfo {
    /// Rod a, and rod b (`None` against an obstacle).
    pub rod_a: RodHandle,
    pub rod_b: Option<RodHandle>,
    /// Abscissae of the touching points (no ub against an obstacle).
    pub ua: f64,
    pub ub: Option<f64>,
    /// Rod a's centreline point (length).
    pub point: [f64; 3],
    /// Unit normal pushing rod a out of contact.
    pub normal: [f64; 3],
    /// Normal force on rod a (force unit, ≥ 0) and tangential (friction) force.
    pub normal_force: f64,
    pub friction_force: [f64; 3],
    pub slipping: bool,
}

impl ContactInfo {
    /// The same contact seen from rod b (a rod–rod pair): the rods and
    /// abscissae swapped, `point_b` (rod b's centreline point at ub) as the
    /// point, and the normal and friction force reversed — the force on b
    /// is minus the force on a (a row's gradient is equal and opposite at
    /// the two touching points). Against an obstacle (no rod b) unchanged.
    pub fn turned(&self, point_b: [f64; 3]) -> ContactInfo {
        let (Some(rod_b), Some(ub)) = (self.rod_b, self.ub) else { return self.clone() };
        ContactInfo {
            rod_a: rod_b,
            rod_b: Some(self.rod_a),
            ua: ub,
            ub: Some(self.ua),
            point: point_b,
            normal: self.normal.map(|x| -x),
            normal_force: self.normal_force,
            friction_force: self.friction_force.map(|x| -x),
            slipping: self.slipping,
        }
    }
}

impl ContactSet {
    /// The active pairs, with their geometry at the rods' current state.
    pub fn report<'r>(&self, rod: impl Fn(RodHandle) -> Result<&'r crate::rod::Rod>) -> Result<Vec<ContactInfo>> {
        let mut out = Vec::new();
        for (_, p) in self.active() {
            let (a, b) = (rod(p.rods[0])?, rod(p.rods[1])?);
            let g = friction::geometry(&p.kind, [a, b])?;
            out.push(ContactInfo {
                rod_a: p.rods[0],
                rod_b: g.ub.map(|_| p.rods[1]),
                ua: g.ua,
                ub: g.ub,
                point: a.position(g.ua)?.into(),
                normal: g.normal.into(),
                normal_force: p.force,
                friction_force: p.friction_force(),
                slipping: p.friction.as_ref().is_some_and(|f| f.slip.is_some() || f.at_limit),
            });
        }
        Ok(out)
    }
}

/// The world's detectors: one variant per detector, so that a snapshot
/// carries them (a restart mid-contact finds the same pairs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Detector {
    Rods(rods::RodContacts),
    Obstacle(obstacle::Obstacle),
}

impl From<rods::RodContacts> for Detector {
    fn from(d: rods::RodContacts) -> Detector {
        Detector::Rods(d)
    }
}
impl From<obstacle::Obstacle> for Detector {
    fn from(d: obstacle::Obstacle) -> Detector {
        Detector::Obstacle(d)
    }
}

impl Detector {
    pub fn validate(&self) -> Result<()> {
        match self {
            Detector::Rods(d) => d.validate(),
            Detector::Obstacle(d) => d.validate(),
        }
    }
}

impl ContactDetector for Detector {
    fn detect_with(&self, rods: &[(RodHandle, &crate::rod::Rod)], out: &mut ContactSet, scratch: &mut Scratch) -> Result<()> {
        match self {
            Detector::Rods(d) => d.detect_with(rods, out, scratch),
            Detector::Obstacle(d) => d.detect_with(rods, out, scratch),
        }
    }
}

/// Fills the contact set from the rods before each solve
/// ([`rods::RodContacts`]); without a detector, pairs put in the set by
/// hand stay as given.
pub trait ContactDetector: Send + Sync + std::fmt::Debug {
    /// Adds the pairs found among `rods` to `out`, using (and keeping for
    /// the next call) the buffers in `scratch`.
    fn detect_with(&self, rods: &[(RodHandle, &crate::rod::Rod)], out: &mut ContactSet, scratch: &mut Scratch) -> Result<()>;

    /// [`ContactDetector::detect_with`] on buffers of its own.
    fn detect(&self, rods: &[(RodHandle, &crate::rod::Rod)], out: &mut ContactSet) -> Result<()> {
        self.detect_with(rods, out, &mut Scratch::default())
    }
}

/// Buffers of contact detection kept between detections (a world keeps
/// one in its workspace): a step allocates little once they have grown,
/// and does not touch fresh pages each time.
#[derive(Debug, Default)]
pub struct Scratch {
    /// Detect in blocks on rayon's pool when called on one of its threads
    /// (a world sets it in steps that use the pool: `parallel` and ≥ 2048
    /// segments); off, detection stays on the calling thread. The rows
    /// are the same either way.
    pub parallel: bool,
    pub(crate) rods: rods::Scratch,
    pub(crate) obstacle: obstacle::Scratch,
}

impl Scratch {
    /// Empty buffers; `parallel` as the field says.
    pub fn new(parallel: bool) -> Scratch {
        Scratch { parallel, ..Default::default() }
    }
}
