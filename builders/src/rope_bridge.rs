//! Rope bridge (SPEC §9.2, thesis III.C.4): two floor ropes and two
//! handrails anchored at both ends, planks held by the floor ropes,
//! verticals between handrails and floor ropes. Axes: x along the span
//! from the first anchors, y up (use gravity (0, −9.81, 0)), z across.
//!
//! The floor ropes' rest length is that of the funicular polygon of the
//! planks' weights with mid-span sag `sag` (nodes on the parabola
//! y = −4d x(S−x)/S² at equal horizontal spacing S/(N+1)), or of the
//! catenary of sag `sag` without planks; the planks sit at the polygon's
//! node arc lengths. A light, stiff rope therefore hangs exactly on that
//! polygon under the planks (the closed form the tests check), and the
//! ropes start on it. Handrails have the floor ropes' length and shape,
//! `handrail_height` higher.
use crate::curves::{Catenary, Polyline};
use crate::rope::Rope;
use nalgebra::Vector3;
use strandkit_core::constraint::kinds::{Position, RelativeDistance, RelativePosition};
use strandkit_core::error::{non_negative, positive, size};
use strandkit_core::force::PointForce;
use strandkit_core::{Assembly, BreakPolicy, Error, Material, Result, RodBuilder, RodHandle, Section};

/// Most planks a bridge may have.
pub const MAX_PLANKS: usize = 10_000;

/// How a plank is modelled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PlankModel {
    /// A stiff wooden rod (4 control points, its own mass and inertia)
    /// pinned to both floor ropes by relative positions: `plank[i]` labels
    /// the rod and its two pins, which break at `plank_break_force`.
    #[default]
    Body,
    /// The thesis' plank: a relative distance between the floor ropes and
    /// its weight m × 9.81 N along −y as two point loads (no inertia).
    Link,
}

/// Parameters of [`rope_bridge`] (SI units). `Default` is a 10 m
/// footbridge: 12 planks of 4 kg, 1 m sag, 1 m wide, handrails 1 m high.
#[derive(Clone, Debug, PartialEq)]
pub struct RopeBridge {
    /// Horizontal distance between the anchors (m).
    pub span: f64,
    pub n_planks: usize,
    /// Mass of one plank (kg).
    pub plank_mass: f64,
    /// Mid-span sag of the floor ropes' design shape (m).
    pub sag: f64,
    /// Distance between the two floor ropes = plank length (m).
    pub width: f64,
    /// Height of the handrails above the floor ropes (m); 0: no handrails.
    pub handrail_height: f64,
    pub rope: Rope,
    /// Plank section along the span × thickness (m).
    pub plank_depth: f64,
    pub plank_thickness: f64,
    /// Young's modulus of the planks (Pa).
    pub plank_young: f64,
    pub plank_model: PlankModel,
    /// Force (N) above which a plank's pin (or link) breaks; None: never.
    pub plank_break_force: Option<f64>,
    /// Control points per rope (None: 4 per plank spacing, at least 8).
    pub rope_control_points: Option<usize>,
}

impl Default for RopeBridge {
    fn default() -> Self {
        RopeBridge {
            span: 10.0,
            n_planks: 12,
            plank_mass: 4.0,
            sag: 1.0,
            width: 1.0,
            handrail_height: 1.0,
            rope: Rope::default(),
            plank_depth: 0.2,
            plank_thickness: 0.03,
            plank_young: 1e10,
            plank_model: PlankModel::Body,
            plank_break_force: None,
            rope_control_points: None,
        }
    }
}

/// Rope order in the assembly and their labels.
pub const ROPES: [&str; 4] = ["floor[0]", "floor[1]", "handrail[0]", "handrail[1]"];

/// Where things are, for experiments: the assembly's rod indices and the
/// planks' abscissae on the floor ropes.
#[derive(Clone, Debug, PartialEq)]
pub struct BridgeLayout {
    /// Rod indices of floor[0], floor[1], handrail[0], handrail[1] (the
    /// handrails are absent when `handrail_height` is 0).
    pub ropes: Vec<usize>,
    /// Rod index of each plank (Body model).
    pub planks: Vec<usize>,
    /// Abscissa of each plank's station on the floor ropes (and handrails).
    pub stations: Vec<f64>,
    /// Horizontal position of each station in the design shape (m).
    pub station_x: Vec<f64>,
}

impl RopeBridge {
    pub fn validate(&self) -> Result<()> {
        positive("span", self.span)?;
        positive("sag", self.sag)?;
        positive("width", self.width)?;
        non_negative("handrail_height", self.handrail_height)?;
        positive("plank_depth", self.plank_depth)?;
        positive("plank_thickness", self.plank_thickness)?;
        positive("plank_young", self.plank_young)?;
        size("n_planks", self.n_planks, MAX_PLANKS)?;
        if self.n_planks > 0 {
            positive("plank_mass", self.plank_mass)?;
        }
        if let Some(f) = self.plank_break_force {
            positive("plank_break_force", f)?;
        }
        self.rope.validate("rope")?;
        if self.sag > 10.0 * self.span {
            return Err(Error::invalid("sag", self.sag, format!("at most 10 spans ({})", 10.0 * self.span)));
        }
        // Planks side by side must fit along the span.
        let spacing = self.span / (self.n_planks + 1) as f64;
        if self.n_planks > 0 && self.plank_depth > spacing {
            return Err(Error::invalid(
                "n_planks",
                self.n_planks,
                format!("at most {} planks of depth {} m on a span of {} m", (self.span / self.plank_depth).floor() as usize - 1, self.plank_depth, self.span),
            ));
        }
        Ok(())
    }
}

/// Builds the bridge (see the module doc); returns the assembly and where
/// its parts are.
pub fn rope_bridge(p: &RopeBridge) -> Result<(Assembly, BridgeLayout)> {
    p.validate()?;
    let n = p.n_planks;
    // Design shape and rest length.
    let (length, shape): (f64, Box<dyn Fn(f64) -> Vector3<f64>>) = if n == 0 {
        let c = Catenary::with_sag(p.span, p.sag)?;
        (c.length(), Box::new(move |s| c.at_arc_length(s)))
    } else {
        let c = Polyline::funicular(p.span, p.sag, n);
        let c2 = c.clone();
        (c.length(), Box::new(move |s| c2.at_arc_length(s)))
    };
    let stations_at: Vec<f64> = if n == 0 { Vec::new() } else { Polyline::funicular(p.span, p.sag, n).at[1..=n].to_vec() };
    let station_x: Vec<f64> = (1..=n).map(|k| k as f64 * p.span / (n + 1) as f64).collect();
    let ncp = p.rope_control_points.unwrap_or(((n + 1) * 4).max(8));
    let mut asm = Assembly::new();
    let mut ropes = Vec::new();
    let levels: &[(f64, f64)] = if p.handrail_height > 0.0 {
        &[(0.0, -0.5), (0.0, 0.5), (1.0, -0.5), (1.0, 0.5)]
    } else {
        &[(0.0, -0.5), (0.0, 0.5)]
    };
    for (k, &(up, side)) in levels.iter().enumerate() {
        let offset = Vector3::new(0.0, up * p.handrail_height, side * p.width);
        let rod = p.rope.rod(ROPES[k], length, ncp, |s| shape(s) + offset)?;
        let (u0, u1) = rod.domain();
        let r = asm.add_rod(rod, Some(ROPES[k]));
        // Anchors at the design end points (where the spline ends are).
        for (e, u) in [u0, u1].into_iter().enumerate() {
            let target = offset + Vector3::new(e as f64 * p.span, 0.0, 0.0);
            asm.constrain(r, Position { u, axes: [true, true, true, false], target: [target.x, target.y, target.z, 0.0] })
                .label(format!("anchor[{k},{e}]"));
        }
        ropes.push(r);
    }
    // Abscissae of the stations (the same on every rope: same rest rod).
    let probe = &asm.rods[ropes[0]].rod;
    let stations: Vec<f64> = stations_at.iter().map(|&s| probe.u_at_rest_arc_length(s)).collect::<Result<_>>()?;
    let g_down = 9.81;
    let mut planks = Vec::new();
    for (i, (&u, &s)) in stations.iter().zip(&stations_at).enumerate() {
        let a = shape(s) + Vector3::new(0.0, 0.0, -0.5 * p.width);
        let b = shape(s) + Vector3::new(0.0, 0.0, 0.5 * p.width);
        let label = format!("plank[{i}]");
        match p.plank_model {
            PlankModel::Body => {
                let volume = p.plank_depth * p.plank_thickness * p.width;
                let wood = Material::new("plank", p.plank_young, 0.3, p.plank_mass / volume)?;
                let rod = RodBuilder::straight(a, b)
                    .control_points(4)
                    .with_roll(false)
                    .section(Section::rectangle(p.plank_depth, p.plank_thickness)?)
                    .material(wood)
                    .build()?;
                let (v0, v1) = rod.domain();
                let pr = asm.add_rod(rod, Some(&label));
                for (side, v) in [(0, v0), (1, v1)] {
                    let c = asm.link(pr, ropes[side], RelativePosition { ua: v, ub: u, axes: [true, true, true, false], offset: [0.0; 4] });
                    c.label(label.clone());
                    if let Some(f) = p.plank_break_force {
                        c.breaks(f, BreakPolicy::Magnitude);
                    }
                }
                planks.push(pr);
            }
            PlankModel::Link => {
                let c = asm.link(ropes[0], ropes[1], RelativeDistance { ua: u, ub: u, distance: p.width });
                c.label(label.clone());
                if let Some(f) = p.plank_break_force {
                    c.breaks(f, BreakPolicy::Magnitude);
                }
                for side in 0..2 {
                    let rod = RodHandle { index: 0, generation: 0 }; // replaced at insertion
                    asm.add_load(ropes[side], PointForce { rod, u, force: [0.0, -0.5 * p.plank_mass * g_down, 0.0] }, Some(&label));
                }
            }
        }
        if p.handrail_height > 0.0 {
            for side in 0..2 {
                asm.link(ropes[2 + side], ropes[side], RelativeDistance { ua: u, ub: u, distance: p.handrail_height })
                    .label(format!("vertical[{i}]"));
            }
        }
    }
    Ok((asm, BridgeLayout { ropes, planks, stations, station_x }))
}
