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
    /// Use rayon's pool when the world has enough segments (≥ 2048) to pay
    /// for waking it: the step (and relax) runs on a pool thread, the
    /// segment kernels in parallel, each batch scattered while the next
    /// one's kernels run, the guard's per-rod energies in parallel, and a
    /// band LDLᵀ whose system falls apart in two (free rods) factored and
    /// solved as two blocks, rod–rod contact detection in blocks. The values are the one-thread ones bit for bit
    /// (an exact zero may differ in sign): every sum keeps its order.
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
    /// relax() takes a Newton step the potential refuses when a
    /// mixed-integration-point merit accepts it (Magisano, Leonetti &
    /// Garcea 2017: the potential less the stretch of turning, measured
    /// along the iterate's tangents; the next stiffness takes the strain
    /// predicted from them), under a watchdog that falls back to the plain
    /// iteration. Same equilibria; the SPEC §10 cantilever at 1e5 N takes 9
    /// solves instead of 28–70 (7–1000 control points). false: the plain Newton /
    /// Levenberg–Marquardt iteration only.
    #[serde(default = "default_true")]
    pub relax_mixed: bool,
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
    /// Reach guard of dynamic steps (length unit; None: off): a solve that
    /// would move any control point farther than this is refused as
    /// `Diverged`, the world unchanged (and, with `adaptive_dt`, retried as
    /// sub-steps). Contact pairs are found within the detection margin at
    /// the start of a step, so with `max_move` ≤ margin no step carries a
    /// rod through another unseen. The trapezoidal schemes check each of
    /// their solves, so a step of several can move farther.
    #[serde(default)]
    pub max_move: Option<f64>,
    /// Off by default. Implicit Euler steps with contact detection look again where they
    /// ended: pairs that went past contact by more than 1 % of their
    /// contact distance at places the step had no row are added and the
    /// step is solved again from its start (up to 3 times; `solves` in
    /// the report counts them). For strands wrapped round each other,
    /// whose closest places move with them (knits).
    #[serde(default)]
    pub contact_recheck: bool,
    /// Time integration of dynamic steps (SPEC §3): implicit Euler (the
    /// thesis' method, the default) or the trapezoidal rule.
    #[serde(default)]
    pub scheme: Scheme,
    /// Temperature T of the thermal bath (kelvin); 0: no thermal noise.
    /// With T > 0 every dynamic step adds the random forces of Langevin
    /// dynamics (SPEC §3) at kT = k_B T, k_B in `units`; every rod then
    /// needs drag (its own, or the fluid's `viscosity`).
    #[serde(default)]
    pub temperature: f64,
    /// Viscosity η of the surrounding fluid (pressure × time: Pa·s in SI,
    /// pN·ns/nm² in molecular units; water at 20 °C is 1.0e-3 Pa·s =
    /// 1.0 pN·ns/nm²). Adds resistive-force drag to every rod (SPEC §3):
    /// γ_⊥ = 4πη/(ln(L/r) + ½) per length across the rod, γ_⊥/2 along it
    /// (unless `isotropic_drag`), 4πηr² on the roll.
    #[serde(default)]
    pub viscosity: f64,
    /// The unit system of the world's numbers, which fixes k_B: `si`
    /// (m, kg, s, N, J) or `molecular` (nm, pN, ns; energy pN·nm,
    /// kT = 4.116 pN·nm at 298.15 K).
    #[serde(default)]
    pub units: Units,
    /// Seed of the thermal noise's random stream (an integer ≥ 0). A new
    /// seed starts its stream from the beginning (seeds A, B, A replay A's
    /// numbers from the start).
    #[serde(default)]
    pub seed: u64,
    /// Brownian (overdamped) dynamics: the mass and momentum terms are
    /// dropped, D ΔX/h = F + P + R; velocities stay zero. Every rod needs
    /// drag. With implicit Euler a mode relaxing at rate λ = k/γ keeps a
    /// variance 1/(1 + λh/2) of kT/k; the trapezoidal rule keeps it exactly
    /// but its Newton iterations may stall when h ≫ 1/λ of the stiffest mode.
    #[serde(default)]
    pub overdamped: bool,
    /// The fluid's drag without resistive-force theory's anisotropy: γ_⊥
    /// on every axis instead of γ_∥ = γ_⊥/2 along the rod. Needed for
    /// Brownian dynamics (`overdamped`) at T > 0, whose configuration-
    /// dependent drag would need the kT ∇·D⁻¹ drift. With inertia the
    /// anisotropic drag keeps the Boltzmann distribution; its tangents are
    /// frozen at each step's start (the Itô choice), so its part of the
    /// motion is first order in h even under the trapezoidal rule.
    /// Snapshots written before this field existed load with it false
    /// (anisotropic drag).
    #[serde(default)]
    pub isotropic_drag: bool,
}

/// The unit system of a world's numbers (SPEC §3: SI by default; molecular
/// units for DNA work). Only Boltzmann's constant depends on it: the
/// equations are the same in any consistent system.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Units {
    /// Metre, kilogram, second (force N, energy J).
    #[default]
    Si,
    /// Nanometre, piconewton, nanosecond (energy pN·nm, mass 1e-21 kg = 1 ag,
    /// modulus pN/nm² = 1 MPa, viscosity pN·ns/nm² = 1e-3 Pa·s).
    Molecular,
}

impl Units {
    /// Boltzmann's constant in the system's energy unit per kelvin.
    pub fn boltzmann(self) -> f64 {
        match self {
            Units::Si => crate::force::thermal::BOLTZMANN_SI,
            // 1 pN·nm = 1e-21 J.
            Units::Molecular => crate::force::thermal::BOLTZMANN_SI * 1e21,
        }
    }
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
    /// f = F + P and the forces of compliant constraints (elastic energies;
    /// those `held_at_end` at the end), the rigid constraints held at the
    /// end of the step and the end velocity projected onto them; solved by
    /// Newton iterations on (2M/h² + D/h + K/2) δ = −residual, the first
    /// of which is the linearised implicit midpoint rule. Second order;
    /// keeps the energy of vibrations (no numerical damping), lengthens
    /// periods by (ωh)²/12. Costs two to six solves per step. Without
    /// any damping of unresolved modes it suits vibration of rods held by
    /// linear constraints (fixed points, clamps); with curved constraints
    /// (relative orientations, sliders) prefer `TrBdf2`. Sliding beads are
    /// refused (as by `TrBdf2`).
    Trapezoidal,
    /// TR-BDF2 (Bank et al. 1985): a trapezoidal stage over γh
    /// (γ = 2 − √2, Newton iterations as for `Trapezoidal`), then a BDF2
    /// stage to t + h through q_n, q_γ, q_{n+1}: one linearised solve of
    /// the same banded system (an implicit Euler solve of step
    /// (1 − γ)/(2 − γ) h with a modified velocity). Second order and
    /// L-stable: resolved vibrations keep their amplitude (99.2 % over 10
    /// periods at 20 steps per period, period +0.40 %), unresolved ones
    /// (stiff stretching, constraint chatter) are damped out as by
    /// implicit Euler. A world with sliding beads is refused (a
    /// bead's abscissa is an unknown of implicit Euler steps only; knotted
    /// beads are fine).
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
            relax_mixed: true,
            linear_solver: LinearSolver::Auto,
            divergence_factor: default_divergence_factor(),
            adaptive_dt: false,
            max_halvings: default_max_halvings(),
            max_move: None,
            contact_recheck: false,
            scheme: Scheme::ImplicitEuler,
            temperature: 0.0,
            viscosity: 0.0,
            units: Units::Si,
            seed: 0,
            overdamped: false,
            isotropic_drag: false,
        }
    }
}

fn default_true() -> bool {
    true
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
    /// `rod`'s drag in this world's fluid (anisotropic unless
    /// `isotropic_drag`).
    pub fn drag_of(&self, rod: &crate::rod::Rod) -> crate::error::Result<crate::rod::drag::Drag> {
        let mut d = rod.drag(self.viscosity)?;
        if self.isotropic_drag {
            d.axial = 0.0;
        }
        Ok(d)
    }

    /// kT = k_B T in the world's energy unit.
    pub fn kt(&self) -> f64 {
        self.units.boltzmann() * self.temperature
    }

    pub fn validate(&self) -> Result<()> {
        crate::error::positive("plastic_tolerance", self.plastic_tolerance)?;
        crate::error::positive("dt", self.dt)?;
        for g in self.gravity {
            crate::error::finite("gravity", g)?;
        }
        crate::error::positive("relax_tolerance", self.relax_tolerance)?;
        crate::error::non_negative("temperature (K)", self.temperature)?;
        crate::error::non_negative("viscosity", self.viscosity)?;
        if !(self.divergence_factor > 1.0) {
            return Err(Error::invalid("divergence_factor", self.divergence_factor, "> 1 (inf: no guard)"));
        }
        if let Some(m) = self.max_move {
            crate::error::positive("max_move", m)?;
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
