//! Named groups seen from Python: `world.group("rung")` answers for every
//! object labelled "rung[…]" at once, as numpy arrays (forces, tensions,
//! positions, broken flags) and live objects.
use crate::convert::tagged;
use crate::guard;
use crate::handles::{to_py, PyConstraintHandle};
use crate::world_data::{read, PyWorld};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use strandkit_core::world::{ConstraintState, ObjectState};
use strandkit_core::Item;

/// The objects of a world labelled `name[…]` (or exactly `name`), read live
/// from the world at every access. Constraint members, in insertion order,
/// give the arrays: `labels`, `constraints` (handles), `forces` (n, 3) and
/// `torques` (n, 3) of the last solve (force, force × length; 0 once
/// gone), `tensions` (n,) (force; NaN for kinds without a line of action
/// or once gone), `positions` (n, 3) of their first abscissa (length; NaN
/// once gone), `alive`, `broken` (n,) bool, `broken_time` (time) and
/// `broken_force` (the measure that broke it) (n,) NaN where not broken,
/// `multipliers` (list of arrays). Rod members' contacts: `contacts`
/// (the arrays of `World.contacts()`, seen from the group's rods) and
/// `contact_force` (3,) (net, from outside the group; force). Other
/// members: `rods`, `beads`, `loads`, `clips` (live objects), `members`
/// ((label, object) pairs of every member).
///
/// >>> import strandkit as sk
/// >>> world = sk.World(gravity=(0, -9.81, 0))
/// >>> rod = world.add_rod(sk.straight((0, 0, 0), (1, 0, 0), section=0.01, material="nylon", with_roll=False))
/// >>> a = world.add_constraint(rod, sk.position(rod.u_start), label="pin[0]")
/// >>> b = world.add_constraint(rod, sk.position(rod.u_end, (1, 0, 0)), label="pin[1]")
/// >>> report = world.relax()
/// >>> pins = world.group("pin")
/// >>> pins.labels, pins.broken.tolist()
/// (['pin[0]', 'pin[1]'], [False, False])
/// >>> round(float(pins.forces[:, 1].sum() / (rod.mass * 9.81)), 9)   # the pins carry the weight
/// 1.0
#[pyclass(name = "Group", module = "strandkit._native", frozen)]
pub struct PyGroup {
    world: Py<PyWorld>,
    name: String,
}

impl PyGroup {
    /// A group of `world`; an InvalidInputError when no object has that label.
    pub(crate) fn new(world: &Bound<'_, PyWorld>, name: &str) -> PyResult<Self> {
        {
            let w = read(world)?;
            guard(|| w.inner.group(name))?;
        }
        Ok(PyGroup { world: world.clone().unbind(), name: name.to_string() })
    }
    fn states(&self, py: Python<'_>) -> PyResult<Vec<ConstraintState>> {
        let w = read(self.world.bind(py))?;
        guard(|| w.inner.group_constraints(&self.name))
    }
    fn objects(&self, py: Python<'_>) -> PyResult<Vec<ObjectState>> {
        let w = read(self.world.bind(py))?;
        guard(|| w.inner.group_objects(&self.name))
    }
    fn rows<'py>(&self, py: Python<'py>, f: impl Fn(&ConstraintState) -> [f64; 3]) -> PyResult<Bound<'py, PyArray2<f64>>> {
        crate::convert::points(py, self.states(py)?.iter().map(f))
    }
    fn column<'py>(&self, py: Python<'py>, f: impl Fn(&ConstraintState) -> f64) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(PyArray1::from_vec(py, self.states(py)?.iter().map(f).collect()))
    }
    fn flags<'py>(&self, py: Python<'py>, f: impl Fn(&ConstraintState) -> bool) -> PyResult<Bound<'py, PyArray1<bool>>> {
        Ok(PyArray1::from_vec(py, self.states(py)?.iter().map(f).collect()))
    }
    /// Live objects of the object members whose item `keep` accepts.
    fn objects_where<'py>(&self, py: Python<'py>, keep: fn(&Item) -> bool) -> PyResult<Vec<Bound<'py, PyAny>>> {
        let w = self.world.bind(py);
        self.objects(py)?.iter().filter(|o| keep(&o.item)).map(|o| item_object(w, &o.item)).collect()
    }
}

/// The live Python object of an item.
fn item_object<'py>(world: &Bound<'py, PyWorld>, item: &Item) -> PyResult<Bound<'py, PyAny>> {
    let v = tagged(item);
    let (_, handle) = crate::convert::variant(&v);
    to_py(world, &handle)
}

#[pymethods]
impl PyGroup {
    /// The group's name (a base name such as "rung", or one exact label).
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }
    /// Labels of the constraint members (the rows of the arrays).
    #[getter]
    fn labels(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        Ok(self.states(py)?.into_iter().map(|s| s.label).collect())
    }
    /// Handles of the constraint members (alive or gone).
    #[getter]
    fn constraints(&self, py: Python<'_>) -> PyResult<Vec<PyConstraintHandle>> {
        Ok(self.states(py)?.into_iter().map(|s| PyConstraintHandle::new(self.world.clone_ref(py), s.constraint)).collect())
    }
    /// Reaction forces of the last solve on each constraint's first rod (force unit), (n, 3).
    #[getter]
    fn forces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.rows(py, |s| s.force)
    }
    /// Reaction torques (force × length unit), (n, 3).
    #[getter]
    fn torques<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.rows(py, |s| s.torque)
    }
    /// Tension along each line of action (force unit, > 0 pulling), (n,); NaN where none.
    #[getter]
    fn tensions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, |s| s.tension.unwrap_or(f64::NAN))
    }
    /// Point of each constraint's first abscissa (length unit), (n, 3); NaN once gone.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.rows(py, |s| s.position.unwrap_or([f64::NAN; 3]))
    }
    /// Still in the world, (n,) bool.
    #[getter]
    fn alive<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<bool>>> {
        self.flags(py, |s| s.alive)
    }
    /// Broke under load, (n,) bool.
    #[getter]
    fn broken<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<bool>>> {
        self.flags(py, |s| s.broken.is_some())
    }
    /// When each broke (time unit), (n,); NaN where not broken.
    #[getter]
    fn broken_time<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, |s| s.broken.map_or(f64::NAN, |b| b.time))
    }
    /// The measure that broke each (force unit, see its break policy), (n,); NaN where not broken.
    #[getter]
    fn broken_force<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.column(py, |s| s.broken.map_or(f64::NAN, |b| b.force))
    }
    /// Multipliers of the last solve per constraint (list of arrays; empty once gone).
    #[getter]
    fn multipliers<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
        Ok(self.states(py)?.into_iter().map(|s| PyArray1::from_vec(py, s.multipliers)).collect())
    }
    /// The active contacts of the last solve touching the group's rods, as
    /// `World.contacts()` gives them but each seen from the group's rod
    /// (`rod_a`, `u_a`, `points` its; `normals` pushing it out;
    /// `friction_force` on it). A pair between two of its rods (or a rod
    /// and itself) appears once.
    #[getter]
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let w = read(self.world.bind(py))?;
        let list = guard(|| w.inner.group_contacts(&self.name))?;
        crate::world::contacts_dict(py, &w.inner, &list)
    }
    /// Net contact force on the group's rods (force unit), (3,): normal and
    /// friction forces from obstacles and rods outside the group (pairs
    /// within it cancel and are left out).
    #[getter]
    fn contact_force<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let w = read(self.world.bind(py))?;
        Ok(PyArray1::from_vec(py, guard(|| w.inner.group_contact_force(&self.name))?.to_vec()))
    }
    /// Rod members (Rod views).
    #[getter]
    fn rods<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyAny>>> {
        self.objects_where(py, |i| matches!(i, Item::Rod(_)))
    }
    /// Bead members (BeadHandles).
    #[getter]
    fn beads<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyAny>>> {
        self.objects_where(py, |i| matches!(i, Item::Bead(_)))
    }
    /// Load members (LoadHandles).
    #[getter]
    fn loads<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyAny>>> {
        self.objects_where(py, |i| matches!(i, Item::Load(_)))
    }
    /// Clip members (ClipHandles).
    #[getter]
    fn clips<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyAny>>> {
        self.objects_where(py, |i| matches!(i, Item::Clip(_)))
    }
    /// Every member as a (label, object) pair, in insertion order.
    #[getter]
    fn members<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyTuple>>> {
        let w = self.world.bind(py);
        let ms = {
            let b = read(w)?;
            guard(|| b.inner.group(&self.name))?
        };
        ms.iter().map(|m| PyTuple::new(py, [m.label.clone().into_pyobject(py)?.into_any(), item_object(w, &m.item)?])).collect()
    }
    fn __len__(&self, py: Python<'_>) -> PyResult<usize> {
        let w = read(self.world.bind(py))?;
        Ok(guard(|| w.inner.group(&self.name))?.len())
    }
    fn __repr__(&self, py: Python<'_>) -> String {
        let (Ok(states), Ok(objects)) = (self.states(py), self.objects(py)) else {
            return format!("Group({:?})", self.name);
        };
        let mut parts = Vec::new();
        if !states.is_empty() {
            let alive = states.iter().filter(|s| s.alive).count();
            let broken = states.iter().filter(|s| s.broken.is_some()).count();
            let fmax = states.iter().map(|s| s.force.iter().map(|x| x * x).sum::<f64>().sqrt()).fold(0.0, f64::max);
            parts.push(format!("{} constraints ({alive} alive, {broken} broken, max |force| {fmax:.4e})", states.len()));
        }
        for (what, keep) in [
            ("rods", (|i: &Item| matches!(i, Item::Rod(_))) as fn(&Item) -> bool),
            ("beads", |i| matches!(i, Item::Bead(_))),
            ("loads", |i| matches!(i, Item::Load(_))),
            ("clips", |i| matches!(i, Item::Clip(_))),
        ] {
            let n = objects.iter().filter(|o| keep(&o.item)).count();
            if n > 0 {
                parts.push(format!("{n} {what}"));
            }
        }
        format!("Group({:?}: {})", self.name, parts.join(", "))
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyGroup>()
}
