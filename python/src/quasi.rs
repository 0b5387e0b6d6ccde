//! Quasi-dynamic driver (thesis algorithm 11) for Python: one frame per
//! `step()`, dynamic or quasi-static by the previous frame's compute time.
use crate::convert::{self, from_json};
use crate::events::events_of;
use crate::guard;
use crate::report::PyFrameReport;
use crate::world_data::{busy, read, write, PyWorld};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use strandkit_core::{Clock, QuasiDynamic, QuasiDynamicParameters, WallClock};

/// Drives a World frame by frame (thesis IV.B.2): dynamic while a frame's
/// compute time stays under `to_dynamic` × budget, quasi-static (one
/// incomplete Newton iteration per frame) above `to_static` × budget,
/// never quasi-static for a rod held at fewer than two points (or one
/// point without an orientation).
///
/// Keyword arguments (every field of the core's QuasiDynamicParameters;
/// None = its default): `dt0` (time step of the free configuration, time
/// unit, 1e-3), `time_budget` (wall-clock seconds per frame; None = real
/// time, the frame's dt), `to_static` (0.95), `to_dynamic` (0.90),
/// `newton_fraction` (1/3), `scale_with_free_length` (True: dt = dt0 ×
/// free length / initial length, IV.15). `params` shows them all.
#[pyclass(name = "QuasiDynamic", module = "strandkit._native")]
pub struct PyQuasiDynamic {
    inner: QuasiDynamic,
    world: Py<PyWorld>,
}

/// A Python callable returning seconds, as a core clock. The frame runs
/// with the GIL released, so the clock takes it back only for the call;
/// the first error it raises is kept and re-raised after the frame.
struct PyClock {
    f: Py<PyAny>,
    error: Option<PyErr>,
    last: f64,
}

impl Clock for PyClock {
    fn now(&mut self) -> f64 {
        Python::attach(|py| match self.f.bind(py).call0().and_then(|v| v.extract::<f64>()) {
            Ok(t) => self.last = t,
            Err(e) => {
                self.error.get_or_insert(e);
            }
        });
        self.last
    }
}

impl PyQuasiDynamic {
    /// The driver for changing; a WorldBusyError while another thread steps it.
    fn driver<'py>(slf: &Bound<'py, Self>) -> PyResult<PyRefMut<'py, Self>> {
        slf.try_borrow_mut().map_err(|_| busy(slf.py(), "this QuasiDynamic"))
    }
    fn driver_ref<'py>(slf: &Bound<'py, Self>) -> PyResult<PyRef<'py, Self>> {
        slf.try_borrow().map_err(|_| busy(slf.py(), "this QuasiDynamic"))
    }
}

#[pymethods]
impl PyQuasiDynamic {
    #[new]
    #[pyo3(signature = (world, **params))]
    fn new(world: Bound<'_, PyWorld>, params: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let p: QuasiDynamicParameters =
            convert::kwargs_into(&QuasiDynamicParameters::default(), convert::kwargs(params)?, "quasi-dynamic parameter")?;
        let inner = {
            let w = read(&world)?;
            guard(|| QuasiDynamic::new(&w.inner, p))?
        };
        Ok(PyQuasiDynamic { inner, world: world.unbind() })
    }

    /// One frame. `clock`: a callable returning seconds (default: the
    /// process' monotonic clock); tests pass a scripted one. The GIL is
    /// released while the core works (like World.step); a Python clock
    /// takes it back only for its calls.
    #[pyo3(signature = (clock = None))]
    fn step(slf: &Bound<'_, Self>, clock: Option<Bound<'_, PyAny>>) -> PyResult<PyFrameReport> {
        let py = slf.py();
        let mut me = Self::driver(slf)?;
        let world = me.world.bind(py).clone();
        let rep = {
            let mut w = write(&world)?;
            let (qd, inner) = (&mut me.inner, &mut w.inner);
            match clock {
                None => py.detach(|| guard(|| qd.step(inner, &mut WallClock::default())))?,
                Some(f) => {
                    let mut c = PyClock { f: f.unbind(), error: None, last: 0.0 };
                    let r = py.detach(|| guard(|| qd.step(inner, &mut c)));
                    if let Some(e) = c.error {
                        return Err(e);
                    }
                    r?
                }
            }
        };
        drop(me);
        let events = events_of(&world, &rep.events)?;
        Ok(PyFrameReport { inner: rep, events })
    }

    /// "dynamic" or "quasi_static".
    #[getter]
    fn mode(slf: &Bound<'_, Self>) -> PyResult<String> {
        Ok(Self::driver_ref(slf)?.mode_name())
    }
    /// The parameters as a dict.
    #[getter]
    fn params<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        from_json(slf.py(), &serde_json::to_value(Self::driver_ref(slf)?.inner.params).unwrap_or_default())
    }
    fn __repr__(slf: &Bound<'_, Self>) -> String {
        let Ok(me) = Self::driver_ref(slf) else { return "QuasiDynamic(<being stepped in another thread>)".into() };
        let p = &me.inner.params;
        format!(
            "QuasiDynamic(mode={}, dt0={}, time_budget={:?}, to_static={}, to_dynamic={})",
            me.mode_name(),
            p.dt0,
            p.time_budget,
            p.to_static,
            p.to_dynamic
        )
    }
}

impl PyQuasiDynamic {
    fn mode_name(&self) -> String {
        serde_json::to_value(self.inner.mode()).ok().and_then(|v| v.as_str().map(String::from)).unwrap_or_default()
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyQuasiDynamic>()
}
