//! Bead necklace (SPEC §9.4, thesis III.C.5): a string (open or closed)
//! with beads threaded on it — sliding-abscissa particles of finite size
//! that do not pass each other, with viscous friction — hung from two
//! points or, closed, over a peg (a sliding point the string runs
//! through). Knotted beads are held at their abscissa (a string of pearls
//! knotted between them): the funicular polygon of the tests.
//! Axes: y up (use gravity (0, −9.81, 0)).
//!
//! The string starts on a circle in the vertical plane of its supports:
//! the arc of its length hanging below two points (open), the loop through
//! two points, or the loop hanging from the peg; the beads are spread
//! evenly along it (they slide down under gravity from there). Not
//! modelled: a bead meeting the peg or a support (beads pass them).
use crate::curves::CircleArc;
use crate::rope::Rope;
use nalgebra::Vector3;
use strandkit_core::constraint::kinds::{Position, SlidingPoint};
use strandkit_core::error::{non_negative, positive, size};
use strandkit_core::{Assembly, Error, Result};

/// Most beads a necklace may have.
pub const MAX_BEADS: usize = 100_000;

/// How the necklace hangs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Hang {
    /// Closed string over a peg at this point (m): the string runs freely
    /// through it (a frictionless sliding point unless `peg_friction`).
    Peg([f64; 3]),
    /// Held at two points (m): an open string by its ends, a closed one by
    /// two of its material points.
    TwoPoints([f64; 3], [f64; 3]),
}

/// Parameters of [`necklace`] (SI units). `Default` is the thesis' scene
/// (16 control points, fig. III.16) as a 60 cm nylon thread tied into a
/// loop over a peg with 12 glass beads of 2 g, radius 6 mm, low friction.
#[derive(Clone, Debug, PartialEq)]
pub struct Necklace {
    pub n_beads: usize,
    /// Mass of one bead (kg).
    pub bead_mass: f64,
    /// Radius of a bead along the string (m): centres stay 2r apart.
    pub bead_radius: f64,
    /// The string: linear density (kg/m), EA (N), EI (N·m²).
    pub string: Rope,
    /// Rest length of the string (m): that of the spline fitted to the
    /// starting curve of this length (within 1e-5 of it at 16 points).
    pub length: f64,
    pub closed: bool,
    pub hang: Hang,
    /// Viscous friction of a bead on the string (N·s/m).
    pub friction: f64,
    /// Viscous friction of the string running over the peg (N·s/m).
    pub peg_friction: f64,
    /// Beads knotted in place (they do not slide).
    pub knotted: bool,
    /// Control points of the string.
    pub control_points: usize,
}

impl Default for Necklace {
    fn default() -> Self {
        Necklace {
            n_beads: 12,
            bead_mass: 0.002,
            bead_radius: 0.006,
            // 0.5 mm nylon: E ≈ 3 GPa, ρ ≈ 1000 kg/m³.
            string: Rope { linear_density: 2e-4, axial_stiffness: 600.0, bending_stiffness: 9e-6 },
            length: 0.6,
            closed: true,
            hang: Hang::Peg([0.0; 3]),
            friction: 1e-3,
            peg_friction: 0.0,
            knotted: false,
            control_points: 16,
        }
    }
}

/// Where things are: the assembly's indices.
#[derive(Clone, Debug, PartialEq)]
pub struct NecklaceLayout {
    /// Rod index of the string.
    pub string: usize,
    /// Assembly bead indices, in order along the string.
    pub beads: Vec<usize>,
    /// Constraint indices of the peg (one) or the two supports.
    pub supports: Vec<usize>,
    /// Rest arc length of each bead's starting place (m).
    pub bead_arc_lengths: Vec<f64>,
}

impl Necklace {
    pub fn validate(&self) -> Result<()> {
        size("n_beads", self.n_beads, MAX_BEADS)?;
        positive("bead_mass", self.bead_mass)?;
        positive("bead_radius", self.bead_radius)?;
        positive("length", self.length)?;
        non_negative("friction", self.friction)?;
        non_negative("peg_friction", self.peg_friction)?;
        self.string.validate("string")?;
        let min_cp = if self.closed { 6 } else { 4 };
        if self.control_points < min_cp {
            return Err(Error::invalid("control_points", self.control_points, format!("at least {min_cp}")));
        }
        size("control_points", self.control_points, crate::rope::MAX_ROPE_CONTROL_POINTS)?;
        match self.hang {
            Hang::Peg(p) => {
                strandkit_core::constraint::finite3(&p, "peg")?;
                if !self.closed {
                    return Err(Error::invalid(
                        "hang",
                        "peg",
                        "a closed necklace (an open string over a peg is unstable: it slips off with its beads); hang it from two points",
                    ));
                }
            }
            Hang::TwoPoints(a, b) => {
                strandkit_core::constraint::finite3(&a, "first support")?;
                strandkit_core::constraint::finite3(&b, "second support")?;
            }
        }
        Ok(())
    }
}

/// Builds the necklace (see the module doc); returns the assembly and
/// where its parts are.
pub fn necklace(p: &Necklace) -> Result<(Assembly, NecklaceLayout)> {
    p.validate()?;
    let n = p.n_beads;
    let mut asm = Assembly::new();
    let xyz = [true, true, true, false];
    // Shape, and the stretch of string the beads are spread over.
    let (rod, beads_span) = match (p.closed, p.hang) {
        (true, Hang::Peg(top)) => {
            let c = CircleArc::hanging_loop(Vector3::from(top), p.length);
            (p.string.ring("string", p.length, p.control_points, move |s| c.at_arc_length(s))?, (0.0, p.length, true))
        }
        (true, Hang::TwoPoints(a, b)) => {
            let (a, b) = (Vector3::from(a), Vector3::from(b));
            let c = CircleArc::loop_through(a, b, p.length)?;
            let sb = c.long_arc(b);
            (p.string.ring("string", p.length, p.control_points, move |s| c.at_arc_length(s))?, (0.0, sb, false))
        }
        (false, Hang::TwoPoints(a, b)) => {
            let c = CircleArc::hanging(Vector3::from(a), Vector3::from(b), p.length)?;
            (p.string.open_curve("string", p.length, p.control_points, move |s| c.at_arc_length(s))?, (0.0, p.length, false))
        }
        (false, Hang::Peg(_)) => unreachable!("refused by validate"),
    };
    // Beads spread evenly: around the loop (between the peg's two sides)
    // or strictly between the supports.
    let (s0, s1, around) = beads_span;
    let spacing = if around { (s1 - s0) / n.max(1) as f64 } else { (s1 - s0) / (n + 1) as f64 };
    if n > 0 && spacing < 2.0 * p.bead_radius {
        let fit = ((s1 - s0) / (2.0 * p.bead_radius)).floor() as usize - usize::from(!around);
        return Err(Error::invalid(
            "n_beads",
            n,
            format!("at most {fit} beads of radius {} m on {:.4} m of string (centres 2r apart)", p.bead_radius, s1 - s0),
        ));
    }
    let arcs: Vec<f64> = (0..n).map(|k| if around { s0 + (k as f64 + 0.5) * spacing } else { s0 + (k + 1) as f64 * spacing }).collect();
    let us: Vec<f64> = arcs.iter().map(|&s| rod.u_at_rest_arc_length(s)).collect::<Result<_>>()?;
    let (u0, u1) = rod.domain();
    let support_u = match (p.closed, p.hang) {
        (false, _) => vec![u0, u1],
        (true, Hang::TwoPoints(..)) => vec![u0, rod.u_at_rest_arc_length(s1)?],
        (true, Hang::Peg(_)) => vec![u0],
    };
    let r = asm.add_rod(rod, Some("string"));
    let mut supports = Vec::new();
    match p.hang {
        Hang::Peg(top) => {
            asm.constrain(r, SlidingPoint { u: support_u[0], point: top, friction: p.peg_friction }).label("peg");
            supports.push(asm.constraints.len() - 1);
        }
        Hang::TwoPoints(a, b) => {
            for (k, (&u, x)) in support_u.iter().zip([a, b]).enumerate() {
                asm.constrain(r, Position { u, axes: xyz, target: [x[0], x[1], x[2], 0.0] }).label(format!("support[{k}]"));
                supports.push(asm.constraints.len() - 1);
            }
        }
    }
    let mut beads = Vec::with_capacity(n);
    for (k, &u) in us.iter().enumerate() {
        let b = asm.add_bead(r, u, p.bead_mass, p.friction, p.bead_radius, Some(&format!("bead[{k}]")));
        asm.beads[b].fixed = p.knotted;
        beads.push(b);
    }
    Ok((asm, NecklaceLayout { string: r, beads, supports, bead_arc_lengths: arcs }))
}
