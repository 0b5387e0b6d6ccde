//! Weft-knit fabrics at the yarn level (SPEC §9.3): jersey, rib, garter,
//! seed or any knit/purl grid, from a loop length, a yarn and its radius.
//!
//! Each yarn is a naturally straight rod (`RodOptions::straight_rest`)
//! wound along the harmonic loop model of [`loop_model`], through points
//! at equal arc length (`control_points_per_loop` per stitch). Nothing
//! ties the loops together: the interlocks are held by yarn–yarn contact,
//! which the world must detect (`World::add_contact_detector` with the
//! yarn's radius; Python `Fabric.world()`), so yarn slides through loops.
//! Edges, each a set of distance links between material points of the
//! yarn as built (a plain jersey unravels from every open edge, and a
//! frictionless one does so under its own curl):
//! - cast-on: neighbouring sinkers of the first course (`caston[i]`, the
//!   chain a cast-on knits its first loops through);
//! - bind-off: neighbouring heads of the last course (`bindoff[i]`, a chain
//!   bind-off, which keeps its loops from running back);
//! - selvedge: the sides are the yarn turning round (one continuous yarn:
//!   each turn's two ends tied, `selvedge[j]`) or yarn ends (one yarn per
//!   course, with a tail of half a wale);
//! - fastened ends: each free yarn end tied to the head of the loop it
//!   begins or ends (`yarn_end[k]`, an end pulled through its loop).
//!
//! The periodic boundary is a tube knitted in the round, one ring per
//! course: no side edges and no yarn ends.
//!
//! The cell boundary is periodic both ways, with no edge at all: one yarn
//! spiralling round a tube, a course per turn, as a circular machine knits
//! (`yarn`), and its image one period up (`image`, the yarn translated by
//! a free vector: [`EqualOffsets`] at every Greville abscissa, each pair
//! against the first). The yarn's end is tied to the image's start in
//! position and tangent (`junction`, `junction_tangent`): the yarn runs on
//! into its image, so the top course's loops are pulled through the
//! image of the first, the image's loops through the top course's, and
//! every contact on the image acts on the yarn one period down. Yarn and
//! image each carry half the yarn's modulus and density (their energies
//! are equal, a translation: together they count the yarn once; an image
//! without energy left a zero pivot). The period along the wale is the
//! equilibrium's, as the circumference is along the course. Contact must
//! skip the image's own pairs (the yarn's repeated) and pairs near the
//! junction (`FabricLayout::image`; Python `Fabric.world()` does both).
pub mod loop_model;
pub mod pattern;
pub mod yarn;

pub use loop_model::LoopModel;
pub use pattern::{Pattern, Stitch, StitchGrid, MAX_STITCHES};
pub use yarn::Yarn;

use nalgebra::Vector3;
use std::f64::consts::{PI, TAU};
use strandkit_core::constraint::kinds::{EqualOffsets, Position, RelativeDistance, RelativeOrientation, RelativePosition};
use strandkit_core::error::{positive, size};
use strandkit_core::rod::RodShape;
use strandkit_core::spline::KnotKind;
use strandkit_core::{Assembly, Error, Material, Result, Rod, RodBuilder, RodOptions};

/// Longest loop (m): a metre of yarn per stitch is no fabric.
pub const MAX_LOOP_LENGTH: f64 = 1.0;

/// Most control points a fabric may have in all.
pub const MAX_CONTROL_POINTS: usize = 4_000_000;

/// Smallest clearance (centreline distance over the yarn diameter) the
/// initial path must have. Below 1 the yarns start inside each other: by
/// at most a tenth of a diameter, where a seed stitch's sinker turns from
/// front to back between neighbours (the loop model's seed reaches 0.91
/// at ℓ = 50 r), which the first contact solve pushes apart.
pub const MIN_CLEARANCE: f64 = 0.9;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Boundary {
    /// A flat swatch with free edges.
    Free,
    /// A tube knitted in the round (periodic along the course).
    Periodic,
    /// A cell periodic along the course and the wale: one yarn spiralling
    /// round a tube and its image one period up (see the module doc).
    Cell,
    /// A flat swatch with its cast-on sinkers and bound-off heads held
    /// where they are built (`bottom_edge[i]`, `top_edge[i]`).
    ClampedEdges,
}

impl Boundary {
    pub fn from_name(name: &str) -> Result<Boundary> {
        Ok(match name {
            "free" => Boundary::Free,
            "periodic" => Boundary::Periodic,
            "cell" => Boundary::Cell,
            "clamped_edges" => Boundary::ClampedEdges,
            _ => return Err(Error::invalid("boundary", name, "\"free\", \"periodic\", \"cell\" or \"clamped_edges\"")),
        })
    }
}

/// Parameters of [`fabric`] (SI units).
#[derive(Clone, Debug, PartialEq)]
pub struct Fabric {
    pub grid: StitchGrid,
    /// Yarn length per stitch ℓ (m).
    pub loop_length: f64,
    pub yarn: Yarn,
    /// One yarn for the whole swatch (true) or one per course.
    pub continuous: bool,
    pub boundary: Boundary,
    /// Initial (wale spacing, course spacing) in m; None: the loop model's
    /// default proportions (w : c = 4 : 3) scaled to the loop length.
    pub spacing: Option<[f64; 2]>,
    pub control_points_per_loop: usize,
    /// Bind off the last course (links between neighbouring heads).
    pub bind_off: bool,
    /// Tie the first course's neighbouring sinkers (a cast-on chain).
    pub cast_on: bool,
    /// Tie each side turn's two ends (one continuous yarn).
    pub selvedge: bool,
    /// Tie each free yarn end to the head of its loop.
    pub fasten_ends: bool,
}

impl Default for Fabric {
    /// A 10 × 10 plain jersey of 0.1 mm-radius nylon monofilament, loop length 5 mm.
    fn default() -> Self {
        Fabric {
            grid: StitchGrid::new(Pattern::Jersey, 10, 10).expect("a 10 × 10 grid is valid"),
            loop_length: 5e-3,
            yarn: Yarn::preset("nylon", 1e-4).expect("a preset yarn is valid"),
            continuous: true,
            boundary: Boundary::Free,
            spacing: None,
            control_points_per_loop: 12,
            bind_off: true,
            cast_on: true,
            selvedge: true,
            fasten_ends: true,
        }
    }
}

/// Where loop (i, j) lies on its yarn: abscissae of its start (the sinker
/// before it), its head and its end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoopSpan {
    pub wale: usize,
    pub course: usize,
    /// Index in `FabricLayout::yarns` (= the assembly's rod index).
    pub rod: usize,
    pub u_start: f64,
    pub u_head: f64,
    pub u_end: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct FabricLayout {
    /// Assembly rod index of each yarn (one, or one per course).
    pub yarns: Vec<usize>,
    /// Loop (i, j) at j·wales + i.
    pub loops: Vec<LoopSpan>,
    /// The initial geometry.
    pub model: LoopModel,
    /// Mean yarn length per stitch of the built yarns (m, within 1e-4 of
    /// the one asked for; single loops differ by a few %, up to ±11 % in
    /// seed with one yarn per course).
    pub loop_length: f64,
    /// Smallest centreline distance over 2r along the loop model's path
    /// (≥ MIN_CLEARANCE; the spline through it may cut corners by ~0.1).
    pub clearance: f64,
    /// Constraint indices of the bind-off links.
    pub bind_off: Vec<usize>,
    /// Constraint indices of the cast-on links (first course's sinkers).
    pub cast_on: Vec<usize>,
    /// Constraint indices of the selvedge links (each side turn's ends).
    pub selvedge: Vec<usize>,
    /// Constraint indices of the yarn-end links (an end to its loop's head).
    pub yarn_ends: Vec<usize>,
    /// Constraint indices of the edge clamps (ClampedEdges).
    pub clamps: Vec<usize>,
    /// Tube radius (m) for the periodic and cell boundaries, else 0.
    pub tube_radius: f64,
    /// Cell: the image's rod index, and the constraint indices of its
    /// ties (`image_tie[k]`) and of the junction (position, tangent).
    pub image: Option<usize>,
    pub image_ties: Vec<usize>,
    pub junction: Vec<usize>,
}

impl Fabric {
    pub fn validate(&self) -> Result<()> {
        positive("loop_length", self.loop_length)?;
        if self.loop_length > MAX_LOOP_LENGTH {
            return Err(Error::invalid("loop_length", self.loop_length, format!("at most {MAX_LOOP_LENGTH} m")));
        }
        self.yarn.validate()?;
        if self.control_points_per_loop < 4 {
            return Err(Error::invalid("control_points_per_loop", self.control_points_per_loop, "at least 4"));
        }
        let stitches = self.grid.wales() * self.grid.courses();
        size("control points (stitches × control_points_per_loop)", stitches.saturating_mul(self.control_points_per_loop), MAX_CONTROL_POINTS)?;
        if let Some([w, c]) = self.spacing {
            positive("wale spacing", w)?;
            positive("course spacing", c)?;
        }
        let periodic = self.boundary == Boundary::Periodic;
        if periodic && self.continuous {
            return Err(Error::invalid("continuous", true, "false with the periodic boundary (the tube is built one ring per course)"));
        }
        if self.boundary == Boundary::Cell && !self.continuous {
            return Err(Error::invalid("continuous", false, "true with the cell boundary (one yarn spirals round the tube)"));
        }
        if self.periodic() && self.grid.wales() < 3 {
            return Err(Error::invalid("wales", self.grid.wales(), "at least 3 for a tube"));
        }
        // A loop's yarn must at least go round the yarn it holds: four
        // crossings of depth 2r each, far below any loop that knits.
        if self.loop_length < 16.0 * self.yarn.radius {
            return Err(Error::invalid(
                "loop_length",
                self.loop_length,
                format!("at least 16 yarn radii ({:.4e} m) for a yarn of radius {:.4e} m", 16.0 * self.yarn.radius, self.yarn.radius),
            ));
        }
        Ok(())
    }

    /// Wrapped round a tube (periodic and cell boundaries).
    fn periodic(&self) -> bool {
        matches!(self.boundary, Boundary::Periodic | Boundary::Cell)
    }

    /// The loop model with the requested loop length: the default
    /// proportions scaled, or the given spacings with the loop height solved.
    pub fn loop_model(&self) -> Result<LoopModel> {
        self.loop_model_for(self.loop_length)
    }

    /// The loop model whose path has mean stitch length `l` (m).
    fn loop_model_for(&self, l: f64) -> Result<LoopModel> {
        let depth = 1.5 * self.yarn.radius;
        let length = |m: &LoopModel| m.mean_loop_length(&self.grid, self.periodic());
        let (model, lo, hi): (Box<dyn Fn(f64) -> LoopModel>, f64, f64) = match self.spacing {
            // w = 12 k, c = 9 k, h = 0.9 c, a = w/4 (clearance ≈ 1.26 at
            // k = r, ℓ ≈ 48 r); scaling k moves ℓ monotonically.
            None => (
                Box::new(move |k| LoopModel { wale_spacing: 12.0 * k, course_spacing: 9.0 * k, loop_height: 8.1 * k, overhang: 3.0 * k, depth }),
                1e-3 * l,
                l,
            ),
            Some([w, c]) => (
                Box::new(move |h| LoopModel { wale_spacing: w, course_spacing: c, loop_height: h, overhang: 0.25 * w, depth }),
                0.5 * c,
                10.0 * (c + l),
            ),
        };
        if length(&model(lo)) > l || length(&model(hi)) < l {
            return Err(Error::invalid(
                "loop_length",
                l,
                format!("a length the loop model reaches with these spacings (from {:.4e} to {:.4e} m)", length(&model(lo)), length(&model(hi))),
            ));
        }
        let (mut a, mut b) = (lo, hi);
        for _ in 0..60 {
            let m = 0.5 * (a + b);
            if length(&model(m)) < l {
                a = m
            } else {
                b = m
            }
        }
        Ok(model(0.5 * (a + b)))
    }
}

/// A dense polyline of one yarn with the arc-length marks of its loops.
struct Path {
    points: Vec<Vector3<f64>>,
    /// Per loop on this yarn: (i, j, index of start, head, end) in `points`.
    loops: Vec<(usize, usize, usize, usize, usize)>,
}

/// Samples per stitch of the dense path.
const DENSE: usize = 64;
/// Loop end index of a ring's last loop: the closing point.
const WRAP: usize = usize::MAX;

impl Path {
    fn new() -> Path {
        Path { points: Vec::new(), loops: Vec::new() }
    }
    fn push(&mut self, p: Vector3<f64>) {
        if self.points.last().is_none_or(|q| (q - p).norm() > 0.0) {
            self.points.push(p);
        }
    }
    /// Appends course j, left to right or (reversed) right to left. The
    /// cell's spiral rises a course spacing per turn and runs on into the
    /// next course (its last loop ends at the next course's first point).
    fn course(&mut self, f: &Fabric, m: &LoopModel, j: usize, reversed: bool) {
        let nw = f.grid.wales();
        let n = DENSE * nw;
        let periodic = f.periodic();
        let (ring, spiral) = (f.boundary == Boundary::Periodic, f.boundary == Boundary::Cell);
        let last = if periodic { n - 1 } else { n };
        let base = self.points.len();
        debug_assert!(!(periodic && reversed), "rings run forwards");
        for k in 0..=last {
            let k = if reversed { n - k } else { k };
            let rise = if spiral { m.course_spacing * k as f64 / n as f64 } else { 0.0 };
            self.points.push(m.point(&f.grid, periodic, j, TAU * k as f64 / DENSE as f64) + Vector3::y() * rise);
        }
        for i in 0..nw {
            let at = |k: usize| if reversed { base + n - k } else { base + k };
            // A ring's last loop ends where the ring closes (WRAP).
            let end = if ring && i + 1 == nw { WRAP } else { at((i + 1) * DENSE) };
            let (s, e) = if reversed { (end, at(i * DENSE)) } else { (at(i * DENSE), end) };
            self.loops.push((i, j, s, at(i * DENSE + DENSE / 2), e));
        }
    }
    fn straight(&mut self, to: Vector3<f64>, n: usize) {
        let from = *self.points.last().expect("a straight piece continues a path");
        for k in 1..=n {
            self.push(from + (to - from) * (k as f64 / n as f64));
        }
    }
    /// Half turn from the last point to `to` (same x), bulging by `side` (±1) along x.
    fn turn(&mut self, to: Vector3<f64>, side: f64, n: usize) {
        let from = *self.points.last().expect("a turn continues a path");
        let centre = 0.5 * (from + to);
        let rho = 0.5 * (to.y - from.y);
        for k in 1..n {
            let th = PI * k as f64 / n as f64;
            let z = from.z + (to.z - from.z) * k as f64 / n as f64;
            self.push(Vector3::new(centre.x + side * rho * th.sin(), centre.y - rho * th.cos(), z));
        }
    }
    fn arc_lengths(&self) -> Vec<f64> {
        let mut s = vec![0.0; self.points.len()];
        for k in 1..self.points.len() {
            s[k] = s[k - 1] + (self.points[k] - self.points[k - 1]).norm();
        }
        s
    }
}

/// Builds the fabric (see the module doc).
pub fn fabric(f: &Fabric) -> Result<(Assembly, FabricLayout)> {
    f.validate()?;
    let periodic = f.periodic();
    // The spline through the path cuts its corners a little: solve the
    // model for a target corrected by the built loops' mean length until
    // they match (two corrections bring it within 1e-4).
    let l = f.loop_length;
    let mut model = f.loop_model_for(l)?;
    // Refuse a fabric too tight for its yarn before building anything.
    check_clearance(f, &model)?;
    let mut built = build_yarns(f, &model, None)?;
    let counts: Vec<usize> = built.0.iter().map(|r| r.n_ctrl()).collect();
    // (target, built mean) of the previous try, for a secant step.
    let mut last: Option<(f64, f64)> = None;
    let mut target = l;
    let mut mean = mean_loop(&built.0, &built.1)?;
    for _ in 0..8 {
        if (mean - l).abs() <= 1e-4 * l {
            break;
        }
        let next = match last {
            Some((t0, m0)) if (mean - m0).abs() > 0.0 => target + (l - mean) * (target - t0) / (mean - m0),
            _ => target * l / mean,
        };
        // A step the model cannot take ends the search (checked below).
        let Ok(m) = f.loop_model_for(next) else { break };
        last = Some((target, mean));
        (target, model) = (next, m);
        built = build_yarns(f, &model, Some(&counts))?;
        mean = mean_loop(&built.0, &built.1)?;
    }
    if (mean - l).abs() > 1e-3 * l {
        return Err(Error::invalid(
            "loop_length",
            l,
            format!("a length the built yarn can match (its loops came to {mean:.6e} m on average; try more control_points_per_loop)"),
        ));
    }
    let (rods, loops) = built;
    let clearance = check_clearance(f, &model)?;
    let loop_length = mean_loop(&rods, &loops)?;
    let (nw, nc) = (f.grid.wales(), f.grid.courses());
    let mut asm = Assembly::new();
    let mut yarns = Vec::new();
    for (y, rod) in rods.into_iter().enumerate() {
        let label = if f.continuous { "yarn".to_string() } else { format!("course[{y}]") };
        yarns.push(asm.add_rod(rod, Some(&label)));
    }
    let (mut bind_off, mut cast_on, mut selvedge, mut yarn_ends) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let clamped = f.boundary == Boundary::ClampedEdges;
    let cell = f.boundary == Boundary::Cell;
    // Clamped edges hold the first course's sinkers and the last course's
    // heads already (links between held points would repeat the clamps).
    if f.bind_off && !clamped && !cell {
        let top = &loops[(nc - 1) * nw..];
        let pairs = if periodic { nw } else { nw - 1 };
        for i in 0..pairs {
            let (a, b) = (&top[i], &top[(i + 1) % nw]);
            bind_off.push(tie(&mut asm, (a.rod, a.u_head), (b.rod, b.u_head), format!("bindoff[{i}]"))?);
        }
    }
    if f.cast_on && !clamped && !cell {
        // The sinkers before each loop of the first course (it runs left to
        // right), and after the last one on a flat swatch.
        let mut sinkers: Vec<(usize, f64)> = loops[..nw].iter().map(|l| (l.rod, l.u_start)).collect();
        if !periodic {
            sinkers.push((loops[nw - 1].rod, loops[nw - 1].u_end));
        }
        // nw links either way: a ring closes on its first sinker.
        for i in 0..nw {
            cast_on.push(tie(&mut asm, sinkers[i], sinkers[(i + 1) % sinkers.len()], format!("caston[{i}]"))?);
        }
    }
    if f.selvedge && f.continuous && !cell {
        // Course j ends and course j + 1 starts on the same side: right
        // after an even course, left after an odd one.
        for j in 0..nc - 1 {
            let i = if j % 2 == 0 { nw - 1 } else { 0 };
            let (a, b) = (&loops[j * nw + i], &loops[(j + 1) * nw + i]);
            selvedge.push(tie(&mut asm, (a.rod, a.u_end), (b.rod, b.u_start), format!("selvedge[{j}]"))?);
        }
    }
    if f.fasten_ends && !periodic {
        // Each yarn's first and last loops along it (a reversed course
        // runs right to left).
        for &y in &yarns {
            let on: Vec<&LoopSpan> = loops.iter().filter(|l| l.rod == y).collect();
            let first = on.iter().min_by(|a, b| a.u_start.total_cmp(&b.u_start)).expect("every yarn carries loops");
            let last = on.iter().max_by(|a, b| a.u_end.total_cmp(&b.u_end)).expect("every yarn carries loops");
            let (u0, u1) = asm_rod(&asm, y).domain();
            let k = yarn_ends.len();
            yarn_ends.push(tie(&mut asm, (y, u0), (y, first.u_head), format!("yarn_end[{k}]"))?);
            yarn_ends.push(tie(&mut asm, (y, u1), (y, last.u_head), format!("yarn_end[{}]", k + 1))?);
        }
    }
    let mut clamps = Vec::new();
    if clamped {
        let mut hold = |asm: &mut Assembly, rod: usize, u: f64, label: String| -> Result<()> {
            let target = asm_rod(asm, rod).position(u)?;
            asm.constrain(rod, Position { u, target: [target.x, target.y, target.z, 0.0], axes: [true, true, true, false] }).label(label);
            clamps.push(asm.constraints.len() - 1);
            Ok(())
        };
        for (i, l) in loops[..nw].iter().enumerate() {
            hold(&mut asm, l.rod, l.u_start, format!("bottom_edge[{i}]"))?;
        }
        let last = &loops[nw - 1];
        hold(&mut asm, last.rod, last.u_end, format!("bottom_edge[{nw}]"))?;
        for (i, l) in loops[(nc - 1) * nw..].iter().enumerate() {
            hold(&mut asm, l.rod, l.u_head, format!("top_edge[{i}]"))?;
        }
    }
    let tube_radius = if periodic { model.tube_radius(&f.grid) } else { 0.0 };
    let (mut image, mut image_ties, mut junction) = (None, Vec::new(), Vec::new());
    if cell {
        let (rod, ties, join) = add_image(&mut asm, yarns[0], nc as f64 * model.course_spacing)?;
        (image, image_ties, junction) = (Some(rod), ties, join);
    }
    Ok((asm, FabricLayout { yarns, loops, model, loop_length, clearance, bind_off, cast_on, selvedge, yarn_ends, clamps, tube_radius, image, image_ties, junction }))
}

/// The cell's image: the yarn moved `period` (m) along the wale (y), tied
/// to it at each Greville abscissa, every pair against the first (ties
/// chained pair to pair failed: one in the middle of a long rod held only
/// to 3e-6 of its terms, see [`EqualOffsets`]). Collocation at the Greville abscissae of a
/// clamped B-spline is invertible (Schoenberg–Whitney), so the ties make
/// the image's control points the yarn's plus one common vector. The
/// yarn's end is tied to the image's start in position and tangent. Yarn
/// and image each get half the yarn's modulus and density. Returns the
/// image's rod index, the ties' and the junction's constraint indices.
fn add_image(asm: &mut Assembly, yarn: usize, period: f64) -> Result<(usize, Vec<usize>, Vec<usize>)> {
    let rod = asm_rod(asm, yarn);
    let dofs = rod.dofs();
    let m = rod.material();
    let half = Material { young: 0.5 * m.young, density: 0.5 * m.density, ..m.clone() };
    let rebuilt = |q: Vec<f64>| Rod::new(rod.knots().clone(), dofs, q, rod.sections().to_vec(), half.clone(), rod.options().clone());
    let mut q = rod.coords().to_vec();
    let halved = rebuilt(q.clone())?;
    q.iter_mut().skip(1).step_by(dofs).for_each(|y| *y += period);
    let image = rebuilt(q)?;
    let at = rod.knots().greville();
    let (u0, u1) = rod.domain();
    asm.rods[yarn].rod = halved;
    let img = asm.add_rod(image, Some("image"));
    let mut ties = Vec::with_capacity(at.len() - 1);
    for (k, &u) in at.iter().enumerate().skip(1) {
        asm.link(yarn, img, EqualOffsets { ua: u, ub: u, va: at[0], vb: at[0] }).label(format!("image_tie[{}]", k - 1));
        ties.push(asm.constraints.len() - 1);
    }
    asm.link(yarn, img, RelativePosition { ua: u1, ub: u0, axes: [true, true, true, false], offset: [0.0; 4] }).label("junction".to_string());
    asm.link(yarn, img, RelativeOrientation { ua: u1, ub: u0, roll: false }).label("junction_tangent".to_string());
    let n = asm.constraints.len();
    Ok((img, ties, vec![n - 2, n - 1]))
}


/// The yarns along the loop model's path and where their loops lie.
fn build_yarns(f: &Fabric, model: &LoopModel, counts: Option<&[usize]>) -> Result<(Vec<Rod>, Vec<LoopSpan>)> {
    // Closed rods: the tube's rings (the cell's spiral is open).
    let periodic = f.boundary == Boundary::Periodic;
    let (nw, nc) = (f.grid.wales(), f.grid.courses());
    let mut paths = Vec::new();
    if f.boundary == Boundary::Cell {
        let mut p = Path::new();
        for j in 0..nc {
            p.course(f, model, j, false);
        }
        // The last loop's end: the first point one period up.
        p.points.push(model.point(&f.grid, true, 0, 0.0) + Vector3::y() * (nc as f64 * model.course_spacing));
        paths.push(p);
    } else if f.continuous {
        let mut p = Path::new();
        for j in 0..nc {
            let reversed = j % 2 == 1;
            if j > 0 {
                let start = model.point(&f.grid, false, j, if reversed { TAU * nw as f64 } else { 0.0 });
                p.turn(start, if reversed { 1.0 } else { -1.0 }, DENSE / 2);
            }
            p.course(f, model, j, reversed);
        }
        paths.push(p);
    } else {
        for j in 0..nc {
            let mut p = Path::new();
            if periodic {
                p.course(f, model, j, false);
            } else {
                // A tail of half a wale before and after the course.
                let first = model.point(&f.grid, false, j, 0.0);
                p.push(first - Vector3::new(0.5 * model.wale_spacing, 0.0, 0.0));
                p.straight(first, DENSE / 4);
                p.points.pop();
                p.course(f, model, j, false);
                let end = *p.points.last().expect("a course has points");
                p.straight(end + Vector3::new(0.5 * model.wale_spacing, 0.0, 0.0), DENSE / 4);
            }
            paths.push(p);
        }
    }
    let opts = RodOptions { straight_rest: true, ..RodOptions::default() };
    let mut rods = Vec::new();
    let mut loops = vec![None; nw * nc];
    for (y, p) in paths.iter().enumerate() {
        let s = p.arc_lengths();
        let total = *s.last().expect("a path has points") + if periodic { (p.points[0] - p.points[p.points.len() - 1]).norm() } else { 0.0 };
        let spacing = f.loop_length / f.control_points_per_loop as f64;
        // Kept across the length iterations, so the built length varies smoothly.
        let n = counts.map_or_else(|| ((total / spacing).round() as usize).max(if periodic { 6 } else { 4 }), |c| c[y]);
        let pts = resample(&p.points, &s, total, n, periodic);
        let rod = RodBuilder::new(RodShape::ThroughPoints(pts))
            .knots(if periodic { KnotKind::Periodic } else { KnotKind::Clamped })
            .with_roll(false)
            .section(f.yarn.section()?)
            .material(f.yarn.material()?)
            .options(opts.clone())
            .build()?;
        let rod = if f.boundary == Boundary::Cell { run_on(rod)? } else { rod };
        let scale = rod.rest_length() / total;
        let u_at = |k: usize| rod.u_at_rest_arc_length((s[k] * scale).min(rod.rest_length()));
        for &(i, j, a, h, e) in &p.loops {
            let u_end = if e == WRAP { rod.domain().1 } else { u_at(e)? };
            loops[j * nw + i] = Some(LoopSpan { wale: i, course: j, rod: y, u_start: u_at(a)?, u_head: u_at(h)?, u_end });
        }
        rods.push(rod);
    }
    Ok((rods, loops.into_iter().map(|l| l.expect("every stitch lies on a yarn")).collect()))
}

/// The cell's yarn with its end tangent the image's start tangent: the
/// interpolating spline's end legs (P1 − P0 and P_n−1 − P_n−2, which set
/// the end tangents of a clamped cubic) both made their mean. As
/// interpolated they were 0.35 rad apart (8 × 3 jersey), which the
/// junction's tangent tie would have had to close in the first step.
fn run_on(rod: Rod) -> Result<Rod> {
    let (n, dofs) = (rod.n_ctrl(), rod.dofs());
    let mut q = rod.coords().to_vec();
    let p = |q: &[f64], k: usize| Vector3::new(q[k * dofs], q[k * dofs + 1], q[k * dofs + 2]);
    let leg = 0.5 * ((p(&q, 1) - p(&q, 0)) + (p(&q, n - 1) - p(&q, n - 2)));
    let (first, last) = (p(&q, 0) + leg, p(&q, n - 1) - leg);
    q[dofs..dofs + 3].copy_from_slice(first.as_slice());
    q[(n - 2) * dofs..(n - 2) * dofs + 3].copy_from_slice(last.as_slice());
    Rod::new(rod.knots().clone(), dofs, q, rod.sections().to_vec(), rod.material().clone(), rod.options().clone())
}

/// The model's clearance, or an error if the yarns would overlap.
fn check_clearance(f: &Fabric, model: &LoopModel) -> Result<f64> {
    let clearance = model.clearance(&f.grid, f.periodic(), f.yarn.radius);
    if clearance < MIN_CLEARANCE {
        return Err(Error::invalid(
            "loop_length",
            f.loop_length,
            format!(
                "a longer loop (or looser spacings): yarns of radius {:.4e} m would overlap in the initial loop model (clearance {clearance:.3} < {MIN_CLEARANCE})",
                f.yarn.radius
            ),
        ));
    }
    Ok(clearance)
}

/// Mean rest arc length of the loops (m).
fn mean_loop(rods: &[Rod], loops: &[LoopSpan]) -> Result<f64> {
    Ok(loops.iter().map(|l| loop_arc(&rods[l.rod], l)).sum::<Result<f64>>()? / loops.len() as f64)
}

/// Rest arc length of a loop (m).
fn loop_arc(rod: &Rod, l: &LoopSpan) -> Result<f64> {
    Ok(rod.rest_arc_length(l.u_end)? - rod.rest_arc_length(l.u_start)?)
}

/// A distance link between two material points (rod, u) at their distance
/// as built; returns its constraint index.
fn tie(asm: &mut Assembly, (ra, ua): (usize, f64), (rb, ub): (usize, f64), label: String) -> Result<usize> {
    let distance = (asm_rod(asm, ra).position(ua)? - asm_rod(asm, rb).position(ub)?).norm();
    asm.link(ra, rb, RelativeDistance { ua, ub, distance }).label(label);
    Ok(asm.constraints.len() - 1)
}

fn asm_rod(asm: &Assembly, i: usize) -> &Rod {
    &asm.rods[i].rod
}

/// `n` points at equal arc length along the polyline (closed: the last
/// point is not repeated).
fn resample(points: &[Vector3<f64>], s: &[f64], total: f64, n: usize, closed: bool) -> Vec<Vector3<f64>> {
    let m = if closed { n } else { n - 1 };
    let mut out = Vec::with_capacity(n);
    let mut k = 0;
    for q in 0..n {
        let target = total * q as f64 / m as f64;
        while k + 1 < s.len() && s[k + 1] < target {
            k += 1;
        }
        if k + 1 < s.len() {
            let f = ((target - s[k]) / (s[k + 1] - s[k])).clamp(0.0, 1.0);
            out.push(points[k] + (points[k + 1] - points[k]) * f);
        } else {
            // Closing segment of a ring (or the very end).
            let last = points[points.len() - 1];
            let rest = total - s[s.len() - 1];
            let f = if rest > 0.0 { ((target - s[s.len() - 1]) / rest).clamp(0.0, 1.0) } else { 0.0 };
            out.push(last + (points[0] - last) * if closed { f } else { 0.0 });
        }
    }
    out
}

#[cfg(test)]
mod tests;
