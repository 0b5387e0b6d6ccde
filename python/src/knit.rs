//! The knit builder (strandkit-builders::knit) for Python; `strandkit.knit`
//! wraps it.
use crate::assembly::PyAssembly;
use crate::guard;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use strandkit_builders::knit::{fabric, Boundary, Fabric, Pattern, StitchGrid, Yarn};

/// Weft-knit fabric (SPEC §9.3); see `strandkit.knit.fabric`. `rows`
/// (custom K/P courses, bottom first) replaces `pattern`, `wales`, `courses`.
#[pyfunction]
#[pyo3(signature = (*, pattern, rows = None, wales, courses, loop_length, yarn, yarn_radius, bending_stiffness = None, continuous, boundary, spacing = None, control_points_per_loop, bind_off, cast_on = true, selvedge = true, fasten_ends = true))]
#[allow(clippy::too_many_arguments)]
fn build_knit_fabric<'py>(
    py: Python<'py>,
    pattern: &str,
    rows: Option<Vec<String>>,
    wales: usize,
    courses: usize,
    loop_length: f64,
    yarn: &str,
    yarn_radius: f64,
    bending_stiffness: Option<f64>,
    continuous: bool,
    boundary: &str,
    spacing: Option<[f64; 2]>,
    control_points_per_loop: usize,
    bind_off: bool,
    cast_on: bool,
    selvedge: bool,
    fasten_ends: bool,
) -> PyResult<(PyAssembly, Bound<'py, PyDict>)> {
    let (p, layout) = guard(|| {
        let grid = match &rows {
            Some(r) => StitchGrid::parse(&r.iter().map(String::as_str).collect::<Vec<_>>())?,
            None => StitchGrid::new(Pattern::from_name(pattern)?, wales, courses)?,
        };
        let mut y = Yarn::preset(yarn, yarn_radius)?;
        y.bending_stiffness = bending_stiffness;
        let p = Fabric { grid, loop_length, yarn: y, continuous, boundary: Boundary::from_name(boundary)?, spacing, control_points_per_loop, bind_off, cast_on, selvedge, fasten_ends };
        let built = fabric(&p)?;
        Ok((p, built))
    })?;
    let (asm, l) = layout;
    let d = PyDict::new(py);
    d.set_item("yarns", l.yarns)?;
    let col = |f: &dyn Fn(&strandkit_builders::knit::LoopSpan) -> f64| l.loops.iter().map(f).collect::<Vec<f64>>();
    d.set_item("loop_wale", l.loops.iter().map(|s| s.wale).collect::<Vec<_>>())?;
    d.set_item("loop_course", l.loops.iter().map(|s| s.course).collect::<Vec<_>>())?;
    d.set_item("loop_rod", l.loops.iter().map(|s| s.rod).collect::<Vec<_>>())?;
    d.set_item("loop_u_start", col(&|s| s.u_start))?;
    d.set_item("loop_u_head", col(&|s| s.u_head))?;
    d.set_item("loop_u_end", col(&|s| s.u_end))?;
    let m = PyDict::new(py);
    m.set_item("wale_spacing", l.model.wale_spacing)?;
    m.set_item("course_spacing", l.model.course_spacing)?;
    m.set_item("loop_height", l.model.loop_height)?;
    m.set_item("overhang", l.model.overhang)?;
    m.set_item("depth", l.model.depth)?;
    d.set_item("model", m)?;
    d.set_item("loop_length", l.loop_length)?;
    d.set_item("clearance", l.clearance)?;
    d.set_item("bind_off", l.bind_off)?;
    d.set_item("cast_on", l.cast_on)?;
    d.set_item("selvedge", l.selvedge)?;
    d.set_item("yarn_ends", l.yarn_ends)?;
    d.set_item("clamps", l.clamps)?;
    d.set_item("tube_radius", l.tube_radius)?;
    d.set_item("image", l.image)?;
    d.set_item("image_ties", l.image_ties)?;
    d.set_item("junction", l.junction)?;
    d.set_item("rows", p.grid.rows())?;
    d.set_item("bending_stiffness", p.yarn.bending())?;
    d.set_item("yarn", p.yarn.name.clone())?;
    Ok((PyAssembly { inner: asm }, d))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(build_knit_fabric, m)?)
}
