//! Sections and materials (SPEC §1.2).
use crate::convert;
use crate::guard;
use pyo3::prelude::*;
use strandkit_core::material::StrainLimits;
use strandkit_core::{Material, Section};

/// Cross-section of a rod (annex D). Build with the static methods; all
/// sizes in the world's length unit (m in SI). Properties: perimeter (L),
/// area (L²), i1, i2, i0, j (L⁴), bounding_radius (L).
#[pyclass(name = "Section", module = "strandkit._native", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct PySection {
    pub inner: Section,
}

#[pymethods]
impl PySection {
    /// Solid disc of `radius` (length).
    #[staticmethod]
    fn circle(radius: f64) -> PyResult<Self> {
        Ok(PySection {
            inner: guard(|| Section::circle(radius))?,
        })
    }
    /// Circular tube, `outer_radius` > `inner_radius` > 0 (length).
    #[staticmethod]
    fn tube(outer_radius: f64, inner_radius: f64) -> PyResult<Self> {
        Ok(PySection {
            inner: guard(|| Section::tube(outer_radius, inner_radius))?,
        })
    }
    /// Solid ellipse, semi-axis `a` along d1 and `b` along d2 (length).
    #[staticmethod]
    fn ellipse(a: f64, b: f64) -> PyResult<Self> {
        Ok(PySection {
            inner: guard(|| Section::ellipse(a, b))?,
        })
    }
    /// Solid square of `side` (length).
    #[staticmethod]
    fn square(side: f64) -> PyResult<Self> {
        Ok(PySection {
            inner: guard(|| Section::square(side))?,
        })
    }
    /// Solid rectangle, `width` along d1 × `height` along d2 (length).
    #[staticmethod]
    fn rectangle(width: f64, height: f64) -> PyResult<Self> {
        Ok(PySection {
            inner: guard(|| Section::rectangle(width, height))?,
        })
    }
    /// I-beam: flange `width`, total `height`, `flange_thickness` < height/2,
    /// `web_thickness` < width (length).
    #[staticmethod]
    fn double_t(
        width: f64,
        height: f64,
        flange_thickness: f64,
        web_thickness: f64,
    ) -> PyResult<Self> {
        Ok(PySection {
            inner: guard(|| Section::double_t(width, height, flange_thickness, web_thickness))?,
        })
    }
    /// Shape name: circle, tube, ellipse, square, rectangle or double_t.
    #[getter]
    fn kind(&self) -> &'static str {
        self.inner.kind_name()
    }
    /// Sizes as a dict (length unit).
    #[getter]
    fn sizes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let v = serde_json::to_value(self.inner).unwrap_or_default();
        convert::from_json(py, &convert::variant(&v).1)
    }
    #[getter]
    fn perimeter(&self) -> PyResult<f64> {
        Ok(guard(|| self.inner.props())?.perimeter)
    }
    #[getter]
    fn area(&self) -> PyResult<f64> {
        Ok(guard(|| self.inner.props())?.area)
    }
    /// Second moment about d1 (resists κ1), length⁴.
    #[getter]
    fn i1(&self) -> PyResult<f64> {
        Ok(guard(|| self.inner.props())?.i1)
    }
    /// Second moment about d2 (resists κ2), length⁴.
    #[getter]
    fn i2(&self) -> PyResult<f64> {
        Ok(guard(|| self.inner.props())?.i2)
    }
    /// Polar moment i1 + i2, length⁴.
    #[getter]
    fn i0(&self) -> PyResult<f64> {
        Ok(guard(|| self.inner.props())?.i0)
    }
    /// Saint-Venant torsion constant, length⁴.
    #[getter]
    fn j(&self) -> PyResult<f64> {
        Ok(guard(|| self.inner.props())?.j)
    }
    /// Radius of the enclosing circle (length), used for display.
    #[getter]
    fn bounding_radius(&self) -> f64 {
        self.inner.bounding_radius()
    }
    fn __repr__(&self) -> String {
        let v = serde_json::to_value(self.inner).unwrap_or_default();
        let (_, fields) = convert::variant(&v);
        let parts: Vec<String> = fields
            .as_object()
            .map(|m| m.iter().map(|(k, x)| format!("{k}={x}")).collect())
            .unwrap_or_default();
        format!("Section.{}({})", self.inner.kind_name(), parts.join(", "))
    }
}

/// Isotropic linear-elastic material: `young` E (pressure, Pa in SI),
/// `poisson` ν in (−1, 0.5], `density` ρ (mass/length³, kg/m³ in SI).
/// `Material.preset(name)` gives the annex-C metals and polymers and the
/// textile yarns (SI).
#[pyclass(name = "Material", module = "strandkit._native", frozen, eq)]
#[derive(Clone, PartialEq)]
pub struct PyMaterial {
    pub inner: Material,
}

fn limits(stretch: f64, bend: f64, twist: f64) -> strandkit_core::Result<StrainLimits> {
    StrainLimits::symmetric(stretch, bend, twist)
}

/// {'stretch': x, 'bend': x, 'twist': x} (missing: inf) → symmetric limits.
pub fn limits_arg(obj: &Bound<'_, PyAny>) -> PyResult<StrainLimits> {
    let d = obj
        .cast::<pyo3::types::PyDict>()
        .map_err(|_| crate::bad("strain limits: expected a dict with keys 'stretch', 'bend', 'twist'"))?;
    let mut v = [f64::INFINITY; 3];
    for (k, x) in d.iter() {
        let key: String = k.extract()?;
        let i = ["stretch", "bend", "twist"].iter().position(|n| *n == key).ok_or_else(|| {
            crate::bad(format!("strain limits: unknown mode {key:?} (use 'stretch', 'bend', 'twist')"))
        })?;
        v[i] = x.extract()?;
    }
    guard(|| limits(v[0], v[1], v[2]))
}

#[pymethods]
impl PyMaterial {
    #[new]
    #[pyo3(signature = (name, young, poisson, density))]
    fn new(name: &str, young: f64, poisson: f64, density: f64) -> PyResult<Self> {
        Ok(PyMaterial {
            inner: guard(|| Material::new(name, young, poisson, density))?,
        })
    }
    /// A shipped material (SI), e.g. "carbon_steel", "nylon", "cotton".
    #[staticmethod]
    fn preset(name: &str) -> PyResult<Self> {
        Ok(PyMaterial {
            inner: guard(|| Material::preset(name))?,
        })
    }
    /// Names of the shipped materials.
    #[staticmethod]
    fn presets() -> Vec<&'static str> {
        Material::preset_names().to_vec()
    }
    /// A copy with symmetric yield strains (stretch: dimensionless; bend,
    /// twist: 1/length). `inf` disables a mode.
    #[pyo3(signature = (*, stretch = f64::INFINITY, bend = f64::INFINITY, twist = f64::INFINITY))]
    fn with_yield(&self, stretch: f64, bend: f64, twist: f64) -> PyResult<Self> {
        let m = self.inner.clone();
        Ok(PyMaterial {
            inner: guard(|| m.with_yield(limits(stretch, bend, twist)?))?,
        })
    }
    /// A copy with symmetric rupture strains (as `with_yield`).
    #[pyo3(signature = (*, stretch = f64::INFINITY, bend = f64::INFINITY, twist = f64::INFINITY))]
    fn with_rupture(&self, stretch: f64, bend: f64, twist: f64) -> PyResult<Self> {
        let m = self.inner.clone();
        Ok(PyMaterial {
            inner: guard(|| m.with_rupture(limits(stretch, bend, twist)?))?,
        })
    }
    #[getter]
    fn name(&self) -> &str {
        &self.inner.name
    }
    /// Young's modulus (pressure unit).
    #[getter]
    fn young(&self) -> f64 {
        self.inner.young
    }
    #[getter]
    fn poisson(&self) -> f64 {
        self.inner.poisson
    }
    /// Density (mass per length³).
    #[getter]
    fn density(&self) -> f64 {
        self.inner.density
    }
    /// G = E / 2(1 + ν) (pressure unit).
    #[getter]
    fn shear_modulus(&self) -> f64 {
        self.inner.shear_modulus()
    }
    /// All fields as a dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        convert::from_json(py, &serde_json::to_value(&self.inner).unwrap_or_default())
    }
    fn __repr__(&self) -> String {
        let m = &self.inner;
        let mut s = format!(
            "Material({:?}, young={:e}, poisson={}, density={}",
            m.name, m.young, m.poisson, m.density
        );
        if m.yield_limits.is_some() {
            s.push_str(", with yield");
        }
        if m.rupture_limits.is_some() {
            s.push_str(", with rupture");
        }
        s + ")"
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PySection>()?;
    m.add_class::<PyMaterial>()?;
    Ok(())
}
