//! Assemblies from Python: a structure described before it exists (rods,
//! constraints with compliance, break thresholds and labels, loads,
//! beads), referring to its own rods by index, inserted into a world in
//! one checked batch by `World.insert`.
use crate::convert::{self, from_json};
use crate::guard;
use crate::rod::PyRod;
use pyo3::prelude::*;
use serde_json::Value;
use strandkit_core::assembly::AssemblyConstraint;
use strandkit_core::constraint::FieldInfo;
use strandkit_core::world::groups::{base_of, check_label};
use strandkit_core::{Assembly, Breaking, ConstraintKind, Load};

/// A structure to insert into a world (`World.insert(assembly)`): rods,
/// constraints, loads and beads, referring to the assembly's rods by the
/// index `add_rod` returned. Labels such as "rung[3]" make groups
/// ("rung") that the world answers for after insertion (`World.group`).
/// Nothing is checked against a world until insertion, which is atomic:
/// on any error the world is unchanged. `to_json()` / `Assembly.from_json`
/// round-trip exactly.
///
/// >>> import strandkit as sk
/// >>> asm = sk.Assembly()
/// >>> rail = lambda y: sk.straight((0, y, 0), (1, y, 0), section=0.005, material="nylon", n_control_points=6)
/// >>> a, b = asm.add_rod(rail(0.0), "rail[0]"), asm.add_rod(rail(-0.1), "rail[1]")
/// >>> for i, u in enumerate([1.0, 2.0, 3.0]):
/// ...     _ = asm.link(a, b, sk.relative_distance(u, u, 0.1), break_force=5.0, policy="tension", label=f"rung[{i}]")
/// >>> asm
/// Assembly(rods=2, constraints=3, loads=0, beads=0, groups=['rail', 'rung'])
/// >>> world = sk.World()
/// >>> inserted = world.insert(asm)
/// >>> len(inserted.rods), world.group("rung").labels
/// (2, ['rung[0]', 'rung[1]', 'rung[2]'])
#[pyclass(name = "Assembly", module = "strandkit._native")]
#[derive(Clone, Default)]
pub struct PyAssembly {
    pub(crate) inner: Assembly,
}

/// A label checked now (the core checks it again at insertion).
fn label_arg(label: Option<String>) -> PyResult<Option<String>> {
    if let Some(l) = &label {
        guard(|| check_label(l))?;
    }
    Ok(label)
}

/// A break threshold from the Python keywords.
pub(crate) fn breaking(break_force: Option<f64>, policy: &str, tension_only: bool) -> PyResult<Option<Breaking>> {
    let p: strandkit_core::BreakPolicy = serde_json::from_value(Value::String(policy.to_string())).map_err(|_| {
        crate::err(strandkit_core::Error::invalid("policy", format!("{policy:?}"), "\"magnitude\", \"tension\" or \"compression\""))
    })?;
    let p = match (tension_only, p) {
        (false, p) => p,
        (true, strandkit_core::BreakPolicy::Compression) => {
            return Err(crate::bad("tension_only=True contradicts policy=\"compression\""))
        }
        (true, _) => strandkit_core::BreakPolicy::Tension,
    };
    match break_force {
        Some(force) => Ok(Some(Breaking::new(force, p))),
        None if p != strandkit_core::BreakPolicy::Magnitude => {
            Err(crate::bad(format!("policy={:?} needs break_force (the force above which the constraint breaks)", policy)))
        }
        None => Ok(None),
    }
}

/// A constraint kind given as a dict (or JSON text).
pub(crate) fn constraint_kind(kind: &Bound<'_, PyAny>, owner: Option<&Bound<'_, PyAny>>) -> PyResult<ConstraintKind> {
    let v = json_arg(kind, "constraint", owner)?;
    let fields = |name: &str| ConstraintKind::CATALOGUE.iter().find(|k| k.name == name).map(|k| k.fields);
    known_fields(&v, "constraint", "add_constraint / add_link", fields)?;
    serde_json::from_value(v).map_err(|e| crate::bad(format!("constraint kind: {e}")))
}

/// A load given as a dict (or JSON text), its rod fields as JSON.
pub(crate) fn load_value(load: &Bound<'_, PyAny>, owner: Option<&Bound<'_, PyAny>>) -> PyResult<Value> {
    let v = json_arg(load, "load", owner)?;
    known_fields(&v, "load", "add_load", |name| Load::CATALOGUE.iter().find(|l| l.name == name).map(|l| l.fields))?;
    Ok(v)
}

/// Every field of a kind `{"Name": {field: …}}` must be one the catalogue
/// lists: serde would silently drop any other (a misspelt field, or a
/// `label` meant for the call). Unknown kind names are left to serde,
/// which lists the variants.
fn known_fields(v: &Value, what: &str, call: &str, fields: impl Fn(&str) -> Option<&'static [FieldInfo]>) -> PyResult<()> {
    let (name, given) = convert::variant(v);
    let (Some(known), Value::Object(given)) = (fields(&name), given) else { return Ok(()) };
    for key in given.keys() {
        if !known.iter().any(|f| f.name == key) {
            let names: Vec<&str> = known.iter().map(|f| f.name).collect();
            let hint = match key.as_str() {
                "label" | "compliance" | "break_force" | "policy" | "tension_only" => {
                    format!(" ({key}= is a keyword of {call}, not a field of the kind)")
                }
                _ => String::new(),
            };
            return Err(crate::err(strandkit_core::Error::invalid(
                format!("unknown {what} {name} field {key:?}{hint}"),
                "",
                format!("one of {}", names.join(", ")),
            )));
        }
    }
    Ok(())
}

/// Names of the fields of type rod of a load kind (from the catalogue).
pub(crate) fn rod_fields(kind: &str) -> Vec<&'static str> {
    Load::CATALOGUE
        .iter()
        .filter(|l| l.name == kind)
        .flat_map(|l| l.fields.iter())
        .filter(|f| f.ty == strandkit_core::constraint::FieldType::Rod)
        .map(|f| f.name)
        .collect()
}

/// A kind given as a dict (or JSON text) → JSON value.
fn json_arg(obj: &Bound<'_, PyAny>, what: &str, owner: Option<&Bound<'_, PyAny>>) -> PyResult<Value> {
    if let Ok(s) = obj.extract::<String>() {
        if s.trim_start().starts_with('{') {
            return serde_json::from_str(&s).map_err(|e| crate::bad(format!("{what}: {e}")));
        }
    }
    convert::to_json_in(obj, what, owner)
}

impl PyAssembly {
    fn rod_index(&self, what: &str, i: usize) -> PyResult<usize> {
        if i < self.inner.rods.len() {
            Ok(i)
        } else {
            Err(crate::err(strandkit_core::Error::invalid(
                what,
                i,
                format!("an index of the assembly's rods (0..{})", self.inner.rods.len()),
            )))
        }
    }
    #[allow(clippy::too_many_arguments)]
    fn push_constraint(
        &mut self,
        rod: usize,
        other: Option<usize>,
        kind: &Bound<'_, PyAny>,
        compliance: f64,
        break_force: Option<f64>,
        policy: &str,
        tension_only: bool,
        label: Option<String>,
    ) -> PyResult<usize> {
        self.rod_index("constraint rod", rod)?;
        if let Some(o) = other {
            self.rod_index("constraint other rod", o)?;
        }
        let kind = constraint_kind(kind, None)?;
        let breaking = breaking(break_force, policy, tension_only)?;
        let label = label_arg(label)?;
        self.inner.constraints.push(AssemblyConstraint { rod, other, kind, compliance, breaking, label, breaks_with: Vec::new(), fails_with: Vec::new(), held_at_end: false });
        Ok(self.inner.constraints.len() - 1)
    }
    fn labels(&self) -> Vec<String> {
        self.inner.labels().map(String::from).collect()
    }
}

#[pymethods]
impl PyAssembly {
    #[new]
    fn new() -> Self {
        PyAssembly::default()
    }
    /// Adds a copy of `rod` (its current state; a free rod or one in a
    /// world) with an optional `label`; returns its index in the assembly.
    #[pyo3(signature = (rod, label = None))]
    fn add_rod(&mut self, py: Python<'_>, rod: &Bound<'_, PyRod>, label: Option<String>) -> PyResult<usize> {
        let r = rod.try_borrow()?.with(py, |r| Ok(r.clone()))?;
        let label = label_arg(label)?;
        Ok(self.inner.add_rod(r, label.as_deref()))
    }
    /// A one-rod constraint (`kind` from strandkit.position, tangent, …) on
    /// the assembly's rod `rod`: `compliance` (length/force; 0 = hard),
    /// `break_force` (force unit; None = unbreakable) measured by `policy`
    /// ("magnitude" | "tension" | "compression"; `tension_only=True` is
    /// policy="tension"), `label` (e.g. "pin[2]"). Returns its index.
    #[pyo3(signature = (rod, kind, *, compliance = 0.0, break_force = None, policy = "magnitude", tension_only = false, label = None))]
    #[allow(clippy::too_many_arguments)]
    fn constrain(
        &mut self,
        rod: usize,
        kind: &Bound<'_, PyAny>,
        compliance: f64,
        break_force: Option<f64>,
        policy: &str,
        tension_only: bool,
        label: Option<String>,
    ) -> PyResult<usize> {
        self.push_constraint(rod, None, kind, compliance, break_force, policy, tension_only, label)
    }
    /// A relative constraint (relative_position, relative_distance, …)
    /// between the assembly's rods `a` and `b` (may be equal). Keywords as
    /// `constrain`. Returns its index.
    #[pyo3(signature = (a, b, kind, *, compliance = 0.0, break_force = None, policy = "magnitude", tension_only = false, label = None))]
    #[allow(clippy::too_many_arguments)]
    fn link(
        &mut self,
        a: usize,
        b: usize,
        kind: &Bound<'_, PyAny>,
        compliance: f64,
        break_force: Option<f64>,
        policy: &str,
        tension_only: bool,
        label: Option<String>,
    ) -> PyResult<usize> {
        self.push_constraint(a, Some(b), kind, compliance, break_force, policy, tension_only, label)
    }
    /// A load (strandkit.point_force, distributed, trap, …) on the
    /// assembly's rod `rod`; the load's own `rod` field is ignored (give
    /// None). Returns its index.
    #[pyo3(signature = (rod, load, label = None))]
    fn add_load(&mut self, rod: usize, load: &Bound<'_, PyAny>, label: Option<String>) -> PyResult<usize> {
        self.rod_index("load rod", rod)?;
        let mut v = load_value(load, None)?;
        if let Value::Object(m) = &mut v {
            for (name, fields) in m.iter_mut() {
                if let Value::Object(f) = fields {
                    for r in rod_fields(name) {
                        f.insert(r.to_string(), serde_json::json!({"index": 0, "generation": 0}));
                    }
                }
            }
        }
        let l: Load = serde_json::from_value(v).map_err(|e| crate::bad(format!("load: {e}")))?;
        let label = label_arg(label)?;
        Ok(self.inner.add_load(rod, l, label.as_deref()))
    }
    /// A bead on the assembly's rod `rod` at abscissa `u`: `mass` (mass
    /// unit, > 0), viscous `friction` (force per speed), `radius` (length).
    /// `fixed`: knotted at `u` (it does not slide). Returns its index.
    #[pyo3(signature = (rod, u, *, mass, friction = 0.0, radius = 0.0, fixed = false, label = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_bead(&mut self, rod: usize, u: f64, mass: f64, friction: f64, radius: f64, fixed: bool, label: Option<String>) -> PyResult<usize> {
        self.rod_index("bead rod", rod)?;
        let label = label_arg(label)?;
        let i = self.inner.add_bead(rod, u, mass, friction, radius, label.as_deref());
        self.inner.beads[i].fixed = fixed;
        Ok(i)
    }
    /// A clip of the assembly: `center` (length), capture `radius`
    /// (length, > 0), exit `axis` (a direction) and pull-out `resistance`
    /// (force, > 0). Once inserted it captures a rod that comes within its
    /// radius and releases it when pulled out along the axis harder than
    /// the resistance (events ClipCaptured / ClipReleased); the values are
    /// checked at insertion. Returns its index.
    #[pyo3(signature = (center, *, radius, axis, resistance, label = None))]
    fn add_clip(&mut self, center: &Bound<'_, PyAny>, radius: f64, axis: &Bound<'_, PyAny>, resistance: f64, label: Option<String>) -> PyResult<usize> {
        let (c, a) = (convert::vec3(center, "clip center")?, convert::vec3(axis, "clip axis")?);
        let label = label_arg(label)?;
        Ok(self.inner.add_clip(c, radius, a, resistance, label.as_deref()))
    }
    /// Clip `clip` holds the assembly's rod `rod` at abscissa `u` from the
    /// start (a point constraint to the clip's centre, released by the
    /// clip like a captured rod). Returns the constraint's index.
    fn hold_in_clip(&mut self, clip: usize, rod: usize, u: f64) -> PyResult<usize> {
        self.rod_index("clip rod", rod)?;
        if !u.is_finite() {
            return Err(crate::err(strandkit_core::Error::invalid("u", u, "a finite abscissa on the rod")));
        }
        self.inner.hold_in_clip(clip, rod, u).map_err(crate::err)
    }
    #[getter]
    fn n_clips(&self) -> usize {
        self.inner.clips.len()
    }
    /// A free copy of the assembly's rod `i`.
    fn rod(&self, i: usize) -> PyResult<PyRod> {
        self.rod_index("rod", i)?;
        Ok(PyRod::free(self.inner.rods[i].rod.clone()))
    }
    #[getter]
    fn n_rods(&self) -> usize {
        self.inner.rods.len()
    }
    #[getter]
    fn n_constraints(&self) -> usize {
        self.inner.constraints.len()
    }
    #[getter]
    fn n_loads(&self) -> usize {
        self.inner.loads.len()
    }
    #[getter]
    fn n_beads(&self) -> usize {
        self.inner.beads.len()
    }
    /// Every label, in the order: rods, constraints, loads, beads.
    #[getter]
    fn get_labels(&self) -> Vec<String> {
        self.labels()
    }
    /// The group names (base names of the labels), sorted.
    #[getter]
    fn groups(&self) -> Vec<String> {
        let mut g: Vec<String> = self.labels().iter().map(|l| base_of(l).to_string()).collect();
        g.sort();
        g.dedup();
        g
    }
    /// The assembly as JSON (floats round-trip exactly).
    fn to_json(&self) -> PyResult<String> {
        guard(|| self.inner.to_json())
    }
    /// An assembly from `to_json()` text (rods rebuilt and checked).
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        Ok(PyAssembly { inner: guard(|| Assembly::from_json(text))? })
    }
    /// The constraint `i` as a dict (rod, other, kind, compliance, breaking, label).
    fn constraint<'py>(&self, py: Python<'py>, i: usize) -> PyResult<Bound<'py, PyAny>> {
        let c = self.inner.constraints.get(i).ok_or_else(|| {
            crate::err(strandkit_core::Error::invalid("constraint index", i, format!("< {}", self.inner.constraints.len())))
        })?;
        from_json(py, &serde_json::to_value(c).unwrap_or_default())
    }
    fn copy(&self) -> Self {
        self.clone()
    }
    fn __copy__(&self) -> Self {
        self.clone()
    }
    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }
    fn __repr__(&self) -> String {
        format!(
            "Assembly(rods={}, constraints={}, loads={}, beads={}, groups={})",
            self.inner.rods.len(),
            self.inner.constraints.len(),
            self.inner.loads.len(),
            self.inner.beads.len(),
            convert::py_strs(self.groups())
        )
    }
}

/// What `World.insert` added: `rods` (Rod views), `constraints`, `loads`,
/// `beads`, `clips` (handles), in the assembly's order, and `bandwidth` (the
/// half-bandwidth of the world's system afterwards).
#[pyclass(name = "Inserted", module = "strandkit._native", frozen)]
pub struct PyInserted {
    pub(crate) rods: Vec<Py<PyAny>>,
    pub(crate) constraints: Vec<Py<PyAny>>,
    pub(crate) loads: Vec<Py<PyAny>>,
    pub(crate) beads: Vec<Py<PyAny>>,
    pub(crate) clips: Vec<Py<PyAny>>,
    #[pyo3(get)]
    pub(crate) bandwidth: usize,
}

#[pymethods]
impl PyInserted {
    /// The inserted rods (views of the world's rods), by assembly index.
    #[getter]
    fn rods(&self, py: Python<'_>) -> Vec<Py<PyAny>> {
        self.rods.iter().map(|x| x.clone_ref(py)).collect()
    }
    /// ConstraintHandles, by assembly index.
    #[getter]
    fn constraints(&self, py: Python<'_>) -> Vec<Py<PyAny>> {
        self.constraints.iter().map(|x| x.clone_ref(py)).collect()
    }
    /// LoadHandles, by assembly index.
    #[getter]
    fn loads(&self, py: Python<'_>) -> Vec<Py<PyAny>> {
        self.loads.iter().map(|x| x.clone_ref(py)).collect()
    }
    /// BeadHandles, by assembly index.
    #[getter]
    fn beads(&self, py: Python<'_>) -> Vec<Py<PyAny>> {
        self.beads.iter().map(|x| x.clone_ref(py)).collect()
    }
    /// ClipHandles, by assembly index.
    #[getter]
    fn clips(&self, py: Python<'_>) -> Vec<Py<PyAny>> {
        self.clips.iter().map(|x| x.clone_ref(py)).collect()
    }
    fn __repr__(&self) -> String {
        format!(
            "Inserted(rods={}, constraints={}, loads={}, beads={}, clips={}, bandwidth={})",
            self.rods.len(),
            self.constraints.len(),
            self.loads.len(),
            self.beads.len(),
            self.clips.len(),
            self.bandwidth
        )
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyAssembly>()?;
    m.add_class::<PyInserted>()
}
