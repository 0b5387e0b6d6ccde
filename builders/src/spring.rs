//! Particles on a spring (SPEC §9.4, thesis fig. III.17): a helical steel
//! spring hanging from a clamp, its rest shape the helix (rest curvature
//! and twist, Frenet model), with beads threaded on its wire near the top.
//! Released, the beads slide down the coils under gravity, stretch the
//! spring as they go, and leave it at its free end (`BeadLeft` events);
//! the spring then springs back.
//! Axes: y up, the coil's axis vertical through `top` (use gravity
//! (0, −9.81, 0)).
//!
//! The wire starts at `top + (0, 0, R)` and winds down as a right-handed
//! helix: r(s) = top + (R sin φ, c φ, R cos φ), φ = −s/√(R² + c²),
//! c = pitch/2π.
use nalgebra::Vector3;
use std::f64::consts::PI;
use strandkit_core::error::{non_negative, positive, size};
use strandkit_core::{Assembly, Error, FrameModel, Material, Result, RodBuilder, RodOptions, Section};

/// Most beads the spring may carry.
pub const MAX_BEADS: usize = 100_000;

/// Parameters of [`beads_on_spring`] (SI units). `Default` is the thesis'
/// scene (fig. III.17): a 4-turn steel spring of coil radius 30 mm, pitch
/// 20 mm, wire radius 0.5 mm, carrying 4 beads of 10 g — with 61 control
/// points (15 per turn) where the thesis had 31: its compliance is then
/// within 2 % of Castigliano's (30 per turn: 0.2 %), while 7.5 per turn
/// makes it 5–6 % too stiff along the axis and 28–30 % sideways, in either
/// frame model (tests/spring.rs).
#[derive(Clone, Debug, PartialEq)]
pub struct BeadsOnSpring {
    /// Radius of the coil, axis to wire centre (m).
    pub coil_radius: f64,
    /// Rise per turn (m, > 0: right-handed).
    pub pitch: f64,
    /// Number of turns (may be fractional).
    pub turns: f64,
    /// Radius of the wire's circular section (m).
    pub wire_radius: f64,
    /// Wire material: Young's modulus (Pa), Poisson's ratio, density (kg/m³).
    pub young_modulus: f64,
    pub poisson_ratio: f64,
    pub density: f64,
    pub n_beads: usize,
    /// Mass of one bead (kg).
    pub bead_mass: f64,
    /// Radius of a bead along the wire (m): centres stay 2r apart.
    pub bead_radius: f64,
    /// Arc length between neighbouring beads' centres at the start (m, ≥ 2r).
    pub bead_spacing: f64,
    /// Viscous friction of a bead sliding on the wire (N·s/m).
    pub friction: f64,
    /// Top of the coil's axis (m): the clamp is at `top + (0, 0, R)`.
    pub top: [f64; 3],
    /// Control points of the wire.
    pub control_points: usize,
    /// The wire's frame model (default: the rods' default, the
    /// reference-frame model). The wire is curved everywhere, so the
    /// thesis' Frenet model measures its twist as well, and its step is
    /// cheaper (BENCHMARKS §28).
    pub model: FrameModel,
}

impl Default for BeadsOnSpring {
    fn default() -> Self {
        BeadsOnSpring {
            coil_radius: 0.03,
            pitch: 0.02,
            turns: 4.0,
            wire_radius: 5e-4,
            young_modulus: 2e11,
            poisson_ratio: 0.3,
            density: 7800.0,
            n_beads: 4,
            bead_mass: 0.01,
            bead_radius: 0.004,
            bead_spacing: 0.012,
            friction: 0.0,
            top: [0.0; 3],
            control_points: 61,
            model: FrameModel::default(),
        }
    }
}

/// Where things are: the assembly's indices, and the spring's numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct SpringLayout {
    /// Rod index of the spring.
    pub spring: usize,
    /// Constraint indices of the clamp at the top.
    pub clamp: Vec<usize>,
    /// Assembly bead indices, bead[0] lowest.
    pub beads: Vec<usize>,
    /// Rest arc length of each bead's starting place from the clamp (m).
    pub bead_arc_lengths: Vec<f64>,
    /// Length of wire (m).
    pub wire_length: f64,
    /// Helix angle α above the horizontal (rad): tan α = pitch / (2π R).
    pub helix_angle: f64,
    /// The close-coiled spring rate G d⁴ / (8 D³ N) (N/m), the textbook
    /// number (torsion of the wire only; ignores the pitch and the end
    /// load's offset from the axis).
    pub close_coiled_rate: f64,
}

impl BeadsOnSpring {
    pub fn validate(&self) -> Result<()> {
        positive("coil_radius", self.coil_radius)?;
        positive("pitch", self.pitch)?;
        positive("turns", self.turns)?;
        positive("wire_radius", self.wire_radius)?;
        positive("young_modulus", self.young_modulus)?;
        positive("density", self.density)?;
        strandkit_core::error::finite("poisson_ratio", self.poisson_ratio)?;
        if !(self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5) {
            return Err(Error::invalid("poisson_ratio", self.poisson_ratio, "in (−1, 0.5)"));
        }
        size("n_beads", self.n_beads, MAX_BEADS)?;
        positive("bead_mass", self.bead_mass)?;
        positive("bead_radius", self.bead_radius)?;
        non_negative("friction", self.friction)?;
        strandkit_core::constraint::finite3(&self.top, "top")?;
        if self.wire_radius >= self.coil_radius {
            return Err(Error::invalid("wire_radius", self.wire_radius, format!("< coil_radius = {} m", self.coil_radius)));
        }
        if self.pitch < 2.0 * self.wire_radius {
            return Err(Error::invalid("pitch", self.pitch, format!("≥ 2 × wire_radius = {} m (the coils would overlap)", 2.0 * self.wire_radius)));
        }
        if self.turns > 1e4 {
            return Err(Error::invalid("turns", self.turns, "at most 10000"));
        }
        size("control_points", self.control_points, crate::rope::MAX_ROPE_CONTROL_POINTS)?;
        // A cubic spline follows a helix to ~1e-3 of its radius with 6
        // control points per turn; fewer make it another curve.
        let min_cp = ((6.0 * self.turns).ceil() as usize).max(4);
        if self.control_points < min_cp {
            return Err(Error::invalid("control_points", self.control_points, format!("at least {min_cp} (6 per turn)")));
        }
        if self.n_beads > 0 && self.bead_spacing < 2.0 * self.bead_radius {
            return Err(Error::invalid("bead_spacing", self.bead_spacing, format!("≥ 2 × bead_radius = {} m", 2.0 * self.bead_radius)));
        }
        let need = self.n_beads as f64 * self.bead_spacing;
        if self.n_beads > 0 && need >= self.wire_length() {
            let fit = (self.wire_length() / self.bead_spacing).ceil() as usize - 1;
            return Err(Error::invalid("n_beads", self.n_beads, format!("at most {fit} beads {} m apart on {:.4} m of wire", self.bead_spacing, self.wire_length())));
        }
        Ok(())
    }

    /// c = pitch / 2π (m per radian).
    fn rise(&self) -> f64 {
        self.pitch / (2.0 * PI)
    }

    /// Length of wire (m): N √((2πR)² + p²).
    pub fn wire_length(&self) -> f64 {
        self.turns * (2.0 * PI * self.coil_radius).hypot(self.pitch)
    }

    /// The wire's centreline at arc length s from the clamp (m).
    pub fn centreline(&self, s: f64) -> Vector3<f64> {
        let c = self.rise();
        let phi = -s / self.coil_radius.hypot(c);
        Vector3::from(self.top) + Vector3::new(self.coil_radius * phi.sin(), c * phi, self.coil_radius * phi.cos())
    }
}

/// Builds the spring with its beads (see the module doc); returns the
/// assembly and where its parts are. Labels: "spring", "clamp", "bead[i]".
pub fn beads_on_spring(p: &BeadsOnSpring) -> Result<(Assembly, SpringLayout)> {
    p.validate()?;
    let length = p.wire_length();
    let shape = p.clone();
    let rod = RodBuilder::curve(length, move |s| shape.centreline(s))
        .control_points(p.control_points)
        .with_roll(true)
        .section(Section::circle(p.wire_radius)?)
        .material(Material::new("spring wire", p.young_modulus, p.poisson_ratio, p.density)?)
        .options(RodOptions { model: p.model, ..RodOptions::default() })
        .build()?;
    let (u0, _) = rod.domain();
    // The beads start near the top, bead[0] lowest: the top one a spacing
    // below the clamp.
    let arcs: Vec<f64> = (0..p.n_beads).map(|k| (p.n_beads - k) as f64 * p.bead_spacing).collect();
    let us: Vec<f64> = arcs.iter().map(|&s| rod.u_at_rest_arc_length(s)).collect::<Result<_>>()?;
    let mut asm = Assembly::new();
    let r = asm.add_rod(rod, Some("spring"));
    let clamp = asm.clamp(r, u0, Some("clamp"))?;
    let beads = us
        .iter()
        .enumerate()
        .map(|(k, &u)| asm.add_bead(r, u, p.bead_mass, p.friction, p.bead_radius, Some(&format!("bead[{k}]"))))
        .collect();
    let g = p.young_modulus / (2.0 * (1.0 + p.poisson_ratio));
    let (d, dd) = (2.0 * p.wire_radius, 2.0 * p.coil_radius);
    let layout = SpringLayout {
        spring: r,
        clamp,
        beads,
        bead_arc_lengths: arcs,
        wire_length: length,
        helix_angle: p.pitch.atan2(2.0 * PI * p.coil_radius),
        close_coiled_rate: g * d.powi(4) / (8.0 * dd.powi(3) * p.turns),
    };
    Ok((asm, layout))
}
