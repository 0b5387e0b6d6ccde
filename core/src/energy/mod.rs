//! Energy densities W(d) per unit rest length (SPEC §2), in closed form with
//! exact gradient and Hessian. Each term is a function F of the invariants of
//! [`invariants`]; `compose` turns F's partial derivatives into ∇W, ∇²W.
//!
//! The frame model (how bending and twist are measured, and what per-sample
//! state it carries in time) is the [`FrameKinematics`] seam; [`FrameModel`]
//! names the implementation a rod uses (serde) and dispatches to it. The
//! Frenet + roll model of the thesis ([`frenet::Frenet`]) carries no state
//! and is written in the invariants; the reference-frame model of SPEC §2.3
//! ([`reference::Reference`]) carries a reference director per sample,
//! transported after every accepted step, and adds its energy in d directly
//! (but for the bending of an isotropic section on a straight rest shape,
//! which is frame-free and written in the invariants). It is the rods'
//! default; rods without roll are always Frenet.
pub mod frenet;
pub mod invariants;
#[cfg(test)]
mod jet;
pub mod qlinear;
pub mod reference;
pub mod stretch;

use invariants::{compose_up_to, LocalState, Mat11, Mat5, Vec11, Vec5};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Which deformation modes carry energy (the thesis' benchmark switches them).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct EnergyTerms {
    pub stretch: bool,
    pub bend: bool,
    pub twist: bool,
}

impl Default for EnergyTerms {
    fn default() -> Self {
        EnergyTerms { stretch: true, bend: true, twist: true }
    }
}

/// How curvature and twist are measured: which [`FrameKinematics`]
/// implementation a rod uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrameModel {
    /// The thesis' model: θ is measured from the Frenet normal (SPEC §2.2),
    /// with the continuity extension of [`frenet`] where κ → 0.
    #[serde(alias = "Frenet")]
    Frenet,
    /// A reference director per sample carried in time by parallel
    /// transport, θ measured from it (SPEC §2.3): twist is defined on
    /// straight stretches (Greenhill, Michell, plectonemes).
    #[default]
    Reference,
}

/// State a frame model keeps per sample and carries in time (transported
/// after each accepted step, through rupture splits and knot insertion, and
/// stored in snapshots). The Frenet model keeps none.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum FrameState {
    #[default]
    None,
    Reference(reference::RefFrame),
}

/// The derivative of a material angle ψ (the angle of director d1 about the
/// tangent, measured from a fixed reference projected ⟂ t) with respect to
/// the local derivative vector: ψ, ∂ψ/∂r', ∂ψ/∂r'', ∂ψ/∂θ at u, and
/// ∂ψ/∂r' at the sample whose state the model read (the reference model
/// carries its director from there; zero in the Frenet model), with that
/// sample's basis derivatives on the same four control points.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MaterialAngle {
    pub angle: f64,
    pub d_r1: Vector3<f64>,
    pub d_r2: Vector3<f64>,
    pub d_th: f64,
    pub d_r1_sample: Vector3<f64>,
    pub sample_b1: [f64; 4],
}

/// How a clamp holds the cross-section at an abscissa (asked of the model by
/// `World::clamp` and the Python `clamp`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HoldCrossSection {
    /// The roll coordinate θ is the cross-section's angle there: fix it.
    RollCoordinate,
    /// Fix the material angle of [`FrameKinematics::material_angle`] (a
    /// `MaterialRoll` constraint).
    MaterialAngle,
}

/// The frame-model seam: the bending/twist kinematics of a rod, with the
/// per-sample state it carries. Implemented by [`frenet::Frenet`] and
/// [`reference::Reference`].
pub trait FrameKinematics {
    /// Slots of d the bending and twist energies use.
    fn active_slots(terms: EnergyTerms) -> ActiveSlots;
    /// The part of the bending and twist energy density written in the
    /// invariants of [`invariants`], added to `fq`, `fqq`; returns it.
    fn add_bend_twist(q: &Vec5, c: &SampleConsts, state: &FrameState, terms: EnergyTerms, fq: &mut Vec5, fqq: &mut Mat5) -> f64;
    /// The part written directly in d, added to `out` (gradient and
    /// Hessian only if `derivs`) after the invariant part was composed;
    /// returns it. None by default.
    fn add_direct(_s: &LocalState, _c: &SampleConsts, _state: &FrameState, _terms: EnergyTerms, _derivs: bool, _out: &mut LocalEnergy) -> f64 {
        0.0
    }
    /// Strains (κ1, κ2, ω) at a local state with invariants q (ε is the
    /// stretch model's).
    fn strains(s: &LocalState, q: &Vec5, c: &SampleConsts, state: &FrameState) -> Strains;
    /// Rest values (κ1⁰, κ2⁰, ω⁰) of a rest local state and its rest frame
    /// state, computed with the energy's own formulas so that the rest
    /// shape is an exact equilibrium.
    fn rest_values(s0: &LocalState, state: &FrameState, delta: f64) -> (f64, f64, f64);
    /// The states of a rod's samples at its rest shape, in order along
    /// the rod (local state, rest weight); `closed` for a ring. Empty when
    /// the model keeps none.
    fn initial_states(samples: &[(LocalState, f64)], closed: bool) -> crate::error::Result<Vec<FrameState>>;
    /// Carries a sample's state to the new configuration after an accepted step.
    fn transport(state: &mut FrameState, s: &LocalState);
    /// Whether `state` can be carried to the local state `s` (a tangent
    /// defined, not turned by a half turn since the last transport).
    fn transportable(_state: &FrameState, _s: &LocalState) -> bool {
        true
    }
    /// The angle of director d1 about the tangent from `reference` (unit,
    /// not parallel to the tangent), with its exact derivative. `delta`:
    /// the curvature regularisation δ = κ_ε |r0'|³ of the sample nearest u.
    fn material_angle(s: &LocalState, at_sample: &LocalState, state: &FrameState, reference: &Vector3<f64>, delta: f64) -> crate::error::Result<MaterialAngle>;
    /// How a clamp at this local state holds the cross-section.
    fn hold_cross_section(s: &LocalState, delta: f64) -> HoldCrossSection;
    /// The material frame (d1, d2, d3) at a local state: d3 the unit
    /// tangent, d1 the director the bending stiffness EI1 bends about
    /// (κ1 = κ b·d1), d2 = d3 × d1. Errors where the model leaves it
    /// undefined.
    fn material_frame(s: &LocalState, state: &FrameState, delta: f64) -> crate::error::Result<MaterialFrame>;
}

/// The material frame at a point: orthonormal, right-handed, d3 = tangent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialFrame {
    pub d1: Vector3<f64>,
    pub d2: Vector3<f64>,
    pub d3: Vector3<f64>,
}

impl FrameModel {
    pub fn active_slots(self, terms: EnergyTerms) -> ActiveSlots {
        match self {
            FrameModel::Frenet => frenet::Frenet::active_slots(terms),
            FrameModel::Reference => reference::Reference::active_slots(terms),
        }
    }
    pub fn initial_states(self, samples: &[(LocalState, f64)], closed: bool) -> crate::error::Result<Vec<FrameState>> {
        match self {
            FrameModel::Frenet => frenet::Frenet::initial_states(samples, closed),
            FrameModel::Reference => reference::Reference::initial_states(samples, closed),
        }
    }
    pub fn transportable(self, state: &FrameState, s: &LocalState) -> bool {
        match self {
            FrameModel::Frenet => frenet::Frenet::transportable(state, s),
            FrameModel::Reference => reference::Reference::transportable(state, s),
        }
    }
    pub fn transport(self, state: &mut FrameState, s: &LocalState) {
        match self {
            FrameModel::Frenet => frenet::Frenet::transport(state, s),
            FrameModel::Reference => reference::Reference::transport(state, s),
        }
    }
    pub fn material_angle(self, s: &LocalState, at_sample: &LocalState, state: &FrameState, reference: &Vector3<f64>, delta: f64) -> crate::error::Result<MaterialAngle> {
        match self {
            FrameModel::Frenet => frenet::Frenet::material_angle(s, at_sample, state, reference, delta),
            FrameModel::Reference => reference::Reference::material_angle(s, at_sample, state, reference, delta),
        }
    }
    pub fn hold_cross_section(self, s: &LocalState, delta: f64) -> HoldCrossSection {
        match self {
            FrameModel::Frenet => frenet::Frenet::hold_cross_section(s, delta),
            FrameModel::Reference => reference::Reference::hold_cross_section(s, delta),
        }
    }
    pub fn material_frame(self, s: &LocalState, state: &FrameState, delta: f64) -> crate::error::Result<MaterialFrame> {
        match self {
            FrameModel::Frenet => frenet::Frenet::material_frame(s, state, delta),
            FrameModel::Reference => reference::Reference::material_frame(s, state, delta),
        }
    }
    /// Whether a rod of this model keeps a state per sample.
    pub fn keeps_state(self) -> bool {
        !matches!(self, FrameModel::Frenet)
    }
    /// Whether `state` is a sound state of this model (snapshot checks).
    pub fn accepts(self, state: &FrameState) -> bool {
        match (self, state) {
            (FrameModel::Reference, FrameState::Reference(r)) => r.is_valid(),
            _ => false,
        }
    }
    /// Model name as used by the Python `model=` keyword.
    pub fn name(self) -> &'static str {
        match self {
            FrameModel::Frenet => "frenet",
            FrameModel::Reference => "reference",
        }
    }
}

/// Constants of the energy at one sample: stiffnesses, rest values, plastic
/// offsets (SPEC §6, zero unless plasticity is on) and the curvature
/// regularisation δ = κ_ε |r0'|³ (same units as |r' × r''|).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SampleConsts {
    /// Axial stiffness EA (force).
    pub ea: f64,
    /// Bending stiffnesses EI1, EI2 (force × length²).
    pub ei1: f64,
    pub ei2: f64,
    /// Torsional stiffness GJ (force × length²).
    pub gj: f64,
    /// Rest parametric speed |r0'| (length per unit u).
    pub speed0: f64,
    /// Rest material curvatures κ1⁰, κ2⁰ and twist ω⁰ (1/length), plastic offsets included.
    pub kappa1: f64,
    pub kappa2: f64,
    pub omega: f64,
    /// Plastic stretch offset ε_p.
    pub eps_p: f64,
    /// Curvature regularisation δ (see [`frenet`]).
    pub delta: f64,
    /// δ of the bending term's linear part: min(δ, ½|C⁰|) on a curved rest
    /// shape, so the rest curvature is never inside the regularised region
    /// (the rest shape stays an exact, zero-energy equilibrium).
    pub delta_bend: f64,
}

/// Strains at one sample: stretch ε, material curvatures κ1, κ2, twist ω.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Strains {
    pub eps: f64,
    pub kappa1: f64,
    pub kappa2: f64,
    pub omega: f64,
}

/// Energy density with its derivatives with respect to d.
#[derive(Clone, Copy, Debug, Default)]
pub struct LocalEnergy {
    pub w: f64,
    pub grad: Vec11,
    pub hess: Mat11,
}

/// Which slots of d = (r′, r″, r‴, θ, θ′) the energy depends on, so that the
/// chain rule through the basis can skip rows and columns of ∇W, ∇²W that
/// are identically zero (the thesis' benchmark switches terms off).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ActiveSlots {
    /// Position derivatives r′ … r^(n) for n = `positions` (0 to 3).
    pub positions: usize,
    pub theta: bool,
    pub theta1: bool,
}

impl ActiveSlots {
    /// The union of what stretch (r′ only) and the frame model use.
    pub fn of(terms: EnergyTerms, model: FrameModel) -> ActiveSlots {
        let bt = model.active_slots(terms);
        ActiveSlots { positions: bt.positions.max(usize::from(terms.stretch)), ..bt }
    }
}

/// W(d) and, if `derivs`, its gradient and Hessian (otherwise left at zero).
pub fn density(
    s: &LocalState,
    c: &SampleConsts,
    state: &FrameState,
    terms: EnergyTerms,
    model: FrameModel,
    derivs: bool,
) -> LocalEnergy {
    let mut out = LocalEnergy::default();
    density_into(s, c, state, terms, model, derivs, &mut out);
    out
}

/// [`density`] into a caller-owned `out` (overwritten): the assembly
/// reuses one per segment rather than moving a 1 KB value per sample.
#[inline]
pub fn density_into(
    s: &LocalState,
    c: &SampleConsts,
    state: &FrameState,
    terms: EnergyTerms,
    model: FrameModel,
    derivs: bool,
    out: &mut LocalEnergy,
) {
    let mut fq = Vec5::zeros();
    let mut fqq = Mat5::zeros();
    out.w = invariant_derivatives(s, c, state, terms, model, &mut fq, &mut fqq);
    if derivs {
        compose_up_to(s, &fq, &fqq, &mut out.grad, &mut out.hess, ActiveSlots::of(terms, model).positions);
    }
    out.w += direct(s, c, state, terms, model, derivs, out);
}

/// The model's part written directly in d (after the composed part).
#[inline(always)]
fn direct(s: &LocalState, c: &SampleConsts, state: &FrameState, terms: EnergyTerms, model: FrameModel, derivs: bool, out: &mut LocalEnergy) -> f64 {
    match model {
        FrameModel::Frenet => frenet::Frenet::add_direct(s, c, state, terms, derivs, out),
        FrameModel::Reference => reference::Reference::add_direct(s, c, state, terms, derivs, out),
    }
}

/// The energy density W alone (energy per rest length). Everything below is
/// inlined, so the derivatives nobody reads are dropped by the compiler
/// (this runs at every sample of every step's divergence guard).
#[inline]
pub fn energy_density(s: &LocalState, c: &SampleConsts, state: &FrameState, terms: EnergyTerms, model: FrameModel) -> f64 {
    let (mut fq, mut fqq) = (Vec5::zeros(), Mat5::zeros());
    let w = invariant_derivatives(s, c, state, terms, model, &mut fq, &mut fqq);
    match model {
        FrameModel::Frenet => w,
        FrameModel::Reference => w + reference::Reference::add_direct(s, c, state, terms, false, &mut LocalEnergy::default()),
    }
}

/// W and its derivatives with respect to the invariants (a, c2, p, θ, θ′).
#[inline(always)]
fn invariant_derivatives(s: &LocalState, c: &SampleConsts, state: &FrameState, terms: EnergyTerms, model: FrameModel, fq: &mut Vec5, fqq: &mut Mat5) -> f64 {
    let q = s.invariants();
    let mut w = 0.0;
    if terms.stretch {
        w += stretch::add(&q, c, fq, fqq);
    }
    w + match model {
        FrameModel::Frenet => frenet::Frenet::add_bend_twist(&q, c, state, terms, fq, fqq),
        FrameModel::Reference => reference::Reference::add_bend_twist(&q, c, state, terms, fq, fqq),
    }
}

/// Strains of a local state under a frame model (for reports and plasticity).
pub fn strains(s: &LocalState, c: &SampleConsts, state: &FrameState, model: FrameModel) -> Strains {
    let q = s.invariants();
    let mut out = match model {
        FrameModel::Frenet => frenet::Frenet::strains(s, &q, c, state),
        FrameModel::Reference => reference::Reference::strains(s, &q, c, state),
    };
    out.eps = stretch::strain(&q, c);
    out
}

/// Rest values (κ1⁰, κ2⁰, ω⁰) of a rest local state, computed with the same
/// formulas as the energy so that the rest shape is an exact equilibrium.
pub fn rest_values(s0: &LocalState, state: &FrameState, delta: f64, model: FrameModel) -> (f64, f64, f64) {
    match model {
        FrameModel::Frenet => frenet::Frenet::rest_values(s0, state, delta),
        FrameModel::Reference => reference::Reference::rest_values(s0, state, delta),
    }
}
