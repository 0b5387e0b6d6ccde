//! Single-point constraints (SPEC §4, thesis III.A), one module per family.
//! Each linearises g(q) into rows L (the Jacobian, normalised so that the
//! multiplier Λ is a force or a torque) and a right-hand side
//! E = target − g(q^n), which carries the drift correction and moving targets.
pub mod geometric;
pub mod material_roll;
pub mod position;
pub mod relative;
pub mod sliding;
pub mod tangent;

use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// What a constraint imposes on a rod at parameter `u`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ConstraintKind {
    /// r(u) (and θ(u), the roll coordinate) equal to `target` on the axes
    /// selected by `axes` = [x, y, z, θ] (III.20). Multipliers: force (x,y,z),
    /// torque about the tangent (θ).
    Position { u: f64, axes: [bool; 4], target: [f64; 4] },
    /// r'(u) parallel to `direction` (two rows ⟂ direction, III.23). Multiplier:
    /// the moment vector ⟂ tangent.
    Tangent { u: f64, direction: [f64; 3] },
    /// Absolute roll of the material frame: the angle of director d1 about the
    /// tangent measured from `reference` (projected ⟂ tangent) equals `angle`
    /// (radians). In the Frenet model this is θ(u) + angle of the Frenet
    /// normal, so it needs a curved rod at u. This is a real clamp of the
    /// cross-section; `Position` with axes[3] only fixes the roll coordinate
    /// relative to the Frenet frame. Multiplier: torque about the tangent.
    MaterialRoll { u: f64, reference: [f64; 3], angle: f64 },
    /// |r(u) − point| = distance (> 0; III.28). Multiplier: force along
    /// (r − point)/|r − point|, negative when the link is in tension.
    Distance { u: f64, point: [f64; 3], distance: f64 },
    /// r(u) stays on the plane through `origin` with `normal` (III.31).
    /// Multiplier: normal force.
    Plane { u: f64, origin: [f64; 3], normal: [f64; 3] },
    /// r(u) stays on the line through `origin` along `direction` (III.34).
    Axis { u: f64, origin: [f64; 3], direction: [f64; 3] },
    /// r''(u) = target (III.27, length per u²).
    Curvature { u: f64, target: [f64; 3] },
    /// Two rods (or two points of one rod): q_a(ua) − q_b(ub) = offset on
    /// the selected axes [x, y, z, θ] (III.55). Multiplier: the force (and
    /// roll torque) on rod a; rod b receives the opposite.
    RelativePosition { ua: f64, ub: f64, axes: [bool; 4], offset: [f64; 4] },
    /// Tangents of rod a at ua and rod b at ub aligned (two rows, III.58),
    /// plus equal roll coordinates when `roll`. Multiplier: the moment on rod a.
    RelativeOrientation { ua: f64, ub: f64, roll: bool },
    /// |r_a(ua) − r_b(ub)| = distance (> 0; III.66). Multiplier: force on rod a
    /// along (r_a − r_b)/|r_a − r_b|, negative in tension.
    RelativeDistance { ua: f64, ub: f64, distance: f64 },
    /// The rod passes through `point`; `u` is an unknown updated every solve
    /// (III.37–III.42). `friction`: viscous coefficient c, tangential force
    /// −c v_s per unit sliding speed v_s (force·time/length). Multiplier: the
    /// force on the rod (⟂ tangent when frictionless). A slider that leaves
    /// the rod is removed with an event.
    SlidingPoint { u: f64, point: [f64; 3], friction: f64 },
    /// Sliding point whose tangent is also held parallel to `direction`
    /// at the same moving abscissa (III.43–III.49): a rod through a tube or
    /// a clip. Multipliers: force (3), moment (2).
    OrientedSlidingPoint { u: f64, point: [f64; 3], direction: [f64; 3], friction: f64 },
    /// Contact between two rods: |r_a(ua) − r_b(ub)| = distance with both
    /// abscissae moved to the closest points before every solve, so the
    /// force is normal to both rods and yarns slide freely (III.42 remark).
    /// Multiplier: force on rod a along (r_a − r_b), negative in tension.
    Contact { ua: f64, ub: f64, distance: f64 },
    /// Coplanar relative clamp (III.61–III.65): r_a(ua) − r_b(ub) =
    /// α0 r_a'(ua) + α1 r_b'(ub), with α fixed from the geometry when it is
    /// made (`World::add_coplanar_clamp`; the link must lie in the plane of
    /// the two tangents). Unlike the thesis' name suggests it is a hinge, not
    /// a weld: it keeps the two tangent lines meeting at a common point P,
    /// and rod b may rotate about P (g stays exactly 0). Multiplier: force on rod a.
    CoplanarClamp { ua: f64, ub: f64, alpha: [f64; 2] },
    /// Barycentric (III.70–III.74): Σ a_j q(u_j) = q(driven) on the selected
    /// axes of one rod (up to 4 points; weights summing to 1 make it
    /// translation invariant). Multiplier: force (torque) at the driven point.
    Barycentric { points: Vec<(f64, f64)>, driven: f64, axes: [bool; 4] },
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

/// One linearised constraint row; entries are (which of the constraint's
/// rods: 0 or 1, rod-local coordinate, value).
#[derive(Clone, Copy, Debug)]
pub struct Row {
    pub entries: [(u8, usize, f64); MAX_ENTRIES],
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
    pub(crate) fn push_on(&mut self, which: u8, i: usize, v: f64) {
        self.entries[self.len] = (which, i, v);
        self.len += 1;
    }
    pub fn entries(&self) -> &[(u8, usize, f64)] {
        &self.entries[..self.len]
    }
}

/// Control points a constraint touches: (which rod, control point).
#[derive(Clone, Copy, Debug)]
pub struct Touched {
    pub items: [(u8, usize); MAX_TOUCHED],
    pub len: usize,
}

/// Most control points one constraint touches (barycentric: 5 points × 4).
pub const MAX_TOUCHED: usize = 20;

impl Touched {
    fn of(which: u8, ctrl: [usize; 4], into: &mut Touched) {
        for c in ctrl {
            into.items[into.len] = (which, c);
            into.len += 1;
        }
    }
    pub fn as_slice(&self) -> &[(u8, usize)] {
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

impl ConstraintKind {
    /// The abscissa (first rod's for relative kinds).
    pub fn u(&self) -> f64 {
        if let Some((ua, _)) = relative::abscissae(self) {
            return ua;
        }
        match self {
            ConstraintKind::Position { u, .. }
            | ConstraintKind::Tangent { u, .. }
            | ConstraintKind::MaterialRoll { u, .. }
            | ConstraintKind::Distance { u, .. }
            | ConstraintKind::Plane { u, .. }
            | ConstraintKind::Axis { u, .. }
            | ConstraintKind::Curvature { u, .. }
            | ConstraintKind::SlidingPoint { u, .. }
            | ConstraintKind::OrientedSlidingPoint { u, .. } => *u,
            ConstraintKind::Barycentric { driven, .. } => *driven,
            _ => unreachable!("relative kinds handled above"), // abscissae() covers them
        }
    }

    /// Every abscissa of the constraint with the side it lies on (0: first
    /// rod, 1: second rod of a relative kind), for moving a constraint to
    /// another rod (rupture).
    pub(crate) fn abscissae_mut(&mut self) -> Vec<(u8, &mut f64)> {
        use ConstraintKind::*;
        match self {
            Position { u, .. }
            | Tangent { u, .. }
            | MaterialRoll { u, .. }
            | Distance { u, .. }
            | Plane { u, .. }
            | Axis { u, .. }
            | Curvature { u, .. }
            | SlidingPoint { u, .. }
            | OrientedSlidingPoint { u, .. } => vec![(0, u)],
            RelativePosition { ua, ub, .. }
            | RelativeOrientation { ua, ub, .. }
            | RelativeDistance { ua, ub, .. }
            | Contact { ua, ub, .. }
            | CoplanarClamp { ua, ub, .. } => vec![(0, ua), (1, ub)],
            Barycentric { points, driven, .. } => {
                let mut v: Vec<(u8, &mut f64)> = points.iter_mut().map(|p| (0, &mut p.0)).collect();
                v.push((0, driven));
                v
            }
        }
    }

    pub fn n_rows(&self) -> usize {
        match self {
            ConstraintKind::Position { axes, .. } => axes.iter().filter(|a| **a).count(),
            ConstraintKind::Tangent { .. } => 2,
            ConstraintKind::MaterialRoll { .. } | ConstraintKind::Distance { .. } | ConstraintKind::Plane { .. } => 1,
            ConstraintKind::Axis { .. } => 2,
            ConstraintKind::Curvature { .. } => 3,
            ConstraintKind::RelativePosition { axes, .. } => axes.iter().filter(|a| **a).count(),
            ConstraintKind::RelativeOrientation { roll, .. } => 2 + usize::from(*roll),
            ConstraintKind::RelativeDistance { .. } => 1,
            ConstraintKind::SlidingPoint { .. } => 3,
            ConstraintKind::OrientedSlidingPoint { .. } => 5,
            ConstraintKind::Contact { .. } => 1,
            ConstraintKind::CoplanarClamp { .. } => 3,
            ConstraintKind::Barycentric { axes, .. } => axes.iter().filter(|a| **a).count(),
        }
    }

    /// Abscissa unknowns the constraint adds to the system (sliders).
    pub fn n_extra(&self) -> usize {
        usize::from(matches!(self, ConstraintKind::SlidingPoint { .. } | ConstraintKind::OrientedSlidingPoint { .. }))
    }

    /// A_uu, rhs and A_(q,u) of the abscissa unknowns, given the previous
    /// multipliers and the friction coefficient factor (1/h in dynamics, 0
    /// in statics).
    pub fn sliding_blocks(&self, rods: &[&Rod], lambda: &[f64], friction_coeff: f64, out: &mut SlidingBlocks) -> Result<()> {
        out.diag = [0.0; 2];
        out.rhs = [0.0; 2];
        out.coupling.len = 0;
        match self {
            ConstraintKind::SlidingPoint { u, friction, .. } | ConstraintKind::OrientedSlidingPoint { u, friction, .. } => {
                sliding::blocks(rods[0], *u, *friction, &lambda[..3], friction_coeff, out)
            }
            _ => Ok(()),
        }
    }

    /// Moves a contact's abscissae to the closest points of its two rods
    /// (called before every linearisation).
    pub fn project(&mut self, rods: &[&Rod]) -> Result<()> {
        if let ConstraintKind::Contact { ua, ub, .. } = self {
            let (a, b) = sliding::closest_points(rods[0], rods[1], *ua, *ub)?;
            *ua = a;
            *ub = b;
        }
        Ok(())
    }

    /// Moves the abscissae by the solved increments; returns false when a
    /// slider left its rod's domain.
    pub fn advance(&mut self, rods: &[&Rod], du: &[f64]) -> bool {
        if let ConstraintKind::SlidingPoint { u, .. } | ConstraintKind::OrientedSlidingPoint { u, .. } = self {
            *u += du[0];
            let (a, b) = rods[0].domain();
            return *u >= a && *u <= b;
        }
        true
    }

    /// Rods the constraint links: 1, or 2 for relative constraints (which
    /// may name the same rod twice).
    pub fn n_rods(&self) -> usize {
        if relative::is_relative(self) {
            2
        } else {
            1
        }
    }

    /// Checks the constraint against its rods (abscissae inside the domain,
    /// finite targets, roll only on rods with roll, …).
    pub fn validate(&self, rods: &[&Rod]) -> Result<()> {
        if relative::is_relative(self) {
            return relative::validate(self, rods);
        }
        let rod = rods[0];
        let u = crate::error::finite("constraint abscissa u", self.u())?;
        rod.knots().locate(u)?;
        match self {
            ConstraintKind::Position { axes, target, .. } => {
                if !axes.iter().any(|a| *a) {
                    return Err(Error::input("position constraint selects no axis"));
                }
                if axes[3] && rod.dofs() == 3 {
                    return Err(Error::input("roll constraint on a rod without roll coordinate"));
                }
                for (a, t) in axes.iter().zip(target) {
                    if *a {
                        crate::error::finite("position target", *t)?;
                    }
                }
            }
            ConstraintKind::Tangent { direction, .. } => {
                unit(direction, "tangent direction")?;
            }
            ConstraintKind::MaterialRoll { reference, angle, .. } => {
                if rod.dofs() == 3 {
                    return Err(Error::input("material roll constraint on a rod without roll coordinate"));
                }
                unit(reference, "material roll reference")?;
                crate::error::finite("material roll angle", *angle)?;
            }
            ConstraintKind::Distance { point, distance, .. } => {
                finite3(point, "distance anchor point")?;
                crate::error::positive("constraint distance (use a Position constraint for zero)", *distance)?;
            }
            ConstraintKind::Plane { origin, normal, .. } => {
                finite3(origin, "plane origin")?;
                unit(normal, "plane normal")?;
            }
            ConstraintKind::Axis { origin, direction, .. } => {
                finite3(origin, "axis origin")?;
                unit(direction, "axis direction")?;
            }
            ConstraintKind::Curvature { target, .. } => finite3(target, "curvature target")?,
            ConstraintKind::SlidingPoint { point, friction, .. } => {
                finite3(point, "sliding point")?;
                crate::error::non_negative("sliding friction", *friction)?;
            }
            ConstraintKind::Barycentric { points, driven, axes } => {
                if points.is_empty() || points.len() > 4 {
                    return Err(Error::input(format!("barycentric constraint needs 1 to 4 points, got {}", points.len())));
                }
                for (u, a) in points {
                    rod.knots().locate(crate::error::finite("barycentric abscissa", *u)?)?;
                    crate::error::finite("barycentric weight", *a)?;
                }
                rod.knots().locate(*driven)?;
                if !axes.iter().any(|a| *a) || (axes[3] && rod.dofs() == 3) {
                    return Err(Error::input("barycentric constraint: select axes the rod has"));
                }
            }
            ConstraintKind::OrientedSlidingPoint { point, direction, friction, .. } => {
                finite3(point, "sliding point")?;
                unit(direction, "oriented slider direction")?;
                crate::error::non_negative("sliding friction", *friction)?;
            }
            _ => {}
        }
        Ok(())
    }

    /// Control points the rows touch (for ordering, IV.3–IV.4).
    pub fn touched(&self, rods: &[&Rod]) -> Result<Touched> {
        let mut t = Touched { items: [(0, 0); MAX_TOUCHED], len: 0 };
        if let ConstraintKind::Barycentric { points, driven, .. } = self {
            for &(u, _) in points.iter().chain(std::iter::once(&(*driven, 0.0))) {
                Touched::of(0, rods[0].basis_at(u)?.0, &mut t);
            }
            return Ok(t);
        }
        if let Some((ua, ub)) = relative::abscissae(self) {
            Touched::of(0, rods[0].basis_at(ua)?.0, &mut t);
            Touched::of(1, rods[1].basis_at(ub)?.0, &mut t);
        } else {
            Touched::of(0, rods[0].basis_at(self.u())?.0, &mut t);
        }
        Ok(t)
    }

    /// Writes `n_rows()` rows linearised at the rods' current coordinates.
    pub fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        rows.iter_mut().for_each(|r| r.len = 0);
        if relative::is_relative(self) {
            return relative::linearize(self, rods, rows);
        }
        let rod = rods[0];
        match self {
            ConstraintKind::Position { u, axes, target } => position::linearize(rod, *u, axes, target, rows),
            ConstraintKind::Tangent { u, direction } => tangent::linearize(rod, *u, direction, rows),
            ConstraintKind::MaterialRoll { u, reference, angle } => {
                material_roll::linearize(rod, *u, reference, *angle, rows)
            }
            ConstraintKind::Distance { u, point, distance } => geometric::distance(rod, *u, point, *distance, rows),
            ConstraintKind::Plane { u, origin, normal } => geometric::plane(rod, *u, origin, normal, rows),
            ConstraintKind::Axis { u, origin, direction } => geometric::axis(rod, *u, origin, direction, rows),
            ConstraintKind::Curvature { u, target } => geometric::curvature(rod, *u, target, rows),
            ConstraintKind::SlidingPoint { u, point, .. } => sliding::linearize(rod, *u, point, rows),
            ConstraintKind::OrientedSlidingPoint { u, point, direction, .. } => {
                sliding::linearize_oriented(rod, *u, point, direction, rows)
            }
            ConstraintKind::Barycentric { points, driven, axes } => {
                let mut r = 0;
                for a in 0..4 {
                    if !axes[a] {
                        continue;
                    }
                    let mut value = 0.0;
                    for &(u, w) in points.iter().chain(std::iter::once(&(*driven, -1.0))) {
                        let (ctrl, b) = rod.basis_at(u)?;
                        for k in 0..4 {
                            rows[r].push(ctrl[k] * rod.dofs() + a, w * b[0][k]);
                        }
                        value += w * rod.eval(u, 0)?[a];
                    }
                    rows[r].rhs = -value;
                    r += 1;
                }
                Ok(())
            }
            _ => unreachable!("relative kinds handled above"), // is_relative covers every other variant
        }
    }

    /// Physical reaction on the (first) rod from the multipliers (see each family).
    pub fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        if relative::is_relative(self) {
            return relative::reaction(self, rods, lambda);
        }
        let rod = rods[0];
        match self {
            ConstraintKind::Position { axes, .. } => Ok(position::reaction(axes, lambda)),
            ConstraintKind::Tangent { u, direction } => tangent::reaction(rod, *u, direction, lambda),
            ConstraintKind::MaterialRoll { u, .. } => {
                let t = rod.tangent(*u)?;
                Ok(Reaction { force: [0.0; 3], torque: (t * lambda[0]).into() })
            }
            ConstraintKind::Distance { u, point, .. } => geometric::distance_reaction(rod, *u, point, lambda),
            ConstraintKind::Plane { normal, .. } => {
                Ok(Reaction { force: (unit(normal, "plane normal")? * lambda[0]).into(), torque: [0.0; 3] })
            }
            ConstraintKind::Axis { direction, .. } => geometric::axis_reaction(direction, lambda),
            ConstraintKind::Curvature { .. } | ConstraintKind::SlidingPoint { .. } => {
                Ok(Reaction { force: [lambda[0], lambda[1], lambda[2]], torque: [0.0; 3] })
            }
            ConstraintKind::Barycentric { axes, .. } => {
                // Λ multiplies −q(driven): the force at the driven point is −Λ.
                let r = position::reaction(axes, lambda);
                Ok(Reaction { force: r.force.map(|f| -f), torque: r.torque.map(|t| -t) })
            }
            ConstraintKind::OrientedSlidingPoint { u, direction, .. } => {
                let m = tangent::reaction(rod, *u, direction, &lambda[3..5])?;
                Ok(Reaction { force: [lambda[0], lambda[1], lambda[2]], torque: m.torque })
            }
            _ => unreachable!("relative kinds handled above"), // is_relative covers every other variant
        }
    }
}

/// Normalised copy of a direction; error on zero / non-finite.
pub(crate) fn unit(v: &[f64; 3], what: &str) -> Result<Vector3<f64>> {
    let x = Vector3::from(*v);
    let n = x.norm();
    if !n.is_finite() || n == 0.0 {
        return Err(Error::input(format!("{what} must be a finite non-zero vector, got {v:?}")));
    }
    Ok(x / n)
}

pub(crate) fn finite3(v: &[f64; 3], what: &str) -> Result<()> {
    for x in v {
        crate::error::finite(what, *x)?;
    }
    Ok(())
}

/// Two unit vectors completing `t` to an orthonormal frame.
pub(crate) fn perpendicular_pair(t: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let helper = if t.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
    let e1 = (helper - t * t.dot(&helper)).normalize();
    (e1, t.cross(&e1))
}
