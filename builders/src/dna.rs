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
//! tension only above its pair's force (A·T weaker than G·C). With
//! [`HBond::Position`] also the pair's stagger ([`PairStagger`]: its two
//! nucleotides' offset along the local axis, compliant), so that the bond
//! is a relative position in the pair's own frame, and the stacking reads
//! stagger-free frames: the shear of the duplex is then de Gennes' ladder
//! of backbone and rungs (measured against his law in
//! `python/tests/test_dna_shear.py`). Per step
//! between consecutive pairs, stacking: a [`BasePairStep`] (six compliant
//! strains of the step, with compliance 1), removed as soon as any of
//! the pairs it reads (the step's two and their neighbours) breaks (`breaks_with`), so that an opened region is
//! two single strands. The strands have single-stranded DNA's bending
//! persistence and no twist energy (the backbone swivels; Frenet model
//! without roll: the reference-frame model without a roll coordinate
//! would pin a naturally curved strand's frame and stiffen the duplex's
//! twist and bending); the duplex's bending, stretch and twist stiffness
//! come from the stacking, calibrated ([`crate::dna_elasticity::calibrated`])
//! so that the whole duplex, strands included, has [`Duplex::elasticity`]
//! at zero temperature.
use nalgebra::Vector3;
use std::f64::consts::PI;
use strandkit_core::constraint::kinds::{BasePairStep, PairStagger, RelativeDistance};
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
    /// Single-stranded DNA's persistence (0.75 nm) and mass (330 Da per
    /// nucleotide); stretch modulus 400 pN, half ssDNA's ≈ 800: the
    /// strands wind round the axis, so twisting or stretching the duplex
    /// stretches them, which stiffens its twist and unwinds it under
    /// tension (at 800 pN: +460 pN·nm² on C and +280 pN·nm on g, measured
    /// by [`crate::dna_elasticity`]), more than a stable stacking
    /// (g² < S·C) can take back; at 500 pN the thesis' 10 bp/turn already
    /// fails, at 400 pN both settings calibrate with g² ≈ S·C / 2.5.
    fn default() -> Self {
        Strand { stretch_modulus: 400.0, persistence_length: 0.75, nucleotide_mass: 330.0 * 1.660_539_07e-6 }
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

impl Elasticity {
    /// Positive constants with g² < S·C (a stable duplex) at `temperature` (K).
    pub fn validate(&self, what: &str, temperature: f64) -> Result<()> {
        positive(&format!("{what} bending_persistence"), self.bending_persistence)?;
        positive(&format!("{what} stretch_modulus"), self.stretch_modulus)?;
        positive(&format!("{what} twist_persistence"), self.twist_persistence)?;
        positive(&format!("{what} shear_modulus"), self.shear_modulus)?;
        finite(&format!("{what} twist_stretch"), self.twist_stretch)?;
        let c = self.twist_persistence * BOLTZMANN * temperature;
        if self.twist_stretch.powi(2) >= self.stretch_modulus * c {
            return Err(Error::invalid(&format!("{what} twist_stretch"), self.twist_stretch, "g² < S·C (a stable duplex)"));
        }
        Ok(())
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

/// How a base pair's hydrogen bonds hold (issue 17).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HBond {
    /// A distance between the pair's two points (rigid or compliant,
    /// breaking in tension). Its rung tilts freely when the two strands
    /// slide along the axis: the duplex's shear stiffness is the
    /// stacking's (rung-first frames read the tilt as shift and roll).
    Distance,
    /// The distance plus the pair's stagger along the local helix axis
    /// ([`PairStagger`], compliance in nm/pN, breaking when its force
    /// exceeds the pair's break force): a relative position in the pair's
    /// own frame. The stacking then reads stagger-free frames, so a
    /// sheared duplex is de Gennes' ladder — backbone stiffness Q per
    /// pair, rung stiffness R = 1/compliance, load decaying over
    /// κ⁻¹ = √(Q/2R) pairs from each end.
    Position { stagger_compliance: f64 },
}

impl HBond {
    /// The rung model of [`HBond::Position`] with this stagger compliance.
    pub fn position(stagger_compliance: f64) -> HBond {
        HBond::Position { stagger_compliance }
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
    /// The rung model.
    pub hbond: HBond,
    /// Break force (pN) of an A·T and of a G·C bond, in tension.
    pub break_force_at: f64,
    pub break_force_gc: f64,
    /// Per-pair break forces (pN; pair k = strand a's nucleotide k),
    /// overriding the two above; `f64::INFINITY` for an unbreakable pair.
    pub break_forces: Option<Vec<f64>>,
    /// Per-pair forces (pN) that break a pair's stagger ([`HBond::Position`];
    /// None: the pair's break force).
    pub stagger_break_forces: Option<Vec<f64>>,
    /// Time (ns) over which a bond's tension is averaged before it is
    /// compared with its break force (0: each step's; with thermal noise
    /// the instantaneous tension of a rigid bond breaks every pair at once:
    /// use ~1 ns, [`strandkit_core::constraint::Breaking`]).
    pub break_averaging_time: f64,
    pub strand: Strand,
    /// The duplex's elastic constants (zero temperature) the stacking is
    /// calibrated for.
    pub elasticity: Elasticity,
    /// The stacking's own constants (per step by [`Stacking::of_rod`]);
    /// None: calibrated so that the whole duplex, strands included, has
    /// `elasticity` ([`crate::dna_elasticity::calibrated`]).
    pub stacking: Option<Elasticity>,
    /// Temperature (K) at which persistence lengths are converted to stiffness.
    pub temperature: f64,
    /// Under the trapezoidal rule, the duplex's compliant constraints
    /// (stacking, compliant bonds, staggers) averaged over each step like
    /// elastic energies: exact base-pair-scale thermal statistics, but
    /// their stiff, strongly nonlinear rows need steps of ~0.25 ps (at
    /// 1–10 ps the Newton iterations stall or diverge). False (default):
    /// held at the step's end, robust at 5–10 ps, the base-pair modes
    /// damped — cooled under noise (`docs/dna_calibration.md`).
    pub averaged_stacking: bool,
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
            hbond: HBond::Distance,
            break_force_at: 9.0,
            break_force_gc: 20.0,
            break_forces: None,
            stagger_break_forces: None,
            break_averaging_time: 0.0,
            strand: Strand::default(),
            elasticity: Elasticity::default(),
            stacking: None,
            temperature: 298.15,
            averaged_stacking: false,
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
        if let HBond::Position { stagger_compliance } = self.hbond {
            positive("stagger_compliance", stagger_compliance)?;
            // A stagger breaks on its force's magnitude, which thermal
            // noise does not average down (Breaking refuses it).
            if self.break_averaging_time > 0.0 {
                return Err(Error::invalid("break_averaging_time", self.break_averaging_time, "0 with position rungs (a stagger's force has no sign to average)"));
            }
        }
        non_negative("break_averaging_time", self.break_averaging_time)?;
        positive("break_force_at", self.break_force_at)?;
        positive("break_force_gc", self.break_force_gc)?;
        positive("strand stretch_modulus", self.strand.stretch_modulus)?;
        positive("strand persistence_length", self.strand.persistence_length)?;
        positive("strand nucleotide_mass", self.strand.nucleotide_mass)?;
        positive("temperature", self.temperature)?;
        self.elasticity.validate("elasticity", self.temperature)?;
        if let Some(e) = &self.stacking {
            e.validate("stacking", self.temperature)?;
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
    /// Constraint index of pair k's stagger ([`HBond::Position`] only).
    pub staggers: Vec<Option<usize>>,
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
    let per_pair = |f: &Option<Vec<f64>>, what: &str| -> Result<Option<Vec<f64>>> {
        let Some(f) = f else { return Ok(None) };
        if f.len() != n {
            return Err(Error::invalid(what, format!("{} values", f.len()), format!("{n}, one per base pair")));
        }
        for v in f {
            if !(*v > 0.0) {
                return Err(Error::invalid(what, v, "> 0 (pN; inf: unbreakable)"));
            }
        }
        Ok(Some(f.clone()))
    };
    let break_forces: Vec<f64> = match per_pair(&p.break_forces, "break_forces")? {
        Some(f) => f,
        None => a.iter().map(|&x| if x == b'G' || x == b'C' { p.break_force_gc } else { p.break_force_at }).collect(),
    };
    let stagger_break_forces = per_pair(&p.stagger_break_forces, "stagger_break_forces")?.unwrap_or_else(|| break_forces.clone());

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
            .options(RodOptions { model: FrameModel::Frenet, ..Default::default() })
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
            c.breaking = c.breaking.map(|b| b.averaged(p.break_averaging_time));
        }
        hbonds[k] = Some(asm.constraints.len() - 1);
    }
    let rods = [&rod_a, &rod_b];
    let mut staggers = vec![None; n];
    if let HBond::Position { stagger_compliance } = p.hbond {
        for k in (0..n).filter(|&k| hbonds[k].is_some()) {
            // The axis from pairs k−1 and k+1 (k itself at an end).
            let (first, last) = (k.saturating_sub(1), (k + 1).min(n - 1));
            let at = |j: usize| (ua[j], ub[partner[j]]);
            let kind = PairStagger::at_rest(&rods, at(k), at(first), at(last))?;
            let c = asm.link(sa, sb, kind).compliance(stagger_compliance).label(format!("stagger[{k}]"));
            if stagger_break_forces[k].is_finite() {
                c.breaks(stagger_break_forces[k], BreakPolicy::Magnitude);
            }
            // Its axis reads these pairs: it goes when any of their bonds
            // does (the pair then holds by its distance alone, with no
            // shear stiffness: the stacking is blind to stagger — at a
            // fork, as unzipping opens it anyway); broken by its own load,
            // it takes the pair's bond along (a sheared pair is open).
            for j in (first..=last).filter(|&j| hbonds[j].is_some()) {
                c.breaks_with(format!("hbond[{j}]"));
            }
            staggers[k] = Some(asm.constraints.len() - 1);
            if let Some(h) = hbonds[k] {
                asm.constraints[h].fails_with(format!("stagger[{k}]"));
            }
        }
    }
    let stacking = match p.stacking {
        Some(e) => e,
        None => crate::dna_elasticity::calibrated(p)?.stacking,
    };
    let s = Stacking::of_rod(&stacking, p.rise, p.temperature);
    let mut stacks = vec![None; n - 1];
    for k in 0..n - 1 {
        if hbonds[k].is_none() || hbonds[k + 1].is_none() {
            continue;
        }
        // The pairs framing the step: k−1 and k+2 where they are bonded,
        // else the end pair again (it then adds nothing to the axis).
        let before = if k > 0 && hbonds[k - 1].is_some() { k - 1 } else { k };
        let after = if k + 2 < n && hbonds[k + 2].is_some() { k + 2 } else { k + 1 };
        let pairs = [before, k, k + 1, after];
        let mut kind = BasePairStep::at_rest(&rods, pairs.map(|j| ua[j]), pairs.map(|j| ub[partner[j]]), p.radius * (0.5 * p.phase()).cos(), s.translation, s.rotation, s.twist_stretch)?;
        if matches!(p.hbond, HBond::Position { .. }) {
            kind = kind.free_of_stagger(&rods)?;
        }
        let c = asm.link(sa, sb, kind).compliance(1.0).label(format!("stack[{k}]"));
        // It reads every pair it is framed by: it goes when any of them breaks.
        let mut framing = pairs.to_vec();
        framing.dedup();
        for j in framing {
            c.breaks_with(format!("hbond[{j}]"));
        }
        stacks[k] = Some(asm.constraints.len() - 1);
    }
    // Only compliant constraints are averaged or held (rigid ones are held).
    for c in asm.constraints.iter_mut().filter(|c| c.compliance > 0.0) {
        c.held_at_end(!p.averaged_stacking);
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
        staggers,
        mismatches,
        break_forces,
        rung_length: rung,
        phase: p.phase(),
        pitch,
        grooves: [minor, pitch - minor],
    };
    Ok((asm, layout))
}
