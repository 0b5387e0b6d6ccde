//! Materials (SPEC §1.2, §6, §9.3; thesis annex C).
//!
//! Linear-elastic isotropic material: Young's modulus E, Poisson ratio ν
//! (shear modulus G = E / 2(1+ν)), density ρ, plus optional yield (ε_A±) and
//! rupture (ε_B±) limits per deformation mode for perfect plasticity and
//! rupture (SPEC §6, thesis II.C). The type is unit-agnostic: E in Pa, ρ in
//! kg/m³ in SI (DNA builders use pN/nm² and their own mass unit). Presets are SI.
use crate::error::{finite, positive, Error, Result};

/// Strain limits per deformation mode, each as (negative limit, positive
/// limit) with negative < 0 < positive: stretch strain (dimensionless),
/// curvature κ1/κ2 and twist rate ω (1/L, 1/m in SI). `±f64::INFINITY`
/// disables a side.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StrainLimits {
    #[serde(with = "limit_pair")]
    pub stretch: (f64, f64),
    #[serde(with = "limit_pair")]
    pub bend: (f64, f64),
    #[serde(with = "limit_pair")]
    pub twist: (f64, f64),
}

/// JSON has no infinity: a disabled side (±∞) is written as `null` and read
/// back as −∞ (first) / +∞ (second), so snapshots round-trip exactly.
mod limit_pair {
    use serde::{Deserialize, Deserializer, Serialize, Serializer};
    pub fn serialize<S: Serializer>(p: &(f64, f64), s: S) -> Result<S::Ok, S::Error> {
        let f = |x: f64| if x.is_finite() { Some(x) } else { None };
        (f(p.0), f(p.1)).serialize(s)
    }
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<(f64, f64), D::Error> {
        let (a, b) = <(Option<f64>, Option<f64>)>::deserialize(d)?;
        Ok((a.unwrap_or(f64::NEG_INFINITY), b.unwrap_or(f64::INFINITY)))
    }
}

impl StrainLimits {
    /// Limits symmetric about 0 (the thesis' case, II.C.2.a: the section's
    /// centre is a centre of symmetry): (−x, x) per mode, x > 0 or +∞.
    pub fn symmetric(stretch: f64, bend: f64, twist: f64) -> Result<Self> {
        let l = StrainLimits {
            stretch: (-stretch, stretch),
            bend: (-bend, bend),
            twist: (-twist, twist),
        };
        l.validate()?;
        Ok(l)
    }

    /// No limit in any mode.
    pub fn unlimited() -> Self {
        let inf = (f64::NEG_INFINITY, f64::INFINITY);
        StrainLimits {
            stretch: inf,
            bend: inf,
            twist: inf,
        }
    }

    /// Error unless every negative limit is in [−∞, 0) and every positive
    /// limit in (0, +∞] (NaN rejected).
    pub fn validate(&self) -> Result<()> {
        self.check("strain limits")
    }

    fn modes(&self) -> [(&'static str, (f64, f64)); 3] {
        [
            ("stretch", self.stretch),
            ("bend", self.bend),
            ("twist", self.twist),
        ]
    }

    fn check(&self, what: &str) -> Result<()> {
        for (mode, (neg, pos)) in self.modes() {
            if neg.is_nan() || neg >= 0.0 {
                return Err(Error::input(format!(
                    "{what} {mode} negative limit must be < 0 (or -inf), got {neg}"
                )));
            }
            if pos.is_nan() || pos <= 0.0 {
                return Err(Error::input(format!(
                    "{what} {mode} positive limit must be > 0 (or inf), got {pos}"
                )));
            }
        }
        Ok(())
    }
}

/// Rupture must lie at or beyond yield on both sides (equality = no plastic
/// range on that side, i.e. a brittle material, thesis I.B.3.b). An
/// infinite yield limit means "never yields" in that mode: any rupture
/// limit goes with it (brittle in that mode).
fn check_order(yield_l: &StrainLimits, rupture: &StrainLimits) -> Result<()> {
    for ((mode, (yn, yp)), (_, (rn, rp))) in yield_l.modes().into_iter().zip(rupture.modes()) {
        if (yn.is_finite() && rn > yn) || (yp.is_finite() && rp < yp) {
            return Err(Error::input(format!(
                "rupture_limits {mode} ({rn}, {rp}) must lie beyond yield_limits {mode} ({yn}, {yp})"
            )));
        }
    }
    Ok(())
}

/// An isotropic linear-elastic material.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Material {
    pub name: String,
    /// Young's modulus E (Pa in SI), finite and > 0.
    pub young: f64,
    /// Poisson ratio ν in (−1, 0.5] (dimensionless).
    pub poisson: f64,
    /// Density ρ (kg/m³ in SI), finite and > 0.
    pub density: f64,
    /// Yield strains ε_A− / ε_A+ (SPEC §6); `None` = purely elastic.
    pub yield_limits: Option<StrainLimits>,
    /// Rupture strains ε_B− / ε_B+ (SPEC §6); `None` = never breaks.
    pub rupture_limits: Option<StrainLimits>,
}

/// Annex C rows and §9.3 yarns: (name, E in Pa, ν, ρ in kg/m³).
///
/// Annex C (values as tabulated; g/cm³ → ×1000, GPa → ×1e9). The thesis
/// gives no yield or rupture strains, so the presets have none.
/// - hair: the table gives ranges E 0.1–3 GPa, ν 0.3–0.48; we take the
///   midpoints (1.55 GPa, 0.39).
/// - "acier, sans étain" is a garbled rendering of stainless steel (acier
///   inoxydable); its values (189.6 GPa = 27.5 Mpsi) are the usual 18-8
///   stainless handbook values.
///
/// §9.3 textile yarns (fibre values). Fibres are anisotropic, so one ν is an
/// assumption for the isotropic rod model:
/// - cotton: no reliable isotropic ν for the cellulose fibre; assume 0.3.
/// - wool: keratin like hair; use the hair midpoint 0.39.
/// - polyester (PET): bulk PET handbook ν ≈ 0.37–0.44; take 0.4.
/// - nylon 6,6: SPEC gives E < 5 GPa; take 3 GPa and annex C's nylon ν 0.33.
/// - aramid: E 70–135 GPa (SPEC), take 100 GPa; ν 0.36 is the longitudinal
///   value quoted for Kevlar 49 fibre (ν12).
const PRESETS: [(&str, f64, f64, f64); 11] = [
    ("nylon", 2.7e9, 0.33, 1100.0),
    ("hair", 1.55e9, 0.39, 1300.0),
    ("aluminium", 71.7e9, 0.34, 2800.0),
    ("copper", 120.7e9, 0.35, 8900.0),
    ("carbon_steel", 206.8e9, 0.28, 7800.0),
    ("stainless_steel", 189.6e9, 0.28, 7800.0),
    ("cotton", 8e9, 0.3, 1540.0),
    ("wool", 2e9, 0.39, 1300.0),
    ("polyester", 15e9, 0.4, 1380.0),
    ("nylon_6_6", 3e9, 0.33, 1140.0),
    ("aramid", 100e9, 0.36, 1450.0),
];

const PRESET_NAMES: [&str; 11] = [
    "nylon",
    "hair",
    "aluminium",
    "copper",
    "carbon_steel",
    "stainless_steel",
    "cotton",
    "wool",
    "polyester",
    "nylon_6_6",
    "aramid",
];

/// Extra spellings accepted by [`Material::preset`] (after normalisation).
const ALIASES: [(&str, &str); 6] = [
    ("aluminum", "aluminium"),
    ("steel", "carbon_steel"),
    ("stainless", "stainless_steel"),
    ("nylon66", "nylon_6_6"),
    ("kevlar", "aramid"),
    ("pet", "polyester"),
];

/// Lower-case and drop separators, so "Nylon 6,6", "nylon-6-6" and
/// "NYLON_66" all match.
fn normalise(name: &str) -> String {
    name.chars()
        .filter(|c| !matches!(c, ' ' | '_' | '-' | ',' | '.'))
        .flat_map(char::to_lowercase)
        .collect()
}

impl Material {
    /// A purely elastic material. `young` E (Pa in SI) > 0, `poisson` ν in
    /// (−1, 0.5], `density` ρ (kg/m³ in SI) > 0.
    pub fn new(name: &str, young: f64, poisson: f64, density: f64) -> Result<Self> {
        let m = Material {
            name: name.to_string(),
            young,
            poisson,
            density,
            yield_limits: None,
            rupture_limits: None,
        };
        m.validate()?;
        Ok(m)
    }

    /// Set the yield strains ε_A± (validated, and inside any rupture limits).
    pub fn with_yield(mut self, l: StrainLimits) -> Result<Self> {
        l.check("yield_limits")?;
        if let Some(r) = &self.rupture_limits {
            check_order(&l, r)?;
        }
        self.yield_limits = Some(l);
        Ok(self)
    }

    /// Set the rupture strains ε_B± (validated, and beyond any yield limits).
    pub fn with_rupture(mut self, l: StrainLimits) -> Result<Self> {
        l.check("rupture_limits")?;
        if let Some(y) = &self.yield_limits {
            check_order(y, &l)?;
        }
        self.rupture_limits = Some(l);
        Ok(self)
    }

    /// Error (InvalidInput naming the field) unless E > 0, −1 < ν ≤ 0.5,
    /// ρ > 0, all finite, and the limits are consistent.
    pub fn validate(&self) -> Result<()> {
        positive("material young", self.young)?;
        finite("material poisson", self.poisson)?;
        // ν > −1 keeps G finite and positive; ν ≤ 0.5 keeps the bulk modulus ≥ 0.
        if !(self.poisson > -1.0 && self.poisson <= 0.5) {
            return Err(Error::input(format!(
                "material poisson must be in (-1, 0.5], got {}",
                self.poisson
            )));
        }
        positive("material density", self.density)?;
        if let Some(y) = &self.yield_limits {
            y.check("yield_limits")?;
        }
        if let Some(r) = &self.rupture_limits {
            r.check("rupture_limits")?;
        }
        if let (Some(y), Some(r)) = (&self.yield_limits, &self.rupture_limits) {
            check_order(y, r)?;
        }
        Ok(())
    }

    /// Shear modulus G = E / (2(1+ν)), same unit as E.
    pub fn shear_modulus(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }

    /// A shipped material (SI units), looked up case-insensitively, ignoring
    /// spaces, '_', '-', ',' and '.'. Also accepts "aluminum", "steel",
    /// "stainless", "nylon66", "kevlar", "pet".
    pub fn preset(name: &str) -> Result<Self> {
        let key = normalise(name);
        let canonical = ALIASES
            .iter()
            .find(|(alias, _)| normalise(alias) == key)
            .map(|(_, c)| *c)
            .unwrap_or(name);
        let key = normalise(canonical);
        match PRESETS.iter().find(|(n, ..)| normalise(n) == key) {
            Some(&(n, e, nu, rho)) => Material::new(n, e, nu, rho),
            None => Err(Error::input(format!(
                "unknown material preset {name:?}; known: {}",
                PRESET_NAMES.join(", ")
            ))),
        }
    }

    /// Canonical names of the shipped materials.
    pub fn preset_names() -> &'static [&'static str] {
        &PRESET_NAMES
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn invalid<T: std::fmt::Debug>(r: Result<T>, field: &str) {
        match r {
            Err(e @ Error::InvalidInput { .. }) => { let m = e.to_string();
                assert!(m.contains(field), "message {m:?} lacks {field:?}")
            }
            other => panic!("expected InvalidInput naming {field}, got {other:?}"),
        }
    }

    #[test]
    fn presets_validate() {
        assert_eq!(PRESETS.len(), PRESET_NAMES.len());
        for (p, n) in PRESETS.iter().zip(Material::preset_names()) {
            assert_eq!(p.0, *n);
            let m = Material::preset(n).unwrap();
            m.validate().unwrap();
            assert_eq!(m.name, *n);
        }
        let s = Material::preset("Carbon Steel").unwrap();
        assert_eq!((s.young, s.density), (206.8e9, 7800.0));
        assert_eq!(Material::preset("NYLON 6,6").unwrap().name, "nylon_6_6");
        assert_eq!(Material::preset("Aluminum").unwrap().young, 71.7e9);
        assert_eq!(Material::preset("kevlar").unwrap().name, "aramid");
        match Material::preset("unobtainium") {
            Err(e @ Error::InvalidInput { .. }) => { let m = e.to_string();
                assert!(
                    m.contains("unobtainium")
                        && m.contains("stainless_steel")
                        && m.contains("aramid")
                )
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn shear_modulus_steel() {
        let s = Material::preset("carbon_steel").unwrap();
        let g = s.shear_modulus();
        assert!((g - 206.8e9 / 2.56).abs() < 1.0); // 80.78 GPa
        assert!((g / 1e9 - 80.78125).abs() < 1e-9);
    }

    #[test]
    fn invalid_materials() {
        invalid(Material::new("x", -1.0, 0.3, 1000.0), "young");
        invalid(Material::new("x", 0.0, 0.3, 1000.0), "young");
        invalid(Material::new("x", f64::NAN, 0.3, 1000.0), "young");
        invalid(Material::new("x", 1e9, 0.6, 1000.0), "poisson");
        invalid(Material::new("x", 1e9, -1.0, 1000.0), "poisson");
        invalid(Material::new("x", 1e9, f64::NAN, 1000.0), "poisson");
        invalid(Material::new("x", 1e9, 0.3, 0.0), "density");
        invalid(Material::new("x", 1e9, 0.3, -5.0), "density");
        invalid(Material::new("x", 1e9, 0.3, f64::INFINITY), "density");
        // Edge values accepted.
        Material::new("rubber", 1e6, 0.5, 1100.0).unwrap();
        Material::new("auxetic", 1e6, -0.99, 100.0).unwrap();
    }

    #[test]
    fn no_yield_in_a_mode_goes_with_any_rupture_there() {
        let y = StrainLimits::symmetric(f64::INFINITY, 0.5, f64::INFINITY).unwrap();
        let r = StrainLimits::symmetric(0.02, f64::INFINITY, f64::INFINITY).unwrap();
        let m = Material::preset("copper").unwrap().with_yield(y).unwrap().with_rupture(r).unwrap();
        assert_eq!(m.rupture_limits.unwrap().stretch, (-0.02, 0.02));
        // A finite yield still bounds the rupture.
        let y2 = StrainLimits::symmetric(0.05, 0.5, f64::INFINITY).unwrap();
        assert!(Material::preset("copper").unwrap().with_yield(y2).unwrap().with_rupture(r).is_err());
    }

    #[test]
    fn infinite_limits_round_trip_through_json() {
        let y = StrainLimits { stretch: (-0.01, f64::INFINITY), bend: (f64::NEG_INFINITY, 2.0), twist: (-3.0, 3.0) };
        let m = Material::preset("copper").unwrap().with_yield(y).unwrap().with_rupture(StrainLimits::unlimited()).unwrap();
        let back: Material = serde_json::from_str(&serde_json::to_string(&m).unwrap()).unwrap();
        assert_eq!(back, m);
    }

    #[test]
    fn limits() {
        let m = Material::preset("copper").unwrap();
        let y = StrainLimits::symmetric(0.002, 5.0, 10.0).unwrap();
        let r = StrainLimits {
            stretch: (-0.3, 0.4),
            bend: (-50.0, 50.0),
            twist: (f64::NEG_INFINITY, f64::INFINITY),
        };
        let m = m.with_yield(y).unwrap().with_rupture(r).unwrap();
        m.validate().unwrap();
        assert_eq!(m.yield_limits.unwrap().stretch, (-0.002, 0.002));
        // Bad sides.
        let mut bad = y;
        bad.bend = (0.1, 1.0);
        invalid(
            Material::preset("copper").unwrap().with_yield(bad),
            "yield_limits bend negative",
        );
        bad.bend = (-0.1, f64::NAN);
        invalid(
            Material::preset("copper").unwrap().with_rupture(bad),
            "rupture_limits bend positive",
        );
        invalid(StrainLimits::symmetric(0.0, 1.0, 1.0), "stretch");
        // Rupture inside yield, in either order of the builders.
        let small = StrainLimits::symmetric(0.001, 5.0, 10.0).unwrap();
        invalid(
            Material::preset("copper")
                .unwrap()
                .with_yield(y)
                .unwrap()
                .with_rupture(small),
            "stretch",
        );
        invalid(
            Material::preset("copper")
                .unwrap()
                .with_rupture(small)
                .unwrap()
                .with_yield(y),
            "stretch",
        );
        // Direct field edits are caught by validate().
        let mut m2 = m.clone();
        m2.rupture_limits = Some(small);
        invalid(m2.validate(), "rupture_limits stretch");
        // Equal limits (brittle) and infinities are fine.
        let u = StrainLimits::unlimited();
        u.validate().unwrap();
        Material::preset("nylon")
            .unwrap()
            .with_yield(u)
            .unwrap()
            .with_rupture(u)
            .unwrap();
        Material::preset("nylon")
            .unwrap()
            .with_yield(y)
            .unwrap()
            .with_rupture(y)
            .unwrap();
    }

    #[test]
    fn serde_round_trip() {
        let m = Material::preset("aramid")
            .unwrap()
            .with_yield(StrainLimits::symmetric(0.01, 1.0, 1.0).unwrap())
            .unwrap();
        let js = serde_json::to_string(&m).unwrap();
        assert_eq!(serde_json::from_str::<Material>(&js).unwrap(), m);
    }
}
