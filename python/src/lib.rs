//! Python bindings of strandkit (module `strandkit._native`).
//!
//! Rust errors become Python exceptions with the core's message:
//! InvalidInput / InvalidHandle → ValueError, Singular → SingularError,
//! NoConvergence → ConvergenceError (both SolverError, a RuntimeError),
//! Io → OSError. Calls into the core run under `catch_unwind`, so even a
//! bug surfaces as a RuntimeError rather than a panic crossing the boundary.
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use strandkit_core::Error;

mod clips;
mod convert;
mod io;
mod props;
mod quasi;
mod report;
mod rod;
mod world;

pyo3::create_exception!(
    strandkit,
    SolverError,
    PyRuntimeError,
    "The solver failed: singular system or no convergence."
);
pyo3::create_exception!(
    strandkit,
    SingularError,
    SolverError,
    "Singular linear system (under-constrained structure, zero pivot)."
);
pyo3::create_exception!(
    strandkit,
    ConvergenceError,
    SolverError,
    "An iterative solve did not reach its tolerance."
);

/// Core error → Python exception with the same message.
pub(crate) fn err(e: Error) -> PyErr {
    let msg = e.to_string();
    #[allow(unreachable_patterns)] // new core variants fall back to RuntimeError
    match e {
        Error::InvalidInput(_) | Error::InvalidHandle(_) => PyValueError::new_err(msg),
        Error::Singular(_) => SingularError::new_err(msg),
        Error::NoConvergence(_) => ConvergenceError::new_err(msg),
        Error::Io(_) => PyOSError::new_err(msg),
        _ => PyRuntimeError::new_err(msg),
    }
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
    let py = m.py();
    m.add("SolverError", py.get_type::<SolverError>())?;
    m.add("SingularError", py.get_type::<SingularError>())?;
    m.add("ConvergenceError", py.get_type::<ConvergenceError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    props::register(m)?;
    rod::register(m)?;
    world::register(m)?;
    quasi::register(m)?;
    clips::register(m)?;
    io::register(m)?;
    Ok(())
}
