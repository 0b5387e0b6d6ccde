//! Builders (strandkit-builders) for Python: each returns the Assembly and
//! a dict saying where its parts are; `strandkit.builders` wraps them.
use crate::assembly::PyAssembly;
use crate::{bad, guard};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use strandkit_core::FrameModel;
use strandkit_builders::{
    beads_on_spring, cable_on_clips, harness, necklace, rope_bridge, BeadsOnSpring, BranchEnd, CableOnClips, Hang, Harness, Necklace, PlankModel, Rope, RopeBridge,
};

/// A rope from a dict {'linear_density': kg/m, 'axial_stiffness': N,
/// 'bending_stiffness': N·m²} (missing keys: the default rope's).
fn rope(d: Option<&Bound<'_, PyDict>>) -> PyResult<Rope> {
    match d {
        Some(d) => rope_from(d, Rope::default(), "rope"),
        None => Ok(Rope::default()),
    }
}

/// `base` with the dict's entries replacing its values.
fn rope_from(d: &Bound<'_, PyDict>, base: Rope, what: &str) -> PyResult<Rope> {
    let mut r = base;
    for (k, v) in d.iter() {
        let key: String = k.extract()?;
        let x: f64 = v.extract()?;
        match key.as_str() {
            "linear_density" => r.linear_density = x,
            "axial_stiffness" => r.axial_stiffness = x,
            "bending_stiffness" => r.bending_stiffness = x,
            _ => return Err(bad(format!("{what}: unknown key {key:?} (accepted: linear_density, axial_stiffness, bending_stiffness)"))),
        }
    }
    Ok(r)
}

/// Rope bridge (SPEC §9.2); see `strandkit.builders.rope_bridge`.
#[pyfunction]
#[pyo3(signature = (*, span, n_planks, plank_mass, sag, width, handrail_height, rope = None, plank_depth, plank_thickness, plank_young, plank_model, plank_break_force = None, rope_control_points = None))]
#[allow(clippy::too_many_arguments)]
fn build_rope_bridge<'py>(
    py: Python<'py>,
    span: f64,
    n_planks: usize,
    plank_mass: f64,
    sag: f64,
    width: f64,
    handrail_height: f64,
    rope: Option<&Bound<'py, PyDict>>,
    plank_depth: f64,
    plank_thickness: f64,
    plank_young: f64,
    plank_model: &str,
    plank_break_force: Option<f64>,
    rope_control_points: Option<usize>,
) -> PyResult<(PyAssembly, Bound<'py, PyDict>)> {
    let plank_model = match plank_model {
        "body" => PlankModel::Body,
        "link" => PlankModel::Link,
        other => return Err(bad(format!("plank_model: {other:?} is not 'body' or 'link'"))),
    };
    let p = RopeBridge {
        span,
        n_planks,
        plank_mass,
        sag,
        width,
        handrail_height,
        rope: self::rope(rope)?,
        plank_depth,
        plank_thickness,
        plank_young,
        plank_model,
        plank_break_force,
        rope_control_points,
    };
    let (asm, layout) = guard(|| rope_bridge(&p))?;
    let d = PyDict::new(py);
    d.set_item("ropes", layout.ropes)?;
    d.set_item("planks", layout.planks)?;
    d.set_item("stations", layout.stations)?;
    d.set_item("station_x", layout.station_x)?;
    Ok((PyAssembly { inner: asm }, d))
}

/// Bead necklace (SPEC §9.4); see `strandkit.builders.necklace`.
#[pyfunction]
#[pyo3(signature = (*, n_beads, bead_mass, bead_radius, string = None, length, closed, hang, peg, supports, friction, peg_friction, knotted, control_points))]
#[allow(clippy::too_many_arguments)]
fn build_necklace<'py>(
    py: Python<'py>,
    n_beads: usize,
    bead_mass: f64,
    bead_radius: f64,
    string: Option<&Bound<'py, PyDict>>,
    length: f64,
    closed: bool,
    hang: &str,
    peg: [f64; 3],
    supports: [[f64; 3]; 2],
    friction: f64,
    peg_friction: f64,
    knotted: bool,
    control_points: usize,
) -> PyResult<(PyAssembly, Bound<'py, PyDict>)> {
    let hang = match hang {
        "peg" => Hang::Peg(peg),
        "two_points" => Hang::TwoPoints(supports[0], supports[1]),
        other => return Err(bad(format!("hang: {other:?} is not 'peg' or 'two_points'"))),
    };
    let mut s = Necklace::default().string;
    if let Some(d) = string {
        s = rope_from(d, s, "string")?;
    }
    let p = Necklace { n_beads, bead_mass, bead_radius, string: s, length, closed, hang, friction, peg_friction, knotted, control_points };
    let (asm, layout) = guard(|| necklace(&p))?;
    let d = PyDict::new(py);
    d.set_item("string", layout.string)?;
    d.set_item("beads", layout.beads)?;
    d.set_item("supports", layout.supports)?;
    d.set_item("bead_arc_lengths", layout.bead_arc_lengths)?;
    Ok((PyAssembly { inner: asm }, d))
}

/// Particles on a spring (SPEC §9.4); see `strandkit.builders.beads_on_spring`.
#[pyfunction]
#[pyo3(signature = (*, coil_radius, pitch, turns, wire_radius, young_modulus, poisson_ratio, density, n_beads, bead_mass, bead_radius, bead_spacing, friction, top, control_points, model=None))]
#[allow(clippy::too_many_arguments)]
fn build_beads_on_spring<'py>(
    py: Python<'py>,
    coil_radius: f64,
    pitch: f64,
    turns: f64,
    wire_radius: f64,
    young_modulus: f64,
    poisson_ratio: f64,
    density: f64,
    n_beads: usize,
    bead_mass: f64,
    bead_radius: f64,
    bead_spacing: f64,
    friction: f64,
    top: [f64; 3],
    control_points: usize,
    model: Option<&str>,
) -> PyResult<(PyAssembly, Bound<'py, PyDict>)> {
    let model = match model {
        None => FrameModel::default(),
        Some("reference") => FrameModel::Reference,
        Some("frenet") => FrameModel::Frenet,
        Some(other) => return Err(bad(format!("model: {other:?} is not 'reference' or 'frenet'"))),
    };
    let p = BeadsOnSpring {
        coil_radius, pitch, turns, wire_radius, young_modulus, poisson_ratio, density, n_beads, bead_mass, bead_radius, bead_spacing, friction, top, control_points, model,
    };
    let (asm, l) = guard(|| beads_on_spring(&p))?;
    let d = PyDict::new(py);
    d.set_item("spring", l.spring)?;
    d.set_item("clamp", l.clamp)?;
    d.set_item("beads", l.beads)?;
    d.set_item("bead_arc_lengths", l.bead_arc_lengths)?;
    d.set_item("wire_length", l.wire_length)?;
    d.set_item("helix_angle", l.helix_angle)?;
    d.set_item("close_coiled_rate", l.close_coiled_rate)?;
    Ok((PyAssembly { inner: asm }, d))
}

/// A B-DNA duplex (SPEC §9.1); see `strandkit.dna.duplex`. Molecular units.
#[pyfunction]
#[pyo3(signature = (*, sequence, complement, bp_per_turn, rise, radius, minor_groove, hbond, hbond_compliance, stagger_compliance, break_force_at, break_force_gc, break_forces, stagger_break_forces, break_averaging_time, strand_stretch_modulus, strand_persistence, bending_persistence, stretch_modulus, twist_persistence, twist_stretch, temperature, averaged_stacking))]
#[allow(clippy::too_many_arguments)]
fn build_duplex<'py>(
    py: Python<'py>,
    sequence: String,
    complement: Option<String>,
    bp_per_turn: f64,
    rise: f64,
    radius: f64,
    minor_groove: f64,
    hbond: String,
    hbond_compliance: f64,
    stagger_compliance: f64,
    break_force_at: f64,
    break_force_gc: f64,
    break_forces: Option<Vec<f64>>,
    stagger_break_forces: Option<Vec<f64>>,
    break_averaging_time: f64,
    strand_stretch_modulus: f64,
    strand_persistence: f64,
    bending_persistence: f64,
    stretch_modulus: f64,
    twist_persistence: f64,
    twist_stretch: f64,
    temperature: f64,
    averaged_stacking: bool,
) -> PyResult<(PyAssembly, Bound<'py, PyDict>)> {
    use strandkit_builders::dna::{duplex, Duplex, Elasticity, HBond};
    let hbond = match hbond.as_str() {
        "distance" => HBond::Distance,
        "position" => HBond::Position { stagger_compliance },
        other => return Err(crate::err(strandkit_core::Error::invalid("hbond", format!("{other:?}"), "'distance' or 'position'"))),
    };
    let mut p = Duplex::new(&sequence);
    p.temperature = temperature;
    p.averaged_stacking = averaged_stacking;
    p.strand.stretch_modulus = strand_stretch_modulus;
    p.strand.persistence_length = strand_persistence;
    p.elasticity = Elasticity { bending_persistence, stretch_modulus, twist_persistence, twist_stretch, ..p.elasticity };
    p = Duplex { complement, bp_per_turn, rise, radius, minor_groove, hbond, hbond_compliance, break_force_at, break_force_gc, break_forces, stagger_break_forces, break_averaging_time, ..p };
    let (asm, l) = guard(|| duplex(&p))?;
    // The calibration the build used (cached: no second run).
    let cal = guard(|| strandkit_builders::dna_elasticity::calibrated(&p))?;
    let d = PyDict::new(py);
    let m = cal.measured;
    let measured = PyDict::new(py);
    measured.set_item("stretch_modulus", m.stretch_modulus)?;
    measured.set_item("twist_stretch", m.twist_stretch)?;
    measured.set_item("twist_stiffness", m.twist_stiffness)?;
    measured.set_item("bending_stiffness", m.bending_stiffness)?;
    d.set_item("measured", measured)?;
    d.set_item("strands", l.strands.to_vec())?;
    d.set_item("sequences", l.sequences.to_vec())?;
    d.set_item("abscissae", l.abscissae.to_vec())?;
    d.set_item("partner", l.partner)?;
    d.set_item("hbonds", l.hbonds)?;
    d.set_item("stacks", l.stacks)?;
    d.set_item("staggers", l.staggers)?;
    d.set_item("mismatches", l.mismatches)?;
    d.set_item("break_forces", l.break_forces)?;
    d.set_item("rung_length", l.rung_length)?;
    d.set_item("phase", l.phase)?;
    d.set_item("pitch", l.pitch)?;
    d.set_item("grooves", l.grooves.to_vec())?;
    Ok((PyAssembly { inner: asm }, d))
}

/// A cable on clips (SPEC §9.5); see `strandkit.builders.cable_on_clips`.
#[pyfunction]
#[pyo3(signature = (*, path, clip_positions, clip_radius, clip_axis, clip_resistance, cable_radius, young_modulus, density, bend_radius, clamp_start, clamp_end, control_points))]
#[allow(clippy::too_many_arguments)]
fn build_cable_on_clips<'py>(
    py: Python<'py>,
    path: Vec<[f64; 3]>,
    clip_positions: Vec<[f64; 3]>,
    clip_radius: f64,
    clip_axis: [f64; 3],
    clip_resistance: f64,
    cable_radius: f64,
    young_modulus: f64,
    density: f64,
    bend_radius: f64,
    clamp_start: bool,
    clamp_end: bool,
    control_points: usize,
) -> PyResult<(PyAssembly, Bound<'py, PyDict>)> {
    let p = CableOnClips { path, clip_positions, clip_radius, clip_axis, clip_resistance, cable_radius, young_modulus, density, bend_radius, clamp_start, clamp_end, control_points };
    let (asm, l) = guard(|| cable_on_clips(&p))?;
    let d = PyDict::new(py);
    d.set_item("cable", l.cable)?;
    d.set_item("clips", l.clips)?;
    d.set_item("clamps", l.clamps)?;
    d.set_item("clip_abscissae", l.clip_abscissae)?;
    d.set_item("clip_distances", l.clip_distances)?;
    d.set_item("length", l.length)?;
    Ok((PyAssembly { inner: asm }, d))
}

fn branch_end((b, e): (usize, String), what: &str) -> PyResult<(usize, BranchEnd)> {
    match e.as_str() {
        "start" => Ok((b, BranchEnd::Start)),
        "end" => Ok((b, BranchEnd::End)),
        other => Err(bad(format!("{what}: end {other:?} is not 'start' or 'end'"))),
    }
}

/// A wiring harness (SPEC §9.5); see `strandkit.builders.harness`.
#[pyfunction]
#[pyo3(signature = (*, branches, radii, junctions, connectors, bend_radius, young_modulus, density, control_points_per_metre))]
#[allow(clippy::too_many_arguments)]
fn build_harness<'py>(
    py: Python<'py>,
    branches: Vec<Vec<[f64; 3]>>,
    radii: Vec<f64>,
    junctions: Vec<Vec<(usize, String)>>,
    connectors: Vec<(usize, String)>,
    bend_radius: f64,
    young_modulus: f64,
    density: f64,
    control_points_per_metre: f64,
) -> PyResult<(PyAssembly, Bound<'py, PyDict>)> {
    let junctions = junctions
        .into_iter()
        .enumerate()
        .map(|(j, ends)| ends.into_iter().map(|e| branch_end(e, &format!("junctions[{j}]"))).collect::<PyResult<Vec<_>>>())
        .collect::<PyResult<Vec<_>>>()?;
    let connectors = connectors.into_iter().enumerate().map(|(c, e)| branch_end(e, &format!("connectors[{c}]"))).collect::<PyResult<Vec<_>>>()?;
    let p = Harness { branches, radii, junctions, connectors, bend_radius, young_modulus, density, control_points_per_metre };
    let (asm, l) = guard(|| harness(&p))?;
    let d = PyDict::new(py);
    d.set_item("branches", l.branches)?;
    let links: Vec<Vec<(usize, usize, usize, usize)>> =
        l.junctions.iter().map(|js| js.iter().map(|j| (j.main.0, j.other.0, j.position, j.orientation)).collect()).collect();
    d.set_item("junctions", links)?;
    d.set_item("connectors", l.connectors)?;
    d.set_item("lengths", l.lengths)?;
    Ok((PyAssembly { inner: asm }, d))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(build_rope_bridge, m)?)?;
    m.add_function(wrap_pyfunction!(build_necklace, m)?)?;
    m.add_function(wrap_pyfunction!(build_beads_on_spring, m)?)?;
    m.add_function(wrap_pyfunction!(build_cable_on_clips, m)?)?;
    m.add_function(wrap_pyfunction!(build_harness, m)?)?;
    m.add_function(wrap_pyfunction!(build_duplex, m)?)
}
