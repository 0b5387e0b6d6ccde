//! Events of a solve as Python objects. The core event is serialised with
//! its handles tagged by type ([`crate::convert::tagged`]), so every handle
//! field — whatever it is called — becomes a live object: a Rod view, a
//! ConstraintHandle, a BeadHandle or a ClipHandle.
use crate::convert::{self, tagged};
use crate::handles::to_py;
use crate::world_data::PyWorld;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::Value;

/// Something that happened during a solve: `kind` (e.g.
/// "ConstraintBroken") and its fields in `data`, also readable as
/// attributes (event.constraint, event.label, event.time, event.force,
/// event.policy, …). The constraint kind of ConstraintBroken and
/// SliderLeft events is `event.constraint_kind` ({"Position": {…}}).
#[pyclass(name = "Event", module = "strandkit._native", frozen)]
pub struct PyEvent {
    /// The event's variant name, e.g. "ConstraintBroken".
    #[pyo3(get)]
    kind: String,
    /// Its fields as a dict (handles as live objects).
    #[pyo3(get)]
    data: Py<PyDict>,
    text: String,
}

#[pymethods]
impl PyEvent {
    fn __getattr__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        self.data.bind(py).get_item(name)?.ok_or_else(|| {
            pyo3::exceptions::PyAttributeError::new_err(format!("{} event has no field {name:?}", self.kind))
        })
    }
    fn __dir__(slf: &Bound<'_, Self>) -> PyResult<Vec<String>> {
        let mut d: Vec<String> = slf.get_type().dir()?.extract()?;
        d.extend(slf.get().data.bind(slf.py()).keys().extract::<Vec<String>>()?);
        d.sort();
        d.dedup();
        Ok(d)
    }
    /// The fields as a new dict, with "kind" the event's variant name.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = self.data.bind(py).copy()?;
        d.set_item("kind", &self.kind)?;
        Ok(d)
    }
    fn __repr__(&self) -> String {
        format!("Event({})", self.text)
    }
}

/// One core event → Event, with its handles live in `world`.
fn event(world: &Bound<'_, PyWorld>, e: &strandkit_core::Event) -> PyResult<PyEvent> {
    let py = world.py();
    let v = tagged(e);
    let (name, fields) = convert::variant(&v);
    let data = PyDict::new(py);
    if let Value::Object(m) = &fields {
        for (k, x) in m {
            // `kind` is the event's own name; a field of that name (the
            // constraint kind of a broken constraint) is `constraint_kind`.
            let key = if k == "kind" { "constraint_kind" } else { k.as_str() };
            data.set_item(key, to_py(world, x)?)?;
        }
    }
    Ok(PyEvent { kind: name, data: data.unbind(), text: convert::describe(&v) })
}

/// Events as Python `Event` objects.
pub(crate) fn events_of(world: &Bound<'_, PyWorld>, es: &[strandkit_core::Event]) -> PyResult<Vec<Py<PyAny>>> {
    let py = world.py();
    es.iter().map(|e| Ok(Bound::new(py, event(world, e)?)?.into_any().unbind())).collect()
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyEvent>()
}
