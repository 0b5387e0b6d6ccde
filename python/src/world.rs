//! The world: rods, constraints, loads, `step`, `relax`, reports, events,
//! snapshots.
//!
//! Constraint and load kinds cross the boundary as serde JSON: the Python
//! helpers build `{"Position": {"u": …, …}}` dicts, which are deserialised
//! into the core's `ConstraintKind` / `Load`, so kinds added to the core
//! work here without binding changes.
use crate::convert::{self, from_json, to_json};
use crate::guard;
use crate::rod::{PyRod, RodState};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use serde_json::Value;
use strandkit_core::handles::BeadHandle;
use strandkit_core::{
    Breaking, ConstraintHandle, ConstraintKind, Error, IntegrationParameters, Load, LoadHandle,
    RodHandle, World,
};

/// A simulation world: rods, constraints and loads, advanced by `step()`
/// (linearised implicit Euler) or brought to equilibrium by `relax()`.
///
/// Keyword arguments (integration parameters; None = core default): `dt`
/// time step (time unit, default 1e-3), `gravity` (length/time², 3 values,
/// default 0), `parallel` (assemble with threads, default True),
/// `relax_tolerance` (relative: increment ≤ tol × rod length, default
/// 1e-10), `relax_max_iterations` (default 500). Any other field of the core's
/// IntegrationParameters can be set with `set_params(**fields)`, e.g.
/// `plastic_tolerance` (relax with plastic flow: largest offset increment
/// per round, strain or curvature × rest length, default 1e-6) or
/// `linear_solver` ("Auto" | "Band" | "Sparse").
///
/// Rods whose material has yield or rupture limits flow plastically and
/// break after every step (and at every relax equilibrium); a rupture is a
/// `RodRuptured` event whose `rod` and `new_rod` are the two pieces.
#[pyclass(name = "World", module = "strandkit._native")]
pub struct PyWorld {
    pub inner: World,
}

use crate::bad;

fn params_to_value(p: &IntegrationParameters) -> Value {
    serde_json::to_value(p).unwrap_or_default()
}

impl PyWorld {
    /// The handle of `rod`, which must be in this world.
    fn rod_handle(slf: &Bound<'_, Self>, rod: &Bound<'_, PyRod>) -> PyResult<RodHandle> {
        let r = rod.try_borrow()?;
        match &r.state {
            RodState::InWorld { world, handle } if world.bind(slf.py()).is(slf) => Ok(*handle),
            RodState::InWorld { .. } => Err(bad("this rod belongs to another world")),
            RodState::Free(_) => Err(bad(
                "this rod is not in the world yet: call world.add_rod(rod) first",
            )),
        }
    }

    fn constraint_kind(kind: &Bound<'_, PyAny>) -> PyResult<ConstraintKind> {
        let v = json_arg(kind, "constraint")?;
        serde_json::from_value(v).map_err(|e| bad(format!("constraint kind: {e}")))
    }

    fn load_kind(load: &Bound<'_, PyAny>) -> PyResult<Load> {
        let v = json_arg(load, "load")?;
        serde_json::from_value(v).map_err(|e| bad(format!("load: {e}")))
    }

    fn handle_c(slf: &Bound<'_, Self>, h: ConstraintHandle) -> PyConstraintHandle {
        PyConstraintHandle {
            world: slf.clone().unbind(),
            handle: h,
        }
    }

    fn breaking(force: Option<f64>, tension_only: bool) -> Option<Breaking> {
        force.map(|force| Breaking {
            force,
            policy: if tension_only { strandkit_core::BreakPolicy::Tension } else { strandkit_core::BreakPolicy::Magnitude },
        })
    }

    fn own_constraint(
        slf: &Bound<'_, Self>,
        c: &Bound<'_, PyConstraintHandle>,
    ) -> PyResult<ConstraintHandle> {
        let c = c.get();
        if !c.world.bind(slf.py()).is(slf) {
            return Err(bad("this constraint belongs to another world"));
        }
        Ok(c.handle)
    }

    fn own_load(slf: &Bound<'_, Self>, l: &Bound<'_, PyLoadHandle>) -> PyResult<LoadHandle> {
        let l = l.get();
        if !l.world.bind(slf.py()).is(slf) {
            return Err(bad("this load belongs to another world"));
        }
        Ok(l.handle)
    }
}

/// A kind given as a dict (or JSON text) → JSON value.
fn json_arg(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<Value> {
    if let Ok(s) = obj.extract::<String>() {
        if s.trim_start().starts_with('{') {
            return serde_json::from_str(&s).map_err(|e| bad(format!("{what}: {e}")));
        }
    }
    to_json(obj, what)
}

/// Event (serde JSON) → Python Event, with constraint handles made live.
fn event<'py>(slf: &Bound<'py, PyWorld>, e: &strandkit_core::Event) -> PyResult<PyEvent> {
    let py = slf.py();
    let v = serde_json::to_value(e).unwrap_or_default();
    let (name, fields) = convert::variant(&v);
    let data = PyDict::new(py);
    if let Value::Object(m) = &fields {
        for (k, x) in m {
            // Handles become live objects: constraint → ConstraintHandle,
            // bead → BeadHandle, rod → Rod (a view of the world's rod).
            let as_handle = |want: bool| if want { Some(x.clone()) } else { None };
            let c: Option<ConstraintHandle> =
                as_handle(k.contains("constraint")).and_then(|v| serde_json::from_value(v).ok());
            let b: Option<BeadHandle> =
                as_handle(k.contains("bead")).and_then(|v| serde_json::from_value(v).ok());
            let r: Option<RodHandle> =
                as_handle(k == "rod" || k == "new_rod").and_then(|v| serde_json::from_value(v).ok());
            if k == "clip" {
                if let Ok(h) = serde_json::from_value(x.clone()) {
                    data.set_item(k, crate::clips::PyClipHandle { world: slf.clone().unbind(), handle: h })?;
                    continue;
                }
            }
            match (c, b, r) {
                (Some(h), _, _) => data.set_item(k, PyWorld::handle_c(slf, h))?,
                (None, Some(h), _) => data.set_item(
                    k,
                    PyBeadHandle {
                        world: slf.clone().unbind(),
                        handle: h,
                    },
                )?,
                (None, None, Some(h)) => {
                    data.set_item(k, PyRod::attached(slf.clone().unbind(), h))?
                }
                _ => data.set_item(k, from_json(py, x)?)?,
            }
        }
    }
    Ok(PyEvent {
        kind: name,
        data: data.unbind(),
        text: convert::describe(&v),
    })
}

/// Events as Python `Event` objects (for other modules' reports).
pub(crate) fn events_of(slf: &Bound<'_, PyWorld>, es: &[strandkit_core::Event]) -> PyResult<Vec<Py<PyAny>>> {
    let py = slf.py();
    es.iter().map(|e| Ok(Bound::new(py, event(slf, e)?)?.into_any().unbind())).collect()
}

#[pymethods]
impl PyWorld {
    #[new]
    #[pyo3(signature = (*, dt = None, gravity = None, parallel = None, relax_tolerance = None, relax_max_iterations = None))]
    fn new(
        dt: Option<f64>,
        gravity: Option<&Bound<'_, PyAny>>,
        parallel: Option<bool>,
        relax_tolerance: Option<f64>,
        relax_max_iterations: Option<usize>,
    ) -> PyResult<Self> {
        let mut p = IntegrationParameters::default();
        if let Some(x) = dt {
            p.dt = x;
        }
        if let Some(g) = gravity {
            p.gravity = convert::vec3(g, "gravity")?;
        }
        if let Some(x) = parallel {
            p.parallel = x;
        }
        if let Some(x) = relax_tolerance {
            p.relax_tolerance = x;
        }
        if let Some(x) = relax_max_iterations {
            p.relax_max_iterations = x;
        }
        guard(|| p.validate())?;
        Ok(PyWorld {
            inner: World::new(p),
        })
    }

    /// Simulated time (time unit).
    #[getter]
    fn time(&self) -> f64 {
        self.inner.time()
    }
    /// Steps taken so far.
    #[getter]
    fn n_steps(&self) -> u64 {
        self.inner.n_steps()
    }
    /// Time step h (time unit).
    #[getter]
    fn get_dt(&self) -> f64 {
        self.inner.params.dt
    }
    #[setter]
    fn set_dt(&mut self, dt: f64) -> PyResult<()> {
        guard(|| strandkit_core::error::positive("dt", dt))?;
        self.inner.params.dt = dt;
        Ok(())
    }
    /// Gravity (length/time²), shape (3,).
    #[getter]
    fn get_gravity<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.inner.params.gravity)
    }
    #[setter]
    fn set_gravity(&mut self, g: &Bound<'_, PyAny>) -> PyResult<()> {
        let g = convert::vec3(g, "gravity")?;
        for x in g {
            guard(|| strandkit_core::error::finite("gravity", x))?;
        }
        self.inner.params.gravity = g;
        Ok(())
    }
    /// All integration parameters as a dict.
    #[getter]
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        from_json(py, &params_to_value(&self.inner.params))
    }
    /// Sets integration parameters by name (any field of the core's
    /// IntegrationParameters, e.g. dt=1e-4, relax_max_iterations=1000).
    #[pyo3(signature = (**fields))]
    fn set_params(&mut self, fields: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        let mut v = params_to_value(&self.inner.params);
        if let (Some(f), Value::Object(m)) = (fields, &mut v) {
            for (k, x) in f.iter() {
                let key: String = k.extract()?;
                if !m.contains_key(&key) {
                    let known: Vec<&String> = m.keys().collect();
                    return Err(bad(format!(
                        "unknown integration parameter {key:?}; known: {known:?}"
                    )));
                }
                m.insert(key.clone(), to_json(&x, &key)?);
            }
        }
        let p: IntegrationParameters =
            serde_json::from_value(v).map_err(|e| bad(format!("parameters: {e}")))?;
        guard(|| p.validate())?;
        self.inner.params = p;
        Ok(())
    }

    /// Adds a free rod to the world and returns it (the same object, now a
    /// live view of the world's rod and its handle).
    fn add_rod<'py>(
        slf: &Bound<'py, Self>,
        rod: &Bound<'py, PyRod>,
    ) -> PyResult<Bound<'py, PyRod>> {
        // Both borrows first, so nothing can fail once the rod is moved.
        let mut w = slf.try_borrow_mut()?;
        let mut r = rod.try_borrow_mut()?;
        if !matches!(r.state, RodState::Free(_)) {
            return Err(bad(
                "this rod is already in a world; add rod.copy() for a second one",
            ));
        }
        let placeholder = RodState::InWorld {
            world: slf.clone().unbind(),
            handle: RodHandle {
                index: u32::MAX,
                generation: 0,
            },
        };
        if let RodState::Free(b) = std::mem::replace(&mut r.state, placeholder) {
            let h = w.inner.add_rod(*b);
            r.state = RodState::InWorld {
                world: slf.clone().unbind(),
                handle: h,
            };
        }
        Ok(rod.clone())
    }
    /// Removes a rod with its constraints and loads; the rod object becomes
    /// free again (holding the rod's last state).
    fn remove_rod<'py>(
        slf: &Bound<'py, Self>,
        rod: &Bound<'py, PyRod>,
    ) -> PyResult<Bound<'py, PyRod>> {
        let h = Self::rod_handle(slf, rod)?;
        let removed = guard(|| {
            slf.try_borrow_mut()
                .map_err(|e| Error::input(e.to_string()))?
                .inner
                .remove_rod(h)
        })?;
        rod.try_borrow_mut()?.state = RodState::Free(Box::new(removed));
        Ok(rod.clone())
    }
    /// The rods, in world order.
    fn rods<'py>(slf: &Bound<'py, Self>) -> PyResult<Vec<PyRod>> {
        let hs: Vec<RodHandle> = slf.try_borrow()?.inner.rods().map(|(h, _)| h).collect();
        Ok(hs
            .into_iter()
            .map(|h| PyRod::attached(slf.clone().unbind(), h))
            .collect())
    }
    #[getter]
    fn n_rods(&self) -> usize {
        self.inner.rods().count()
    }

    /// Adds a constraint on one rod (`kind` from strandkit.position,
    /// tangent, …). `compliance` (length/force; 0 = hard, > 0 = spring of
    /// stiffness 1/compliance); `break_force` (force unit; None =
    /// unbreakable) with `tension_only` (distance links only).
    #[pyo3(signature = (rod, kind, *, compliance = 0.0, break_force = None, tension_only = false))]
    fn add_constraint(
        slf: &Bound<'_, Self>,
        rod: &Bound<'_, PyRod>,
        kind: &Bound<'_, PyAny>,
        compliance: f64,
        break_force: Option<f64>,
        tension_only: bool,
    ) -> PyResult<PyConstraintHandle> {
        let h = Self::rod_handle(slf, rod)?;
        let k = Self::constraint_kind(kind)?;
        let mut w = slf.try_borrow_mut()?;
        let c = guard(|| w.inner.add_constraint(h, k, compliance))?;
        if break_force.is_some() {
            if let Err(e) = guard(|| {
                w.inner
                    .set_breaking(c, Self::breaking(break_force, tension_only))
            }) {
                let _ = w.inner.remove_constraint(c);
                return Err(e);
            }
        }
        Ok(Self::handle_c(slf, c))
    }
    /// Adds a relative constraint between rod `a` (abscissa ua) and rod `b`
    /// (ub), which may be the same rod (kinds: relative_position,
    /// relative_orientation, relative_distance). Keywords as add_constraint.
    #[pyo3(signature = (a, b, kind, *, compliance = 0.0, break_force = None, tension_only = false))]
    fn add_link(
        slf: &Bound<'_, Self>,
        a: &Bound<'_, PyRod>,
        b: &Bound<'_, PyRod>,
        kind: &Bound<'_, PyAny>,
        compliance: f64,
        break_force: Option<f64>,
        tension_only: bool,
    ) -> PyResult<PyConstraintHandle> {
        let (ha, hb) = (Self::rod_handle(slf, a)?, Self::rod_handle(slf, b)?);
        let k = Self::constraint_kind(kind)?;
        let mut w = slf.try_borrow_mut()?;
        let c = guard(|| w.inner.add_link(ha, hb, k, compliance))?;
        if break_force.is_some() {
            if let Err(e) = guard(|| {
                w.inner
                    .set_breaking(c, Self::breaking(break_force, tension_only))
            }) {
                let _ = w.inner.remove_constraint(c);
                return Err(e);
            }
        }
        Ok(Self::handle_c(slf, c))
    }
    /// Coplanar relative clamp (III.61) between rod `a` at `ua` and rod `b`
    /// at `ub`: the two tangent lines keep meeting at their current common
    /// point (a hinge there, not a weld). Errors when the tangents are
    /// parallel or the link is not in their plane.
    #[pyo3(signature = (a, ua, b, ub, *, compliance = 0.0))]
    fn add_coplanar_clamp(
        slf: &Bound<'_, Self>,
        a: &Bound<'_, PyRod>,
        ua: f64,
        b: &Bound<'_, PyRod>,
        ub: f64,
        compliance: f64,
    ) -> PyResult<PyConstraintHandle> {
        let (ha, hb) = (Self::rod_handle(slf, a)?, Self::rod_handle(slf, b)?);
        let mut w = slf.try_borrow_mut()?;
        let c = guard(|| w.inner.add_coplanar_clamp(ha, ua, hb, ub, compliance))?;
        Ok(Self::handle_c(slf, c))
    }
    /// Adds a clip (thesis algorithms 4–5): capture sphere `center`
    /// (length, 3 values) and `radius` (length, > 0), exit `axis` (3
    /// values, non-zero), pull-out `resistance` (force, > 0). A rod that
    /// enters the sphere is held at its closest point; it is released when
    /// pulled out along the axis harder than the resistance (events
    /// ClipCaptured / ClipReleased).
    #[pyo3(signature = (center, radius, axis, resistance))]
    fn add_clip(
        slf: &Bound<'_, Self>,
        center: &Bound<'_, PyAny>,
        radius: f64,
        axis: &Bound<'_, PyAny>,
        resistance: f64,
    ) -> PyResult<crate::clips::PyClipHandle> {
        let (c, a) = (convert::vec3(center, "clip center")?, convert::vec3(axis, "clip axis")?);
        let mut w = slf.try_borrow_mut()?;
        let h = guard(|| w.inner.add_clip(c, radius, a, resistance))?;
        Ok(crate::clips::PyClipHandle { world: slf.clone().unbind(), handle: h })
    }
    /// Interleaves the control points of these rods in the band (linked
    /// rods such as the two strands of a helix keep a narrow band).
    fn interleave(slf: &Bound<'_, Self>, rods: Vec<Bound<'_, PyRod>>) -> PyResult<()> {
        let hs = rods
            .iter()
            .map(|r| Self::rod_handle(slf, r))
            .collect::<PyResult<Vec<_>>>()?;
        let mut w = slf.try_borrow_mut()?;
        guard(|| w.inner.interleave(&hs))
    }
    /// Replaces a constraint's kind (same kind and rows): moving targets.
    fn set_constraint(
        slf: &Bound<'_, Self>,
        constraint: &Bound<'_, PyConstraintHandle>,
        kind: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let h = Self::own_constraint(slf, constraint)?;
        let k = Self::constraint_kind(kind)?;
        let mut w = slf.try_borrow_mut()?;
        guard(|| w.inner.set_constraint(h, k))
    }
    /// Removes a constraint.
    fn remove_constraint(
        slf: &Bound<'_, Self>,
        constraint: &Bound<'_, PyConstraintHandle>,
    ) -> PyResult<()> {
        let h = Self::own_constraint(slf, constraint)?;
        let mut w = slf.try_borrow_mut()?;
        guard(|| w.inner.remove_constraint(h).map(|_| ()))
    }
    /// Makes a constraint break when its reaction force exceeds `force`
    /// (force unit); `tension_only` for distance links; force=None: unbreakable.
    #[pyo3(signature = (constraint, force = None, *, tension_only = false))]
    fn set_breaking(
        slf: &Bound<'_, Self>,
        constraint: &Bound<'_, PyConstraintHandle>,
        force: Option<f64>,
        tension_only: bool,
    ) -> PyResult<()> {
        let h = Self::own_constraint(slf, constraint)?;
        let mut w = slf.try_borrow_mut()?;
        guard(|| w.inner.set_breaking(h, Self::breaking(force, tension_only)))
    }
    /// Force (force unit) and torque (force × length) the constraint
    /// exerted on its (first) rod in the last solve.
    fn reaction(
        slf: &Bound<'_, Self>,
        constraint: &Bound<'_, PyConstraintHandle>,
    ) -> PyResult<PyReaction> {
        let h = Self::own_constraint(slf, constraint)?;
        let r = guard(|| slf.borrow().inner.reaction(h))?;
        Ok(PyReaction {
            force: r.force,
            torque: r.torque,
        })
    }
    /// Lagrange multipliers of the last solve (force / torque units), shape (rows,).
    fn multipliers<'py>(
        slf: &Bound<'py, Self>,
        constraint: &Bound<'py, PyConstraintHandle>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let h = Self::own_constraint(slf, constraint)?;
        let m = guard(|| Ok(slf.borrow().inner.constraint(h)?.multipliers.clone()))?;
        Ok(PyArray1::from_vec(slf.py(), m))
    }

    /// Adds a load (from strandkit.point_force, point_torque, distributed).
    fn add_load(slf: &Bound<'_, Self>, load: &Bound<'_, PyAny>) -> PyResult<PyLoadHandle> {
        let l = Self::load_kind(load)?;
        let mut w = slf.try_borrow_mut()?;
        let h = guard(|| w.inner.add_load(l))?;
        Ok(PyLoadHandle {
            world: slf.clone().unbind(),
            handle: h,
        })
    }
    /// Replaces a load (e.g. a new force value).
    fn set_load(
        slf: &Bound<'_, Self>,
        handle: &Bound<'_, PyLoadHandle>,
        load: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let h = Self::own_load(slf, handle)?;
        let l = Self::load_kind(load)?;
        let mut w = slf.try_borrow_mut()?;
        guard(|| w.inner.set_load(h, l))
    }
    fn remove_load(slf: &Bound<'_, Self>, handle: &Bound<'_, PyLoadHandle>) -> PyResult<()> {
        let h = Self::own_load(slf, handle)?;
        let mut w = slf.try_borrow_mut()?;
        guard(|| w.inner.remove_load(h).map(|_| ()))
    }

    /// Threads a bead (sliding-abscissa particle) on `rod` at abscissa `u`:
    /// `mass` (mass unit, > 0), viscous `friction` (force per sliding speed,
    /// ≥ 0), `radius` (length, ≥ 0: beads on one rod keep their centres
    /// r_a + r_b apart). Gravity acts on it; see set_bead_force.
    #[pyo3(signature = (rod, u, *, mass, friction = 0.0, radius = 0.0))]
    fn add_bead(
        slf: &Bound<'_, Self>,
        rod: &Bound<'_, PyRod>,
        u: f64,
        mass: f64,
        friction: f64,
        radius: f64,
    ) -> PyResult<PyBeadHandle> {
        let h = Self::rod_handle(slf, rod)?;
        let mut w = slf.try_borrow_mut()?;
        let b = guard(|| w.inner.add_bead(h, u, mass, friction, radius))?;
        Ok(PyBeadHandle {
            world: slf.clone().unbind(),
            handle: b,
        })
    }
    /// Takes a bead off its rod.
    fn remove_bead(slf: &Bound<'_, Self>, bead: &Bound<'_, PyBeadHandle>) -> PyResult<()> {
        let b = bead.get();
        if !b.world.bind(slf.py()).is(slf) {
            return Err(bad("this bead belongs to another world"));
        }
        let mut w = slf.try_borrow_mut()?;
        guard(|| w.inner.remove_bead(b.handle).map(|_| ()))
    }
    /// External force on a bead besides gravity (force unit, 3 values).
    fn set_bead_force(
        slf: &Bound<'_, Self>,
        bead: &Bound<'_, PyBeadHandle>,
        force: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let b = bead.get();
        if !b.world.bind(slf.py()).is(slf) {
            return Err(bad("this bead belongs to another world"));
        }
        let f = convert::vec3(force, "bead force")?;
        let mut w = slf.try_borrow_mut()?;
        guard(|| w.inner.set_bead_force(b.handle, f))
    }

    /// One linearised implicit Euler step of `dt`. The GIL is released
    /// while the core works. Raises SingularError / ConvergenceError.
    fn step(slf: &Bound<'_, Self>) -> PyResult<PyStepReport> {
        let py = slf.py();
        let rep = {
            let mut w = slf.try_borrow_mut()?;
            let inner = &mut w.inner;
            py.detach(|| guard(|| inner.step()))?
        };
        let events = if rep.events.is_empty() {
            Vec::new()
        } else {
            events_of(slf, &rep.events)?
        };
        Ok(PyStepReport { inner: rep, events })
    }
    /// Quasi-static equilibrium (Newton with pseudo-transient continuation).
    fn relax(slf: &Bound<'_, Self>) -> PyResult<PyRelaxReport> {
        let py = slf.py();
        let rep = {
            let mut w = slf.try_borrow_mut()?;
            let inner = &mut w.inner;
            py.detach(|| guard(|| inner.relax()))?
        };
        let events = events_of(slf, &rep.events)?;
        Ok(PyRelaxReport { inner: rep, events })
    }
    /// Benchmark helper: seconds taken by `n` steps run in a Rust loop
    /// (no Python in between), to measure the binding overhead.
    fn _time_steps(&mut self, py: Python<'_>, n: usize) -> PyResult<f64> {
        let inner = &mut self.inner;
        py.detach(|| {
            guard(|| {
                let t = std::time::Instant::now();
                for _ in 0..n {
                    inner.step()?;
                }
                Ok(t.elapsed().as_secs_f64())
            })
        })
    }

    /// The whole world as JSON (floats round-trip exactly).
    fn to_json(&self) -> PyResult<String> {
        guard(|| self.inner.to_json())
    }
    /// A world from `to_json()` text.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        Ok(PyWorld {
            inner: guard(|| World::from_json(text))?,
        })
    }
    /// Writes a snapshot (JSON) atomically; `World.load` reads it back and
    /// continues bit-for-bit.
    fn save(&self, path: std::path::PathBuf) -> PyResult<()> {
        guard(|| self.inner.save(&path))
    }
    #[staticmethod]
    fn load(path: std::path::PathBuf) -> PyResult<Self> {
        Ok(PyWorld {
            inner: guard(|| World::load(&path))?,
        })
    }
    /// An independent deep copy.
    fn copy(&self) -> Self {
        PyWorld {
            inner: self.inner.clone(),
        }
    }
    fn __copy__(&self) -> Self {
        self.copy()
    }
    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.copy()
    }
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let json = slf.borrow().to_json()?;
        Ok((
            slf.get_type().getattr("from_json")?,
            PyTuple::new(slf.py(), [json])?,
        ))
    }
    fn __repr__(&self) -> String {
        let p = &self.inner.params;
        format!(
            "World(time={}, steps={}, rods={}, dt={}, gravity={:?})",
            self.inner.time(),
            self.inner.n_steps(),
            self.inner.rods().count(),
            p.dt,
            p.gravity
        )
    }
}

/// Handle of a constraint in a world.
#[pyclass(name = "ConstraintHandle", module = "strandkit._native", frozen)]
pub struct PyConstraintHandle {
    pub world: Py<PyWorld>,
    pub handle: ConstraintHandle,
}

#[pymethods]
impl PyConstraintHandle {
    #[getter]
    fn index(&self) -> u32 {
        self.handle.index
    }
    #[getter]
    fn generation(&self) -> u32 {
        self.handle.generation
    }
    /// False once removed (or broken).
    #[getter]
    fn alive(&self, py: Python<'_>) -> PyResult<bool> {
        Ok(self
            .world
            .bind(py)
            .try_borrow()?
            .inner
            .constraint(self.handle)
            .is_ok())
    }
    /// The constraint kind as a dict {"Kind": {fields}}.
    #[getter]
    fn kind<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = self.world.bind(py).try_borrow()?;
        let c = guard(|| w.inner.constraint(self.handle))?;
        from_json(py, &serde_json::to_value(&c.kind).unwrap_or_default())
    }
    /// Compliance (length/force; 0 = hard).
    #[getter]
    fn compliance(&self, py: Python<'_>) -> PyResult<f64> {
        let w = self.world.bind(py).try_borrow()?;
        Ok(guard(|| w.inner.constraint(self.handle))?.compliance)
    }
    /// Multipliers of the last solve (force / torque units).
    #[getter]
    fn multipliers<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let w = self.world.bind(py).try_borrow()?;
        let m = guard(|| w.inner.constraint(self.handle))?
            .multipliers
            .clone();
        Ok(PyArray1::from_vec(py, m))
    }
    /// Force and torque on the (first) rod in the last solve.
    fn reaction(&self, py: Python<'_>) -> PyResult<PyReaction> {
        let r = guard(|| self.world.bind(py).borrow().inner.reaction(self.handle))?;
        Ok(PyReaction {
            force: r.force,
            torque: r.torque,
        })
    }
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyConstraintHandle>()
            .is_ok_and(|o| o.get().handle == self.handle && o.get().world.is(&self.world))
    }
    fn __hash__(&self) -> u64 {
        ((self.handle.generation as u64) << 32) | self.handle.index as u64
    }
    fn __repr__(&self, py: Python<'_>) -> String {
        let w = match self.world.bind(py).try_borrow() {
            Ok(w) => w,
            Err(_) => return format!("ConstraintHandle({})", self.handle.index),
        };
        match w.inner.constraint(self.handle) {
            Ok(c) => {
                let kind = convert::describe(&serde_json::to_value(&c.kind).unwrap_or_default());
                let rods = match c.other {
                    Some(b) => format!("rods {} and {}", c.rod.index, b.index),
                    None => format!("rod {}", c.rod.index),
                };
                let mut s = format!("ConstraintHandle({}: {kind} on {rods}", self.handle.index);
                if c.compliance > 0.0 {
                    s += &format!(", compliance={}", c.compliance);
                }
                if let Some(b) = c.breaking {
                    s += &format!(
                        ", breaks above {}{}",
                        b.force,
                        if b.policy == strandkit_core::BreakPolicy::Tension { " (tension)" } else { "" }
                    );
                }
                s + ")"
            }
            Err(_) => format!("ConstraintHandle({}: removed)", self.handle.index),
        }
    }
}

/// Handle of a load in a world.
#[pyclass(name = "LoadHandle", module = "strandkit._native", frozen)]
pub struct PyLoadHandle {
    pub world: Py<PyWorld>,
    pub handle: LoadHandle,
}

#[pymethods]
impl PyLoadHandle {
    #[getter]
    fn index(&self) -> u32 {
        self.handle.index
    }
    #[getter]
    fn generation(&self) -> u32 {
        self.handle.generation
    }
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyLoadHandle>()
            .is_ok_and(|o| o.get().handle == self.handle && o.get().world.is(&self.world))
    }
    fn __hash__(&self) -> u64 {
        ((self.handle.generation as u64) << 32) | self.handle.index as u64
    }
    fn __repr__(&self) -> String {
        format!("LoadHandle({})", self.handle.index)
    }
}

/// Handle of a bead in a world; its properties read the world's bead.
#[pyclass(name = "BeadHandle", module = "strandkit._native", frozen)]
pub struct PyBeadHandle {
    pub world: Py<PyWorld>,
    pub handle: BeadHandle,
}

impl PyBeadHandle {
    fn with<R>(
        &self,
        py: Python<'_>,
        f: impl FnOnce(&World, &strandkit_core::bead::Bead) -> PyResult<R>,
    ) -> PyResult<R> {
        let w = self.world.bind(py).try_borrow()?;
        let b = guard(|| w.inner.bead(self.handle))?;
        f(&w.inner, b)
    }
}

#[pymethods]
impl PyBeadHandle {
    #[getter]
    fn index(&self) -> u32 {
        self.handle.index
    }
    /// False once the bead left its rod.
    #[getter]
    fn alive(&self, py: Python<'_>) -> PyResult<bool> {
        Ok(self
            .world
            .bind(py)
            .try_borrow()?
            .inner
            .bead(self.handle)
            .is_ok())
    }
    /// Spline abscissa on its rod.
    #[getter]
    fn u(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |_, b| Ok(b.u))
    }
    /// Sliding speed along the rod (length/time, towards increasing u).
    #[getter]
    fn velocity(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |_, b| Ok(b.velocity))
    }
    #[getter]
    fn mass(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |_, b| Ok(b.mass))
    }
    #[getter]
    fn friction(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |_, b| Ok(b.friction))
    }
    #[getter]
    fn radius(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |_, b| Ok(b.radius))
    }
    /// External force besides gravity (force unit).
    #[getter]
    fn force<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let f = self.with(py, |_, b| Ok(b.force))?;
        Ok(PyArray1::from_slice(py, &f))
    }
    /// Position (length unit), shape (3,).
    #[getter]
    fn position<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let p = guard(|| {
            self.world
                .bind(py)
                .borrow()
                .inner
                .bead_position(self.handle)
        })?;
        Ok(PyArray1::from_vec(py, vec![p.x, p.y, p.z]))
    }
    /// The rod the bead is threaded on.
    #[getter]
    fn rod(&self, py: Python<'_>) -> PyResult<PyRod> {
        let h = self.with(py, |_, b| Ok(b.rod))?;
        Ok(PyRod::attached(self.world.clone_ref(py), h))
    }
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyBeadHandle>()
            .is_ok_and(|o| o.get().handle == self.handle && o.get().world.is(&self.world))
    }
    fn __hash__(&self) -> u64 {
        ((self.handle.generation as u64) << 32) | self.handle.index as u64
    }
    fn __repr__(&self, py: Python<'_>) -> String {
        self.with(py, |_, b| {
            Ok(format!(
                "BeadHandle({}: on rod {} at u={:.6}, mass={}, friction={}, radius={})",
                self.handle.index, b.rod.index, b.u, b.mass, b.friction, b.radius
            ))
        })
        .unwrap_or_else(|_| format!("BeadHandle({}: gone)", self.handle.index))
    }
}

/// Force (force unit) and torque (force × length) a constraint exerts on its rod.
#[pyclass(name = "Reaction", module = "strandkit._native", frozen)]
pub struct PyReaction {
    force: [f64; 3],
    torque: [f64; 3],
}

#[pymethods]
impl PyReaction {
    #[getter]
    fn force<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.force)
    }
    #[getter]
    fn torque<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.torque)
    }
    fn __repr__(&self) -> String {
        format!("Reaction(force={:?}, torque={:?})", self.force, self.torque)
    }
}

/// Something that happened during a solve: `kind` (e.g.
/// "ConstraintBroken") and its fields in `data` (also readable as
/// attributes: event.constraint, event.time, event.force, …).
#[pyclass(name = "Event", module = "strandkit._native", frozen)]
pub struct PyEvent {
    #[pyo3(get)]
    kind: String,
    #[pyo3(get)]
    data: Py<PyDict>,
    text: String,
}

#[pymethods]
impl PyEvent {
    fn __getattr__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        self.data.bind(py).get_item(name)?.ok_or_else(|| {
            pyo3::exceptions::PyAttributeError::new_err(format!(
                "{} event has no field {name:?}",
                self.kind
            ))
        })
    }
    fn __repr__(&self) -> String {
        format!("Event({})", self.text)
    }
}

crate::report::report_class!(
    /// What a step did, as attributes: `time` (after the step), `n_unknowns`,
    /// `n_multipliers`, `bandwidth` (half), `residual` (relative, of the
    /// linear solve), `elastic_energy` (before the step, energy unit),
    /// `plastic_samples`, `factorisation` ("band_ldlt" | "band_lu" | "sparse"),
    /// `factor_entries` (stored, fill included), `events`; `dir()` lists them.
    PyStepReport,
    "StepReport",
    strandkit_core::StepReport,
    ["time", "n_unknowns", "n_multipliers", "bandwidth", "residual", "elastic_energy"],
    |_| Vec::new()
);

crate::report::report_class!(
    /// What relax did, as attributes: `iterations` (accepted + rejected),
    /// `rejected`, final `increment` (length unit) and `violation`,
    /// `potential` (U − F·q, energy unit), `plastic_samples`,
    /// `plastic_increment`, `bandwidth`, `n_unknowns`, `events`.
    PyRelaxReport,
    "RelaxReport",
    strandkit_core::RelaxReport,
    ["iterations", "rejected", "increment", "violation", "potential"],
    |_| Vec::new()
);

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyWorld>()?;
    m.add_class::<PyConstraintHandle>()?;
    m.add_class::<PyLoadHandle>()?;
    m.add_class::<PyBeadHandle>()?;
    m.add_class::<PyReaction>()?;
    m.add_class::<PyEvent>()?;
    m.add_class::<PyStepReport>()?;
    m.add_class::<PyRelaxReport>()?;
    Ok(())
}
