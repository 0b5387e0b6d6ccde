//! All integration settings in one place (Rapier-style).
use crate::error::{Error, Result};
use crate::system::LinearSolver;
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IntegrationParameters {
    /// Time step h (time unit).
    pub dt: f64,
    /// Gravity (length/time²); the body force is μ g per unit length.
    pub gravity: [f64; 3],
    /// Assemble segments in parallel (rayon) when the world has enough of
    /// them (≥ 2048 segments) to pay for waking the pool.
    pub parallel: bool,
    /// Quasi-static convergence: Newton increment ≤ tol × rod length (and
    /// tol radians on roll), constraint violation ≤ tol × rod length.
    pub relax_tolerance: f64,
    pub relax_max_iterations: usize,
    /// relax() with plastic flow: equilibrium and plastic update alternate
    /// until the largest offset increment (strain, or curvature/twist ×
    /// rest length) is below this (dimensionless). The alternation converges
    /// linearly (≈ 0.9 per round in a bent clamped wire), so this is looser
    /// than `relax_tolerance`.
    #[serde(default = "default_plastic_tolerance")]
    pub plastic_tolerance: f64,
    /// Which factorisation the solves try first (see [`LinearSolver`]); a
    /// failed one falls back along the chain, reported in the step report.
    #[serde(default)]
    pub linear_solver: LinearSolver,
    /// Divergence guard of dynamic steps. Implicit Euler never creates
    /// energy; a step that ends with more elastic + kinetic energy than it
    /// began with plus the work of the loads and constraints multiplies a
    /// running growth factor, which dissipating steps bring back toward 1
    /// (never below). A step is refused as `Diverged` (the world unchanged)
    /// when that factor exceeds this value after two or more growing steps,
    /// or its square after one (a single overshoot of a linearised step
    /// with a large dt passes: the next steps dissipate it). `inf` switches
    /// the guard off. Dimensionless, > 1.
    #[serde(default = "default_divergence_factor")]
    pub divergence_factor: f64,
    /// Adaptive stepping: a step that diverges (or would reach a non-finite
    /// state) is retried as 2, 4, … sub-steps of dt/2, dt/4, … (at most
    /// `2^max_halvings` sub-steps) before the error is raised.
    #[serde(default)]
    pub adaptive_dt: bool,
    #[serde(default = "default_max_halvings")]
    pub max_halvings: u32,
    /// Time integration of dynamic steps (SPEC §3): implicit Euler (the
    /// thesis' method, the default) or the trapezoidal rule.
    #[serde(default)]
    pub scheme: Scheme,
}

/// How a dynamic step advances in time (SPEC §3). Both solve the same
/// banded system (mass, drag, stiffness and constraint rows).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Scheme {
    /// Linearised implicit Euler (II.77–II.82):
    /// (M/h² + D/h + K) ΔX = M V/h + F + P, V' = ΔX/h. First order; damps
    /// every mode it does not resolve (robust for quasi-static-like work).
    #[default]
    ImplicitEuler,
    /// The trapezoidal rule (Newmark γ = ½, β = ¼):
    /// M (V' − V)/h = ½ (f(t, q) + f(t + h, q')) with ΔX = h (V + V')/2,
    /// f = F + P, the constraints held at the end of the step; solved by
    /// Newton iterations on (2M/h² + D/h + K/2) δ = −residual, the first
    /// of which is the linearised implicit midpoint rule. Second order;
    /// keeps the energy of vibrations (no numerical damping), lengthens
    /// periods by (ωh)²/12. Costs two to six solves per step. Without
    /// any damping of unresolved modes it suits vibration of rods held by
    /// linear constraints (fixed points, clamps); with curved constraints
    /// (relative orientations, sliders, beads) prefer `TrBdf2`.
    Trapezoidal,
    /// TR-BDF2 (Bank et al. 1985): a trapezoidal stage over γh
    /// (γ = 2 − √2, Newton iterations as for `Trapezoidal`), then a BDF2
    /// stage to t + h through q_n, q_γ, q_{n+1}: one linearised solve of
    /// the same banded system (an implicit Euler solve of step
    /// (1 − γ)/(2 − γ) h with a modified velocity). Second order and
    /// L-stable: resolved vibrations keep their amplitude (99.2 % over 10
    /// periods at 20 steps per period, period +0.40 %), unresolved ones
    /// (stiff stretching, constraint chatter) are damped out as by
    /// implicit Euler.
    TrBdf2,
}

impl Default for IntegrationParameters {
    fn default() -> Self {
        IntegrationParameters {
            dt: 1e-3,
            gravity: [0.0, 0.0, 0.0],
            parallel: true,
            relax_tolerance: 1e-10,
            relax_max_iterations: 500,
            plastic_tolerance: default_plastic_tolerance(),
            linear_solver: LinearSolver::Auto,
            divergence_factor: default_divergence_factor(),
            adaptive_dt: false,
            max_halvings: default_max_halvings(),
            scheme: Scheme::ImplicitEuler,
        }
    }
}

fn default_plastic_tolerance() -> f64 {
    1e-6
}
fn default_divergence_factor() -> f64 {
    10.0
}
fn default_max_halvings() -> u32 {
    10
}

impl IntegrationParameters {
    pub fn validate(&self) -> Result<()> {
        crate::error::positive("plastic_tolerance", self.plastic_tolerance)?;
        crate::error::positive("dt", self.dt)?;
        for g in self.gravity {
            crate::error::finite("gravity", g)?;
        }
        crate::error::positive("relax_tolerance", self.relax_tolerance)?;
        if !(self.divergence_factor > 1.0) {
            return Err(Error::invalid("divergence_factor", self.divergence_factor, "> 1 (inf: no guard)"));
        }
        if self.max_halvings > 30 {
            return Err(Error::invalid("max_halvings", self.max_halvings, "at most 30"));
        }
        if self.relax_max_iterations == 0 || self.relax_max_iterations > 1_000_000 {
            return Err(Error::invalid("relax_max_iterations", self.relax_max_iterations, "in 1..=1000000"));
        }
        Ok(())
    }
}
