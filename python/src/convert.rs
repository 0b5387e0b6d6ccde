//! numpy, JSON and keyword-argument conversions shared by the bindings.
//!
//! A leaf module: it knows no binding type. Python objects that stand for
//! an object of a world (a Rod in a world, a ConstraintHandle, …) are
//! recognised by their `_handle` attribute, a tuple `(kind, index,
//! generation)`; in the other direction, handles inside core values are
//! tagged by their serde type ([`tagged`]) and turned into live objects by
//! a factory the caller passes to [`from_json_with`].
use crate::bad;
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLike1, PyArrayLike2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde::de::DeserializeOwned;
use serde::ser::{self, Serialize};
use serde_json::{Map, Number, Value};

/// Flat row-major values → numpy array of shape (rows, cols).
pub fn array2<'py>(py: Python<'py>, flat: Vec<f64>, cols: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let rows = flat.len().checked_div(cols).unwrap_or(0);
    PyArray1::from_vec(py, flat).reshape([rows, cols])
}

/// Points → (n, 3) array.
pub fn points<'py>(py: Python<'py>, p: impl IntoIterator<Item = [f64; 3]>) -> PyResult<Bound<'py, PyArray2<f64>>> {
    array2(py, p.into_iter().flatten().collect(), 3)
}

fn join(cols: &[usize]) -> String {
    cols.iter().map(|c| c.to_string()).collect::<Vec<_>>().join(" or ")
}

/// Any array-like of shape (n, c) with c in `cols` → (flat values, n, c),
/// all finite.
pub fn matrix(obj: &Bound<'_, PyAny>, cols: &[usize], what: &str) -> PyResult<(Vec<f64>, usize, usize)> {
    let arr: PyArrayLike2<f64, AllowTypeChange> = obj
        .extract()
        .map_err(|_| bad(format!("{what}: expected a 2-D array of numbers with {} columns", join(cols))))?;
    let shape = arr.shape().to_vec();
    if !cols.contains(&shape[1]) {
        return Err(bad(format!("{what}: expected shape (n, {}), got ({}, {})", join(cols), shape[0], shape[1])));
    }
    let flat: Vec<f64> = arr.as_array().iter().copied().collect();
    if let Some(i) = flat.iter().position(|x| !x.is_finite()) {
        return Err(bad(format!("{what}[{}] has a non-finite coordinate ({})", i / shape[1], flat[i])));
    }
    Ok((flat, shape[0], shape[1]))
}

/// A 1-D array-like of numbers (finiteness not checked).
pub fn vector(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    let arr: PyArrayLike1<f64, AllowTypeChange> =
        obj.extract().map_err(|_| bad(format!("{what}: expected a 1-D sequence of numbers")))?;
    Ok(arr.as_array().iter().copied().collect())
}

/// A 3-vector.
pub fn vec3(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<[f64; 3]> {
    let v = vector(obj, what)?;
    <[f64; 3]>::try_from(v.as_slice()).map_err(|_| bad(format!("{what}: expected 3 values (x, y, z), got {}", v.len())))
}

/// The `(kind, index, generation)` of an object that stands for something
/// in a world (its `_handle` attribute), or None for any other object.
/// A free rod has `_handle` None: an error naming `path`.
pub fn handle_of(obj: &Bound<'_, PyAny>, path: &str) -> PyResult<Option<(String, u32, u32)>> {
    let Ok(h) = obj.getattr("_handle") else { return Ok(None) };
    if h.is_none() {
        return Err(bad(format!("{path}: this {} is not in a world yet (add it to the world first)", obj.get_type().name()?)));
    }
    Ok(Some(h.extract()?))
}

/// Checks that `obj` (which has a `world` attribute) belongs to `owner`.
fn check_owner(obj: &Bound<'_, PyAny>, owner: Option<&Bound<'_, PyAny>>, path: &str, kind: &str) -> PyResult<()> {
    if let Some(w) = owner {
        if !obj.getattr("world")?.is(w) {
            return Err(bad(format!("{path}: this {kind} belongs to another world")));
        }
    }
    Ok(())
}

/// Python value → JSON for serde: dicts, lists, tuples, numbers, bools,
/// strings, None, numpy arrays and scalars; objects with a `_handle`
/// (rods in a world, handles) become `{"index": …, "generation": …}` —
/// when `owner` is given they must belong to that world. Non-finite floats
/// are rejected here (JSON cannot carry them), naming the field.
pub fn to_json_in(obj: &Bound<'_, PyAny>, path: &str, owner: Option<&Bound<'_, PyAny>>) -> PyResult<Value> {
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
        return Number::from_f64(x).map(Value::Number).ok_or_else(|| {
            crate::err(strandkit_core::Error::invalid(path, x, "finite"))
        });
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return Ok(Value::String(s.to_cow()?.into_owned()));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut m = Map::new();
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| bad(format!("{path}: dict keys must be str")))?;
            let sub = if path.is_empty() { key.clone() } else { format!("{path}.{key}") };
            m.insert(key, to_json_in(&v, &sub, owner)?);
        }
        return Ok(Value::Object(m));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut out = Vec::new();
        for (i, v) in obj.try_iter()?.enumerate() {
            out.push(to_json_in(&v?, &format!("{path}[{i}]"), owner)?);
        }
        return Ok(Value::Array(out));
    }
    if let Some((kind, index, generation)) = handle_of(obj, path)? {
        check_owner(obj, owner, path, &kind)?;
        return Ok(serde_json::json!({ "index": index, "generation": generation }));
    }
    // numpy arrays and scalars (np.float64 is a float already; np.bool_ and arrays are not).
    if obj.hasattr("tolist")? {
        return to_json_in(&obj.call_method0("tolist")?, path, owner);
    }
    if obj.hasattr("to_dict")? {
        return to_json_in(&obj.call_method0("to_dict")?, path, owner);
    }
    Err(bad(format!("{path}: cannot convert {} to a field value", obj.get_type().name()?)))
}

/// [`to_json_in`] without an ownership check.
pub fn to_json(obj: &Bound<'_, PyAny>, path: &str) -> PyResult<Value> {
    to_json_in(obj, path, None)
}

/// A factory turning a tagged handle `(kind, index, generation)` into a
/// live Python object.
pub type Live<'a, 'py> = &'a dyn Fn(&str, u32, u32) -> PyResult<Bound<'py, PyAny>>;

/// JSON → Python (dict / list / float / int / str / bool / None); tagged
/// handles (see [`tagged`]) become `live(kind, index, generation)`, or a
/// dict `{"index", "generation"}` without a factory.
pub fn from_json_with<'py>(py: Python<'py>, v: &Value, live: Option<Live<'_, 'py>>) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else {
                n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any()
            }
        }
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(a) => {
            let l = PyList::empty(py);
            for x in a {
                l.append(from_json_with(py, x, live)?)?;
            }
            l.into_any()
        }
        Value::Object(m) => {
            if let Some((kind, index, generation)) = tag_of(m) {
                if let Some(f) = live {
                    return f(kind, index, generation);
                }
            }
            let d = PyDict::new(py);
            for (k, x) in m {
                if k != TAG {
                    d.set_item(k, from_json_with(py, x, live)?)?;
                }
            }
            d.into_any()
        }
    })
}

/// [`from_json_with`] without a factory.
pub fn from_json<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    from_json_with(py, v, None)
}

/// `{"Variant": {fields}}` (serde's external tagging) → (variant, fields).
pub fn variant(v: &Value) -> (String, Value) {
    match v {
        Value::Object(m) if m.len() == 1 => {
            let (k, x) = m.iter().next().map(|(k, x)| (k.clone(), x.clone())).unwrap_or_default();
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
            let parts: Vec<String> = m.iter().filter(|(k, _)| *k != TAG).map(|(k, x)| format!("{k}={}", short(x))).collect();
            format!("{name}({})", parts.join(", "))
        }
        Value::Null => name,
        other => format!("{name}({})", short(&other)),
    }
}

/// Strings as a Python list literal: `['a', 'b']`.
pub fn py_strs<S: AsRef<str>>(items: impl IntoIterator<Item = S>) -> String {
    let quoted: Vec<String> = items.into_iter().map(|s| format!("'{}'", s.as_ref().replace('\\', "\\\\").replace('\'', "\\'"))).collect();
    format!("[{}]", quoted.join(", "))
}

/// Short rendering of one value (floats to 6 significant places, handles as #index).
pub fn short(v: &Value) -> String {
    match v {
        Value::Number(n) => match n.as_f64() {
            Some(x) if n.is_f64() => format!("{x:.6}").trim_end_matches('0').trim_end_matches('.').to_string(),
            _ => n.to_string(),
        },
        Value::Bool(b) => if *b { "True" } else { "False" }.into(),
        Value::Array(a) => format!("[{}]", a.iter().map(short).collect::<Vec<_>>().join(", ")),
        Value::Object(m) if m.contains_key("index") && m.contains_key("generation") => format!("#{}", m["index"]),
        Value::Object(_) => describe(v),
        Value::String(s) => format!("{s:?}"),
        Value::Null => "None".into(),
    }
}

// ---------------------------------------------------------------------------
// keyword arguments → serde struct

/// Keyword arguments as (name, value) pairs.
pub fn kwargs<'py>(d: Option<&Bound<'py, PyDict>>) -> PyResult<Vec<(String, Bound<'py, PyAny>)>> {
    let mut out = Vec::new();
    if let Some(d) = d {
        for (k, v) in d.iter() {
            out.push((k.extract()?, v));
        }
    }
    Ok(out)
}

/// `base` with the given fields replaced: the one converter from keyword
/// arguments to a core struct (integration parameters, quasi-dynamic
/// parameters, rod options). Every key must be a field of `T` (else an
/// InvalidInputError listing the accepted ones); None sets the field to
/// `T::default()`'s value; a dict given for a struct-valued field updates
/// only the keys it names. `what` names the struct in messages.
pub fn kwargs_into<'py, T>(base: &T, pairs: impl IntoIterator<Item = (String, Bound<'py, PyAny>)>, what: &str) -> PyResult<T>
where
    T: Serialize + DeserializeOwned + Default,
{
    let object = |v: Value| match v {
        Value::Object(m) => m,
        _ => Map::new(),
    };
    let mut cur = object(serde_json::to_value(base).map_err(|e| bad(format!("{what}: {e}")))?);
    let defaults = object(serde_json::to_value(T::default()).map_err(|e| bad(format!("{what}: {e}")))?);
    for (key, x) in pairs {
        let Some(slot) = cur.get_mut(&key) else {
            let known: Vec<&str> = cur.keys().map(|k| k.as_str()).collect();
            return Err(crate::err(strandkit_core::Error::invalid(
                format!("unknown {what} {key:?}"),
                "",
                format!("one of {}", known.join(", ")),
            )));
        };
        if x.is_none() {
            *slot = defaults.get(&key).cloned().unwrap_or(Value::Null);
            continue;
        }
        let new = to_json(&x, &key)?;
        merge(slot, new, &format!("{what} {key}"))?;
        // Checked field by field, so that a bad value is named.
        serde_json::from_value::<T>(Value::Object(cur.clone())).map_err(|e| bad(format!("{what} {key}: {e}")))?;
    }
    serde_json::from_value(Value::Object(cur)).map_err(|e| bad(format!("{what}: {e}")))
}

/// Replaces `slot` by `new`, or, both being objects, updates the keys `new` names.
fn merge(slot: &mut Value, new: Value, what: &str) -> PyResult<()> {
    match (slot, new) {
        (Value::Object(cur), Value::Object(upd)) => {
            for (k, v) in upd {
                let Some(s) = cur.get_mut(&k) else {
                    let known: Vec<&str> = cur.keys().map(|k| k.as_str()).collect();
                    return Err(crate::err(strandkit_core::Error::invalid(
                        format!("unknown {what} field {k:?}"),
                        "",
                        format!("one of {}", known.join(", ")),
                    )));
                };
                merge(s, v, &format!("{what}.{k}"))?;
            }
            Ok(())
        }
        (slot, new) => {
            *slot = new;
            Ok(())
        }
    }
}

// ---------------------------------------------------------------------------
// serde → JSON with handles tagged by their type

/// The key marking a tagged handle, and the serde struct names of the
/// core's handle types with the kind they are tagged as.
pub const TAG: &str = "$handle";
const HANDLE_TYPES: [(&str, &str); 5] = [
    ("RodHandle", "rod"),
    ("ConstraintHandle", "constraint"),
    ("LoadHandle", "load"),
    ("BeadHandle", "bead"),
    ("ClipHandle", "clip"),
];

fn tag_of(m: &Map<String, Value>) -> Option<(&str, u32, u32)> {
    let kind = m.get(TAG)?.as_str()?;
    let index = u32::try_from(m.get("index")?.as_u64()?).ok()?;
    let generation = u32::try_from(m.get("generation")?.as_u64()?).ok()?;
    Some((kind, index, generation))
}

/// A core value as JSON (like `serde_json::to_value`), with every handle
/// recognised by its serde type: `{"$handle": "rod", "index": …,
/// "generation": …}` for a RodHandle, and so on. Events, constraints,
/// beads, clips and group states go through this, so their handles become
/// live objects whatever the field is called.
pub fn tagged<T: Serialize + ?Sized>(v: &T) -> Value {
    v.serialize(Tagging).unwrap_or(Value::Null)
}

struct Tagging;
type SerError = serde_json::Error;

fn key_string(v: Value) -> Result<String, SerError> {
    match v {
        Value::String(s) => Ok(s),
        Value::Number(n) => Ok(n.to_string()),
        Value::Bool(b) => Ok(b.to_string()),
        _ => Err(ser::Error::custom("map key must be a string")),
    }
}

impl ser::Serializer for Tagging {
    type Ok = Value;
    type Error = SerError;
    type SerializeSeq = Seq;
    type SerializeTuple = Seq;
    type SerializeTupleStruct = Seq;
    type SerializeTupleVariant = VariantSeq;
    type SerializeMap = MapSer;
    type SerializeStruct = StructSer;
    type SerializeStructVariant = VariantStruct;

    fn serialize_bool(self, v: bool) -> Result<Value, SerError> {
        Ok(Value::Bool(v))
    }
    fn serialize_i8(self, v: i8) -> Result<Value, SerError> {
        Ok(Value::from(v))
    }
    fn serialize_i16(self, v: i16) -> Result<Value, SerError> {
        Ok(Value::from(v))
    }
    fn serialize_i32(self, v: i32) -> Result<Value, SerError> {
        Ok(Value::from(v))
    }
    fn serialize_i64(self, v: i64) -> Result<Value, SerError> {
        Ok(Value::from(v))
    }
    fn serialize_u8(self, v: u8) -> Result<Value, SerError> {
        Ok(Value::from(v))
    }
    fn serialize_u16(self, v: u16) -> Result<Value, SerError> {
        Ok(Value::from(v))
    }
    fn serialize_u32(self, v: u32) -> Result<Value, SerError> {
        Ok(Value::from(v))
    }
    fn serialize_u64(self, v: u64) -> Result<Value, SerError> {
        Ok(Value::from(v))
    }
    fn serialize_f32(self, v: f32) -> Result<Value, SerError> {
        self.serialize_f64(f64::from(v))
    }
    fn serialize_f64(self, v: f64) -> Result<Value, SerError> {
        Ok(Number::from_f64(v).map_or(Value::Null, Value::Number))
    }
    fn serialize_char(self, v: char) -> Result<Value, SerError> {
        Ok(Value::String(v.to_string()))
    }
    fn serialize_str(self, v: &str) -> Result<Value, SerError> {
        Ok(Value::String(v.to_string()))
    }
    fn serialize_bytes(self, v: &[u8]) -> Result<Value, SerError> {
        Ok(Value::Array(v.iter().map(|b| Value::from(*b)).collect()))
    }
    fn serialize_none(self) -> Result<Value, SerError> {
        Ok(Value::Null)
    }
    fn serialize_some<T: Serialize + ?Sized>(self, v: &T) -> Result<Value, SerError> {
        v.serialize(self)
    }
    fn serialize_unit(self) -> Result<Value, SerError> {
        Ok(Value::Null)
    }
    fn serialize_unit_struct(self, _: &'static str) -> Result<Value, SerError> {
        Ok(Value::Null)
    }
    fn serialize_unit_variant(self, _: &'static str, _: u32, variant: &'static str) -> Result<Value, SerError> {
        Ok(Value::String(variant.to_string()))
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(self, _: &'static str, v: &T) -> Result<Value, SerError> {
        v.serialize(self)
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        variant: &'static str,
        v: &T,
    ) -> Result<Value, SerError> {
        let mut m = Map::new();
        m.insert(variant.to_string(), v.serialize(Tagging)?);
        Ok(Value::Object(m))
    }
    fn serialize_seq(self, len: Option<usize>) -> Result<Seq, SerError> {
        Ok(Seq(Vec::with_capacity(len.unwrap_or(0))))
    }
    fn serialize_tuple(self, len: usize) -> Result<Seq, SerError> {
        Ok(Seq(Vec::with_capacity(len)))
    }
    fn serialize_tuple_struct(self, _: &'static str, len: usize) -> Result<Seq, SerError> {
        Ok(Seq(Vec::with_capacity(len)))
    }
    fn serialize_tuple_variant(self, _: &'static str, _: u32, variant: &'static str, len: usize) -> Result<VariantSeq, SerError> {
        Ok(VariantSeq(variant, Vec::with_capacity(len)))
    }
    fn serialize_map(self, _: Option<usize>) -> Result<MapSer, SerError> {
        Ok(MapSer(Map::new(), None))
    }
    fn serialize_struct(self, name: &'static str, _: usize) -> Result<StructSer, SerError> {
        Ok(StructSer(name, Map::new()))
    }
    fn serialize_struct_variant(self, _: &'static str, _: u32, variant: &'static str, _: usize) -> Result<VariantStruct, SerError> {
        Ok(VariantStruct(variant, Map::new()))
    }
}

struct Seq(Vec<Value>);
struct VariantSeq(&'static str, Vec<Value>);
struct MapSer(Map<String, Value>, Option<String>);
struct StructSer(&'static str, Map<String, Value>);
struct VariantStruct(&'static str, Map<String, Value>);

fn wrap(variant: &str, v: Value) -> Value {
    let mut m = Map::new();
    m.insert(variant.to_string(), v);
    Value::Object(m)
}

macro_rules! seq_impl {
    ($tr:ident, $method:ident) => {
        impl ser::$tr for Seq {
            type Ok = Value;
            type Error = SerError;
            fn $method<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), SerError> {
                self.0.push(v.serialize(Tagging)?);
                Ok(())
            }
            fn end(self) -> Result<Value, SerError> {
                Ok(Value::Array(self.0))
            }
        }
    };
}
seq_impl!(SerializeSeq, serialize_element);
seq_impl!(SerializeTuple, serialize_element);
seq_impl!(SerializeTupleStruct, serialize_field);

impl ser::SerializeTupleVariant for VariantSeq {
    type Ok = Value;
    type Error = SerError;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), SerError> {
        self.1.push(v.serialize(Tagging)?);
        Ok(())
    }
    fn end(self) -> Result<Value, SerError> {
        Ok(wrap(self.0, Value::Array(self.1)))
    }
}

impl ser::SerializeMap for MapSer {
    type Ok = Value;
    type Error = SerError;
    fn serialize_key<T: Serialize + ?Sized>(&mut self, k: &T) -> Result<(), SerError> {
        self.1 = Some(key_string(k.serialize(Tagging)?)?);
        Ok(())
    }
    fn serialize_value<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), SerError> {
        let k = self.1.take().ok_or_else(|| <SerError as ser::Error>::custom("map value without a key"))?;
        self.0.insert(k, v.serialize(Tagging)?);
        Ok(())
    }
    fn end(self) -> Result<Value, SerError> {
        Ok(Value::Object(self.0))
    }
}

impl ser::SerializeStruct for StructSer {
    type Ok = Value;
    type Error = SerError;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, key: &'static str, v: &T) -> Result<(), SerError> {
        self.1.insert(key.to_string(), v.serialize(Tagging)?);
        Ok(())
    }
    fn end(mut self) -> Result<Value, SerError> {
        if let Some((_, kind)) = HANDLE_TYPES.iter().find(|(n, _)| *n == self.0) {
            self.1.insert(TAG.to_string(), Value::String((*kind).to_string()));
        }
        Ok(Value::Object(self.1))
    }
}

impl ser::SerializeStructVariant for VariantStruct {
    type Ok = Value;
    type Error = SerError;
    fn serialize_field<T: Serialize + ?Sized>(&mut self, key: &'static str, v: &T) -> Result<(), SerError> {
        self.1.insert(key.to_string(), v.serialize(Tagging)?);
        Ok(())
    }
    fn end(self) -> Result<Value, SerError> {
        Ok(wrap(self.0, Value::Object(self.1)))
    }
}
