//! Fixed obstacles (SPEC §7): a plane, a sphere, a capsule (a cylinder with
//! round ends; a long one stands for a cylinder) or a triangle mesh. The
//! rods' points closer to one than their radius plus `margin` become
//! unilateral [`ConstraintKind::Plane`] rows on the obstacle's tangent
//! plane at the nearest point, lifted by the rod's radius and re-taken at
//! every assembly (first order in the obstacle's curvature, like the
//! closest-point rows between rods). Along a rod the local minima of the
//! gap and candidates at least a segment from the last kept row are kept
//! (a minimum within half a segment of a row kept for spacing replaces
//! it): a rod lying on an obstacle gets about one row per segment (its
//! n + 3 control points meet at most that many heights independently).
use super::mesh::TriMesh;
use super::{ContactDetector, ContactPair, ContactSet};
use crate::constraint::kinds::Plane;
use crate::constraint::ConstraintKind;
use crate::error::{Error, Result};
use crate::handles::RodHandle;
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The obstacle's geometry (lengths in the world's unit).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    /// The half-space behind the plane through `origin` whose unit
    /// `normal` points out of the obstacle.
    Plane { origin: [f64; 3], normal: [f64; 3] },
    Sphere { center: [f64; 3], radius: f64 },
    /// The points within `radius` of the segment `a`–`b`.
    Capsule { a: [f64; 3], b: [f64; 3], radius: f64 },
    /// A triangle mesh whose outside is where its faces' normals point
    /// (counter-clockwise vertices seen from outside).
    Mesh(Arc<TriMesh>),
}

/// A fixed obstacle detected `margin` (length) ahead of contact, with
/// Coulomb coefficient `friction` against the rods.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Obstacle {
    pub shape: Shape,
    pub margin: f64,
    pub friction: f64,
}

fn finite_point(p: &[f64; 3], what: &str) -> Result<()> {
    crate::constraint::finite3(p, what)
}

impl Obstacle {
    fn new(shape: Shape) -> Result<Obstacle> {
        let o = Obstacle { shape, margin: 0.0, friction: 0.0 };
        o.validate()?;
        Ok(o)
    }
    /// The half-space behind the plane through `origin` (length), `normal`
    /// pointing out of it (normalised here).
    pub fn plane(origin: [f64; 3], normal: [f64; 3]) -> Result<Obstacle> {
        let n = Vector3::from(normal);
        if !n.iter().all(|x| x.is_finite()) || !(n.norm() > 0.0) {
            return Err(Error::invalid("plane obstacle normal", format!("{normal:?}"), "a finite, non-zero direction"));
        }
        Obstacle::new(Shape::Plane { origin, normal: n.normalize().into() })
    }
    /// A ball of `radius` (length, > 0) about `center` (length).
    pub fn sphere(center: [f64; 3], radius: f64) -> Result<Obstacle> {
        Obstacle::new(Shape::Sphere { center, radius })
    }
    /// The points within `radius` (length, > 0) of the segment `a`–`b`.
    pub fn capsule(a: [f64; 3], b: [f64; 3], radius: f64) -> Result<Obstacle> {
        Obstacle::new(Shape::Capsule { a, b, radius })
    }
    /// A triangle mesh (see [`TriMesh::from_file`] for OBJ and STL).
    pub fn mesh(mesh: TriMesh) -> Result<Obstacle> {
        Obstacle::new(Shape::Mesh(Arc::new(mesh)))
    }
    /// Detected `margin` (length, ≥ 0) ahead of contact.
    pub fn with_margin(mut self, margin: f64) -> Result<Obstacle> {
        self.margin = margin;
        self.validate()?;
        Ok(self)
    }
    /// Coulomb coefficient `mu` (≥ 0) against the rods.
    pub fn with_friction(mut self, mu: f64) -> Result<Obstacle> {
        self.friction = mu;
        self.validate()?;
        Ok(self)
    }
    pub fn validate(&self) -> Result<()> {
        super::check_margin_and_friction(self.margin, self.friction)?;
        match &self.shape {
            Shape::Plane { origin, normal } => {
                finite_point(origin, "plane obstacle origin")?;
                crate::constraint::unit(normal, "plane obstacle normal").map(|_| ())
            }
            Shape::Sphere { center, radius } => {
                finite_point(center, "sphere obstacle center")?;
                crate::error::positive("sphere obstacle radius", *radius).map(|_| ())
            }
            Shape::Capsule { a, b, radius } => {
                finite_point(a, "capsule obstacle end a")?;
                finite_point(b, "capsule obstacle end b")?;
                crate::error::positive("capsule obstacle radius", *radius).map(|_| ())
            }
            Shape::Mesh(m) => m.validate(),
        }
    }
    /// The signed distance from `p` to the obstacle's surface and the unit
    /// normal there pointing out of it; `None` when nothing of the obstacle
    /// is within `reach` (a mesh only looks that far).
    pub fn nearest(&self, p: &Vector3<f64>, reach: f64) -> Option<(f64, Vector3<f64>)> {
        let round = |c: Vector3<f64>, radius: f64| {
            let d = p - c;
            let n = d.norm();
            // At the centre every direction is as good: take one.
            let dir = if n > 0.0 { d / n } else { Vector3::z() };
            (n - radius, dir)
        };
        match &self.shape {
            Shape::Plane { origin, normal } => {
                let n = Vector3::from(*normal);
                Some(((p - Vector3::from(*origin)).dot(&n), n))
            }
            Shape::Sphere { center, radius } => Some(round(Vector3::from(*center), *radius)),
            Shape::Capsule { a, b, radius } => {
                let (a, b) = (Vector3::from(*a), Vector3::from(*b));
                let ab = b - a;
                let t = if ab.norm_squared() > 0.0 { ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0) } else { 0.0 };
                Some(round(a + ab * t, *radius))
            }
            Shape::Mesh(m) => m.nearest(p, reach),
        }
    }
}

/// Buffers of obstacle detection, per rod: the probed abscissae, each
/// probe's gap and normal (None beyond the margin), the rows kept (probe,
/// is a local minimum).
#[derive(Debug, Default)]
pub(crate) struct Scratch {
    us: Vec<f64>,
    near: Vec<Option<(f64, Vector3<f64>)>>,
    kept: Vec<(usize, bool)>,
}

impl ContactDetector for Obstacle {
    fn detect_with(&self, rods: &[(RodHandle, &Rod)], out: &mut ContactSet, scratch: &mut super::Scratch) -> Result<()> {
        let Scratch { us, near, kept } = &mut scratch.obstacle;
        for (h, rod) in rods {
            let radius = super::probe_points(rod, us);
            let (u0, u1) = rod.domain();
            let reach = radius + self.margin;
            near.clear();
            for &u in us.iter() {
                let p = rod.position(u)?;
                near.push(self.nearest(&p, reach).map(|(d, n)| (d - radius, n)).filter(|(g, _)| *g < self.margin));
            }
            // One segment, in the parameter.
            let span = (u1 - u0) / rod.n_segments().max(1) as f64;
            let n = us.len();
            let gap = |j: usize| near[j].map_or(f64::INFINITY, |x| x.0);
            // Gaps closer than 1e-7 of the radius are equal (the sag of a
            // stiff rod between its rows is below it; 1e-8 left a stiff
            // rope on a slope creeping, 1e-6 made the capstan's pull
            // noisier: tests/contact_friction.rs).
            let tie = 1e-7 * radius;
            // (probe, is a local minimum) of the rows kept so far.
            kept.clear();
            for k in 0..n {
                if near[k].is_none() {
                    continue;
                }
                // A minimum is lower than a neighbour by more than `tie`
                // and higher than neither. Along a rod lying flat on a face
                // the probes differ by round-off: rows at every such
                // "minimum" outnumbered the control points (a singular
                // system), and moved from step to step with their friction
                // anchors (a rope below the friction angle crept). There
                // rows follow the spacing alone.
                let (before, after) = (if k > 0 { gap(k - 1) } else { f64::INFINITY }, if k + 1 < n { gap(k + 1) } else { f64::INFINITY });
                let minimum = before >= gap(k) - tie && after >= gap(k) - tie && (before > gap(k) + tie || after > gap(k) + tie);
                let last = kept.last().copied();
                let dist = last.map(|(j, _)| (us[k] - us[j]).abs());
                if dist.is_some_and(|d| d < 0.5 * span) {
                    // The same touching point: a minimum replaces a row
                    // kept only for spacing (a rod rolling over a curved
                    // obstacle brings its deepest point along).
                    if minimum && last.is_some_and(|(j, m)| !m || gap(k) < gap(j)) {
                        kept.pop();
                        kept.push((k, true));
                    }
                    continue;
                }
                if !minimum && dist.is_some_and(|d| d < span) {
                    continue;
                }
                kept.push((k, minimum));
            }
            for &(k, _) in kept.iter() {
                let Some((g, normal)) = near[k] else { continue };
                // The tangent plane at the nearest point, lifted by the radius.
                let lifted = rod.position(us[k])? - normal * g;
                let kind = ConstraintKind::Plane(Plane { u: us[k], origin: lifted.into(), normal: normal.into() });
                out.pairs.push(ContactPair::new([*h, *h], kind)?.with_friction(self.friction)?);
            }
        }
        Ok(())
    }
}
