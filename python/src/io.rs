//! Output: tube meshes (OBJ, VTK) and trajectories (PDB, PSF, DCD), all
//! written by the Rust core (atomically; see core/src/io).
use crate::convert::{self, points};
use crate::guard;
use crate::rod::PyRod;
use crate::world_data::{read, PyWorld};
use numpy::{PyArray1, PyArray3, PyArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use strandkit_core::io::mesh::{self, TubeMesh, TubeOptions};
use strandkit_core::io::trajectory::{self as traj, DcdHeader, DcdWriter, Topology};

fn mesh_of(obj: &Bound<'_, PyAny>, o: &TubeOptions) -> PyResult<TubeMesh> {
    if let Ok(w) = obj.cast::<PyWorld>() {
        let w = read(w)?;
        return guard(|| mesh::world_tubes(&w.inner, o));
    }
    if let Ok(r) = obj.cast::<PyRod>() {
        return r
            .try_borrow()?
            .with(obj.py(), |rod| guard(|| mesh::tube(rod, o)));
    }
    Err(PyTypeError::new_err("expected a World or a Rod"))
}

type MeshArrays<'py> = (
    Bound<'py, numpy::PyArray2<f64>>,
    Bound<'py, numpy::PyArray2<f64>>,
    Bound<'py, numpy::PyArray2<i64>>,
    Bound<'py, PyArray1<i64>>,
);

/// Tube mesh of a World (all rods) or a Rod: (vertices (N,3) length unit,
/// normals (N,3), triangles (T,3) vertex indices, part (N,) rod index).
/// `rings_per_segment` rings per spline segment, `points_per_ring`
/// vertices per ring, radius = section bounding radius × `radius_scale`,
/// `caps` closes open ends. At most 10^7 vertices in all (an
/// InvalidInputError beyond, before anything is allocated).
#[pyfunction]
#[pyo3(signature = (obj, *, rings_per_segment = 6, points_per_ring = 12, radius_scale = 1.0, caps = true))]
fn tube_mesh<'py>(
    obj: &Bound<'py, PyAny>,
    rings_per_segment: usize,
    points_per_ring: usize,
    radius_scale: f64,
    caps: bool,
) -> PyResult<MeshArrays<'py>> {
    let py = obj.py();
    let m = mesh_of(
        obj,
        &TubeOptions {
            rings_per_segment,
            points_per_ring,
            radius_scale,
            caps,
        },
    )?;
    let nt = m.triangles.len();
    let tri: Vec<i64> = m.triangles.iter().flat_map(|t| t.map(i64::from)).collect();
    Ok((
        points(py, m.vertices)?,
        points(py, m.normals)?,
        PyArray1::from_vec(py, tri).reshape([nt, 3])?,
        PyArray1::from_vec(py, m.part.iter().map(|&p| i64::from(p)).collect()),
    ))
}

/// One pyfunction per mesh format: same keywords (tube resolution), a
/// different writer of `TubeMesh` (each writes atomically).
macro_rules! mesh_writer {
    ($(#[$doc:meta])* $name:ident => $method:ident) => {
        $(#[$doc])*
        #[pyfunction]
        #[pyo3(signature = (obj, path, *, rings_per_segment = 6, points_per_ring = 12, radius_scale = 1.0, caps = true))]
        fn $name(
            obj: &Bound<'_, PyAny>,
            path: PathBuf,
            rings_per_segment: usize,
            points_per_ring: usize,
            radius_scale: f64,
            caps: bool,
        ) -> PyResult<()> {
            let m = mesh_of(obj, &TubeOptions { rings_per_segment, points_per_ring, radius_scale, caps })?;
            guard(|| m.$method(&path))
        }
    };
}

mesh_writer!(
    /// Writes the tube mesh of a World or Rod as Wavefront OBJ (atomically).
    write_obj => write_obj
);
mesh_writer!(
    /// Writes the tube mesh of a World or Rod as legacy VTK polydata (ParaView), atomically.
    write_vtk => write_vtk
);
mesh_writer!(
    /// Writes the tube mesh of a World or Rod as binary glTF 2.0 (`.glb`:
    /// Blender, three.js, any glTF viewer), one named node per rod, atomically.
    write_gltf => write_glb
);

/// Bead positions of a world (length unit), shape (N, 3): the sample
/// points of every rod in world order (one bead per sample point).
#[pyfunction]
fn bead_positions<'py>(world: &Bound<'py, PyWorld>) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
    let p = traj::bead_positions(&read(world)?.inner);
    points(world.py(), p)
}

/// Frames given as (N, 3) or (F, N, 3) → list of frames.
fn frames_arg(obj: &Bound<'_, PyAny>) -> PyResult<Vec<Vec<[f64; 3]>>> {
    let msg = "positions: expected an array of shape (n_beads, 3) or (n_frames, n_beads, 3)";
    let arr: numpy::PyArrayLikeDyn<f64, numpy::AllowTypeChange> =
        obj.extract().map_err(|_| crate::bad(msg))?;
    let a = arr.as_array();
    let shape = a.shape().to_vec();
    if !(2..=3).contains(&shape.len()) || shape[shape.len() - 1] != 3 {
        return Err(crate::bad(format!("{msg}, got shape {shape:?}")));
    }
    let flat: Vec<f64> = a.iter().copied().collect();
    let per = shape[shape.len() - 2] * 3;
    Ok(flat
        .chunks(per.max(1))
        .map(|f| f.chunks(3).map(|c| [c[0], c[1], c[2]]).collect())
        .collect())
}

/// Bead topology of a world: one chain per rod, one bead per sample point,
/// bonds between consecutive beads (and last–first on closed rods).
#[pyclass(name = "Topology", module = "strandkit._native", frozen)]
pub struct PyTopology {
    inner: Topology,
}

#[pymethods]
impl PyTopology {
    #[new]
    fn new(world: &Bound<'_, PyWorld>) -> PyResult<Self> {
        Ok(PyTopology {
            inner: Topology::from_world(&read(world)?.inner),
        })
    }
    /// A topology of given chains: `chains` beads per chain; `residues`
    /// one list of residue names (1–3 letters or digits) per chain, one
    /// per bead (default `SKB`); `closed` per chain; `links` (L, 2) bonds
    /// between any two beads (0-based over all chains), such as hydrogen
    /// bonds; a link may not repeat a bond.
    #[staticmethod]
    #[pyo3(signature = (chains, *, residues = None, closed = None, links = None))]
    fn of_beads(
        chains: Vec<usize>,
        residues: Option<Vec<Vec<String>>>,
        closed: Option<Vec<bool>>,
        links: Option<Vec<[usize; 2]>>,
    ) -> PyResult<Self> {
        let n = chains.len();
        let residues = residues.unwrap_or_else(|| vec![Vec::new(); n]);
        let closed = closed.unwrap_or_else(|| vec![false; n]);
        if residues.len() != n || closed.len() != n {
            return Err(crate::bad(format!(
                "{n} chains but {} residue lists and {} closed flags",
                residues.len(),
                closed.len()
            )));
        }
        let total: usize = chains.iter().try_fold(0usize, |a, &b| a.checked_add(b)).unwrap_or(usize::MAX);
        if total > 99_999_999 {
            return Err(crate::bad(format!("{total} beads: a PSF holds at most 99,999,999")));
        }
        let chains = chains
            .into_iter()
            .zip(residues)
            .zip(closed)
            .map(|((beads, residues), closed)| traj::Chain { beads, closed, residues })
            .collect();
        Ok(PyTopology {
            inner: guard(|| Topology::new(chains, links.unwrap_or_default()))?,
        })
    }
    #[getter]
    fn n_beads(&self) -> usize {
        self.inner.n_beads()
    }
    /// Residue name of every bead, in bead order.
    #[getter]
    fn residues(&self) -> Vec<String> {
        let t = &self.inner;
        t.chains
            .iter()
            .enumerate()
            .flat_map(|(c, ch)| (0..ch.beads).map(move |k| t.residue(c, k).to_string()))
            .collect()
    }
    /// Beads per chain (rod).
    #[getter]
    fn chains(&self) -> Vec<usize> {
        self.inner.chains.iter().map(|c| c.beads).collect()
    }
    /// Bonds as 0-based bead index pairs, shape (B, 2).
    #[getter]
    fn bonds<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray2<i64>>> {
        let b = self.inner.bonds();
        let n = b.len();
        PyArray1::from_vec(
            py,
            b.into_iter().flat_map(|p| p.map(|x| x as i64)).collect(),
        )
        .reshape([n, 2])
    }
    /// Chain index of every bead, shape (N,).
    fn chain_of_bead<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        PyArray1::from_vec(
            py,
            self.inner
                .chain_of_bead()
                .into_iter()
                .map(|x| x as i64)
                .collect(),
        )
    }
    /// Writes PDB (+CONECT), atomically. `positions`: (N, 3) or (F, N, 3)
    /// in length unit (one MODEL per frame); `scale`: Å per length unit
    /// (10 for nm; a metre-scale scene fits PDB's columns only scaled down);
    /// `bfactors`: one per bead (the temperature-factor column VMD colours by).
    #[pyo3(signature = (path, positions, *, scale = 10.0, bfactors = None))]
    fn write_pdb(
        &self,
        path: PathBuf,
        positions: &Bound<'_, PyAny>,
        scale: f64,
        bfactors: Option<Vec<f64>>,
    ) -> PyResult<()> {
        let f = frames_arg(positions)?;
        guard(|| traj::write_pdb(&path, &self.inner, &f, scale, bfactors.as_deref()))
    }
    /// Writes the CHARMM PSF (atoms, bonds), atomically.
    fn write_psf(&self, path: PathBuf) -> PyResult<()> {
        guard(|| traj::write_psf(&path, &self.inner))
    }
    fn __repr__(&self) -> String {
        format!(
            "Topology({} beads in {} chains, {} bonds)",
            self.inner.n_beads(),
            self.inner.chains.len(),
            self.inner.bonds().len()
        )
    }
}

/// Writes the world's current state as PDB (+CONECT): one bead per sample
/// point, one chain per rod; `scale` Å per length unit.
#[pyfunction]
#[pyo3(signature = (world, path, *, scale = 10.0))]
fn write_pdb(world: &Bound<'_, PyWorld>, path: PathBuf, scale: f64) -> PyResult<()> {
    let w = read(world)?;
    let topo = Topology::from_world(&w.inner);
    let p = traj::bead_positions(&w.inner);
    guard(|| traj::write_pdb(&path, &topo, &[p], scale, None))
}

/// Writes the world's bead topology as a CHARMM PSF.
#[pyfunction]
fn write_psf(world: &Bound<'_, PyWorld>, path: PathBuf) -> PyResult<()> {
    let topo = Topology::from_world(&read(world)?.inner);
    guard(|| traj::write_psf(&path, &topo))
}

/// CHARMM DCD writer (SPEC §8). `DcdWriter(path, n_atoms, dt=…, nsavc=…)`
/// creates the file; `DcdWriter.append(path)` reopens one (cutting a
/// partial frame left by an interrupted run). Every frame is complete on
/// disk before the frame count in the header includes it. Use as a
/// context manager or call close().
#[pyclass(name = "DcdWriter", module = "strandkit._native")]
pub struct PyDcdWriter {
    inner: Option<DcdWriter>,
    /// Counts kept after close().
    n_frames: usize,
    n_atoms: usize,
}

impl PyDcdWriter {
    fn w(&mut self) -> PyResult<&mut DcdWriter> {
        self.inner
            .as_mut()
            .ok_or_else(|| crate::bad("DCD writer is closed"))
    }
}

#[pymethods]
impl PyDcdWriter {
    /// `dt`: time between steps (stored as DELTA, world time unit);
    /// `nsavc`: steps between frames; `istart`: step of the first frame.
    #[new]
    #[pyo3(signature = (path, n_atoms, *, dt = 0.0, nsavc = 1, istart = 0, title = "strandkit trajectory"))]
    fn new(
        path: PathBuf,
        n_atoms: usize,
        dt: f64,
        nsavc: i32,
        istart: i32,
        title: &str,
    ) -> PyResult<Self> {
        let h = DcdHeader {
            n_atoms,
            n_frames: 0,
            istart,
            nsavc,
            delta: dt as f32,
            titles: [
                title.to_string(),
                "REMARKS written by strandkit; lengths in Angstrom".into(),
            ],
        };
        Ok(PyDcdWriter {
            inner: Some(guard(|| DcdWriter::create(&path, h))?),
            n_frames: 0,
            n_atoms,
        })
    }
    #[staticmethod]
    fn append(path: PathBuf) -> PyResult<Self> {
        let w = guard(|| DcdWriter::open_append(&path))?;
        let (n_frames, n_atoms) = (w.n_frames(), w.header().n_atoms);
        Ok(PyDcdWriter {
            inner: Some(w),
            n_frames,
            n_atoms,
        })
    }
    /// Appends one frame of positions (N, 3) in length unit × `scale` → Å.
    #[pyo3(signature = (positions, *, scale = 10.0))]
    fn write_frame(&mut self, positions: &Bound<'_, PyAny>, scale: f64) -> PyResult<()> {
        let (flat, _, _) = convert::matrix(positions, &[3], "positions")?;
        let p: Vec<[f64; 3]> = flat.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        let w = self.w()?;
        guard(|| w.write_frame(&p, scale))?;
        self.n_frames = w.n_frames();
        Ok(())
    }
    /// Appends the world's current bead positions.
    #[pyo3(signature = (world, *, scale = 10.0))]
    fn write_world(&mut self, world: &Bound<'_, PyWorld>, scale: f64) -> PyResult<()> {
        let p = traj::bead_positions(&read(world)?.inner);
        let w = self.w()?;
        guard(|| w.write_frame(&p, scale))?;
        self.n_frames = w.n_frames();
        Ok(())
    }
    /// Frames in the file (also after close()).
    #[getter]
    fn n_frames(&self) -> usize {
        self.n_frames
    }
    #[getter]
    fn n_atoms(&self) -> usize {
        self.n_atoms
    }
    /// fsync the file.
    fn flush(&mut self) -> PyResult<()> {
        let w = self.w()?;
        guard(|| w.flush())
    }
    fn close(&mut self) -> PyResult<()> {
        match self.inner.take() {
            Some(w) => guard(|| w.close()),
            None => Ok(()),
        }
    }
    fn __enter__(slf: Py<Self>) -> Py<Self> {
        slf
    }
    #[pyo3(signature = (*_args))]
    fn __exit__(&mut self, _args: &Bound<'_, pyo3::types::PyTuple>) -> PyResult<bool> {
        self.close()?;
        Ok(false)
    }
    fn __repr__(&self) -> String {
        match &self.inner {
            Some(w) => format!(
                "DcdWriter({} atoms, {} frames)",
                w.header().n_atoms,
                w.n_frames()
            ),
            None => format!(
                "DcdWriter(closed, {} atoms, {} frames)",
                self.n_atoms, self.n_frames
            ),
        }
    }
}

/// Reads a DCD written by strandkit: (header dict, positions (F, N, 3)
/// float32 in Å). Frames are counted from the file size.
#[pyfunction]
fn read_dcd<'py>(
    py: Python<'py>,
    path: PathBuf,
) -> PyResult<(Bound<'py, PyDict>, Bound<'py, PyArray3<f32>>)> {
    let (h, frames) = guard(|| traj::read_dcd(&path))?;
    let d = PyDict::new(py);
    d.set_item("n_atoms", h.n_atoms)?;
    d.set_item("n_frames", h.n_frames)?;
    d.set_item("istart", h.istart)?;
    d.set_item("nsavc", h.nsavc)?;
    d.set_item("delta", h.delta)?;
    d.set_item("titles", h.titles.to_vec())?;
    let (nf, na) = (frames.len(), h.n_atoms);
    let flat: Vec<f32> = frames.into_iter().flatten().flatten().collect();
    Ok((d, PyArray1::from_vec(py, flat).reshape([nf, na, 3])?))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(tube_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(write_obj, m)?)?;
    m.add_function(wrap_pyfunction!(write_vtk, m)?)?;
    m.add_function(wrap_pyfunction!(write_gltf, m)?)?;
    m.add_function(wrap_pyfunction!(bead_positions, m)?)?;
    m.add_function(wrap_pyfunction!(write_pdb, m)?)?;
    m.add_function(wrap_pyfunction!(write_psf, m)?)?;
    m.add_function(wrap_pyfunction!(read_dcd, m)?)?;
    m.add_class::<PyTopology>()?;
    m.add_class::<PyDcdWriter>()?;
    Ok(())
}
