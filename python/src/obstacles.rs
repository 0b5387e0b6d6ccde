//! Obstacles for contact (SPEC §7): plane, sphere, capsule, triangle mesh.
use crate::convert;
use crate::guard;
use numpy::{PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use std::path::PathBuf;
use strandkit_core::{Obstacle, TriMesh};

/// A fixed obstacle for `World.add_obstacle`: build with
/// `strandkit.obstacles.plane / sphere / capsule / mesh` (lengths in the
/// world's unit).
#[pyclass(name = "Obstacle", module = "strandkit._native", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct PyObstacle {
    pub inner: Obstacle,
}

#[pymethods]
impl PyObstacle {
    /// "plane", "sphere", "capsule" or "mesh".
    #[getter]
    fn kind(&self) -> &'static str {
        use strandkit_core::contact::obstacle::Shape;
        match &self.inner.shape {
            Shape::Plane { .. } => "plane",
            Shape::Sphere { .. } => "sphere",
            Shape::Capsule { .. } => "capsule",
            Shape::Mesh(_) => "mesh",
        }
    }
    /// Signed distance (length) from each of the (n, 3) `points` to the
    /// surface, negative inside.
    fn distance<'py>(&self, py: Python<'py>, points: &Bound<'py, PyAny>) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
        let (flat, rows, _) = convert::matrix(points, &[3], "points")?;
        let d: Vec<f64> = (0..rows)
            .map(|i| {
                let p = nalgebra::Vector3::new(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
                self.inner.nearest(&p, f64::INFINITY).map_or(f64::INFINITY, |x| x.0)
            })
            .collect();
        Ok(numpy::PyArray1::from_vec(py, d))
    }
    fn __repr__(&self) -> String {
        use strandkit_core::contact::obstacle::Shape;
        match &self.inner.shape {
            Shape::Plane { origin, normal } => format!("Obstacle.plane(origin={origin:?}, normal={normal:?})"),
            Shape::Sphere { center, radius } => format!("Obstacle.sphere(center={center:?}, radius={radius})"),
            Shape::Capsule { a, b, radius } => format!("Obstacle.capsule(a={a:?}, b={b:?}, radius={radius})"),
            Shape::Mesh(m) => format!("Obstacle.mesh({} triangles)", m.n_triangles()),
        }
    }
}

/// The half-space behind the plane through `origin` (length) whose
/// `normal` points out of the obstacle.
#[pyfunction]
fn obstacle_plane(origin: &Bound<'_, PyAny>, normal: &Bound<'_, PyAny>) -> PyResult<PyObstacle> {
    let (o, n) = (convert::vec3(origin, "plane origin")?, convert::vec3(normal, "plane normal")?);
    Ok(PyObstacle { inner: guard(|| Obstacle::plane(o, n))? })
}

/// A ball of `radius` (length) about `center` (length).
#[pyfunction]
fn obstacle_sphere(center: &Bound<'_, PyAny>, radius: f64) -> PyResult<PyObstacle> {
    let c = convert::vec3(center, "sphere center")?;
    Ok(PyObstacle { inner: guard(|| Obstacle::sphere(c, radius))? })
}

/// The points within `radius` (length) of the segment `a`–`b` (length).
#[pyfunction]
fn obstacle_capsule(a: &Bound<'_, PyAny>, b: &Bound<'_, PyAny>, radius: f64) -> PyResult<PyObstacle> {
    let (a, b) = (convert::vec3(a, "capsule end a")?, convert::vec3(b, "capsule end b")?);
    Ok(PyObstacle { inner: guard(|| Obstacle::capsule(a, b, radius))? })
}

/// A triangle mesh from an .obj or .stl file.
#[pyfunction]
fn obstacle_mesh_file(path: PathBuf) -> PyResult<PyObstacle> {
    Ok(PyObstacle { inner: guard(|| Obstacle::mesh(TriMesh::from_file(&path)?))? })
}

/// A triangle mesh from (n, 3) `vertices` (length) and (m, 3) `triangles`
/// (vertex indices, counter-clockwise seen from outside).
#[pyfunction]
fn obstacle_mesh_arrays(vertices: &Bound<'_, PyAny>, triangles: &Bound<'_, PyAny>) -> PyResult<PyObstacle> {
    let (v, nv, _) = convert::matrix(vertices, &[3], "mesh vertices")?;
    let (t, nt, _) = convert::matrix(triangles, &[3], "mesh triangles")?;
    let verts: Vec<[f64; 3]> = (0..nv).map(|i| [v[3 * i], v[3 * i + 1], v[3 * i + 2]]).collect();
    let mut tris = Vec::with_capacity(nt);
    for i in 0..nt {
        let mut f = [0u32; 3];
        for (k, x) in f.iter_mut().enumerate() {
            let y = t[3 * i + k];
            if !(y >= 0.0 && y.fract() == 0.0 && y < u32::MAX as f64) {
                return Err(crate::bad(format!("mesh triangle {i}: index {y} is not a vertex index")));
            }
            *x = y as u32;
        }
        tris.push(f);
    }
    Ok(PyObstacle { inner: guard(|| Obstacle::mesh(TriMesh::new(verts, tris)?))? })
}

/// The (n, 3) vertices and (m, 3) triangles of a mesh obstacle.
#[pyfunction]
fn obstacle_mesh_data<'py>(py: Python<'py>, obstacle: &PyObstacle) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<i64>>)> {
    use strandkit_core::contact::obstacle::Shape;
    let Shape::Mesh(m) = &obstacle.inner.shape else { return Err(crate::bad("not a mesh obstacle")) };
    let v = convert::points(py, m.vertices())?;
    let t: Vec<i64> = m.triangles().iter().flat_map(|f| f.map(i64::from)).collect();
    let t = numpy::PyArray1::from_vec(py, t).reshape([m.n_triangles(), 3])?;
    Ok((v, t))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyObstacle>()?;
    m.add_function(wrap_pyfunction!(obstacle_plane, m)?)?;
    m.add_function(wrap_pyfunction!(obstacle_sphere, m)?)?;
    m.add_function(wrap_pyfunction!(obstacle_capsule, m)?)?;
    m.add_function(wrap_pyfunction!(obstacle_mesh_file, m)?)?;
    m.add_function(wrap_pyfunction!(obstacle_mesh_arrays, m)?)?;
    m.add_function(wrap_pyfunction!(obstacle_mesh_data, m)?)?;
    Ok(())
}
