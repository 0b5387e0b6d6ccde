//! Yarns: a circular section of the yarn's radius (the contact radius) and
//! a material. Presets from the fibre values of SPEC §9.3; by default the
//! yarn bends like a solid rod of its fibre (a monofilament, B = Eπr⁴/4).
//! A measured bending stiffness B overrides the modulus: E = B/I, so the
//! axial stiffness follows as EA = 4B/r² (a spun yarn with a measured B is
//! modelled as a homogeneous rod of that modulus).
use strandkit_core::error::positive;
use strandkit_core::{Error, Material, Result, Section};

/// Fibre values: (name, density kg/m³, Young's modulus Pa, Poisson ratio).
/// Nylon 6,6 is "< 5 GPa" in SPEC §9.3: 3 GPa; aramid 70–135: 100 GPa.
pub const PRESETS: [(&str, f64, f64, f64); 5] = [
    ("cotton", 1540.0, 8e9, 0.3),
    ("wool", 1300.0, 2e9, 0.3),
    ("polyester", 1380.0, 15e9, 0.3),
    ("nylon", 1140.0, 3e9, 0.35),
    ("aramid", 1450.0, 100e9, 0.35),
];

#[derive(Clone, Debug, PartialEq)]
pub struct Yarn {
    /// Preset name or a user's label.
    pub name: String,
    /// Yarn radius (m): the contact radius and the section's radius.
    pub radius: f64,
    /// Fibre density (kg/m³).
    pub density: f64,
    /// Young's modulus of the fibre (Pa); ignored when `bending_stiffness` is set.
    pub young: f64,
    pub poisson: f64,
    /// Measured bending stiffness B (N·m²), overriding the solid-rod value.
    pub bending_stiffness: Option<f64>,
}

impl Yarn {
    /// A preset yarn ("cotton", "wool", "polyester", "nylon", "aramid") of this radius (m).
    pub fn preset(name: &str, radius: f64) -> Result<Yarn> {
        let key = name.to_ascii_lowercase();
        let key = match key.as_str() {
            "nylon66" | "nylon 6,6" | "polyamide" => "nylon",
            "kevlar" => "aramid",
            "pet" => "polyester",
            k => k,
        };
        let (n, rho, e, nu) = PRESETS.iter().copied().find(|p| p.0 == key).ok_or_else(|| {
            Error::invalid("yarn", name, format!("one of {}", PRESETS.map(|p| p.0).join(", ")))
        })?;
        let y = Yarn { name: n.to_string(), radius, density: rho, young: e, poisson: nu, bending_stiffness: None };
        y.validate()?;
        Ok(y)
    }

    pub fn validate(&self) -> Result<()> {
        positive("yarn radius", self.radius)?;
        if self.radius > 0.05 {
            return Err(Error::invalid("yarn radius", self.radius, "at most 0.05 m (a rope, not a yarn, past that)"));
        }
        positive("yarn density", self.density)?;
        positive("yarn young", self.young)?;
        if let Some(b) = self.bending_stiffness {
            positive("yarn bending_stiffness", b)?;
        }
        self.material().map(|_| ())
    }

    /// Second moment of area of the section (m⁴).
    fn inertia(&self) -> f64 {
        std::f64::consts::PI * self.radius.powi(4) / 4.0
    }

    /// Bending stiffness B (N·m²).
    pub fn bending(&self) -> f64 {
        self.bending_stiffness.unwrap_or(self.young * self.inertia())
    }

    pub fn section(&self) -> Result<Section> {
        Section::circle(self.radius)
    }

    /// The rod material: the fibre's, or the modulus B/I of a measured B.
    pub fn material(&self) -> Result<Material> {
        Material::new(&self.name, self.bending() / self.inertia(), self.poisson, self.density)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_and_override() {
        let y = Yarn::preset("Nylon", 1e-4).unwrap();
        let b = 3e9 * std::f64::consts::PI * 1e-16 / 4.0;
        assert!((y.bending() - b).abs() < 1e-12 * b);
        let mut m = y.clone();
        m.bending_stiffness = Some(1e-9);
        assert!((m.material().unwrap().young * std::f64::consts::PI * 1e-16 / 4.0 - 1e-9).abs() < 1e-21);
        assert!(Yarn::preset("silk", 1e-4).unwrap_err().to_string().contains("cotton"));
        assert!(Yarn::preset("wool", -1.0).unwrap_err().to_string().contains("radius"));
        assert!(Yarn::preset("wool", f64::NAN).is_err());
    }
}
