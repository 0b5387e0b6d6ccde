//! The catalogues of constraint and load kinds (name, Python helper, rods,
//! documentation, fields with type, unit, default and roll keyword), from
//! the core's registries. `strandkit.constraints` and `strandkit.loads`
//! build their helper functions, signatures and docstrings from them.
use crate::convert::from_json;
use pyo3::prelude::*;
use strandkit_core::{ConstraintKind, Load};

/// Every constraint kind the core registers, as a list of dicts: `name`
/// (serde tag), `helper` (Python function name), `rods` (1 or 2), `doc`,
/// `fields` (each: `name`, `ty`, `unit`, `doc`, `default` as JSON text or
/// None, `roll_keyword`).
#[pyfunction]
fn constraint_catalogue(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    from_json(py, &serde_json::to_value(ConstraintKind::CATALOGUE).unwrap_or_default())
}

/// Every load kind the core registers (as `constraint_catalogue`, without `rods`).
#[pyfunction]
fn load_catalogue(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    from_json(py, &serde_json::to_value(Load::CATALOGUE).unwrap_or_default())
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(constraint_catalogue, m)?)?;
    m.add_function(wrap_pyfunction!(load_catalogue, m)?)?;
    Ok(())
}
