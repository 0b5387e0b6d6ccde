//! The world: rods, constraints, loads, beads, clips, groups, `step`,
//! `relax`, snapshots.
//!
//! Constraint and load kinds cross the boundary as serde JSON: the Python
//! helpers build `{"Position": {"u": …, …}}` dicts, which are deserialised
//! into the core's `ConstraintKind` / `Load`, so kinds added to the core
//! work here without binding changes. Integration parameters go through the
//! one keyword converter, `convert::kwargs_into`.
use crate::assembly::{self, PyAssembly, PyInserted};
use crate::convert::{self, from_json};
use crate::events::events_of;
use crate::groups::PyGroup;
use crate::guard;
use crate::handles::{self, PyBeadHandle, PyClipHandle, PyConstraintHandle, PyLoadHandle, PyReaction};
use crate::report::{PyRelaxReport, PyStepReport};
use crate::rod::{PyRod, RodState};
pub use crate::world_data::PyWorld;
use crate::world_data::{read, write};
use crate::bad;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use serde_json::Value;
use strandkit_core::{Constraint, ConstraintHandle, IntegrationParameters, Load, RodHandle, World};

impl PyWorld {
    /// The handle of `rod`, which must be in this world.
    fn rod_handle(slf: &Bound<'_, Self>, rod: &Bound<'_, PyRod>) -> PyResult<RodHandle> {
        let r = rod.try_borrow()?;
        match &r.state {
            RodState::InWorld { world, handle } if world.bind(slf.py()).is(slf) => Ok(*handle),
            RodState::InWorld { .. } => Err(bad("this rod belongs to another world")),
            RodState::Free(_) => Err(bad("this rod is not in the world yet: call world.add_rod(rod) first")),
        }
    }

    fn load_kind(slf: &Bound<'_, Self>, load: &Bound<'_, PyAny>) -> PyResult<Load> {
        let v = assembly::load_value(load, Some(slf.as_any()))?;
        let (name, fields) = convert::variant(&v);
        for r in assembly::rod_fields(&name) {
            if !fields.get(r).is_some_and(Value::is_object) {
                return Err(bad(format!("load {r}: expected a Rod of this world, got {}", convert::short(fields.get(r).unwrap_or(&Value::Null)))));
            }
        }
        serde_json::from_value(v).map_err(|e| bad(format!("load: {e}")))
    }

    fn constraint(slf: &Bound<'_, Self>, h: ConstraintHandle) -> PyConstraintHandle {
        PyConstraintHandle::new(slf.clone().unbind(), h)
    }

    fn own(slf: &Bound<'_, Self>, c: &Bound<'_, PyConstraintHandle>) -> PyResult<ConstraintHandle> {
        c.get().owned_by(slf)
    }

    /// Adds a fully described constraint (one rod or a link).
    #[allow(clippy::too_many_arguments)]
    fn add(
        slf: &Bound<'_, Self>,
        a: &Bound<'_, PyRod>,
        b: Option<&Bound<'_, PyRod>>,
        kind: &Bound<'_, PyAny>,
        compliance: f64,
        break_force: Option<f64>,
        policy: &str,
        tension_only: bool,
        label: Option<String>,
        held_at_end: bool,
    ) -> PyResult<PyConstraintHandle> {
        let ha = Self::rod_handle(slf, a)?;
        let hb = b.map(|b| Self::rod_handle(slf, b)).transpose()?;
        let k = assembly::constraint_kind(kind, Some(slf.as_any()))?;
        let breaking = assembly::breaking(break_force, policy, tension_only)?;
        let c = Constraint { breaking, label, held_at_end, ..Constraint::new(ha, hb, k, compliance) };
        let h = {
            let mut w = write(slf)?;
            guard(|| w.inner.insert_constraint(c))?
        };
        Ok(Self::constraint(slf, h))
    }

    fn with_mut<R>(slf: &Bound<'_, Self>, f: impl FnOnce(&mut World) -> strandkit_core::Result<R>) -> PyResult<R> {
        let mut w = write(slf)?;
        guard(|| f(&mut w.inner))
    }
}

#[pymethods]
impl PyWorld {
    #[new]
    #[pyo3(signature = (**params))]
    fn new(params: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let p: IntegrationParameters =
            convert::kwargs_into(&IntegrationParameters::default(), convert::kwargs(params)?, "integration parameter")?;
        guard(|| p.validate())?;
        Ok(PyWorld { inner: World::new(p) })
    }

    /// Simulated time (time unit).
    #[getter]
    fn time(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(read(slf)?.inner.time())
    }
    /// Steps taken so far.
    #[getter]
    fn n_steps(slf: &Bound<'_, Self>) -> PyResult<u64> {
        Ok(read(slf)?.inner.n_steps())
    }
    /// Time step h (time unit).
    #[getter]
    fn get_dt(slf: &Bound<'_, Self>) -> PyResult<f64> {
        Ok(read(slf)?.inner.params.dt)
    }
    #[setter]
    fn set_dt(slf: &Bound<'_, Self>, dt: f64) -> PyResult<()> {
        guard(|| strandkit_core::error::positive("dt", dt))?;
        write(slf)?.inner.params.dt = dt;
        Ok(())
    }
    /// Gravity (length/time²), shape (3,).
    #[getter]
    fn get_gravity<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_slice(slf.py(), &read(slf)?.inner.params.gravity))
    }
    #[setter]
    fn set_gravity(slf: &Bound<'_, Self>, g: &Bound<'_, PyAny>) -> PyResult<()> {
        let g = convert::vec3(g, "gravity")?;
        for x in g {
            guard(|| strandkit_core::error::finite("gravity", x))?;
        }
        write(slf)?.inner.params.gravity = g;
        Ok(())
    }
    /// All integration parameters as a dict.
    #[getter]
    fn params<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        from_json(slf.py(), &serde_json::to_value(&read(slf)?.inner.params).unwrap_or_default())
    }
    /// Sets integration parameters by name (any field of the core's
    /// IntegrationParameters, e.g. dt=1e-4, relax_max_iterations=1000;
    /// None restores a field's default). Nothing changes on an error.
    #[pyo3(signature = (**fields))]
    fn set_params(slf: &Bound<'_, Self>, fields: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        // The keywords are converted without holding the world: converting
        // them may run Python code (numpy's tolist), during which another
        // thread may use the world.
        let base = read(slf)?.inner.params.clone();
        let p = convert::kwargs_into(&base, convert::kwargs(fields)?, "integration parameter")?;
        guard(|| p.validate())?;
        write(slf)?.inner.params = p;
        Ok(())
    }

    /// Adds a free rod to the world and returns it (the same object, now a
    /// live view of the world's rod and its handle).
    fn add_rod<'py>(slf: &Bound<'py, Self>, rod: &Bound<'py, PyRod>) -> PyResult<Bound<'py, PyRod>> {
        // Both borrows first, so nothing can fail once the rod is moved.
        let mut w = write(slf)?;
        let mut r = rod.try_borrow_mut()?;
        if !matches!(r.state, RodState::Free(_)) {
            return Err(bad("this rod is already in a world; add rod.copy() for a second one"));
        }
        let placeholder = RodState::InWorld { world: slf.clone().unbind(), handle: RodHandle { index: u32::MAX, generation: 0 } };
        if let RodState::Free(b) = std::mem::replace(&mut r.state, placeholder) {
            let h = w.inner.add_rod(*b);
            r.state = RodState::InWorld { world: slf.clone().unbind(), handle: h };
        }
        Ok(rod.clone())
    }
    /// Removes a rod with its constraints and loads; the rod object becomes
    /// free again (holding the rod's last state).
    fn remove_rod<'py>(slf: &Bound<'py, Self>, rod: &Bound<'py, PyRod>) -> PyResult<Bound<'py, PyRod>> {
        let h = Self::rod_handle(slf, rod)?;
        let removed = Self::with_mut(slf, |w| w.remove_rod(h))?;
        rod.try_borrow_mut()?.state = RodState::Free(Box::new(removed));
        Ok(rod.clone())
    }
    /// The rods, in world order.
    fn rods<'py>(slf: &Bound<'py, Self>) -> PyResult<Vec<PyRod>> {
        let hs: Vec<RodHandle> = read(slf)?.inner.rods().map(|(h, _)| h).collect();
        Ok(hs.into_iter().map(|h| PyRod::attached(slf.clone().unbind(), h)).collect())
    }
    /// The live constraints, in handle order.
    fn constraints(slf: &Bound<'_, Self>) -> PyResult<Vec<PyConstraintHandle>> {
        let hs: Vec<ConstraintHandle> = read(slf)?.inner.constraints().map(|(h, _)| h).collect();
        Ok(hs.into_iter().map(|h| Self::constraint(slf, h)).collect())
    }
    /// The live loads, in handle order.
    fn loads(slf: &Bound<'_, Self>) -> PyResult<Vec<PyLoadHandle>> {
        let hs: Vec<_> = read(slf)?.inner.loads().map(|(h, _)| h).collect();
        Ok(hs.into_iter().map(|h| PyLoadHandle::new(slf.clone().unbind(), h)).collect())
    }
    /// The beads on rods, in handle order.
    fn beads(slf: &Bound<'_, Self>) -> PyResult<Vec<PyBeadHandle>> {
        let hs: Vec<_> = read(slf)?.inner.beads().map(|(h, _)| h).collect();
        Ok(hs.into_iter().map(|h| PyBeadHandle::new(slf.clone().unbind(), h)).collect())
    }
    /// The clips, in handle order.
    fn clips(slf: &Bound<'_, Self>) -> PyResult<Vec<PyClipHandle>> {
        let hs: Vec<_> = read(slf)?.inner.clips().map(|(h, _)| h).collect();
        Ok(hs.into_iter().map(|h| PyClipHandle::new(slf.clone().unbind(), h)).collect())
    }
    #[getter]
    fn n_rods(slf: &Bound<'_, Self>) -> PyResult<usize> {
        Ok(read(slf)?.inner.n_rods())
    }
    #[getter]
    fn n_constraints(slf: &Bound<'_, Self>) -> PyResult<usize> {
        Ok(read(slf)?.inner.n_constraints())
    }

    /// Adds a constraint on one rod (`kind` from strandkit.position,
    /// tangent, …). `compliance` (length/force; 0 = hard, > 0 = spring of
    /// stiffness 1/compliance); `break_force` (force unit; None =
    /// unbreakable) measured by `policy`: "magnitude" (|force|, or |torque|
    /// for moment-only kinds), "tension" or "compression" along the line of
    /// action (distance links, contacts, offset relative positions);
    /// `tension_only=True` means policy="tension". `label` (e.g. "pin[3]")
    /// makes it a member of a group (`group("pin")`). `held_at_end=True`
    /// puts a compliant constraint's whole force at the end of a
    /// trapezoidal step, as implicit Euler does (damped), instead of
    /// averaging it over the step like an elastic energy (the default,
    /// which keeps the energy). Atomic: on an error nothing is added.
    #[pyo3(signature = (rod, kind, *, compliance = 0.0, break_force = None, policy = "magnitude", tension_only = false, label = None, held_at_end = false))]
    #[allow(clippy::too_many_arguments)]
    fn add_constraint(
        slf: &Bound<'_, Self>,
        rod: &Bound<'_, PyRod>,
        kind: &Bound<'_, PyAny>,
        compliance: f64,
        break_force: Option<f64>,
        policy: &str,
        tension_only: bool,
        label: Option<String>,
        held_at_end: bool,
    ) -> PyResult<PyConstraintHandle> {
        Self::add(slf, rod, None, kind, compliance, break_force, policy, tension_only, label, held_at_end)
    }
    /// Adds a relative constraint between rod `a` (abscissa ua) and rod `b`
    /// (ub), which may be the same rod (kinds: relative_position,
    /// relative_orientation, relative_distance, contact, …). Keywords as
    /// add_constraint.
    #[pyo3(signature = (a, b, kind, *, compliance = 0.0, break_force = None, policy = "magnitude", tension_only = false, label = None, held_at_end = false))]
    #[allow(clippy::too_many_arguments)]
    fn add_link(
        slf: &Bound<'_, Self>,
        a: &Bound<'_, PyRod>,
        b: &Bound<'_, PyRod>,
        kind: &Bound<'_, PyAny>,
        compliance: f64,
        break_force: Option<f64>,
        policy: &str,
        tension_only: bool,
        label: Option<String>,
        held_at_end: bool,
    ) -> PyResult<PyConstraintHandle> {
        Self::add(slf, a, Some(b), kind, compliance, break_force, policy, tension_only, label, held_at_end)
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
        let c = Self::with_mut(slf, |w| w.add_coplanar_clamp(ha, ua, hb, ub, compliance))?;
        Ok(Self::constraint(slf, c))
    }
    /// Clamps `rod` at `u` (default: its start) where it is now: position,
    /// tangent, and the cross-section held as the rod's frame model says
    /// (the roll coordinate on a straight stretch; an absolute material
    /// roll on a curved one in the Frenet model; nothing for rods without
    /// roll). `compliance` (length/force) applies to all. Returns the 2 or
    /// 3 handles (position, tangent[, material roll]).
    #[pyo3(signature = (rod, u = None, *, compliance = 0.0))]
    fn clamp<'py>(slf: &Bound<'py, Self>, rod: &Bound<'py, PyRod>, u: Option<f64>, compliance: f64) -> PyResult<Bound<'py, PyTuple>> {
        let h = Self::rod_handle(slf, rod)?;
        let hs = Self::with_mut(slf, |w| {
            let u = match u {
                Some(u) => u,
                None => w.rod(h)?.domain().0,
            };
            w.clamp(h, u, compliance)
        })?;
        PyTuple::new(slf.py(), hs.into_iter().map(|c| Self::constraint(slf, c)))
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
    ) -> PyResult<PyClipHandle> {
        let (c, a) = (convert::vec3(center, "clip center")?, convert::vec3(axis, "clip axis")?);
        let h = Self::with_mut(slf, |w| w.add_clip(c, radius, a, resistance))?;
        Ok(PyClipHandle::new(slf.clone().unbind(), h))
    }
    /// Interleaves the control points of these rods in the band by their
    /// relative position along each rod (an override of the computed ordering).
    fn interleave(slf: &Bound<'_, Self>, rods: Vec<Bound<'_, PyRod>>) -> PyResult<()> {
        let hs = rods.iter().map(|r| Self::rod_handle(slf, r)).collect::<PyResult<Vec<_>>>()?;
        Self::with_mut(slf, |w| w.interleave(&hs))
    }
    /// Detects contacts between rods before every solve (SPEC §7): each rod
    /// a chain of capsules of its largest section radius; pairs closer than
    /// their radii plus `margin` (length; large enough that a step does not
    /// carry a rod through another) become unilateral contact rows with an
    /// active set, with Coulomb `friction` (dimensionless μ ≥ 0: stick while
    /// the friction force is within μ N, else slip against the motion).
    /// `self_contact`: a rod against itself (plectonemes, knots);
    /// `between_rods`: rod against rod. `no_self_contact`: rods of this
    /// world never paired with themselves (an image rod repeating another's
    /// self-contacts); `joined`: pairs (a, b) of rods where b continues a
    /// (a's end tied at b's start), whose points closer along the join than
    /// the self-contact exclusion are never paired; `pair_friction`:
    /// triples (a, b, μ) giving rods a and b (either order; a rod twice for
    /// its self-contact) their own coefficient instead of `friction`.
    /// `line_stiffness` (force/length², finite > 0; None: rigid rows):
    /// distributed rows — a penalty row at every sample of a strand within
    /// reach of another, so that a line of contact (a yarn wrapped round
    /// another) is held along its length, instead of one rigid row per
    /// place of contact, which moves wherever the last step pressed
    /// deepest. Two strands pressed side by side with a line load q
    /// (force/length) sink by q/k (where one crosses or wraps round the
    /// other, the other's rows gather at the crossing). With friction, each
    /// row's is a tangential spring of the row's compliance trimmed to μ N
    /// at the start of each step (no active-set rounds): within μ N at rest;
    /// sliding, above it by the step's slide times k per row length (small
    /// steps, or a drag much larger than k·dt, for Coulomb's sliding force).
    /// Snapshots keep the detection and the contacts' state.
    #[pyo3(signature = (*, margin, self_contact = true, between_rods = true, friction = 0.0, no_self_contact = Vec::new(), joined = Vec::new(), pair_friction = Vec::new(), line_stiffness = None))]
    #[allow(clippy::too_many_arguments)]
    fn contact(
        slf: &Bound<'_, Self>,
        margin: f64,
        self_contact: bool,
        between_rods: bool,
        friction: f64,
        no_self_contact: Vec<Bound<'_, PyRod>>,
        joined: Vec<(Bound<'_, PyRod>, Bound<'_, PyRod>)>,
        pair_friction: Vec<(Bound<'_, PyRod>, Bound<'_, PyRod>, f64)>,
        line_stiffness: Option<f64>,
    ) -> PyResult<()> {
        let alone = no_self_contact.iter().map(|r| Self::rod_handle(slf, r)).collect::<PyResult<Vec<_>>>()?;
        let pairs = joined.iter().map(|(a, b)| Ok((Self::rod_handle(slf, a)?, Self::rod_handle(slf, b)?))).collect::<PyResult<Vec<_>>>()?;
        let mus = pair_friction.iter().map(|(a, b, mu)| Ok((Self::rod_handle(slf, a)?, Self::rod_handle(slf, b)?, *mu))).collect::<PyResult<Vec<_>>>()?;
        Self::with_mut(slf, |w| {
            let mut d = strandkit_core::RodContacts::new(margin, self_contact, between_rods)?.with_friction(friction)?.without_self_contact(&alone);
            for (a, b) in pairs {
                d = d.with_joined(a, b)?;
            }
            for (a, b, mu) in mus {
                d = d.with_pair_friction(a, b, mu)?;
            }
            if let Some(k) = line_stiffness {
                d = d.with_line_stiffness(k)?;
            }
            w.add_contact_detector(d)
        })
    }
    /// Adds a fixed obstacle (`strandkit.obstacles.plane / sphere / capsule
    /// / mesh`) the rods' surfaces cannot enter, detected `margin` (length)
    /// ahead of contact, with Coulomb `friction` (μ ≥ 0) against the rods.
    #[pyo3(signature = (obstacle, *, margin = 0.0, friction = 0.0))]
    fn add_obstacle(slf: &Bound<'_, Self>, obstacle: &Bound<'_, PyAny>, margin: f64, friction: f64) -> PyResult<()> {
        let Ok(obstacle) = obstacle.cast::<crate::obstacles::PyObstacle>() else {
            // `sk.plane` is the constraint holding a rod point on a plane
            // (the catalogue's name), which is what gets passed here by mistake.
            return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "add_obstacle takes a strandkit.obstacles shape (plane, sphere, capsule, cylinder, mesh, mesh_arrays), got {}; \
                 sk.plane(u, origin, normal) is the constraint holding a rod point on a plane, the wall is sk.obstacles.plane(origin=..., normal=...)",
                obstacle.get_type().name()?
            )));
        };
        let o = obstacle.borrow().inner.clone();
        Self::with_mut(slf, |w| w.add_contact_detector(o.with_margin(margin)?.with_friction(friction)?))
    }
    /// Removes every contact detector and obstacle, and the contacts found.
    fn clear_contact(slf: &Bound<'_, Self>) -> PyResult<()> {
        Self::with_mut(slf, |w| {
            w.clear_contact_detectors();
            Ok(())
        })
    }
    /// The active contacts of the last solve, as arrays (n pairs):
    /// `rod_a`, `rod_b` (positions in `world.rods()`; −1 for an obstacle),
    /// `u_a`, `u_b` (abscissae; NaN against an obstacle), `points` (n, 3:
    /// rod a's centreline point, length), `normals` (n, 3: unit, pushing
    /// rod a out), `normal_force` (n: force unit, ≥ 0), `friction_force`
    /// (n, 3: tangential force on rod a), `slipping` (n: bool).
    fn contacts<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        let w = read(slf)?;
        let list = guard(|| w.inner.contact_report())?;
        contacts_dict(slf.py(), &w.inner, &list)
    }
    /// Replaces a constraint's kind (same kind and rows): moving targets.
    fn set_constraint(slf: &Bound<'_, Self>, constraint: &Bound<'_, PyConstraintHandle>, kind: &Bound<'_, PyAny>) -> PyResult<()> {
        let h = Self::own(slf, constraint)?;
        let k = assembly::constraint_kind(kind, Some(slf.as_any()))?;
        Self::with_mut(slf, |w| w.set_constraint(h, k))
    }
    /// Removes a constraint.
    fn remove_constraint(slf: &Bound<'_, Self>, constraint: &Bound<'_, PyConstraintHandle>) -> PyResult<()> {
        let h = Self::own(slf, constraint)?;
        Self::with_mut(slf, |w| w.remove_constraint(h).map(|_| ()))
    }
    /// Makes a constraint break when its measure exceeds `force` (force
    /// unit) — |force| for policy="magnitude", the tension or compression
    /// along its line of action for "tension" / "compression"
    /// (`tension_only=True` is policy="tension"); force=None: unbreakable.
    /// `averaging_time` (time unit): compare the measure averaged over that
    /// time of dynamics (an exponential moving average from 0) instead of
    /// each step's — with thermal noise, hard constraints' instantaneous
    /// forces fluctuate far beyond their mean.
    #[pyo3(signature = (constraint, force = None, *, policy = "magnitude", tension_only = false, averaging_time = 0.0))]
    fn set_breaking(
        slf: &Bound<'_, Self>,
        constraint: &Bound<'_, PyConstraintHandle>,
        force: Option<f64>,
        policy: &str,
        tension_only: bool,
        averaging_time: f64,
    ) -> PyResult<()> {
        let h = Self::own(slf, constraint)?;
        if force.is_none() && averaging_time != 0.0 {
            return Err(crate::bad("averaging_time needs a break force"));
        }
        let b = assembly::breaking(force, policy, tension_only)?.map(|b| b.averaged(averaging_time));
        Self::with_mut(slf, |w| w.set_breaking(h, b))
    }
    /// Force (force unit) and torque (force × length) the constraint
    /// exerted on its (first) rod in the last solve.
    fn reaction(slf: &Bound<'_, Self>, constraint: &Bound<'_, PyConstraintHandle>) -> PyResult<PyReaction> {
        let h = Self::own(slf, constraint)?;
        let r = {
            let w = read(slf)?;
            guard(|| w.inner.reaction(h))?
        };
        Ok(PyReaction { force: r.force, torque: r.torque })
    }
    /// Tension along the constraint's line of action in the last solve
    /// (force unit, > 0 pulling its ends together); None for kinds without one.
    fn tension(slf: &Bound<'_, Self>, constraint: &Bound<'_, PyConstraintHandle>) -> PyResult<Option<f64>> {
        let h = Self::own(slf, constraint)?;
        let w = read(slf)?;
        guard(|| w.inner.tension(h))
    }
    /// Lagrange multipliers of the last solve (force / torque units), shape (rows,).
    fn multipliers<'py>(slf: &Bound<'py, Self>, constraint: &Bound<'py, PyConstraintHandle>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let h = Self::own(slf, constraint)?;
        let w = read(slf)?;
        let m = guard(|| Ok(w.inner.constraint(h)?.multipliers.clone()))?;
        Ok(PyArray1::from_vec(slf.py(), m))
    }

    /// Adds a load (strandkit.point_force, point_torque, distributed,
    /// trap, …); `label` (e.g. "pull[0]") makes it a group member.
    #[pyo3(signature = (load, *, label = None))]
    fn add_load(slf: &Bound<'_, Self>, load: &Bound<'_, PyAny>, label: Option<String>) -> PyResult<PyLoadHandle> {
        let l = Self::load_kind(slf, load)?;
        let h = Self::with_mut(slf, |w| {
            if let Some(x) = &label {
                strandkit_core::world::groups::check_label(x)?;
            }
            let h = w.add_load(l)?;
            if let Some(x) = &label {
                w.set_label(strandkit_core::Item::Load(h), x)?;
            }
            Ok(h)
        })?;
        Ok(PyLoadHandle::new(slf.clone().unbind(), h))
    }
    /// Replaces a load (e.g. a new force value).
    fn set_load(slf: &Bound<'_, Self>, handle: &Bound<'_, PyLoadHandle>, load: &Bound<'_, PyAny>) -> PyResult<()> {
        let h = handle.get().owned_by(slf)?;
        let l = Self::load_kind(slf, load)?;
        Self::with_mut(slf, |w| w.set_load(h, l))
    }
    /// Removes a load.
    fn remove_load(slf: &Bound<'_, Self>, handle: &Bound<'_, PyLoadHandle>) -> PyResult<()> {
        let h = handle.get().owned_by(slf)?;
        Self::with_mut(slf, |w| w.remove_load(h).map(|_| ()))
    }

    /// Threads a bead (sliding-abscissa particle) on `rod` at abscissa `u`:
    /// `mass` (mass unit, > 0), viscous `friction` (force per sliding speed,
    /// ≥ 0), `radius` (length, ≥ 0: beads on one rod keep their centres
    /// r_a + r_b apart), `fixed` (knotted at `u`: it does not slide),
    /// `label`. Gravity acts on it; see set_bead_force.
    #[pyo3(signature = (rod, u, *, mass, friction = 0.0, radius = 0.0, fixed = false, label = None))]
    #[allow(clippy::too_many_arguments)]
    fn add_bead(
        slf: &Bound<'_, Self>,
        rod: &Bound<'_, PyRod>,
        u: f64,
        mass: f64,
        friction: f64,
        radius: f64,
        fixed: bool,
        label: Option<String>,
    ) -> PyResult<PyBeadHandle> {
        let h = Self::rod_handle(slf, rod)?;
        let b = Self::with_mut(slf, |w| {
            if let Some(x) = &label {
                strandkit_core::world::groups::check_label(x)?;
            }
            let b = w.add_bead(h, u, mass, friction, radius)?;
            w.set_bead_fixed(b, fixed)?;
            if let Some(x) = &label {
                w.set_label(strandkit_core::Item::Bead(b), x)?;
            }
            Ok(b)
        })?;
        Ok(PyBeadHandle::new(slf.clone().unbind(), b))
    }
    /// Knots a bead at its abscissa (`True`) or lets it slide again.
    fn set_bead_fixed(slf: &Bound<'_, Self>, bead: &Bound<'_, PyBeadHandle>, fixed: bool) -> PyResult<()> {
        let b = bead.get().owned_by(slf)?;
        Self::with_mut(slf, |w| w.set_bead_fixed(b, fixed))
    }
    /// Mechanical energy now (energy unit), beads included: a dict with
    /// `kinetic` (rods ½VᵀMV + beads ½m|v|²), `elastic`, `external`
    /// (potential of gravity, loads and bead forces) and `total`.
    fn energy<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let w = read(slf)?;
        let e = guard(|| w.inner.energy())?;
        let d = pyo3::types::PyDict::new(slf.py());
        d.set_item("kinetic", e.kinetic)?;
        d.set_item("elastic", e.elastic)?;
        d.set_item("external", e.external)?;
        d.set_item("total", e.total())?;
        Ok(d)
    }
    /// Takes a bead off its rod.
    fn remove_bead(slf: &Bound<'_, Self>, bead: &Bound<'_, PyBeadHandle>) -> PyResult<()> {
        let b = bead.get().owned_by(slf)?;
        Self::with_mut(slf, |w| w.remove_bead(b).map(|_| ()))
    }
    /// External force on a bead besides gravity (force unit, 3 values).
    fn set_bead_force(slf: &Bound<'_, Self>, bead: &Bound<'_, PyBeadHandle>, force: &Bound<'_, PyAny>) -> PyResult<()> {
        let b = bead.get().owned_by(slf)?;
        let f = convert::vec3(force, "bead force")?;
        Self::with_mut(slf, |w| w.set_bead_force(b, f))
    }

    /// Gives `obj` (a Rod of this world or any handle) a label such as
    /// "plank[3]", making it a member of the group "plank".
    fn set_label(slf: &Bound<'_, Self>, obj: &Bound<'_, PyAny>, label: &str) -> PyResult<()> {
        let Some((kind, index, generation)) = convert::handle_of(obj, "set_label")? else {
            return Err(bad(format!("set_label: expected a Rod or a handle, got {}", obj.get_type().name()?)));
        };
        if !obj.getattr("world")?.is(slf) {
            return Err(bad(format!("set_label: this {kind} belongs to another world")));
        }
        let item = handles::item_of(&kind, index, generation)?;
        Self::with_mut(slf, |w| w.set_label(item, label))
    }
    /// The objects labelled `name[…]` (or exactly `name`) as a Group:
    /// forces, tensions, positions and broken flags as numpy arrays.
    fn group(slf: &Bound<'_, Self>, name: &str) -> PyResult<PyGroup> {
        PyGroup::new(slf, name)
    }
    /// Names of the groups (base names of the labels), sorted.
    #[getter]
    fn groups(slf: &Bound<'_, Self>) -> PyResult<Vec<String>> {
        Ok(read(slf)?.inner.groups().names().map(String::from).collect())
    }
    /// Adds an Assembly in one checked batch (atomic: on any error the
    /// world is unchanged); returns what was added (`rods`, `constraints`,
    /// `loads`, `beads`, `clips`, `bandwidth`).
    fn insert(slf: &Bound<'_, Self>, assembly: &Bound<'_, PyAssembly>) -> PyResult<PyInserted> {
        let py = slf.py();
        let ins = {
            let a = assembly.try_borrow()?;
            Self::with_mut(slf, |w| w.insert(&a.inner))?
        };
        let w = slf.clone().unbind();
        let objs = |v: Vec<PyResult<Py<PyAny>>>| v.into_iter().collect::<PyResult<Vec<_>>>();
        Ok(PyInserted {
            rods: objs(ins.rods.iter().map(|h| Ok(Bound::new(py, PyRod::attached(w.clone_ref(py), *h))?.into_any().unbind())).collect())?,
            constraints: objs(ins.constraints.iter().map(|h| Ok(Bound::new(py, Self::constraint(slf, *h))?.into_any().unbind())).collect())?,
            loads: objs(ins.loads.iter().map(|h| Ok(Bound::new(py, PyLoadHandle::new(w.clone_ref(py), *h))?.into_any().unbind())).collect())?,
            beads: objs(ins.beads.iter().map(|h| Ok(Bound::new(py, PyBeadHandle::new(w.clone_ref(py), *h))?.into_any().unbind())).collect())?,
            clips: objs(ins.clips.iter().map(|h| Ok(Bound::new(py, PyClipHandle::new(w.clone_ref(py), *h))?.into_any().unbind())).collect())?,
            bandwidth: ins.bandwidth,
        })
    }

    /// One linearised implicit Euler step of `dt`. The GIL is released
    /// while the core works. Raises SingularError / ConvergenceError.
    fn step(slf: &Bound<'_, Self>) -> PyResult<PyStepReport> {
        let py = slf.py();
        let rep = {
            let mut w = write(slf)?;
            let inner = &mut w.inner;
            py.detach(|| guard(|| inner.step()))?
        };
        let events = if rep.events.is_empty() { Vec::new() } else { events_of(slf, &rep.events)? };
        Ok(PyStepReport { inner: rep, events })
    }
    /// Quasi-static equilibrium: Newton's method damped by
    /// Levenberg–Marquardt (K + λ|diag K|), accepting a step when the
    /// potential energy does not rise; refuses a world that is not
    /// statically defined (SingularError naming the free rigid motion)
    /// and leaves it as it was. The report says whether the equilibrium
    /// is stable (`stable`, `unstable_directions`, from the inertia of the
    /// constrained stiffness). `perturb` (length unit): if the equilibrium
    /// found is unstable, push the control points by at most this much
    /// along a direction of decreasing energy and relax again (a column
    /// straight above its buckling load ends buckled).
    #[pyo3(signature = (*, perturb = None))]
    fn relax(slf: &Bound<'_, Self>, perturb: Option<f64>) -> PyResult<PyRelaxReport> {
        let py = slf.py();
        let rep = {
            let mut w = write(slf)?;
            let inner = &mut w.inner;
            py.detach(|| guard(|| match perturb {
                Some(a) => inner.relax_perturbed(a),
                None => inner.relax(),
            }))?
        };
        let events = events_of(slf, &rep.events)?;
        Ok(PyRelaxReport { inner: rep, events })
    }
    /// Benchmark helper: seconds taken by `n` steps run in a Rust loop
    /// (no Python in between), to measure the binding overhead.
    fn _time_steps(slf: &Bound<'_, Self>, n: usize) -> PyResult<f64> {
        let mut w = write(slf)?;
        let inner = &mut w.inner;
        slf.py().detach(|| {
            guard(|| {
                let t = std::time::Instant::now();
                for _ in 0..n {
                    inner.step()?;
                }
                Ok(t.elapsed().as_secs_f64())
            })
        })
    }

    /// The whole world as JSON (a versioned snapshot; floats round-trip exactly).
    fn to_json(slf: &Bound<'_, Self>) -> PyResult<String> {
        let w = read(slf)?;
        guard(|| w.inner.to_json())
    }
    /// A world from `to_json()` text; other formats or versions raise FileError.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        Ok(PyWorld { inner: guard(|| World::from_json(text))? })
    }
    /// Writes a snapshot (JSON) atomically; `World.load` reads it back and
    /// continues bit-for-bit.
    fn save(slf: &Bound<'_, Self>, path: std::path::PathBuf) -> PyResult<()> {
        let w = read(slf)?;
        guard(|| w.inner.save(&path))
    }
    /// A world from a snapshot file written by `save`.
    #[staticmethod]
    fn load(path: std::path::PathBuf) -> PyResult<Self> {
        Ok(PyWorld { inner: guard(|| World::load(&path))? })
    }
    /// An independent deep copy.
    fn copy(slf: &Bound<'_, Self>) -> PyResult<Self> {
        Ok(PyWorld { inner: read(slf)?.inner.clone() })
    }
    fn __copy__(slf: &Bound<'_, Self>) -> PyResult<Self> {
        Self::copy(slf)
    }
    fn __deepcopy__(slf: &Bound<'_, Self>, _memo: &Bound<'_, PyAny>) -> PyResult<Self> {
        Self::copy(slf)
    }
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let json = Self::to_json(slf)?;
        Ok((slf.get_type().getattr("from_json")?, PyTuple::new(slf.py(), [json])?))
    }
    fn __repr__(slf: &Bound<'_, Self>) -> String {
        // A repr never raises: a world busy in another thread says so.
        let Ok(w) = read(slf) else { return "World(<being stepped in another thread>)".into() };
        let p = &w.inner.params;
        let groups: Vec<&str> = w.inner.groups().names().collect();
        let mut s = format!(
            "World(time={}, steps={}, rods={}, constraints={}, dt={}, gravity={:?}",
            w.inner.time(),
            w.inner.n_steps(),
            w.inner.n_rods(),
            w.inner.n_constraints(),
            p.dt,
            p.gravity
        );
        if p.temperature > 0.0 || p.viscosity > 0.0 || p.overdamped || p.units != strandkit_core::Units::Si {
            let units = serde_json::to_value(p.units).ok().and_then(|v| v.as_str().map(String::from)).unwrap_or_default();
            s += &format!(", units='{units}', temperature={} K, viscosity={}, seed={}", p.temperature, p.viscosity, p.seed);
            if p.overdamped {
                s += ", overdamped=True";
            }
            if p.isotropic_drag {
                s += ", isotropic_drag=True";
            }
        }
        if !groups.is_empty() {
            s += &format!(", groups={}", convert::py_strs(groups));
        }
        s + ")"
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyWorld>()
}

/// Contacts as `World.contacts()` and `Group.contacts` give them: a dict of
/// arrays, rods named by their position in `world.rods()` (−1: an obstacle).
pub(crate) fn contacts_dict<'py>(py: Python<'py>, w: &World, list: &[strandkit_core::contact::ContactInfo]) -> PyResult<Bound<'py, PyDict>> {
    let order: Vec<RodHandle> = w.rods().map(|(h, _)| h).collect();
    let index = |h: Option<RodHandle>| h.and_then(|h| order.iter().position(|x| *x == h)).map_or(-1, |i| i as i64);
    let d = PyDict::new(py);
    d.set_item("rod_a", PyArray1::from_vec(py, list.iter().map(|c| index(Some(c.rod_a))).collect()))?;
    d.set_item("rod_b", PyArray1::from_vec(py, list.iter().map(|c| index(c.rod_b)).collect()))?;
    d.set_item("u_a", PyArray1::from_vec(py, list.iter().map(|c| c.ua).collect()))?;
    d.set_item("u_b", PyArray1::from_vec(py, list.iter().map(|c| c.ub.unwrap_or(f64::NAN)).collect()))?;
    d.set_item("points", convert::points(py, list.iter().map(|c| c.point))?)?;
    d.set_item("normals", convert::points(py, list.iter().map(|c| c.normal))?)?;
    d.set_item("normal_force", PyArray1::from_vec(py, list.iter().map(|c| c.normal_force).collect()))?;
    d.set_item("friction_force", convert::points(py, list.iter().map(|c| c.friction_force))?)?;
    d.set_item("slipping", PyArray1::from_vec(py, list.iter().map(|c| c.slipping).collect()))?;
    Ok(d)
}
