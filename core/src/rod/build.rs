//! Building rods (Rapier-style builder): a shape, a discretisation, a
//! section and a material. The shape given is also the rest shape.
use super::{Rod, RodOptions};
use crate::error::{finite, positive, Error, Result};
use crate::material::Material;
use crate::section::Section;
use crate::spline::{self, KnotKind, KnotVector};
use nalgebra::Vector3;

/// The centreline to build (length unit).
pub enum RodShape {
    /// Straight segment from `start` to `end`.
    Straight { start: Vector3<f64>, end: Vector3<f64> },
    /// Circular helix about the z axis starting at (radius, 0, 0): `pitch`
    /// is the rise per turn (> 0 right-handed, < 0 left-handed).
    Helix { radius: f64, pitch: f64, turns: f64 },
    /// Any curve given by arc length: `f(s)` for s in [0, length].
    Curve { length: f64, f: Box<dyn Fn(f64) -> Vector3<f64> + Send + Sync> },
    /// A curve through these points (assumed roughly evenly spaced); one
    /// control point per point.
    ThroughPoints(Vec<Vector3<f64>>),
    /// Explicit control points (x, y, z) on the builder's knot vector.
    ControlPoints(Vec<Vector3<f64>>),
}

pub struct RodBuilder {
    shape: RodShape,
    n_ctrl: usize,
    knot_kind: KnotKind,
    with_roll: bool,
    sections: Vec<Section>,
    material: Option<Material>,
    opts: RodOptions,
    roll: Option<Vec<f64>>,
}

impl RodBuilder {
    pub fn new(shape: RodShape) -> Self {
        RodBuilder {
            shape,
            n_ctrl: 20,
            knot_kind: KnotKind::Clamped,
            with_roll: true,
            sections: Vec::new(),
            material: None,
            opts: RodOptions::default(),
            roll: None,
        }
    }
    pub fn straight(start: Vector3<f64>, end: Vector3<f64>) -> Self {
        Self::new(RodShape::Straight { start, end })
    }
    pub fn helix(radius: f64, pitch: f64, turns: f64) -> Self {
        Self::new(RodShape::Helix { radius, pitch, turns })
    }
    pub fn curve(length: f64, f: impl Fn(f64) -> Vector3<f64> + Send + Sync + 'static) -> Self {
        Self::new(RodShape::Curve { length, f: Box::new(f) })
    }
    /// Number of control points (≥ 4; ignored for point-based shapes).
    pub fn control_points(mut self, n: usize) -> Self {
        self.n_ctrl = n;
        self
    }
    /// Uniform, Clamped (default: the curve ends at the end control points) or Periodic.
    pub fn knots(mut self, kind: KnotKind) -> Self {
        self.knot_kind = kind;
        self
    }
    /// false: 3 coordinates per control point (no roll, no twist energy).
    pub fn with_roll(mut self, on: bool) -> Self {
        self.with_roll = on;
        self
    }
    /// One section for the whole rod.
    pub fn section(mut self, s: Section) -> Self {
        self.sections = vec![s];
        self
    }
    /// One section per control point (radii varying along the rod, II.26).
    pub fn sections(mut self, s: Vec<Section>) -> Self {
        self.sections = s;
        self
    }
    pub fn material(mut self, m: Material) -> Self {
        self.material = Some(m);
        self
    }
    pub fn options(mut self, o: RodOptions) -> Self {
        self.opts = o;
        self
    }
    /// Initial (= rest) roll angle per control point (radians).
    pub fn roll(mut self, theta: Vec<f64>) -> Self {
        self.roll = Some(theta);
        self
    }

    pub fn build(self) -> Result<Rod> {
        let material = self
            .material
            .ok_or_else(|| Error::input("a rod needs a material (RodBuilder::material)"))?;
        if self.sections.is_empty() {
            return Err(Error::input("a rod needs a section (RodBuilder::section)"));
        }
        let n = match &self.shape {
            RodShape::ThroughPoints(p) | RodShape::ControlPoints(p) => p.len(),
            _ => self.n_ctrl,
        };
        let knots = match self.knot_kind {
            KnotKind::Uniform => KnotVector::uniform(n)?,
            KnotKind::Clamped => KnotVector::clamped(n)?,
            KnotKind::Periodic => KnotVector::periodic(n)?,
            KnotKind::General => {
                return Err(Error::input("use Rod::new for a general knot vector"));
            }
        };
        let (ua, ub) = knots.domain();
        let to_s = |u: f64, len: f64| (u - ua) / (ub - ua) * len;
        let pts: Vec<[f64; 3]> = match self.shape {
            RodShape::ControlPoints(p) => p.iter().map(|v| [v.x, v.y, v.z]).collect(),
            RodShape::ThroughPoints(p) => {
                let vals: Vec<[f64; 3]> = p.iter().map(|v| [v.x, v.y, v.z]).collect();
                spline::interpolate(&knots, &spline::default_params(&knots), &vals)?
            }
            RodShape::Straight { start, end } => {
                for (name, v) in [("start", start), ("end", end)] {
                    for x in v.iter() {
                        finite(name, *x)?;
                    }
                }
                if (end - start).norm() == 0.0 {
                    return Err(Error::input("straight rod: start and end coincide"));
                }
                spline::fit(&knots, |u| {
                    let p = start + (end - start) * ((u - ua) / (ub - ua));
                    [p.x, p.y, p.z]
                })?
            }
            RodShape::Helix { radius, pitch, turns } => {
                positive("helix radius", radius)?;
                finite("helix pitch", pitch)?;
                positive("helix turns", turns)?;
                let c = pitch / (2.0 * std::f64::consts::PI);
                let len = 2.0 * std::f64::consts::PI * turns * (radius * radius + c * c).sqrt();
                spline::fit(&knots, |u| {
                    let phi = to_s(u, len) / (radius * radius + c * c).sqrt();
                    [radius * phi.cos(), radius * phi.sin(), c * phi]
                })?
            }
            RodShape::Curve { length, f } => {
                positive("curve length", length)?;
                spline::fit(&knots, |u| {
                    let p = f(to_s(u, length));
                    [p.x, p.y, p.z]
                })?
            }
        };
        let dofs = if self.with_roll { 4 } else { 3 };
        if let Some(r) = &self.roll {
            if !self.with_roll {
                return Err(Error::input("roll angles given, but the rod has no roll coordinate (with_roll(false))"));
            }
            super::check_vec("roll angles", r, n)?;
        }
        let mut q = Vec::with_capacity(n * dofs);
        for (i, p) in pts.iter().enumerate() {
            q.extend_from_slice(p);
            if dofs == 4 {
                q.push(self.roll.as_ref().map_or(0.0, |r| r[i]));
            }
        }
        Rod::new(knots, dofs, q, self.sections, material, self.opts)
    }
}
