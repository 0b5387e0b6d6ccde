//! The constraint catalogue: what each kind is called, which rods it links,
//! what it means and what its fields are (type, unit, default), as data. The
//! Python helpers (`strandkit.position(...)`, …), their docstrings and the
//! type stubs are generated from it, so a kind added here appears in Python
//! without a hand-written wrapper.
use serde::Serialize;

/// How a field is given and checked (the Python helpers coerce by it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FieldType {
    /// A spline parameter of the first (or, named `ub`, the second) rod.
    Abscissa,
    /// A real number.
    Scalar,
    /// A boolean.
    Flag,
    /// Three reals (a point, a force).
    Vec3,
    /// Three reals, not all zero (normalised by the core).
    Direction,
    /// Two reals.
    Vec2,
    /// Four booleans selecting x, y, z, roll (Python also takes letters
    /// such as "xyz" or "xyzr").
    Axes,
    /// Four reals x, y, z, roll; Python accepts 3 (roll 0) and a keyword
    /// (named by `roll_keyword`) that sets the roll value and selects the
    /// roll axis.
    Vec4,
    /// A list of (abscissa, weight) pairs.
    WeightedAbscissae,
    /// A rod of the world (loads name the rod they act on).
    Rod,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct FieldInfo {
    pub name: &'static str,
    pub ty: FieldType,
    /// Unit, e.g. "length", "force", "rad", "u" (spline parameter), "" (none).
    pub unit: &'static str,
    pub doc: &'static str,
    /// Default as JSON text (None: required).
    pub default: Option<&'static str>,
    /// For `Vec4`: the Python keyword that sets the roll component.
    pub roll_keyword: Option<&'static str>,
}

impl FieldInfo {
    pub const fn new(name: &'static str, ty: FieldType, unit: &'static str, doc: &'static str) -> FieldInfo {
        FieldInfo { name, ty, unit, doc, default: None, roll_keyword: None }
    }
    pub const fn default(self, json: &'static str) -> FieldInfo {
        FieldInfo { default: Some(json), ..self }
    }
    pub const fn roll_keyword(self, kw: &'static str) -> FieldInfo {
        FieldInfo { roll_keyword: Some(kw), ..self }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct KindInfo {
    /// The serde tag, e.g. "Position".
    pub name: &'static str,
    /// The Python helper's name, e.g. "position".
    pub helper: &'static str,
    /// 1 (`World::add_constraint`) or 2 (`World::add_link`).
    pub rods: usize,
    /// What it imposes and what its multipliers are (with units).
    pub doc: &'static str,
    pub fields: &'static [FieldInfo],
}
