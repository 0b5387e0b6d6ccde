//! Builders (strandkit-builders) for Python: each returns the Assembly and
//! a dict saying where its parts are; `strandkit.builders` wraps them.
use crate::assembly::PyAssembly;
use crate::{bad, guard};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use strandkit_builders::{rope_bridge, PlankModel, Rope, RopeBridge};

/// A rope from a dict {'linear_density': kg/m, 'axial_stiffness': N,
/// 'bending_stiffness': N·m²} (missing keys: the default rope's).
fn rope(d: Option<&Bound<'_, PyDict>>) -> PyResult<Rope> {
    let mut r = Rope::default();
    let Some(d) = d else { return Ok(r) };
    for (k, v) in d.iter() {
        let key: String = k.extract()?;
        let x: f64 = v.extract()?;
        match key.as_str() {
            "linear_density" => r.linear_density = x,
            "axial_stiffness" => r.axial_stiffness = x,
            "bending_stiffness" => r.bending_stiffness = x,
            _ => return Err(bad(format!("rope: unknown key {key:?} (accepted: linear_density, axial_stiffness, bending_stiffness)"))),
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

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(build_rope_bridge, m)?)
}
