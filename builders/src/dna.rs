//! B-DNA duplex from a sequence (SPEC §9.1, thesis III.C.3), in molecular
//! units: nm, pN, ns, ag (= pN·ns²/nm), K.
//!
//! Two backbone strands, each a rod through its nucleotides (one control
//! point per nucleotide, interpolated: the nucleotides lie exactly on the
//! helix), wound as right-handed helices of radius R about the z axis:
//! strand a (chain A, the given sequence) runs 5′→3′ up the axis,
//! nucleotide k at height z_k = k·rise and angle θ_k = 2πk / bp_per_turn;
//! strand b (chain B, its complement) runs 5′→3′ down it, its nucleotide
//! paired with a's k at the same height and at angle θ_k + φ. Strand b is
//! strand a turned by φ about the axis, so along the axis it lies
//! φ/2π of a pitch P below strand a: the groove between b and the a above
//! it spans φP/2π (the minor groove), the other (1 − φ/2π)P. φ comes from
//! the minor groove's share of the pitch — 12/34 by default (phosphate
//! groove widths ≈ 12 and 22 Å: φ ≈ 127°), 2/5 in the thesis (φ = 144°).
//!
//! Per base pair, one hydrogen bond: a distance constraint between the two
//! paired nucleotides (length 2R sin(φ/2)), compliant or rigid, breaking in
//! tension only above its pair's force (A·T weaker than G·C). Per step
//! between consecutive pairs, stacking: a [`BasePairStep`] (six compliant
//! strains of the step, with compliance 1), removed as soon as either of
//! its pairs breaks (`breaks_with`), so that an opened region is two single
//! strands. The strands are as flexible as single-stranded DNA; the
//! duplex's bending, stretch and twist stiffness come from the stacking,
//! set by [`Stacking::of_rod`] from the duplex's [`Elasticity`] at the
//! builder's rise and temperature (the strands add their own share:
//! measured by [`crate::dna_elasticity`]; the calibration is open).
use nalgebra::Vector3;
use std::f64::consts::PI;
use strandkit_core::constraint::kinds::{BasePairStep, RelativeDistance};
use strandkit_core::constraint::BreakPolicy;
use strandkit_core::energy::FrameModel;
use strandkit_core::error::{finite, non_negative, positive, size};
use strandkit_core::{Assembly, Error, Material, Result, Rod, RodBuilder, RodOptions, Section};

/// Longest duplex the builder accepts (base pairs).
pub const MAX_BASE_PAIRS: usize = 200_000;
/// Boltzmann's constant in pN·nm/K.
pub const BOLTZMANN: f64 = 1.380649e-2;

/// A single strand's material (molecular units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Strand {
    /// Stretch modulus EA (pN).
    pub stretch_modulus: f64,
    /// Bending persistence length (nm) at the builder's temperature.
    pub persistence_length: f64,
    /// Mass of one nucleotide (ag; 330 Da = 5.5e-4 ag).
    pub nucleotide_mass: f64,
}

impl Default for Strand {
    /// Single-stranded DNA: 800 pN, 0.75 nm, 330 Da per nucleotide.
    fn default() -> Self {
        Strand { stretch_modulus: 800.0, persistence_length: 0.75, nucleotide_mass: 330.0 * 1.660_539_07e-6 }
    }
}

/// Stiffness of one base-pair step (see [`BasePairStep`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stacking {
    /// Shift, slide, rise (pN/nm).
    pub translation: [f64; 3],
    /// Tilt, roll, twist (pN·nm/rad²).
    pub rotation: [f64; 3],
    /// Rise–twist coupling (pN/rad); < 0 overwinds under tension.
    pub twist_stretch: f64,
}

/// The duplex's elastic constants (what the stacking is calibrated to).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Elasticity {
    /// Bending persistence A (nm): B = A kT.
    pub bending_persistence: f64,
    /// Stretch modulus S (pN).
    pub stretch_modulus: f64,
    /// Twist persistence C/kT (nm).
    pub twist_persistence: f64,
    /// Twist–stretch coupling g (pN·nm); < 0: overwinds when stretched.
    pub twist_stretch: f64,
    /// Shear stiffness of the duplex (pN): resists the pairs sliding over
    /// each other.
    pub shear_modulus: f64,
}

impl Default for Elasticity {
    /// B-DNA (SPEC §9.1): A = 50 nm, S = 1100 pN, C = 100 nm × kT,
    /// g = −90 pN·nm; shear as stiff as stretch.
    fn default() -> Self {
        Elasticity { bending_persistence: 50.0, stretch_modulus: 1100.0, twist_persistence: 100.0, twist_stretch: -90.0, shear_modulus: 1100.0 }
    }
}

impl Stacking {
    /// The step stiffness of a continuous rod with these constants, one
    /// step per `rise` (nm) at temperature `temperature` (K): k_rise = S/h,
    /// k_tilt = k_roll = A kT/h, k_twist = C/h, coupling g/h, shift and
    /// slide G/h.
    pub fn of_rod(e: &Elasticity, rise: f64, temperature: f64) -> Stacking {
        let kt = BOLTZMANN * temperature;
        let (b, c) = (e.bending_persistence * kt, e.twist_persistence * kt);
        Stacking {
            translation: [e.shear_modulus / rise, e.shear_modulus / rise, e.stretch_modulus / rise],
            rotation: [b / rise, b / rise, c / rise],
            twist_stretch: e.twist_stretch / rise,
        }
    }
}

/// Parameters of [`duplex`] (molecular units).
#[derive(Clone, Debug, PartialEq)]
pub struct Duplex {
    /// Strand a, 5′→3′ (A, C, G, T in either case).
    pub sequence: String,
    /// Strand b, 5′→3′ (None: the Watson–Crick complement). Mismatched
    /// pairs get no hydrogen bond and no stacking.
    pub complement: Option<String>,
    pub bp_per_turn: f64,
    /// Rise per base pair (nm).
    pub rise: f64,
    /// Radius of the strands' helices (nm).
    pub radius: f64,
    /// Share of the pitch spanned by the minor groove along the axis.
    pub minor_groove: f64,
    /// Compliance of a hydrogen bond (nm/pN; 0 = rigid).
    pub hbond_compliance: f64,
    /// Break force (pN) of an A·T and of a G·C bond, in tension.
    pub break_force_at: f64,
    pub break_force_gc: f64,
    /// Per-pair break forces (pN; pair k = strand a's nucleotide k),
    /// overriding the two above; `f64::INFINITY` for an unbreakable pair.
    pub break_forces: Option<Vec<f64>>,
    pub strand: Strand,
    /// The duplex's elastic constants the stacking is set for.
    pub elasticity: Elasticity,
    /// Frame model of the strands.
    pub model: FrameModel,
    /// Temperature (K) at which persistence lengths are converted to stiffness.
    pub temperature: f64,
}

impl Duplex {
    /// A duplex of `sequence` with the default B-DNA parameters.
    pub fn new(sequence: &str) -> Duplex {
        Duplex {
            sequence: sequence.to_string(),
            complement: None,
            bp_per_turn: 10.5,
            rise: 0.34,
            radius: 1.0,
            minor_groove: 12.0 / 34.0,
            hbond_compliance: 0.0,
            break_force_at: 9.0,
            break_force_gc: 20.0,
            break_forces: None,
            strand: Strand::default(),
            elasticity: Elasticity::default(),
            model: FrameModel::Reference,
            temperature: 298.15,
        }
    }

    /// The strand phase offset φ (rad).
    pub fn phase(&self) -> f64 {
        2.0 * PI * self.minor_groove
    }
    /// Pitch (nm per turn).
    pub fn pitch(&self) -> f64 {
        self.rise * self.bp_per_turn
    }
    /// Length of a hydrogen bond at rest: the chord 2R sin(φ/2) (nm).
    pub fn rung_length(&self) -> f64 {
        2.0 * self.radius * (0.5 * self.phase()).sin()
    }
    /// Position of strand a's nucleotide k (nm).
    pub fn position_a(&self, k: usize) -> Vector3<f64> {
        let t = 2.0 * PI * k as f64 / self.bp_per_turn;
        Vector3::new(self.radius * t.cos(), self.radius * t.sin(), k as f64 * self.rise)
    }
    /// Position of the strand-b nucleotide paired with a's k (nm).
    pub fn position_b(&self, k: usize) -> Vector3<f64> {
        let t = 2.0 * PI * k as f64 / self.bp_per_turn + self.phase();
        Vector3::new(self.radius * t.cos(), self.radius * t.sin(), k as f64 * self.rise)
    }

    fn validate(&self) -> Result<()> {
        positive("bp_per_turn", self.bp_per_turn)?;
        positive("rise", self.rise)?;
        positive("radius", self.radius)?;
        if !(self.minor_groove > 0.0 && self.minor_groove < 1.0) {
            return Err(Error::invalid("minor_groove", self.minor_groove, "a share of the pitch in (0, 1)"));
        }
        non_negative("hbond_compliance", self.hbond_compliance)?;
        positive("break_force_at", self.break_force_at)?;
        positive("break_force_gc", self.break_force_gc)?;
        positive("strand stretch_modulus", self.strand.stretch_modulus)?;
        positive("strand persistence_length", self.strand.persistence_length)?;
        positive("strand nucleotide_mass", self.strand.nucleotide_mass)?;
        positive("temperature", self.temperature)?;
        let e = &self.elasticity;
        positive("bending_persistence", e.bending_persistence)?;
        positive("stretch_modulus", e.stretch_modulus)?;
        positive("twist_persistence", e.twist_persistence)?;
        positive("shear_modulus", e.shear_modulus)?;
        finite("twist_stretch", e.twist_stretch)?;
        let c = e.twist_persistence * BOLTZMANN * self.temperature;
        if e.twist_stretch.powi(2) >= e.stretch_modulus * c {
            return Err(Error::invalid("twist_stretch", e.twist_stretch, "g² < S·C (a stable duplex)"));
        }
        Ok(())
    }
}

/// The Watson–Crick partner of a base.
pub fn complement_base(b: u8) -> u8 {
    match b {
        b'A' => b'T',
        b'T' => b'A',
        b'G' => b'C',
        _ => b'G',
    }
}

/// A sequence in upper case, checked: A, C, G, T only (either case);
/// anything else is refused with its 1-based position.
pub fn parse_sequence(s: &str, what: &str) -> Result<Vec<u8>> {
    if s.is_empty() {
        return Err(Error::invalid(what, "an empty sequence", "at least 4 bases (A, C, G, T)"));
    }
    size(&format!("{what} length"), s.len(), MAX_BASE_PAIRS)?;
    s.chars()
        .enumerate()
        .map(|(i, c)| match c.to_ascii_uppercase() {
            u @ ('A' | 'C' | 'G' | 'T') => Ok(u as u8),
            _ => Err(Error::invalid(what, format!("{c:?} at position {}", i + 1), "A, C, G or T (either case)")),
        })
        .collect()
}

/// Where the parts of a built duplex are.
#[derive(Clone, Debug, PartialEq)]
pub struct DuplexLayout {
    /// Assembly rod indices of strand a and strand b.
    pub strands: [usize; 2],
    /// Both strands 5′→3′, upper case.
    pub sequences: [String; 2],
    /// Abscissa of each nucleotide on its strand, 5′→3′.
    pub abscissae: [Vec<f64>; 2],
    /// For pair k (strand a's nucleotide k): strand b's nucleotide index.
    pub partner: Vec<usize>,
    /// Constraint index of pair k's hydrogen bond (None: a mismatch).
    pub hbonds: Vec<Option<usize>>,
    /// Constraint index of the stacking between pairs k and k+1.
    pub stacks: Vec<Option<usize>>,
    /// Pairs that are not Watson–Crick (unbonded).
    pub mismatches: Vec<usize>,
    /// Break force of pair k (pN).
    pub break_forces: Vec<f64>,
    pub rung_length: f64,
    pub phase: f64,
    pub pitch: f64,
    /// Groove widths along the axis (nm): minor φP/2π, major P − minor.
    pub grooves: [f64; 2],
}

/// Builds the duplex (see the module documentation).
pub fn duplex(p: &Duplex) -> Result<(Assembly, DuplexLayout)> {
    p.validate()?;
    let a = parse_sequence(&p.sequence, "sequence")?;
    let n = a.len();
    if n < 4 {
        return Err(Error::invalid("sequence", format!("{n} bases"), "at least 4 base pairs (a strand is a cubic spline)"));
    }
    let b: Vec<u8> = match &p.complement {
        Some(c) => {
            let b = parse_sequence(c, "complement")?;
            if b.len() != n {
                return Err(Error::invalid("complement", format!("{} bases", b.len()), format!("{n}, as many as the sequence")));
            }
            b
        }
        None => a.iter().rev().map(|&x| complement_base(x)).collect(),
    };
    let partner: Vec<usize> = (0..n).map(|k| n - 1 - k).collect();
    let mismatches: Vec<usize> = (0..n).filter(|&k| b[partner[k]] != complement_base(a[k])).collect();
    let break_forces: Vec<f64> = match &p.break_forces {
        Some(f) => {
            if f.len() != n {
                return Err(Error::invalid("break_forces", format!("{} values", f.len()), format!("{n}, one per base pair")));
            }
            for v in f {
                if !(*v > 0.0) {
                    return Err(Error::invalid("break_forces", v, "> 0 (pN; inf: unbreakable)"));
                }
            }
            f.clone()
        }
        None => a.iter().map(|&x| if x == b'G' || x == b'C' { p.break_force_gc } else { p.break_force_at }).collect(),
    };

    // Strand material: the circular section and material giving exactly
    // the stretch modulus and the bending stiffness A_ss kT.
    let kt = BOLTZMANN * p.temperature;
    let (ea, ei) = (p.strand.stretch_modulus, p.strand.persistence_length * kt);
    let r = 2.0 * (ei / ea).sqrt();
    let area = PI * r * r;
    let step = (p.position_a(1) - p.position_a(0)).norm(); // chord per nucleotide
    let density = p.strand.nucleotide_mass / step / area;
    let material = Material::new("ssDNA", ea / area, 0.5, density)?;
    let strand = |pts: Vec<Vector3<f64>>| -> Result<Rod> {
        RodBuilder::new(strandkit_core::rod::RodShape::ThroughPoints(pts))
            .with_roll(false)
            .section(Section::circle(r)?)
            .material(material.clone())
            .options(RodOptions { model: p.model, ..Default::default() })
            .build()
    };
    let rod_a = strand((0..n).map(|k| p.position_a(k)).collect())?;
    let rod_b = strand((0..n).map(|j| p.position_b(n - 1 - j)).collect())?;
    let ua = strandkit_core::spline::default_params(rod_a.knots());
    let ub = strandkit_core::spline::default_params(rod_b.knots());

    let mut asm = Assembly::new();
    let sa = asm.add_rod(rod_a.clone(), Some("strand[0]"));
    let sb = asm.add_rod(rod_b.clone(), Some("strand[1]"));
    let rung = p.rung_length();
    let mut hbonds = vec![None; n];
    for k in (0..n).filter(|k| !mismatches.contains(k)) {
        let c = asm.link(sa, sb, RelativeDistance { ua: ua[k], ub: ub[partner[k]], distance: rung });
        c.compliance(p.hbond_compliance).label(format!("hbond[{k}]"));
        if break_forces[k].is_finite() {
            c.breaks(break_forces[k], BreakPolicy::Tension);
        }
        hbonds[k] = Some(asm.constraints.len() - 1);
    }
    let rods = [&rod_a, &rod_b];
    let s = Stacking::of_rod(&p.elasticity, p.rise, p.temperature);
    let mut stacks = vec![None; n - 1];
    for k in 0..n - 1 {
        if hbonds[k].is_none() || hbonds[k + 1].is_none() {
            continue;
        }
        let kind = BasePairStep::at_rest(&rods, [ua[k], ua[k + 1]], [ub[partner[k]], ub[partner[k + 1]]], p.radius * (0.5 * p.phase()).cos(), s.translation, s.rotation, s.twist_stretch)?;
        asm.link(sa, sb, kind).compliance(1.0).label(format!("stack[{k}]")).breaks_with(format!("hbond[{k}]")).breaks_with(format!("hbond[{}]", k + 1));
        stacks[k] = Some(asm.constraints.len() - 1);
    }
    let pitch = p.pitch();
    let minor = p.minor_groove * pitch;
    let layout = DuplexLayout {
        strands: [sa, sb],
        sequences: [String::from_utf8_lossy(&a).into_owned(), String::from_utf8_lossy(&b).into_owned()],
        abscissae: [ua, ub],
        partner,
        hbonds,
        stacks,
        mismatches,
        break_forces,
        rung_length: rung,
        phase: p.phase(),
        pitch,
        grooves: [minor, pitch - minor],
    };
    Ok((asm, layout))
}
