//! Clips (thesis III.A.5.a, algorithms 4–5) seen from Python: capture
//! spheres that hold a rod by a position constraint until it is pulled out
//! along their exit axis harder than their resistance.
use crate::guard;
use crate::rod::PyRod;
use crate::world::{PyConstraintHandle, PyWorld};
use pyo3::prelude::*;
use strandkit_core::ClipHandle;

/// Handle of a clip: `center` (length), `radius` (length), `axis` (unit
/// exit axis), `resistance` (force), `held` (the Rod it holds, or None),
/// `constraint` (the position constraint holding it, or None), `disarmed`
/// (released, waiting for the rod to leave the sphere).
#[pyclass(name = "ClipHandle", module = "strandkit._native", frozen)]
pub struct PyClipHandle {
    pub world: Py<PyWorld>,
    pub handle: ClipHandle,
}

impl PyClipHandle {
    fn with<R>(&self, py: Python<'_>, f: impl FnOnce(&strandkit_core::Clip) -> R) -> PyResult<R> {
        let w = self.world.bind(py).try_borrow()?;
        Ok(f(guard(|| w.inner.clip(self.handle))?))
    }
}

#[pymethods]
impl PyClipHandle {
    #[getter]
    fn center(&self, py: Python<'_>) -> PyResult<[f64; 3]> {
        self.with(py, |c| c.center)
    }
    #[getter]
    fn radius(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |c| c.radius)
    }
    #[getter]
    fn axis(&self, py: Python<'_>) -> PyResult<[f64; 3]> {
        self.with(py, |c| c.axis)
    }
    #[getter]
    fn resistance(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |c| c.resistance)
    }
    #[getter]
    fn disarmed(&self, py: Python<'_>) -> PyResult<bool> {
        self.with(py, |c| c.disarmed)
    }
    #[getter]
    fn held(&self, py: Python<'_>) -> PyResult<Option<PyRod>> {
        let h = self.with(py, |c| c.held.map(|(r, _)| r))?;
        Ok(h.map(|r| PyRod::attached(self.world.clone_ref(py), r)))
    }
    #[getter]
    fn constraint(&self, py: Python<'_>) -> PyResult<Option<PyConstraintHandle>> {
        let h = self.with(py, |c| c.held.map(|(_, k)| k))?;
        Ok(h.map(|k| PyConstraintHandle { world: self.world.clone_ref(py), handle: k }))
    }
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.cast::<PyClipHandle>().is_ok_and(|o| o.get().handle == self.handle && o.get().world.is(&self.world))
    }
    fn __hash__(&self) -> u64 {
        ((self.handle.generation as u64) << 32) | self.handle.index as u64
    }
    fn __repr__(&self, py: Python<'_>) -> String {
        match self.with(py, |c| c.clone()) {
            Ok(c) => format!(
                "ClipHandle({}: center={:?}, radius={}, resistance={}, {})",
                self.handle.index,
                c.center,
                c.radius,
                c.resistance,
                match (c.held, c.disarmed) {
                    (Some((r, _)), _) => format!("holding rod {}", r.index),
                    (None, true) => "released".into(),
                    (None, false) => "armed".into(),
                }
            ),
            Err(_) => format!("ClipHandle({})", self.handle.index),
        }
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyClipHandle>()
}
