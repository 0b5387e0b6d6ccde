//! The `World` class's data: the core world a Python `World` owns. Its
//! methods are in `world.rs`; the views of its objects (rods, handles,
//! groups, events) need only this module, so the bindings form no import
//! circle.
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use strandkit_core::{Item, World};

/// A simulation world: rods, constraints and loads, advanced by `step()`
/// (linearised implicit Euler, or a second-order scheme) or brought to
/// equilibrium by `relax()`.
///
/// Keyword arguments: every field of the core's IntegrationParameters
/// (None = its default; `params` lists them): `dt` time step (time unit,
/// default 1e-3), `gravity` (length/time², 3 values, default 0),
/// `parallel` (assemble with threads when the world has ≥ 2048 segments, default True), `relax_tolerance`
/// (relative: increment ≤ tol × rod length, default 1e-10),
/// `relax_max_iterations` (default 500), `plastic_tolerance` (relax with
/// plastic flow: largest offset increment per round, strain or curvature ×
/// rest length, default 1e-6), `relax_mixed` (relax may take a Newton
/// step the potential refuses when a mixed-integration-point merit, which
/// does not charge the stretch of turning, accepts it, under a watchdog:
/// the same equilibria in fewer solves on bent stiff rods; default True),
/// `linear_solver` ("Auto" | "Band" |
/// "BandLu" | "Sparse"), `scheme` ("implicit_euler", the default: first
/// order, damps what dt does not resolve | "tr_bdf2": second order,
/// L-stable, keeps resolved vibrations, two or more solves per step |
/// "trapezoidal": second order, no numerical damping, for rods held by
/// linear constraints only; both second-order schemes refuse sliding
/// beads). `set_params(**fields)` changes them later.
///
/// Rods whose material has yield or rupture limits flow plastically and
/// break after every step (and at every relax equilibrium); a rupture is a
/// `RodRuptured` event whose `rod` and `new_rod` are the two pieces.
///
/// Threads: `step`, `relax` and `QuasiDynamic.step` release the GIL. While
/// one thread steps a world, any use of it from another thread (reading a
/// rod, a handle, stepping it too) raises WorldBusyError at once; nothing
/// waits and nothing is changed.
///
/// >>> import strandkit as sk
/// >>> world = sk.World(dt=1e-3, gravity=(0, -9.81, 0))
/// >>> world.params["relax_max_iterations"]
/// 500
/// >>> rod = world.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", n_control_points=8))
/// >>> pin = world.add_constraint(rod, sk.position(rod.u_start), label="pin")
/// >>> report = world.step()
/// >>> report.factorisation, world.n_steps
/// ('band_ldlt', 1)
/// >>> world
/// World(time=0.001, steps=1, rods=1, constraints=1, dt=0.001, gravity=[0.0, -9.81, 0.0], groups=['pin'])
#[pyclass(name = "World", module = "strandkit._native")]
pub struct PyWorld {
    pub inner: World,
}

/// `strandkit.WorldBusyError` saying that `what` is in use elsewhere.
pub(crate) fn busy(py: Python<'_>, what: &str) -> PyErr {
    let msg = format!("{what} is being stepped in another thread: wait for its step to return");
    match py.import("strandkit.errors").and_then(|m| m.getattr("WorldBusyError")).and_then(|c| c.call1((&msg,))) {
        Ok(e) => PyErr::from_value(e),
        Err(_) => PyRuntimeError::new_err(msg),
    }
}

/// The world's data for reading. `step`, `relax` and quasi-dynamic frames
/// hold the world mutably with the GIL released, so another Python thread
/// can get here meanwhile: it gets a WorldBusyError, never pyo3's
/// "Already borrowed".
pub(crate) fn read<'py>(w: &Bound<'py, PyWorld>) -> PyResult<PyRef<'py, PyWorld>> {
    w.try_borrow().map_err(|_| busy(w.py(), "world"))
}

/// The world's data for changing (see [`read`]).
pub(crate) fn write<'py>(w: &Bound<'py, PyWorld>) -> PyResult<PyRefMut<'py, PyWorld>> {
    w.try_borrow_mut().map_err(|_| busy(w.py(), "world"))
}

/// The label of an object (constraints carry theirs; other objects are
/// found in the world's groups), alive or gone.
pub(crate) fn label_of(w: &World, item: Item) -> Option<String> {
    if let Item::Constraint(h) = item {
        if let Some(l) = w.constraint(h).ok().and_then(|c| c.label.clone()) {
            return Some(l);
        }
    }
    let g = w.groups();
    g.names().find_map(|name| g.members(name).ok()?.into_iter().find(|m| m.item == item).map(|m| m.label))
}

