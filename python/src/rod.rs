//! Rods: the builders (straight, helix, curve, through points, control
//! points) and access to a rod's state as numpy arrays.
//!
//! A `Rod` object is either free (just built, owns its Rust rod) or in a
//! world (then it is a live view: reading it reads the world's rod, so it
//! always shows the current state, and it doubles as the rod's handle).
use crate::convert::{self, array2, points};
use crate::guard;
use crate::props::{PyMaterial, PySection};
use crate::world_data::{read, write, PyWorld};
use nalgebra::Vector3;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use crate::bad;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::{Arc, Mutex};
use strandkit_core::energy::Strains;
use strandkit_core::io::mesh::{self, TubeOptions};
use strandkit_core::io::MAX_OUTPUT_POINTS;
use strandkit_core::spline::KnotKind;
use strandkit_core::{frames, Error, Material, Rod, RodBuilder, RodHandle, RodOptions, Section};

type Array<'py> = Bound<'py, PyArray2<f64>>;
type Arrays4<'py> = (Array<'py>, Array<'py>, Array<'py>, Array<'py>);
type MeshArrays<'py> = (Array<'py>, Array<'py>, Bound<'py, PyArray2<i64>>);

pub enum RodState {
    Free(Box<Rod>),
    InWorld {
        world: Py<PyWorld>,
        handle: RodHandle,
    },
}

/// A rod: cubic B-spline centreline with (optionally) a roll angle per
/// control point. Built by `strandkit.straight`, `helix`, `curve`,
/// `through_points`, `from_control_points`; once added to a world, this
/// object is a live view of the world's rod and serves as its handle.
///
/// Units: positions in the world's length unit, roll θ in radians,
/// velocities per time unit, energies in energy units, mass in mass units.
#[pyclass(name = "Rod", module = "strandkit._native")]
pub struct PyRod {
    pub state: RodState,
}

impl PyRod {
    pub fn free(rod: Rod) -> Self {
        PyRod {
            state: RodState::Free(Box::new(rod)),
        }
    }
    pub fn attached(world: Py<PyWorld>, handle: RodHandle) -> Self {
        PyRod {
            state: RodState::InWorld { world, handle },
        }
    }
    pub fn handle_parts(&self) -> Option<(u32, u32)> {
        match &self.state {
            RodState::InWorld { handle, .. } => Some((handle.index, handle.generation)),
            RodState::Free(_) => None,
        }
    }
    /// Runs `f` on the Rust rod (free, or the world's).
    pub fn with<R>(&self, py: Python<'_>, f: impl FnOnce(&Rod) -> PyResult<R>) -> PyResult<R> {
        match &self.state {
            RodState::Free(r) => f(r),
            RodState::InWorld { world, handle } => {
                let w = read(world.bind(py))?;
                let r = w.inner.rod(*handle).map_err(crate::err)?;
                f(r)
            }
        }
    }
    fn with_mut<R>(
        &mut self,
        py: Python<'_>,
        f: impl FnOnce(&mut Rod) -> PyResult<R>,
    ) -> PyResult<R> {
        match &mut self.state {
            RodState::Free(r) => f(r),
            RodState::InWorld { world, handle } => {
                let mut w = write(world.bind(py))?;
                let r = w.inner.rod_mut(*handle).map_err(crate::err)?;
                f(r)
            }
        }
    }
}

/// A requested output size `n`: an InvalidInputError beyond the cap on
/// generated output (checked before anything is allocated, so a typo such
/// as 10**10 is an error rather than an aborted process).
fn output_size(what: &str, n: usize) -> PyResult<()> {
    if n > MAX_OUTPUT_POINTS {
        return Err(crate::err(Error::invalid(what, n, format!("at most {MAX_OUTPUT_POINTS}"))));
    }
    Ok(())
}

fn strains_flat(s: &[Strains]) -> Vec<f64> {
    s.iter().flat_map(|x| [x.eps, x.kappa1, x.kappa2, x.omega]).collect()
}

/// Parameters given as a float or an array: (values, was_scalar).
fn params(obj: &Bound<'_, PyAny>) -> PyResult<(Vec<f64>, bool)> {
    if let Ok(x) = obj.extract::<f64>() {
        return Ok((vec![x], true));
    }
    Ok((convert::vector(obj, "u")?, false))
}

#[pymethods]
impl PyRod {
    /// Control points, shape (n, 4) = (x, y, z, θ) or (n, 3) without roll
    /// (length unit, radians). Assign an array of the same shape to move them.
    #[getter]
    fn control_points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (q, d) = self.with(py, |r| Ok((r.coords().to_vec(), r.dofs())))?;
        array2(py, q, d)
    }
    #[setter]
    fn set_control_points(&mut self, py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let (flat, _, _) = convert::matrix(value, &[3, 4], "control_points")?;
        self.with_mut(py, |r| guard(|| r.set_coords(&flat)))
    }
    /// Velocities of the control points, same shape as `control_points`
    /// (length/time, rad/time). Assignable.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (v, d) = self.with(py, |r| Ok((r.velocities().to_vec(), r.dofs())))?;
        array2(py, v, d)
    }
    #[setter]
    fn set_velocities(&mut self, py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let (flat, _, _) = convert::matrix(value, &[3, 4], "velocities")?;
        self.with_mut(py, |r| guard(|| r.set_velocities(&flat)))
    }
    /// Rest-shape control points (same shape as `control_points`).
    #[getter]
    fn rest_control_points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (q, d) = self.with(py, |r| Ok((r.rest_coords().to_vec(), r.dofs())))?;
        array2(py, q, d)
    }
    /// Centreline points at the sample (Gauss) points, shape (m, 3), length unit.
    fn sample_points<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let p = self.with(py, |r| Ok(r.sample_points()))?;
        points(py, p.into_iter().map(|v| [v.x, v.y, v.z]))
    }
    /// Parameter u of every sample point, shape (m,).
    fn sample_params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let u = self.with(py, |r| Ok(r.sample_params()))?;
        Ok(PyArray1::from_vec(py, u))
    }
    /// `n` parameters evenly spread over the domain, ends included
    /// (2 ≤ n ≤ 10^7, the cap on generated output).
    fn uniform_params<'py>(
        &self,
        py: Python<'py>,
        n: usize,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        output_size("uniform_params n", n)?;
        let u = self.with(py, |r| guard(|| frames::uniform_params(r, n)))?;
        Ok(PyArray1::from_vec(py, u))
    }
    /// Centreline point r(u) (length unit): shape (3,) for a float u,
    /// (m, 3) for an array. Error if u is outside `domain`.
    fn position<'py>(&self, py: Python<'py>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        self.eval_impl(py, u, 0, true)
    }
    /// Unit tangent at u: shape (3,) or (m, 3).
    fn tangent<'py>(&self, py: Python<'py>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let (us, scalar) = params(u)?;
        let t = self.with(py, |r| {
            us.iter()
                .map(|&u| guard(|| r.tangent(u)).map(|v| [v.x, v.y, v.z]))
                .collect::<PyResult<Vec<_>>>()
        })?;
        if scalar {
            Ok(PyArray1::from_vec(py, t[0].to_vec()).into_any())
        } else {
            Ok(points(py, t)?.into_any())
        }
    }
    /// Rest arc length (length unit) from the start of the domain to u: a
    /// float for a float u, an array for an array.
    fn arc_length<'py>(&self, py: Python<'py>, u: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let (us, scalar) = params(u)?;
        let s = self.with(py, |r| us.iter().map(|&u| guard(|| r.rest_arc_length(u))).collect::<PyResult<Vec<_>>>())?;
        Ok(if scalar { s[0].into_pyobject(py)?.into_any() } else { PyArray1::from_vec(py, s).into_any() })
    }
    /// The abscissa u at rest arc length s (length unit, 0 ≤ s ≤
    /// rest_length): a material coordinate that deformation does not move,
    /// e.g. base pair i of a strand. Inverse of `arc_length`, to 1e-12 of
    /// the rest length.
    fn u_at_arc_length<'py>(&self, py: Python<'py>, s: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let (ss, scalar) = params(s)?;
        let u = self.with(py, |r| ss.iter().map(|&s| guard(|| r.u_at_rest_arc_length(s))).collect::<PyResult<Vec<_>>>())?;
        Ok(if scalar { u[0].into_pyobject(py)?.into_any() } else { PyArray1::from_vec(py, u).into_any() })
    }
    /// The material frame at abscissa `u` — or at rest arc length `s`
    /// (length unit), not both: an array (3, 3) whose rows are d1, d2, d3
    /// (d3 the unit tangent; κ1 = κ b·d1 is the curvature about d1), or
    /// (m, 3, 3) for an array of abscissae. The Frenet model leaves it
    /// undefined where the rod is straight: SingularError there.
    #[pyo3(signature = (u = None, *, s = None))]
    fn material_frame<'py>(&self, py: Python<'py>, u: Option<&Bound<'py, PyAny>>, s: Option<&Bound<'py, PyAny>>) -> PyResult<Bound<'py, PyAny>> {
        let (xs, scalar, by_arc) = match (u, s) {
            (Some(u), None) => {
                let (x, sc) = params(u)?;
                (x, sc, false)
            }
            (None, Some(s)) => {
                let (x, sc) = params(s)?;
                (x, sc, true)
            }
            _ => return Err(bad("material_frame: give exactly one of u (abscissa) or s= (rest arc length)")),
        };
        let frames = self.with(py, |r| {
            xs.iter()
                .map(|&x| {
                    guard(|| {
                        let u = if by_arc { r.u_at_rest_arc_length(x)? } else { x };
                        r.material_frame(u)
                    })
                    .map(|f| [f.d1, f.d2, f.d3].map(|d| [d.x, d.y, d.z]))
                })
                .collect::<PyResult<Vec<_>>>()
        })?;
        let flat: Vec<f64> = frames.iter().flat_map(|f| f.iter().flatten().copied()).collect();
        let arr = PyArray1::from_vec(py, flat);
        let shape: Vec<usize> = if scalar { vec![3, 3] } else { vec![frames.len(), 3, 3] };
        Ok(arr.reshape(shape)?.into_any())
    }
    /// Excess link ΔLk (turns) imposed on a closed rod with roll: its
    /// material frame turns ΔLk more times around the ring than at rest (a
    /// DNA minicircle's ΔLk); the twist stiffness GJ acts on ω − (ω⁰ −
    /// 2π ΔLk / L). Assignable (rings with roll only); 0 by default.
    #[getter]
    fn excess_link(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |r| Ok(r.excess_link()))
    }
    #[setter]
    fn set_excess_link(&mut self, py: Python<'_>, turns: f64) -> PyResult<()> {
        self.with_mut(py, |r| guard(|| r.set_excess_link(turns)))
    }
    /// Twist Tw (turns), plus the imposed excess link. model="frenet"
    /// (closed rods only): (1/2π)∮τ ds with the exact Frenet torsion
    /// (SingularError if the ring has an inflection); model="reference"
    /// (closed or open rods with roll): (1/2π)∫ω ds with the material twist
    /// of the energy, defined everywhere; on a ring Tw + Wr is conserved
    /// while it deforms (up to ±2 per strand passage without contact).
    fn twist(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |r| guard(|| r.twist()))
    }
    /// Writhe Wr of a closed rod's centreline (turns), the Gauss double
    /// integral (cost: the square of 8 points per segment; the diagonal
    /// kink handled so it converges as fast as the curve is smooth).
    fn writhe(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |r| guard(|| r.writhe()))
    }
    /// Link Lk = Tw + Wr of a closed rod (turns; Călugăreanu–White–Fuller).
    fn link(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |r| guard(|| r.link()))
    }
    /// The `derivative`-th u-derivative of (x, y, z[, θ]) at u: shape
    /// (dofs,) or (m, dofs).
    #[pyo3(signature = (u, derivative = 0))]
    fn eval<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
        derivative: usize,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.eval_impl(py, u, derivative, false)
    }
    /// Rotation-minimising frames (double reflection, Wang et al. 2008)
    /// rotated by θ: returns (points, tangents, d1, d2), each (m, 3). `u`:
    /// increasing parameters (default: the sample points); or `n` evenly
    /// spread ones (n ≤ 10^7). `reference`: direction fixing the first d1
    /// (before roll).
    #[pyo3(signature = (u = None, *, n = None, reference = None))]
    fn frames<'py>(
        &self,
        py: Python<'py>,
        u: Option<&Bound<'py, PyAny>>,
        n: Option<usize>,
        reference: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Arrays4<'py>> {
        let us = match u {
            Some(u) => Some(params(u)?.0),
            None => None,
        };
        let reference = reference
            .map(|r| convert::vec3(r, "reference"))
            .transpose()?;
        if let Some(n) = n {
            output_size("frames n", n)?;
        }
        let f = self.with(py, |r| {
            let us = match (us, n) {
                (Some(u), _) => u,
                (None, Some(n)) => guard(|| frames::uniform_params(r, n))?,
                (None, None) => r.sample_params(),
            };
            guard(|| frames::rotation_minimising(r, &us, reference))
        })?;
        let col = |g: fn(&frames::Frame) -> Vector3<f64>| points(py, f.iter().map(|x| g(x).into()));
        Ok((
            col(|x| x.point)?,
            col(|x| x.tangent)?,
            col(|x| x.d1)?,
            col(|x| x.d2)?,
        ))
    }
    /// Strains at the sample points, shape (m, 4): stretch ε (dimensionless),
    /// material curvatures κ1, κ2 and twist ω (1/length).
    fn strains<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let s = self.with(py, |r| Ok(r.strains()))?;
        array2(py, strains_flat(&s), 4)
    }
    /// Relative strains ε_r = ε − ε⁰ at the sample points, shape (m, 4):
    /// stretch (dimensionless), κ1 − κ1⁰, κ2 − κ2⁰, ω − ω⁰ (1/length). These
    /// are what the yield and rupture limits are compared with (SPEC §6).
    fn relative_strains<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let s = self.with(py, |r| Ok(r.relative_strains()))?;
        array2(py, strains_flat(&s), 4)
    }
    /// Plastic offsets Δε_p at the sample points, shape (m, 4), same columns
    /// and units as `strains`. Assignable (an array of that shape).
    #[getter]
    fn plastic_offsets<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let s = self.with(py, |r| Ok(r.plastic_offsets()))?;
        array2(py, strains_flat(&s), 4)
    }
    #[setter]
    fn set_plastic_offsets(&mut self, py: Python<'_>, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let (flat, _, _) = convert::matrix(value, &[4], "plastic_offsets")?;
        let s: Vec<Strains> = flat
            .chunks(4)
            .map(|c| Strains { eps: c[0], kappa1: c[1], kappa2: c[2], omega: c[3] })
            .collect();
        self.with_mut(py, |r| guard(|| r.set_plastic_offsets(&s)))
    }
    /// Replaces the yield and rupture strain limits, each a dict
    /// {'stretch': x, 'bend': 1/length, 'twist': 1/length} of symmetric
    /// limits (missing or inf: no limit) or None (purely elastic / never
    /// breaks). Plastic offsets already accumulated are kept.
    #[pyo3(signature = (*, yield_limits = None, rupture_limits = None))]
    fn set_strain_limits(
        &mut self,
        py: Python<'_>,
        yield_limits: Option<&Bound<'_, PyAny>>,
        rupture_limits: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let y = yield_limits.map(crate::props::limits_arg).transpose()?;
        let b = rupture_limits.map(crate::props::limits_arg).transpose()?;
        self.with_mut(py, |r| guard(|| r.set_strain_limits(y, b)))
    }
    /// Internal generalised forces −∂U/∂q, shape like `control_points`.
    fn internal_forces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (p, d) = self.with(py, |r| Ok((r.internal_forces(), r.dofs())))?;
        array2(py, p, d)
    }
    /// Tube mesh (generalised cylinder): (vertices (N,3), normals (N,3),
    /// triangles (T,3) int). Radius = section bounding radius × radius_scale.
    /// At most 10^7 vertices (segments × rings_per_segment × points_per_ring).
    #[pyo3(signature = (*, rings_per_segment = 6, points_per_ring = 12, radius_scale = 1.0, caps = true))]
    fn mesh<'py>(
        &self,
        py: Python<'py>,
        rings_per_segment: usize,
        points_per_ring: usize,
        radius_scale: f64,
        caps: bool,
    ) -> PyResult<MeshArrays<'py>> {
        let o = TubeOptions {
            rings_per_segment,
            points_per_ring,
            radius_scale,
            caps,
        };
        let m = self.with(py, |r| guard(|| mesh::tube(r, &o)))?;
        let tri: Vec<i64> = m.triangles.iter().flat_map(|t| t.map(i64::from)).collect();
        let nt = m.triangles.len();
        Ok((
            points(py, m.vertices)?,
            points(py, m.normals)?,
            PyArray1::from_vec(py, tri).reshape([nt, 3])?,
        ))
    }
    /// Parameter domain (u_start, u_end).
    #[getter]
    fn domain(&self, py: Python<'_>) -> PyResult<(f64, f64)> {
        self.with(py, |r| Ok(r.domain()))
    }
    /// First parameter of the domain (the rod's start).
    #[getter]
    fn u_start(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |r| Ok(r.domain().0))
    }
    /// Last parameter of the domain (the rod's end).
    #[getter]
    fn u_end(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |r| Ok(r.domain().1))
    }
    #[getter]
    fn n_control_points(&self, py: Python<'_>) -> PyResult<usize> {
        self.with(py, |r| Ok(r.n_ctrl()))
    }
    #[getter]
    fn n_segments(&self, py: Python<'_>) -> PyResult<usize> {
        self.with(py, |r| Ok(r.n_segments()))
    }
    /// Coordinates per control point: 4 (x, y, z, θ) or 3.
    #[getter]
    fn dofs(&self, py: Python<'_>) -> PyResult<usize> {
        self.with(py, |r| Ok(r.dofs()))
    }
    /// Knot vector kind: "uniform", "clamped", "periodic" or "general".
    #[getter]
    fn knots(&self, py: Python<'_>) -> PyResult<String> {
        self.with(py, |r| Ok(format!("{:?}", r.knots().kind()).to_lowercase()))
    }
    /// Rest length (length unit).
    #[getter]
    fn rest_length(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |r| Ok(r.rest_length()))
    }
    /// Total mass (mass unit).
    #[getter]
    fn mass(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |r| Ok(r.mass()))
    }
    /// Elastic energy U (energy unit).
    #[getter]
    fn elastic_energy(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |r| guard(|| Ok(r.elastic_energy())))
    }
    /// Kinetic energy ½ VᵀMV (energy unit).
    #[getter]
    fn kinetic_energy(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |r| Ok(r.kinetic_energy()))
    }
    /// Elastic + kinetic energy (energy unit).
    #[getter]
    fn energy(&self, py: Python<'_>) -> PyResult<f64> {
        self.with(py, |r| {
            guard(|| Ok(r.elastic_energy() + r.kinetic_energy()))
        })
    }
    /// Linear momentum (mass × length/time), shape (3,).
    #[getter]
    fn momentum<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let p = self.with(py, |r| Ok(r.momentum()))?;
        Ok(PyArray1::from_vec(py, vec![p.x, p.y, p.z]))
    }
    #[getter]
    fn material(&self, py: Python<'_>) -> PyResult<PyMaterial> {
        self.with(py, |r| {
            Ok(PyMaterial {
                inner: r.material().clone(),
            })
        })
    }
    /// One section per control point.
    #[getter]
    fn sections(&self, py: Python<'_>) -> PyResult<Vec<PySection>> {
        self.with(py, |r| {
            Ok(r.sections()
                .iter()
                .map(|s| PySection { inner: *s })
                .collect())
        })
    }
    /// (index, generation) of the rod in its world, or None if free.
    #[getter]
    fn handle(&self) -> Option<(u32, u32)> {
        self.handle_parts()
    }
    /// ("rod", index, generation) in its world, or None if free: how other
    /// calls recognise a rod of a world.
    #[getter]
    fn _handle(&self) -> Option<(&'static str, u32, u32)> {
        self.handle_parts().map(|(i, g)| ("rod", i, g))
    }
    /// Its label in the world's groups (e.g. "strand[0]"), or None.
    #[getter]
    fn label(&self, py: Python<'_>) -> PyResult<Option<String>> {
        match &self.state {
            RodState::InWorld { world, handle } => {
                let w = read(world.bind(py))?;
                Ok(crate::world_data::label_of(&w.inner, strandkit_core::Item::Rod(*handle)))
            }
            RodState::Free(_) => Ok(None),
        }
    }
    /// The rod options (the core's RodOptions) as a dict: samples_per_segment,
    /// terms, model, curvature_threshold, drag, roll_drag, poisson_update.
    #[getter]
    fn options<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let o = self.with(py, |r| Ok(*r.options()))?;
        convert::from_json(py, &serde_json::to_value(o).unwrap_or_default())
    }
    /// The rod's drag coefficients in a fluid of viscosity `viscosity` (the
    /// world's, by default; 0 for its own only), as a dict: `trans` (force
    /// per velocity per length, each axis), `roll` (torque per angular
    /// velocity per length, times ∫b b ds) and `roll_r2` (4πη, times
    /// ∫r² b b ds): its own `drag`/`roll_drag` plus the resistive-force drag;
    /// `axial` is added along the tangent (γ_∥ − γ_⊥ = −γ_⊥/2; 0 in a world
    /// with `isotropic_drag=True`).
    #[pyo3(signature = (viscosity = None))]
    fn drag<'py>(&self, py: Python<'py>, viscosity: Option<f64>) -> PyResult<Bound<'py, PyDict>> {
        let (world_eta, isotropic) = match &self.state {
            RodState::InWorld { world, .. } => {
                let p = &read(world.bind(py))?.inner.params;
                (p.viscosity, p.isotropic_drag)
            }
            RodState::Free(_) => (0.0, false),
        };
        let eta = viscosity.unwrap_or(world_eta);
        let d = self.with(py, |r| guard(|| r.drag(eta)))?;
        let out = PyDict::new(py);
        out.set_item("trans", d.trans)?;
        out.set_item("axial", if isotropic { 0.0 } else { d.axial })?;
        out.set_item("roll", d.roll)?;
        out.set_item("roll_r2", d.roll_r2)?;
        Ok(out)
    }
    /// Frame model ("frenet" | "reference").
    #[getter]
    fn model(&self, py: Python<'_>) -> PyResult<String> {
        let m = self.with(py, |r| Ok(r.frame_model()))?;
        Ok(serde_json::to_value(m).ok().and_then(|v| v.as_str().map(String::from)).unwrap_or_default())
    }
    /// The world holding this rod, or None.
    #[getter]
    fn world(&self, py: Python<'_>) -> Option<Py<PyWorld>> {
        match &self.state {
            RodState::InWorld { world, .. } => Some(world.clone_ref(py)),
            RodState::Free(_) => None,
        }
    }
    /// A free copy of this rod (current state as its shape, same rest shape).
    fn copy(&self, py: Python<'_>) -> PyResult<PyRod> {
        self.with(py, |r| Ok(PyRod::free(r.clone())))
    }
    /// The rod as JSON (serde; floats round-trip exactly).
    fn to_json(&self, py: Python<'_>) -> PyResult<String> {
        self.with(py, |r| {
            guard(|| serde_json::to_string(r).map_err(|e| Error::io("", e.to_string())))
        })
    }
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        let Ok(o) = other.cast::<PyRod>() else {
            return false;
        };
        let Ok(o) = o.try_borrow() else { return false };
        match (&self.state, &o.state) {
            (
                RodState::InWorld {
                    world: a,
                    handle: h,
                },
                RodState::InWorld {
                    world: b,
                    handle: k,
                },
            ) => a.is(b) && h == k,
            (RodState::Free(a), RodState::Free(b)) => std::ptr::eq(&**a, &**b),
            _ => false,
        }
    }
    fn __hash__(&self) -> u64 {
        self.handle_parts()
            .map_or(0, |(i, g)| ((g as u64) << 32) | i as u64)
    }
    fn __repr__(&self, py: Python<'_>) -> String {
        let place = match &self.state {
            RodState::Free(_) => "free".to_string(),
            RodState::InWorld { handle, world } => {
                let label = world
                    .bind(py)
                    
                    .try_borrow()
                    .ok()
                    .and_then(|w| crate::world_data::label_of(&w.inner, strandkit_core::Item::Rod(*handle)));
                match label {
                    Some(l) => format!("rod {} {l:?} in a world", handle.index),
                    None => format!("rod {} in a world", handle.index),
                }
            }
        };
        self.with(py, |r| {
            Ok(format!(
                "Rod({} control points × {}, {} knots, rest_length={:.6}, mass={:.6}, section={}, material={:?}, {place})",
                r.n_ctrl(),
                r.dofs(),
                format!("{:?}", r.knots().kind()).to_lowercase(),
                r.rest_length(),
                r.mass(),
                r.sections()[0].kind_name(),
                r.material().name
            ))
        })
        .unwrap_or_else(|e| format!("Rod(<{place}: {e}>)"))
    }
}

impl PyRod {
    fn eval_impl<'py>(
        &self,
        py: Python<'py>,
        u: &Bound<'py, PyAny>,
        deriv: usize,
        xyz: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (us, scalar) = params(u)?;
        let (vals, d) = self.with(py, |r| {
            let d = if xyz { 3 } else { r.dofs() };
            let mut out = Vec::with_capacity(us.len() * d);
            for &u in &us {
                out.extend_from_slice(&guard(|| r.eval(u, deriv))?[..d]);
            }
            Ok((out, d))
        })?;
        if scalar {
            Ok(PyArray1::from_vec(py, vals).into_any())
        } else {
            Ok(array2(py, vals, d)?.into_any())
        }
    }
}

fn section_arg(obj: &Bound<'_, PyAny>) -> PyResult<Section> {
    if let Ok(s) = obj.cast::<PySection>() {
        return Ok(s.get().inner);
    }
    if let Ok(r) = obj.extract::<f64>() {
        return guard(|| Section::circle(r));
    }
    Err(PyTypeError::new_err(
        "section: expected a strandkit.Section or a radius (float) for a circle",
    ))
}

fn material_arg(obj: &Bound<'_, PyAny>) -> PyResult<Material> {
    if let Ok(m) = obj.cast::<PyMaterial>() {
        return Ok(m.get().inner.clone());
    }
    if let Ok(name) = obj.extract::<String>() {
        return guard(|| Material::preset(&name));
    }
    Err(PyTypeError::new_err(
        "material: expected a strandkit.Material or a preset name",
    ))
}

fn knot_kind(s: &str) -> PyResult<KnotKind> {
    match s.to_ascii_lowercase().as_str() {
        "clamped" => Ok(KnotKind::Clamped),
        "uniform" => Ok(KnotKind::Uniform),
        "periodic" | "closed" => Ok(KnotKind::Periodic),
        _ => Err(crate::err(Error::invalid("knots", format!("{s:?}"), "'clamped', 'uniform' or 'periodic'"))),
    }
}

/// Keyword options shared by every builder. The rod options (RodOptions
/// fields, with `stretch`, `bend`, `twist` standing for `terms`) go through
/// the one keyword converter, so a field added to the core's RodOptions is
/// accepted here as a keyword without a binding change.
struct Common<'a, 'py> {
    py: Python<'py>,
    section: Option<&'a Bound<'py, PyAny>>,
    sections: Option<&'a Bound<'py, PyAny>>,
    material: Option<&'a Bound<'py, PyAny>>,
    n_control_points: usize,
    knots: &'a str,
    with_roll: bool,
    roll: Option<&'a Bound<'py, PyAny>>,
    /// (name, value) of the rod options given (None left out).
    options: Vec<(String, Bound<'py, PyAny>)>,
}

/// Rod options from builder keywords: `stretch`, `bend`, `twist` go into
/// `terms`; every other key must be a RodOptions field.
fn rod_options<'py>(py: Python<'py>, given: Vec<(String, Bound<'py, PyAny>)>) -> PyResult<RodOptions> {
    let terms = PyDict::new(py);
    let mut pairs = Vec::new();
    for (k, v) in given {
        match k.as_str() {
            "stretch" | "bend" | "twist" => terms.set_item(k, v)?,
            _ => pairs.push((k, v)),
        }
    }
    if !terms.is_empty() {
        pairs.push(("terms".to_string(), terms.into_any()));
    }
    convert::kwargs_into(&RodOptions::default(), pairs, "rod option")
}

impl Common<'_, '_> {
    fn apply(self, b: RodBuilder) -> PyResult<RodBuilder> {
        let opts = rod_options(self.py, self.options)?;
        if !(1..=8).contains(&opts.samples_per_segment) {
            return Err(crate::err(Error::invalid("samples_per_segment", opts.samples_per_segment, "in 1..=8")));
        }
        let mut b = b.control_points(self.n_control_points).knots(knot_kind(self.knots)?).with_roll(self.with_roll).options(opts);
        match (self.section, self.sections) {
            (Some(s), None) => b = b.section(section_arg(s)?),
            (None, Some(list)) => {
                let v = list.try_iter()?.map(|s| section_arg(&s?)).collect::<PyResult<Vec<_>>>()?;
                b = b.sections(v);
            }
            (None, None) => return Err(bad("a rod needs section= (or sections=, one per control point)")),
            (Some(_), Some(_)) => return Err(bad("give section= or sections=, not both")),
        }
        let m = self.material.ok_or_else(|| bad("a rod needs material= (a Material or a preset name)"))?;
        b = b.material(material_arg(m)?);
        if let Some(r) = self.roll {
            b = b.roll(convert::vector(r, "roll")?);
        }
        Ok(b)
    }
}

macro_rules! builder_fn {
    ($(#[$doc:meta])* $name:ident ( $($arg:ident : $ty:ty),* ) => |$c:ident| $body:expr) => {
        $(#[$doc])*
        #[pyfunction]
        #[pyo3(signature = ($($arg),*, *, section = None, material = None, n_control_points = 20, knots = "clamped",
            with_roll = true, roll = None, sections = None, samples_per_segment = None, drag = None, roll_drag = None,
            curvature_threshold = None, stretch = None, bend = None, twist = None, poisson_update = None,
            model = None, **options))]
        #[allow(clippy::too_many_arguments)]
        fn $name<'py>(
            py: Python<'py>,
            $($arg: $ty,)*
            section: Option<&Bound<'py, PyAny>>,
            material: Option<&Bound<'py, PyAny>>,
            n_control_points: usize,
            knots: &str,
            with_roll: bool,
            roll: Option<&Bound<'py, PyAny>>,
            sections: Option<&Bound<'py, PyAny>>,
            samples_per_segment: Option<Bound<'py, PyAny>>,
            drag: Option<Bound<'py, PyAny>>,
            roll_drag: Option<Bound<'py, PyAny>>,
            curvature_threshold: Option<Bound<'py, PyAny>>,
            stretch: Option<Bound<'py, PyAny>>,
            bend: Option<Bound<'py, PyAny>>,
            twist: Option<Bound<'py, PyAny>>,
            poisson_update: Option<Bound<'py, PyAny>>,
            model: Option<Bound<'py, PyAny>>,
            options: Option<&Bound<'py, PyDict>>,
        ) -> PyResult<PyRod> {
            let mut given: Vec<(String, Bound<'py, PyAny>)> = [
                ("samples_per_segment", samples_per_segment),
                ("drag", drag),
                ("roll_drag", roll_drag),
                ("curvature_threshold", curvature_threshold),
                ("stretch", stretch),
                ("bend", bend),
                ("twist", twist),
                ("poisson_update", poisson_update),
                ("model", model),
            ]
            .into_iter()
            .filter_map(|(k, v)| v.map(|v| (k.to_string(), v)))
            .collect();
            given.extend(convert::kwargs(options)?);
            let $c = Common { py, section, sections, material, n_control_points, knots, with_roll, roll, options: given };
            $body
        }
    };
}

fn build(b: RodBuilder) -> PyResult<PyRod> {
    Ok(PyRod::free(guard(|| b.build())?))
}

builder_fn!(
    /// Straight rod from `start` to `end` (length unit).
    ///
    /// Keyword options of every builder: `section` (Section, or a float =
    /// circle radius) or `sections` (one per control point), `material`
    /// (Material or preset name), `n_control_points` (≥ 4, default 20),
    /// `knots` ('clamped' | 'uniform' | 'periodic'), `with_roll` (False: 3
    /// coordinates per control point, no twist), `roll` (θ per control
    /// point, rad). Rod options (the core's RodOptions; None = its
    /// default): `samples_per_segment` (Gauss points, 1..8, default 5),
    /// `drag` (force/(velocity·length), default 0), `roll_drag`
    /// (torque/(angular velocity·length), default 0), `curvature_threshold`
    /// (1/length, 0 = 1/rest length), `stretch`, `bend`, `twist` (energy
    /// terms on/off, default True), `poisson_update` (sections contract
    /// with stretch, II.59, default False), `model` (frame model:
    /// "reference", a transported reference director per sample, SPEC
    /// §2.3, twist defined on straight stretches, default; or "frenet",
    /// the thesis' Frenet + roll, for its validations; a rod without roll
    /// is always "frenet"); any other RodOptions field by name.
    straight(start: [f64; 3], end: [f64; 3]) => |c| {
        build(c.apply(RodBuilder::straight(Vector3::from(start), Vector3::from(end)))?)
    }
);

builder_fn!(
    /// Circular helix about z starting at (radius, 0, 0): `radius` and
    /// `pitch` (rise per turn; > 0 right-handed) in length unit, `turns`.
    /// Keyword options as `straight`.
    helix(radius: f64, pitch: f64, turns: f64) => |c| {
        build(c.apply(RodBuilder::helix(radius, pitch, turns))?)
    }
);

builder_fn!(
    /// Rod along a curve given by arc length: `f(s)` → (x, y, z) for s in
    /// [0, `length`] (length unit). Keyword options as `straight`.
    curve(f: Bound<'py, PyAny>, length: f64) => |c| {
        let func: Py<PyAny> = f.unbind();
        let failure: Arc<Mutex<Option<PyErr>>> = Arc::new(Mutex::new(None));
        let slot = failure.clone();
        let b = RodBuilder::curve(length, move |s| {
            Python::attach(|py| {
                let r = func.call1(py, (s,)).and_then(|v| convert::vec3(v.bind(py), "curve f(s)"));
                r.map(Vector3::from).unwrap_or_else(|e| {
                    if let Ok(mut g) = slot.lock() {
                        g.get_or_insert(e);
                    }
                    Vector3::repeat(f64::NAN)
                })
            })
        });
        let built = c.apply(b).and_then(build);
        if let Some(e) = failure.lock().ok().and_then(|mut g| g.take()) {
            return Err(e);
        }
        built
    }
);

builder_fn!(
    /// Rod through `points` (array (n, 3), length unit; roughly evenly
    /// spaced): one control point per point, solved by interpolation.
    /// Keyword options as `straight` (`n_control_points` is ignored).
    through_points(points: Bound<'py, PyAny>) => |c| {
        let (flat, n, _) = convert::matrix(&points, &[3], "points")?;
        let pts = (0..n).map(|i| Vector3::new(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2])).collect();
        build(c.apply(RodBuilder::new(strandkit_core::rod::RodShape::ThroughPoints(pts)))?)
    }
);

builder_fn!(
    /// Rod from explicit control points: array (n, 3), or (n, 4) whose last
    /// column is the roll θ (rad). Keyword options as `straight`.
    from_control_points(points: Bound<'py, PyAny>) => |c| {
        let (flat, n, d) = convert::matrix(&points, &[3, 4], "points")?;
        let pts = (0..n).map(|i| Vector3::new(flat[d * i], flat[d * i + 1], flat[d * i + 2])).collect();
        if d == 4 && c.roll.is_some() {
            return Err(bad("roll given twice: in the 4th column of points and as roll="));
        }
        let mut b = c.apply(RodBuilder::new(strandkit_core::rod::RodShape::ControlPoints(pts)))?;
        if d == 4 {
            b = b.roll((0..n).map(|i| flat[4 * i + 3]).collect());
        }
        build(b)
    }
);

/// Resistive-force theory drag of a slender rod (SPEC §3): for viscosity
/// `viscosity` (Pa·s in SI, pN·ns/nm² in molecular units), `radius` and
/// `length` (length unit), returns (γ⊥, γ∥, γθ) per unit length =
/// (4πη/(ln(L/r) + ½), γ⊥/2, 4πηr²), SPEC §3's approximations (slender-body
/// theory's γ∥ is 2πη/(ln(L/r) − ½), 16 % above γ⊥/2 at L/r = 1000): force per velocity per length on each
/// transverse and on the axial direction, torque per angular velocity per
/// length on the roll. A World's `viscosity` applies γ⊥ on every axis (the
/// smaller axial drag is not modelled) and γθ on the roll.
#[pyfunction]
#[pyo3(signature = (viscosity, radius, length))]
fn resistive_force_drag(viscosity: f64, radius: f64, length: f64) -> PyResult<(f64, f64, f64)> {
    let [a, b, c] = guard(|| strandkit_core::rod::drag::resistive_force(viscosity, radius, length))?;
    Ok((a, b, c))
}

/// A rod from `Rod.to_json()` text (free).
#[pyfunction]
fn rod_from_json(text: &str) -> PyResult<PyRod> {
    let mut r: Rod =
        serde_json::from_str(text).map_err(|e| crate::err(Error::io("", format!("rod json: {e}"))))?;
    guard(|| r.prepare())?;
    Ok(PyRod::free(r))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyRod>()?;
    m.add_function(wrap_pyfunction!(straight, m)?)?;
    m.add_function(wrap_pyfunction!(helix, m)?)?;
    m.add_function(wrap_pyfunction!(curve, m)?)?;
    m.add_function(wrap_pyfunction!(through_points, m)?)?;
    m.add_function(wrap_pyfunction!(from_control_points, m)?)?;
    m.add_function(wrap_pyfunction!(rod_from_json, m)?)?;
    m.add_function(wrap_pyfunction!(resistive_force_drag, m)?)?;
    Ok(())
}
