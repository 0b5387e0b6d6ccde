//! numpy and JSON conversions shared by the bindings.
use crate::rod::PyRod;
use crate::world::{PyBeadHandle, PyConstraintHandle, PyLoadHandle};
use numpy::{
    AllowTypeChange, PyArray1, PyArray2, PyArrayLike1, PyArrayLike2, PyArrayMethods,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde_json::{Map, Value};

/// Flat row-major values → numpy array of shape (rows, cols).
pub fn array2<'py>(
    py: Python<'py>,
    flat: Vec<f64>,
    cols: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let rows = flat.len().checked_div(cols).unwrap_or(0);
    PyArray1::from_vec(py, flat).reshape([rows, cols])
}

/// Points → (n, 3) array.
pub fn points<'py>(
    py: Python<'py>,
    p: impl IntoIterator<Item = [f64; 3]>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    array2(py, p.into_iter().flatten().collect(), 3)
}

/// Any array-like of shape (n, c) with c in `cols` → (flat values, n, c),
/// all finite.
pub fn matrix(
    obj: &Bound<'_, PyAny>,
    cols: &[usize],
    what: &str,
) -> PyResult<(Vec<f64>, usize, usize)> {
    let arr: PyArrayLike2<f64, AllowTypeChange> = obj.extract().map_err(|_| {
        PyValueError::new_err(format!(
            "{what}: expected a 2-D array of numbers with {} columns",
            cols.iter()
                .map(|c| c.to_string())
                .collect::<Vec<_>>()
                .join(" or ")
        ))
    })?;
    let shape = arr.shape().to_vec();
    if !cols.contains(&shape[1]) {
        return Err(PyValueError::new_err(format!(
            "{what}: expected shape (n, {}), got ({}, {})",
            cols.iter()
                .map(|c| c.to_string())
                .collect::<Vec<_>>()
                .join(" or "),
            shape[0],
            shape[1]
        )));
    }
    let flat: Vec<f64> = arr.as_array().iter().copied().collect();
    if let Some(i) = flat.iter().position(|x| !x.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "invalid input: {what}[{}] has a non-finite coordinate ({})",
            i / shape[1],
            flat[i]
        )));
    }
    Ok((flat, shape[0], shape[1]))
}

/// A 1-D array-like of numbers (finiteness not checked).
pub fn vector(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    let arr: PyArrayLike1<f64, AllowTypeChange> = obj.extract().map_err(|_| {
        PyValueError::new_err(format!("{what}: expected a 1-D sequence of numbers"))
    })?;
    Ok(arr.as_array().iter().copied().collect())
}

/// A 3-vector.
pub fn vec3(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<[f64; 3]> {
    let v = vector(obj, what)?;
    <[f64; 3]>::try_from(v.as_slice()).map_err(|_| {
        PyValueError::new_err(format!(
            "{what}: expected 3 values (x, y, z), got {}",
            v.len()
        ))
    })
}

fn handle_json(index: u32, generation: u32) -> Value {
    serde_json::json!({ "index": index, "generation": generation })
}

/// Python value → JSON for serde: dicts, lists, tuples, numbers, bools,
/// strings, None, numpy arrays and scalars; Rod objects and handles become
/// their handle. Non-finite floats are rejected here (JSON cannot carry
/// them), naming the field.
pub fn to_json(obj: &Bound<'_, PyAny>, path: &str) -> PyResult<Value> {
    if obj.is_none() {
        return Ok(Value::Null);
    }
    if obj.is_instance_of::<PyBool>() {
        return Ok(Value::Bool(obj.extract()?));
    }
    if obj.is_instance_of::<PyInt>() {
        if let Ok(i) = obj.extract::<i64>() {
            return Ok(Value::from(i));
        }
        return Ok(Value::from(obj.extract::<u64>()?));
    }
    if obj.is_instance_of::<PyFloat>() {
        let x: f64 = obj.extract()?;
        return serde_json::Number::from_f64(x)
            .map(Value::Number)
            .ok_or_else(|| {
                PyValueError::new_err(format!("invalid input: {path} must be finite, got {x}"))
            });
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return Ok(Value::String(s.to_cow()?.into_owned()));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut m = Map::new();
        for (k, v) in d.iter() {
            let key: String = k
                .extract()
                .map_err(|_| PyTypeError::new_err(format!("{path}: dict keys must be str")))?;
            let sub = if path.is_empty() {
                key.clone()
            } else {
                format!("{path}.{key}")
            };
            m.insert(key, to_json(&v, &sub)?);
        }
        return Ok(Value::Object(m));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for (i, v) in obj.try_iter()?.enumerate() {
            out.push(to_json(&v?, &format!("{path}[{i}]"))?);
        }
        return Ok(Value::Array(out));
    }
    if let Ok(r) = obj.cast::<PyRod>() {
        let (i, g) = r.borrow().handle_parts().ok_or_else(|| {
            PyValueError::new_err(format!(
                "{path}: this rod is not in a world yet (add it with world.add_rod first)"
            ))
        })?;
        return Ok(handle_json(i, g));
    }
    if let Ok(c) = obj.cast::<PyConstraintHandle>() {
        let h = c.get().handle;
        return Ok(handle_json(h.index, h.generation));
    }
    if let Ok(b) = obj.cast::<PyBeadHandle>() {
        let h = b.get().handle;
        return Ok(handle_json(h.index, h.generation));
    }
    if let Ok(l) = obj.cast::<PyLoadHandle>() {
        let h = l.get().handle;
        return Ok(handle_json(h.index, h.generation));
    }
    // numpy arrays and scalars (np.float64 is a float already; np.bool_ and arrays are not).
    if obj.hasattr("tolist")? {
        return to_json(&obj.call_method0("tolist")?, path);
    }
    if obj.hasattr("to_dict")? {
        return to_json(&obj.call_method0("to_dict")?, path);
    }
    Err(PyTypeError::new_err(format!(
        "{path}: cannot convert {} to a constraint/load field",
        obj.get_type().name()?
    )))
}

/// JSON → Python (dict / list / float / int / str / bool / None).
pub fn from_json<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else {
                n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any()
            }
        }
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(a) => {
            let l = PyList::empty(py);
            for x in a {
                l.append(from_json(py, x)?)?;
            }
            l.into_any()
        }
        Value::Object(m) => {
            let d = PyDict::new(py);
            for (k, x) in m {
                d.set_item(k, from_json(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// `{"Variant": {fields}}` (serde's external tagging) → (variant, fields).
pub fn variant(v: &Value) -> (String, Value) {
    match v {
        Value::Object(m) if m.len() == 1 => {
            let (k, x) = m
                .iter()
                .next()
                .map(|(k, x)| (k.clone(), x.clone()))
                .unwrap_or_default();
            (k, x)
        }
        Value::String(s) => (s.clone(), Value::Null),
        other => (String::new(), other.clone()),
    }
}

/// Short "Name(a=1, b=[0, 0, 1])" rendering of a serde enum value.
pub fn describe(v: &Value) -> String {
    let (name, fields) = variant(v);
    match fields {
        Value::Object(m) => {
            let parts: Vec<String> = m.iter().map(|(k, x)| format!("{k}={}", short(x))).collect();
            format!("{name}({})", parts.join(", "))
        }
        Value::Null => name,
        other => format!("{name}({})", short(&other)),
    }
}

fn short(v: &Value) -> String {
    match v {
        Value::Number(n) => match n.as_f64() {
            Some(x) if n.is_f64() => format!("{x:.6}")
                .trim_end_matches('0')
                .trim_end_matches('.')
                .to_string(),
            _ => n.to_string(),
        },
        Value::Bool(b) => if *b { "True" } else { "False" }.into(),
        Value::Array(a) => format!("[{}]", a.iter().map(short).collect::<Vec<_>>().join(", ")),
        Value::Object(m) if m.contains_key("index") => format!("#{}", m["index"]),
        Value::Object(_) => describe(v),
        Value::String(s) => format!("{s:?}"),
        Value::Null => "None".into(),
    }
}
