//! A cable on clips (SPEC §9.5, thesis III.C.1, algorithms 4–5): a cable
//! laid along a route on a structure (a car door), held by clips — capture
//! spheres that catch the cable passing within their radius and hold it at
//! their centre (a position constraint), and let go when the cable pulls
//! out along their exit axis harder than their resistance
//! (`ClipCaptured` / `ClipReleased` events). Connectors clamp its ends.
//!
//! The cable is straight at rest (a cable off its reel), laid along the
//! route's polyline, and inserted clipped: each clip holds the cable's
//! point nearest its centre (released, a clip catches whatever cable
//! enters its sphere again). A cable is a
//! solid rod of its radius here, without torsion (3 coordinates per
//! control point: position and tangent are held at clamps and clips).
//! Axes: y up (use gravity (0, −9.81, 0)); the default door is the plane
//! z = 0 and clips let go along +z.
use crate::curves::Polyline;
use crate::rope::Rope;
use nalgebra::Vector3;
use strandkit_core::error::{positive, size};
use strandkit_core::{Assembly, Error, Result, Rod};

/// Most clips, and most route points, a cable may have.
pub const MAX_CLIPS: usize = 100_000;
pub const MAX_PATH_POINTS: usize = 1_000_000;

/// Parameters of [`cable_on_clips`] (SI units). `Default` is the thesis'
/// "cable on a door" (table IV.2: 18 control points): a 6 mm cable run
/// 1.9 m across a door from a connector, down and out, held by 4 clips.
#[derive(Clone, Debug, PartialEq)]
pub struct CableOnClips {
    /// The route (m): the cable is laid along this polyline, from its start.
    pub path: Vec<[f64; 3]>,
    /// Clip centres (m), each within `clip_radius` of the laid cable.
    pub clip_positions: Vec<[f64; 3]>,
    /// Capture radius of the clips' spheres (m).
    pub clip_radius: f64,
    /// Exit axis of the clips (pulled along it, the cable comes out).
    pub clip_axis: [f64; 3],
    /// Pull-out force releasing the cable (N).
    pub clip_resistance: f64,
    /// Cable radius (m), Young's modulus (Pa), density (kg/m³).
    pub cable_radius: f64,
    pub young_modulus: f64,
    pub density: f64,
    /// Radius (m) of the bends the route's corners are rounded to.
    pub bend_radius: f64,
    /// Connectors clamping the cable's start / end (position and tangent).
    pub clamp_start: bool,
    pub clamp_end: bool,
    pub control_points: usize,
}

impl Default for CableOnClips {
    fn default() -> Self {
        CableOnClips {
            path: vec![[0.0, 1.0, 0.0], [0.6, 1.0, 0.0], [0.9, 0.7, 0.0], [0.9, 0.2, 0.0], [1.2, 0.0, 0.0]],
            clip_positions: vec![[0.25, 1.0, 0.0], [0.9, 0.55, 0.0], [0.9, 0.35, 0.0], [1.14, 0.04, 0.0]],
            clip_radius: 0.01,
            clip_axis: [0.0, 0.0, 1.0],
            clip_resistance: 20.0,
            cable_radius: 0.003,
            // A PVC-insulated copper cable: EI = 6.4e-3 N·m², 0.057 kg/m.
            young_modulus: 1e8,
            density: 2000.0,
            bend_radius: 0.15,
            clamp_start: true,
            clamp_end: false,
            control_points: 18,
        }
    }
}

/// Where things are in the assembly.
#[derive(Clone, Debug, PartialEq)]
pub struct CableLayout {
    /// Rod index of the cable.
    pub cable: usize,
    /// Assembly clip indices, in the order given.
    pub clips: Vec<usize>,
    /// Constraint indices of the connectors' clamps.
    pub clamps: Vec<usize>,
    /// Abscissa u of the cable point nearest each clip, and its distance (m).
    pub clip_abscissae: Vec<f64>,
    pub clip_distances: Vec<f64>,
    /// Rest length of the cable (m).
    pub length: f64,
}

impl CableOnClips {
    pub fn validate(&self) -> Result<Polyline> {
        size("path", self.path.len(), MAX_PATH_POINTS)?;
        size("clip_positions", self.clip_positions.len(), MAX_CLIPS)?;
        let route = Polyline::new(self.path.iter().map(|&p| Vector3::from(p)).collect(), "path")?;
        for (k, c) in self.clip_positions.iter().enumerate() {
            strandkit_core::constraint::finite3(c, &format!("clip_positions[{k}]"))?;
        }
        positive("clip_radius", self.clip_radius)?;
        positive("bend_radius", self.bend_radius)?;
        strandkit_core::constraint::unit(&self.clip_axis, "clip_axis")?;
        positive("clip_resistance", self.clip_resistance)?;
        check_cable(self.cable_radius, "cable_radius", self.young_modulus, self.density)?;
        size("control_points", self.control_points, crate::rope::MAX_ROPE_CONTROL_POINTS)?;
        Ok(route)
    }
}

/// Radius, Young's modulus and density of a cable, each named in errors.
pub(crate) fn check_cable(radius: f64, what: &str, young_modulus: f64, density: f64) -> Result<()> {
    positive(what, radius)?;
    positive("young_modulus", young_modulus)?;
    positive("density", density).map(|_| ())
}

/// Builds the cable and its clips (see the module doc). Labels: "cable",
/// "clip[k]", "connector[0|1]" (start, end). A clip farther than its
/// capture radius from the laid cable is an error naming it.
pub fn cable_on_clips(p: &CableOnClips) -> Result<(Assembly, CableLayout)> {
    let route = p.validate()?.rounded(p.bend_radius);
    let rope = Rope::solid(p.cable_radius, p.young_modulus, p.density);
    let rod = lay(&rope, "cable", &route, p.control_points)?;
    let length = rod.rest_length();
    let mut clip_abscissae = Vec::with_capacity(p.clip_positions.len());
    let mut clip_distances = Vec::with_capacity(p.clip_positions.len());
    for (k, c) in p.clip_positions.iter().enumerate() {
        let (u, d) = rod.closest_point(&Vector3::from(*c))?;
        if d > p.clip_radius {
            return Err(Error::invalid(
                format!("clip_positions[{k}]"),
                format!("{c:?}"),
                format!("a point within clip_radius = {} m of the cable (it is {d:.4} m from it: the clip would never hold it)", p.clip_radius),
            ));
        }
        clip_abscissae.push(u);
        clip_distances.push(d);
    }
    let (u0, u1) = rod.domain();
    let mut asm = Assembly::new();
    let r = asm.add_rod(rod, Some("cable"));
    let mut clamps = Vec::new();
    for (on, u, label) in [(p.clamp_start, u0, "connector[0]"), (p.clamp_end, u1, "connector[1]")] {
        if on {
            clamps.extend(asm.clamp(r, u, Some(label))?);
        }
    }
    let mut clips = Vec::with_capacity(p.clip_positions.len());
    for (k, (c, &u)) in p.clip_positions.iter().zip(&clip_abscissae).enumerate() {
        let clip = asm.add_clip(*c, p.clip_radius, p.clip_axis, p.clip_resistance, Some(&format!("clip[{k}]")));
        asm.hold_in_clip(clip, r, u)?;
        clips.push(clip);
    }
    Ok((asm, CableLayout { cable: r, clips, clamps, clip_abscissae, clip_distances, length }))
}

/// A cable straight at rest laid along `route` with `n` control points,
/// its rest length that of the laid spline (which cuts the route's bends
/// a little): laid, it is neither stretched nor compressed overall — a
/// compressed cable would spring out of its route at the first step.
pub(crate) fn lay(rope: &Rope, what: &str, route: &Polyline, n: usize) -> Result<Rod> {
    let l = route.length();
    let first = rope.rod(what, l, n, |s| route.at_arc_length(s))?;
    let (a, b) = first.domain();
    let m = 64 * n;
    let mut laid = 0.0;
    let mut prev = first.position(a)?;
    for k in 1..=m {
        let x = first.position(a + (b - a) * k as f64 / m as f64)?;
        laid += (x - prev).norm();
        prev = x;
    }
    rope.rod(what, laid, n, |s| route.at_arc_length(s * l / laid))
}
