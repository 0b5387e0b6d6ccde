//! The registry of constraint kinds: one line per kind in
//! `constraint_kinds!`, which declares the module, generates the
//! [`ConstraintKind`] enum (serde form `{"Position": {…fields…}}`), a
//! `From` conversion per kind, the catalogue, and the exhaustive dispatch of
//! every [`ConstraintLaw`] method (no wildcard arms).
use super::{Anchoring, ConstraintLaw, KindInfo, Reaction, Row, Side, SlidingBlocks, Touched};
use crate::error::Result;
use crate::rod::Rod;
use serde::{Deserialize, Serialize};

macro_rules! constraint_kinds {
    ($($module:ident :: $ty:ident),* $(,)?) => {
        $(pub mod $module;)*
        $(pub use $module::$ty;)*

        /// What a constraint imposes on its rod(s); one variant per kind of
        /// [`crate::constraint::kinds`], each documented on its struct.
        #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
        pub enum ConstraintKind {
            $($ty($ty),)*
        }

        $(impl From<$ty> for ConstraintKind {
            fn from(k: $ty) -> Self {
                ConstraintKind::$ty(k)
            }
        })*

        impl ConstraintKind {
            /// Every registered kind, in registration order.
            pub const CATALOGUE: &'static [KindInfo] = &[$(<$ty as ConstraintLaw>::INFO,)*];

            pub fn info(&self) -> &'static KindInfo {
                match self { $(ConstraintKind::$ty(_) => &<$ty as ConstraintLaw>::INFO,)* }
            }
            pub fn n_rows(&self) -> usize {
                match self { $(ConstraintKind::$ty(k) => k.n_rows(),)* }
            }
            pub fn n_extra(&self) -> usize {
                match self { $(ConstraintKind::$ty(k) => k.n_extra(),)* }
            }
            pub fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
                match self { $(ConstraintKind::$ty(k) => k.visit_abscissae(f),)* }
            }
            pub fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
                match self { $(ConstraintKind::$ty(k) => k.visit_abscissae_mut(f),)* }
            }
            /// Checks the constraint against its rods (abscissae inside the
            /// domain, finite targets, roll only on rods with roll, …).
            pub fn validate(&self, rods: &[&Rod]) -> Result<()> {
                match self { $(ConstraintKind::$ty(k) => super::validate_law(k, rods),)* }
            }
            /// Control points the rows touch (for ordering, IV.3–IV.4).
            pub fn touched(&self, rods: &[&Rod]) -> Result<Touched> {
                match self { $(ConstraintKind::$ty(k) => super::touched_by(k, rods),)* }
            }
            /// Writes `n_rows()` rows linearised at the rods' current coordinates.
            pub fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
                rows.iter_mut().for_each(|r| r.len = 0);
                match self { $(ConstraintKind::$ty(k) => k.linearize(rods, rows),)* }
            }
            /// Force and torque on the first side from the multipliers.
            pub fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
                match self { $(ConstraintKind::$ty(k) => k.reaction(rods, lambda),)* }
            }
            /// Tension along the line of action (None: the kind has none).
            pub fn tension(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Option<f64>> {
                match self { $(ConstraintKind::$ty(k) => k.tension(rods, lambda),)* }
            }
            pub fn anchoring(&self) -> Anchoring {
                match self { $(ConstraintKind::$ty(k) => k.anchoring(),)* }
            }
            pub fn sliding_blocks(&self, rods: &[&Rod], lambda: &[f64], friction_coeff: f64, out: &mut SlidingBlocks) -> Result<()> {
                out.diag = [0.0; 2];
                out.rhs = [0.0; 2];
                out.coupling.len = 0;
                match self { $(ConstraintKind::$ty(k) => k.sliding_blocks(rods, lambda, friction_coeff, out),)* }
            }
            pub fn project(&mut self, rods: &[&Rod]) -> Result<()> {
                match self { $(ConstraintKind::$ty(k) => k.project(rods),)* }
            }
            pub fn advance(&mut self, rods: &[&Rod], du: &[f64]) -> bool {
                match self { $(ConstraintKind::$ty(k) => k.advance(rods, du),)* }
            }
            /// Same kind imposing the same thing at the same place.
            pub fn duplicates(&self, other: &ConstraintKind) -> bool {
                match (self, other) {
                    $((ConstraintKind::$ty(a), ConstraintKind::$ty(b)) => a.duplicates(b),)*
                    _ => false,
                }
            }
        }
    };
}

constraint_kinds! {
    position::Position,
    tangent::Tangent,
    material_roll::MaterialRoll,
    distance::Distance,
    plane::Plane,
    axis::Axis,
    curvature::Curvature,
    relative_position::RelativePosition,
    relative_orientation::RelativeOrientation,
    relative_distance::RelativeDistance,
    relative_axis::RelativeAxis,
    relative_plane::RelativePlane,
    sliding_point::SlidingPoint,
    oriented_sliding_point::OrientedSlidingPoint,
    contact::Contact,
    coplanar_clamp::CoplanarClamp,
    barycentric::Barycentric,
    base_pair_step::BasePairStep,
    pair_stagger::PairStagger,
    equal_offsets::EqualOffsets,
}

impl ConstraintKind {
    /// The kind's name (its serde tag), e.g. "Position".
    pub fn name(&self) -> &'static str {
        self.info().name
    }
    /// Rods the kind links: 1, or 2 for relative constraints (which may
    /// name the same rod twice).
    pub fn n_rods(&self) -> usize {
        self.info().rods
    }
    /// The first abscissa (where the reaction is reported).
    pub fn u(&self) -> f64 {
        let mut first = None;
        self.visit_abscissae(&mut |_, u| {
            first.get_or_insert(u);
        });
        first.unwrap_or(f64::NAN)
    }
    /// The catalogue entry of a kind by name.
    pub fn info_of(name: &str) -> Option<&'static KindInfo> {
        Self::CATALOGUE.iter().find(|k| k.name == name)
    }
}
