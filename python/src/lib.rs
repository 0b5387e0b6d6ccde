//! Python bindings of strandkit (module `strandkit._native`).
//!
//! Rust errors become the exceptions of `strandkit.errors` (one class per
//! core variant, all under StrandkitError) with the core's message and the
//! variant's fields as attributes. Calls into the core run under
//! `catch_unwind`, so even a bug surfaces as a RuntimeError rather than a
//! panic crossing the boundary.
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use strandkit_core::Error;

mod assembly;
mod builders;
mod knit;
mod catalogue;
mod convert;
mod events;
mod groups;
mod handles;
mod io;
mod obstacles;
mod props;
mod quasi;
mod report;
mod rod;
mod world;
mod world_data;

/// Core error → the exception class of `strandkit.errors` for its variant
/// (InvalidInputError, SingularError, …), with the same message and the
/// variant's fields as attributes.
pub(crate) fn err(e: Error) -> PyErr {
    let msg = e.to_string();
    Python::attach(|py| match build_error(py, &e, &msg) {
        Ok(x) => x,
        // The package's errors module could not be imported (a broken
        // install): still raise, with the same message.
        Err(_) => PyRuntimeError::new_err(msg),
    })
}

fn build_error(py: Python<'_>, e: &Error, msg: &str) -> PyResult<PyErr> {
    use pyo3::types::PyAnyMethods;
    let cls = py.import("strandkit.errors")?.getattr("BY_KIND")?.get_item(e.kind())?;
    let x = cls.call1((msg,))?;
    x.setattr("kind", e.kind())?;
    let json = |v: &serde_json::Value| convert::from_json(py, v);
    match e {
        Error::InvalidInput { what, value, expected } => {
            x.setattr("what", what)?;
            x.setattr("value", value)?;
            x.setattr("expected", expected)?;
        }
        Error::InvalidHandle { what } => x.setattr("what", what)?,
        Error::Singular { unknown, constraints, detail } => {
            x.setattr("unknown", json(&serde_json::to_value(unknown).unwrap_or_default())?)?;
            x.setattr("constraints", json(&serde_json::to_value(constraints).unwrap_or_default())?)?;
            x.setattr("detail", detail)?;
        }
        Error::NotConverged { iterations, residual, detail } => {
            x.setattr("iterations", iterations)?;
            x.setattr("residual", residual)?;
            x.setattr("detail", detail)?;
        }
        Error::NonFinite { rod, detail } => {
            x.setattr("rod", rod.map(|r| r.index))?;
            x.setattr("detail", detail)?;
        }
        Error::Diverged { step, rod, factor, detail } => {
            x.setattr("step", step)?;
            x.setattr("rod", rod.map(|r| r.index))?;
            x.setattr("factor", factor)?;
            x.setattr("detail", detail)?;
        }
        Error::Io { path, message } => {
            x.setattr("path", path)?;
            x.setattr("message", message)?;
        }
    }
    Ok(PyErr::from_value(x))
}

/// A bad argument detected on the Python side of the boundary.
pub(crate) fn bad(msg: impl Into<String>) -> PyErr {
    err(Error::input(msg))
}

/// Runs core code; errors and (defensively) panics become Python exceptions.
pub(crate) fn guard<T>(f: impl FnOnce() -> strandkit_core::Result<T>) -> PyResult<T> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(r) => r.map_err(err),
        Err(p) => {
            let what = p
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| p.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(PyRuntimeError::new_err(format!(
                "strandkit internal error (please report): {what}"
            )))
        }
    }
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    props::register(m)?;
    rod::register(m)?;
    world::register(m)?;
    handles::register(m)?;
    events::register(m)?;
    report::register(m)?;
    groups::register(m)?;
    assembly::register(m)?;
    builders::register(m)?;
    knit::register(m)?;
    catalogue::register(m)?;
    quasi::register(m)?;
    io::register(m)?;
    obstacles::register(m)?;
    Ok(())
}
