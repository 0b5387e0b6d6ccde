//! A rope as a rod: given by what a rope is measured by — linear density,
//! axial stiffness EA and bending stiffness EI — rather than by a solid
//! section (a fibre rope bends far more easily than a solid rod of its
//! diameter). The rod gets the circular section and material that give
//! exactly these three numbers: r = 2√(EI/EA), E = EA/(πr²), ρ = μ/(πr²).
use nalgebra::Vector3;
use strandkit_core::error::{positive, size};
use strandkit_core::spline::KnotKind;
use strandkit_core::{Error, Material, Result, Rod, RodBuilder, RodOptions, Section};

/// Largest number of control points a builder gives one rope.
pub const MAX_ROPE_CONTROL_POINTS: usize = 100_000;

/// A rope's mechanical properties (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rope {
    /// Mass per length (kg/m).
    pub linear_density: f64,
    /// Axial stiffness EA (N).
    pub axial_stiffness: f64,
    /// Bending stiffness EI (N·m²).
    pub bending_stiffness: f64,
}

impl Default for Rope {
    /// A 20 mm polyamide rope: 0.25 kg/m, EA = 2e5 N, EI = 0.05 N·m².
    fn default() -> Self {
        Rope { linear_density: 0.25, axial_stiffness: 2e5, bending_stiffness: 0.05 }
    }
}

impl Rope {
    /// A solid cable of circular section: radius (m), Young's modulus (Pa),
    /// density (kg/m³) — μ = ρπr², EA = Eπr², EI = Eπr⁴/4 (its equivalent
    /// radius is then `radius`). Checked by `validate` like any rope.
    pub fn solid(radius: f64, young_modulus: f64, density: f64) -> Rope {
        let area = std::f64::consts::PI * radius * radius;
        Rope { linear_density: density * area, axial_stiffness: young_modulus * area, bending_stiffness: young_modulus * area * radius * radius / 4.0 }
    }

    pub fn validate(&self, what: &str) -> Result<()> {
        positive(&format!("{what} linear_density"), self.linear_density)?;
        positive(&format!("{what} axial_stiffness"), self.axial_stiffness)?;
        positive(&format!("{what} bending_stiffness"), self.bending_stiffness)?;
        Ok(())
    }

    /// The equivalent circular section's radius (m).
    pub fn radius(&self) -> f64 {
        2.0 * (self.bending_stiffness / self.axial_stiffness).sqrt()
    }

    /// Checks a rope of `length` with `n` control points (at least
    /// `min_n`) and returns the circular section and material giving
    /// exactly μ, EA and EI.
    fn section_and_material(&self, what: &str, length: f64, n: usize, min_n: usize) -> Result<(Section, Material)> {
        self.validate(what)?;
        positive(&format!("{what} length"), length)?;
        size(&format!("{what} control points"), n, MAX_ROPE_CONTROL_POINTS)?;
        if n < min_n {
            return Err(Error::invalid(format!("{what} control points"), n, format!("at least {min_n}")));
        }
        let r = self.radius();
        let area = std::f64::consts::PI * r * r;
        Ok((Section::circle(r)?, Material::new(what, self.axial_stiffness / area, 0.3, self.linear_density / area)?))
    }

    /// A rope of rest length `length` (straight at rest, no roll), with `n`
    /// control points placed along `shape(σ)` — the point of material arc
    /// length σ ∈ [0, length] in the initial configuration.
    pub fn rod(&self, what: &str, length: f64, n: usize, shape: impl Fn(f64) -> Vector3<f64>) -> Result<Rod> {
        let (section, material) = self.section_and_material(what, length, n, 4)?;
        let mut rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(length, 0.0, 0.0))
            .control_points(n)
            .with_roll(false)
            .section(section)
            .material(material)
            .build()?;
        // A straight clamped spline's control points sit at its Greville
        // abscissae, linear in arc length: control point i carries the
        // material point at σ_i = its rest x.
        let rest = rod.rest_coords().to_vec();
        let q: Vec<f64> = rest.chunks(3).flat_map(|p| {
            let x = shape(p[0].clamp(0.0, length));
            [x.x, x.y, x.z]
        }).collect();
        rod.set_coords(&q)?;
        Ok(rod)
    }

    /// An open rope fitted to the curve `shape(σ)` (σ ∈ [0, length], the
    /// ends exact), straight at rest with the fitted curve's own arc length
    /// (within 1e-5 of `length` for a 60 cm loop on 16 points): it starts
    /// without stretch, where [`Rope::rod`]'s control points placed on a
    /// tight curve make the spline cut inside it (a 60 cm string on 16
    /// points hanging in a loop started compressed by up to 1.4 %, 0.03 J
    /// released in the first steps).
    pub fn open_curve(&self, what: &str, length: f64, n: usize, shape: impl Fn(f64) -> Vector3<f64> + Send + Sync + 'static) -> Result<Rod> {
        self.wound(what, length, n, KnotKind::Clamped, 4, shape)
    }

    /// A closed rope (a ring) of rest length `length` with `n` control
    /// points, built on the closed curve `shape(σ)` (σ ∈ [0, length],
    /// shape(0) = shape(length)). Straight at rest — a rope tied into a
    /// loop, not a bent ring (`RodOptions::straight_rest`).
    pub fn ring(&self, what: &str, length: f64, n: usize, shape: impl Fn(f64) -> Vector3<f64> + Send + Sync + 'static) -> Result<Rod> {
        self.wound(what, length, n, KnotKind::Periodic, 6, shape)
    }

    /// A naturally straight rope wound along `shape` (fitted with `knots`,
    /// at least `min_n` control points), its rest length the fitted curve's.
    fn wound(&self, what: &str, length: f64, n: usize, knots: KnotKind, min_n: usize, shape: impl Fn(f64) -> Vector3<f64> + Send + Sync + 'static) -> Result<Rod> {
        let (section, material) = self.section_and_material(what, length, n, min_n)?;
        RodBuilder::curve(length, shape)
            .control_points(n)
            .knots(knots)
            .with_roll(false)
            .section(section)
            .material(material)
            .options(RodOptions { straight_rest: true, ..RodOptions::default() })
            .build()
    }
}
