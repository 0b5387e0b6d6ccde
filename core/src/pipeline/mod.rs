//! The stepping of a world (SPEC §3), one pipeline for every regime:
//!
//!   gather forces (force fields, beads) → detect contacts → assemble the
//!   KKT system → factorise/solve (fallback chain) → apply → post-solve
//!   stages (one ordered list, [`post_solve::STAGES`]) → events
//!
//! used by the linearised implicit Euler step ([`dynamic`]), the quasi-static
//! equilibrium ([`statics`]) and the quasi-dynamic frames
//! ([`quasi_dynamic`]). The world holds the data; this module holds the
//! behaviour, and the world never calls into it (`World::step` and
//! `World::relax` are one-line conveniences defined here).
mod assemble;
pub(crate) mod beads;
mod clips;
mod definedness;
pub mod dynamic;
pub mod post_solve;
pub mod quasi_dynamic;
mod recheck;
mod rupture;
mod solve;
pub(crate) mod trapezoidal;
pub mod statics;
pub(crate) mod thermal;

use crate::error::Result;
use crate::system::Factorisation;
use crate::world::{Event, World};
use serde::{Deserialize, Serialize};


/// What a step did.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StepReport {
    /// Time after the step.
    pub time: f64,
    pub n_unknowns: usize,
    pub n_multipliers: usize,
    /// Half-bandwidth of the KKT band.
    pub bandwidth: usize,
    /// Relative residual of the last linear solve.
    pub residual: f64,
    /// The factorisation that solved the last system, and how many of the
    /// chain failed before it (see [`Factorisation`]).
    pub factorisation: Factorisation,
    pub fallbacks: u8,
    /// Entries stored by the factorisation (fill included): n (2 kl + ku + 1)
    /// for the band LU, the factor's nonzeros for the sparse path.
    pub factor_entries: usize,
    /// Elastic energy before the step.
    pub elastic_energy: f64,
    /// Samples whose plastic offset moved after this step (SPEC §6).
    pub plastic_samples: usize,
    /// Contact pairs active at the end of the step.
    pub active_contacts: usize,
    /// Sub-steps taken (1, or 2^k after adaptive halving; see
    /// `IntegrationParameters::adaptive_dt`).
    #[serde(default)]
    pub substeps: u32,
    /// Linear solves of the step (sub-steps included): one per implicit
    /// Euler step, one per Newton iteration of a trapezoidal one.
    #[serde(default)]
    pub solves: u32,
    /// What happened in this step (broken constraints, departed sliders,
    /// clips, ruptures), in the order it happened.
    pub events: Vec<Event>,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RelaxReport {
    /// Linear solves performed (accepted and rejected): one factorisation
    /// each.
    pub iterations: usize,
    pub rejected: usize,
    /// Newton steps that took a second-order correction (one more assembly
    /// and a solve with the factors of the step, no new factorisation).
    #[serde(default)]
    pub corrections: usize,
    /// Final Newton increment (max norm, length unit) and constraint violation.
    pub increment: f64,
    pub violation: f64,
    /// Total potential energy U − Fᵀq at the end.
    pub potential: f64,
    pub bandwidth: usize,
    pub n_unknowns: usize,
    /// The factorisation of the last solve.
    pub factorisation: Factorisation,
    /// Samples whose plastic offset moved during the solve (counted at
    /// every intermediate equilibrium) (SPEC §6).
    pub plastic_samples: usize,
    /// Largest plastic offset increment of the last round (see
    /// `IntegrationParameters::plastic_tolerance`); above the tolerance when
    /// the flow stagnated (a plastic distribution left indeterminate).
    pub plastic_increment: f64,
    /// What happened at the equilibrium found (broken constraints, clips,
    /// a rupture — which ends the solve).
    pub events: Vec<Event>,
    /// Stability of the equilibrium found, from the inertia of its static
    /// KKT matrix (an unpivoted LDLᵀ: negative pivots beyond the multiplier
    /// rows are directions in which the potential energy decreases). None
    /// when that factorisation declines (a near-zero pivot: a neutral
    /// direction, e.g. exactly at a bifurcation) or the solve ended with a
    /// topology change.
    #[serde(default)]
    pub stable: Option<bool>,
    #[serde(default)]
    pub unstable_directions: Option<usize>,
}

impl World {
    /// Advances the world by one time step `params.dt` (linearised implicit
    /// Euler, [`dynamic::step`]).
    pub fn step(&mut self) -> Result<StepReport> {
        dynamic::step(self)
    }
    /// Moves the world to static equilibrium under its loads and
    /// constraints ([`statics::relax`]).
    pub fn relax(&mut self) -> Result<RelaxReport> {
        statics::relax(self)
    }
    /// [`World::relax`], leaving an unstable equilibrium by a push of
    /// `amplitude` (length unit) along a direction of decreasing energy
    /// ([`statics::relax_perturbed`]).
    pub fn relax_perturbed(&mut self, amplitude: f64) -> Result<RelaxReport> {
        statics::relax_perturbed(self, amplitude)
    }
}

/// Whether this world uses rayon's pool: `params.parallel` and enough
/// segments in all (≥ 2048) to pay for waking it (below that the pool cost
/// more than it saved on 2 cores, BENCHMARKS §16).
pub(crate) fn uses_pool(world: &World) -> bool {
    world.params.parallel && world.rods.iter().map(|(_, r)| r.n_segments()).sum::<usize>() >= crate::system::kkt::PAR_MIN_SEGMENTS
}

/// Runs `f` on one of rayon's pool threads when the world uses the pool
/// (and not there already). Called from outside the pool, the pool's idle
/// workers spin while the calling thread does the serial part of a step:
/// three threads on two cores. Measured (BENCHMARKS §32, 400 rods, 2
/// cores): 0.89–0.93× of one thread from outside.
pub(crate) fn on_pool<T: Send>(world: &mut World, f: fn(&mut World) -> Result<T>) -> Result<T> {
    if uses_pool(world) && rayon::current_thread_index().is_none() {
        rayon::join(|| f(world), || ()).0
    } else {
        f(world)
    }
}

/// The half-bandwidth the world's system has now (builds the layout).
pub fn bandwidth(world: &mut World) -> Result<usize> {
    if world.rods.is_empty() {
        return Ok(0);
    }
    assemble::layout(world, false)?;
    Ok(world.ws.layout.bandwidth)
}

#[cfg(test)]
mod tests {
    use crate::{IntegrationParameters, Material, RodBuilder, Section, World};
    use nalgebra::Vector3;

    /// 100 rods of 25 control points (2200 segments) under gravity, rod 0
    /// tied to rod 99 by their ends when `tie_ends`.
    fn hundred_rods(parallel: bool, tie_ends: bool) -> World {
        let mut w = World::new(IntegrationParameters { dt: 2e-3, gravity: [0.0, -9.81, 0.0], parallel, ..Default::default() });
        let mut hs = Vec::new();
        for i in 0..100 {
            let z = 0.05 * i as f64;
            let rod = RodBuilder::straight(Vector3::new(0.0, 0.0, z), Vector3::new(1.0, 0.0, z))
                .control_points(25)
                .section(Section::circle(0.01).unwrap())
                .material(Material::new("rubber", 1e7, 0.45, 1000.0).unwrap())
                .build()
                .unwrap();
            hs.push(w.add_rod(rod));
        }
        if tie_ends {
            let (a, b) = (hs[0], hs[99]);
            let (_, ua) = w.rod(a).unwrap().domain();
            let (_, ub) = w.rod(b).unwrap().domain();
            let d = w.rod(a).unwrap().position(ua).unwrap() - w.rod(b).unwrap().position(ub).unwrap();
            let kind = crate::ConstraintKind::RelativePosition(crate::constraint::kinds::RelativePosition { ua, ub, axes: [true, true, true, false], offset: [d.x, d.y, d.z, 0.0] });
            w.add_link(a, b, kind, 0.0).unwrap();
        }
        w
    }

    /// 100 free rods: the step runs on the pool and its band LDLᵀ falls
    /// apart in two (`tests/parallel.rs` checks that the answer is the
    /// serial one); one thread never splits. On a pool of two the assembly
    /// splits too, 50 rods a side. With rod 0 tied to rod 99 (the ordering
    /// puts rod 99's columns next to rod 0's) no rod index cuts the
    /// columns in two: the assembly does not split, and the step is still
    /// the serial one bit for bit.
    #[test]
    fn free_rods_factor_in_two_on_the_pool() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        for parallel in [true, false] {
            let mut w = hundred_rods(parallel, false);
            assert_eq!(super::uses_pool(&w), parallel);
            let report = pool.install(|| w.step()).unwrap();
            assert_eq!(report.factorisation, crate::system::Factorisation::BandLdlt);
            let split = w.ws.sys.ldlt.split();
            let cut = w.ws.sys.assembly_cut;
            if parallel {
                let n = report.n_unknowns;
                assert!(4 * split.min(n - split) >= n, "split at {split} of {n}");
                assert_eq!(cut, Some((50, *w.ws.layout.cp_index[50].iter().min().unwrap())));
            } else {
                assert_eq!(split, 0);
                assert_eq!(cut, None);
            }
        }
        let (mut one, mut two) = (hundred_rods(false, true), hundred_rods(true, true));
        for _ in 0..3 {
            one.step().unwrap();
            pool.install(|| two.step()).unwrap();
            assert_eq!(two.ws.sys.assembly_cut, None);
        }
        for ((_, a), (_, b)) in one.rods().zip(two.rods()) {
            assert!(a.coords().iter().zip(b.coords()).all(|(x, y)| x.to_bits() == y.to_bits()));
        }
    }
}
