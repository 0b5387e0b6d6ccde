//! Builders (strandkit-builders) for Python: each returns the Assembly and
//! a dict saying where its parts are; `strandkit.builders` wraps them.
use crate::assembly::PyAssembly;
use crate::{bad, guard};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use strandkit_builders::{necklace, rope_bridge, Hang, Necklace, PlankModel, Rope, RopeBridge};

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

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(build_rope_bridge, m)?)?;
    m.add_function(wrap_pyfunction!(build_necklace, m)?)
}
