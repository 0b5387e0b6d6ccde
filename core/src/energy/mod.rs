//! Energy densities W(d) per unit rest length (SPEC §2), in closed form with
//! exact gradient and Hessian. Each term is a function F of the invariants of
//! [`invariants`]; `compose` turns F's partial derivatives into ∇W, ∇²W.
//!
//! The frame model (how bending and twist are measured) sits behind
//! [`FrameModel`], so the reference-frame model of SPEC §2.3 can be added as
//! another variant without touching assembly.
pub mod frenet;
pub mod invariants;
pub mod stretch;

use invariants::{compose, LocalState, Mat11, Mat5, Vec11, Vec5};
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

/// How curvature and twist are measured.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum FrameModel {
    /// The thesis' model: θ is measured from the Frenet normal (SPEC §2.2),
    /// with the continuity extension of [`frenet`] where κ → 0.
    #[default]
    Frenet,
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
    /// Stretch F(a) uses r′ only; Frenet bending F(a, c2, θ) adds r″ and θ
    /// (c2 = |r′×r″|²); Frenet twist F(a, c2, p, θ′) adds r‴ (p = (r′×r″)·r‴)
    /// and θ′ (SPEC §2, [`invariants`]).
    pub fn of(terms: EnergyTerms, model: FrameModel) -> ActiveSlots {
        match model {
            FrameModel::Frenet => ActiveSlots {
                positions: if terms.twist {
                    3
                } else if terms.bend {
                    2
                } else {
                    usize::from(terms.stretch)
                },
                theta: terms.bend,
                theta1: terms.twist,
            },
        }
    }
}

/// W(d) and, if `derivs`, its gradient and Hessian (otherwise left at zero).
pub fn density(
    s: &LocalState,
    c: &SampleConsts,
    terms: EnergyTerms,
    model: FrameModel,
    derivs: bool,
) -> LocalEnergy {
    let q = s.invariants();
    let mut fq = Vec5::zeros();
    let mut fqq = Mat5::zeros();
    let mut w = 0.0;
    if terms.stretch {
        w += stretch::add(&q, c, &mut fq, &mut fqq);
    }
    match model {
        FrameModel::Frenet => {
            if terms.bend {
                w += frenet::add_bend(&q, c, &mut fq, &mut fqq);
            }
            if terms.twist {
                w += frenet::add_twist(&q, c, &mut fq, &mut fqq);
            }
        }
    }
    let mut out = LocalEnergy { w, ..Default::default() };
    if derivs {
        compose(s, &fq, &fqq, &mut out.grad, &mut out.hess);
    }
    out
}

/// Strains of a local state under a frame model (for reports and plasticity).
pub fn strains(s: &LocalState, c: &SampleConsts, model: FrameModel) -> Strains {
    let q = s.invariants();
    match model {
        FrameModel::Frenet => frenet::strains(&q, c),
    }
}

/// Rest values (κ1⁰, κ2⁰, ω⁰) of a rest local state, computed with the same
/// formulas as the energy so that the rest shape is an exact equilibrium.
pub fn rest_values(s0: &LocalState, delta: f64, model: FrameModel) -> (f64, f64, f64) {
    let q = s0.invariants();
    match model {
        FrameModel::Frenet => frenet::rest_values(&q, delta),
    }
}
