//! Reports of `step`, `relax` and quasi-dynamic frames as Python objects.
//! Each keeps the core's report and serves its fields by name through
//! serde (attribute access, `dir()`, `to_dict()`), so a field added to a
//! core report appears in Python without a binding change. Conversion
//! happens only when a field is read: a step pays nothing for it.
use crate::convert::from_json;
use pyo3::exceptions::PyAttributeError;
use pyo3::prelude::*;
use serde_json::{Map, Value};

/// The report's fields as a JSON object, with `extra` derived entries.
pub(crate) fn fields<T: serde::Serialize>(inner: &T, extra: &[(&str, Value)]) -> Map<String, Value> {
    let mut m = match serde_json::to_value(inner) {
        Ok(Value::Object(m)) => m,
        _ => Map::new(),
    };
    m.remove("events"); // served as live Event objects instead
    for (k, v) in extra {
        m.insert((*k).into(), v.clone());
    }
    m
}

pub(crate) fn field<'py>(py: Python<'py>, m: &Map<String, Value>, kind: &str, name: &str) -> PyResult<Bound<'py, PyAny>> {
    match m.get(name) {
        Some(v) => from_json(py, v),
        None => Err(PyAttributeError::new_err(format!("'{kind}' object has no attribute '{name}'"))),
    }
}

/// `Kind(a=…, b=…, events=n)` with the listed fields (floats in short form).
pub(crate) fn repr(kind: &str, m: &Map<String, Value>, shown: &[&str], n_events: usize) -> String {
    let mut parts: Vec<String> = shown
        .iter()
        .filter_map(|k| {
            m.get(*k).map(|v| match v {
                Value::Number(x) if x.is_f64() => format!("{k}={:.4e}", x.as_f64().unwrap_or(f64::NAN)),
                Value::String(s) => format!("{k}={s}"),
                other => format!("{k}={other}"),
            })
        })
        .collect();
    parts.push(format!("events={n_events}"));
    format!("{kind}({})", parts.join(", "))
}

/// A report class: `$derived` computes extra entries from the core report.
macro_rules! report_class {
    ($(#[$doc:meta])* $ty:ident, $name:literal, $inner:ty, [$($shown:literal),*], $derived:expr) => {
        $(#[$doc])*
        #[pyclass(name = $name, module = "strandkit._native", frozen)]
        pub struct $ty {
            pub(crate) inner: $inner,
            pub(crate) events: Vec<Py<PyAny>>,
        }

        impl $ty {
            fn fields(&self) -> serde_json::Map<String, serde_json::Value> {
                let derived: fn(&$inner) -> Vec<(&'static str, serde_json::Value)> = $derived;
                crate::report::fields(&self.inner, &derived(&self.inner))
            }
        }

        #[pymethods]
        impl $ty {
            /// What happened (Event objects: broken constraints, departed
            /// sliders and beads, clips, ruptures), in order.
            #[getter]
            fn events(&self, py: Python<'_>) -> Vec<Py<PyAny>> {
                self.events.iter().map(|e| e.clone_ref(py)).collect()
            }
            fn __getattr__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
                crate::report::field(py, &self.fields(), $name, name)
            }
            fn __dir__(&self) -> Vec<String> {
                let mut d: Vec<String> = self.fields().keys().cloned().collect();
                d.extend(["events", "to_dict"].map(String::from));
                d
            }
            /// Every field as a dict (events as dicts).
            fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
                let mut m = self.fields();
                let ev = serde_json::to_value(&self.inner.events).unwrap_or_default();
                m.insert("events".into(), ev);
                crate::convert::from_json(py, &serde_json::Value::Object(m))
            }
            fn __repr__(&self) -> String {
                crate::report::repr($name, &self.fields(), &[$($shown),*], self.events.len())
            }
        }
    };
}

report_class!(
    /// What a step did, as attributes: `time` (after the step), `n_unknowns`,
    /// `n_multipliers`, `bandwidth` (half), `residual` (relative, of the
    /// linear solve), `factorisation` ("band_ldlt" | "band_lu" | "sparse"),
    /// `fallbacks` (factorisations that failed before it), `factor_entries`
    /// (stored, fill included), `elastic_energy` (before the step, energy
    /// unit), `plastic_samples`, `active_contacts`, `events`; `dir()` lists them.
    PyStepReport,
    "StepReport",
    strandkit_core::StepReport,
    ["time", "n_unknowns", "n_multipliers", "bandwidth", "residual", "factorisation", "elastic_energy"],
    |_| Vec::new()
);

report_class!(
    /// What relax did, as attributes: `iterations` (linear solves, accepted
    /// + rejected), `rejected`, `corrections` (Newton steps that took the
    /// second-order path: one more assembly and a solve with the same
    /// factors), final `increment` (length unit) and `violation`,
    /// `potential` (U − F·q, energy unit), `plastic_samples`,
    /// `plastic_increment`, `bandwidth`, `n_unknowns`, `factorisation`, `events`.
    PyRelaxReport,
    "RelaxReport",
    strandkit_core::RelaxReport,
    ["iterations", "rejected", "increment", "violation", "potential"],
    |_| Vec::new()
);

report_class!(
    /// What a quasi-dynamic frame did, as attributes: `mode` ("dynamic" |
    /// "quasi_static"), `switched`, `static_refused` and `refusal` (why),
    /// `dt` (time unit), `free_length` (length unit), `compute_time` and
    /// `slack` (seconds of the clock; a real-time caller sleeps `slack`
    /// when positive), `motion` (largest control-point displacement,
    /// length unit), `events`.
    PyFrameReport,
    "FrameReport",
    strandkit_core::FrameReport,
    ["mode", "switched", "dt", "compute_time", "motion"],
    |_| Vec::new()
);

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyStepReport>()?;
    m.add_class::<PyRelaxReport>()?;
    m.add_class::<PyFrameReport>()?;
    Ok(())
}
