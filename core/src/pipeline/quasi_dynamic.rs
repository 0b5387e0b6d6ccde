//! Quasi-dynamic simulation (thesis IV.B.2, algorithm 11): one frame per
//! call, dynamic (implicit Euler) while the computation keeps up with the
//! time budget, quasi-static (one incomplete Newton iteration per frame)
//! when it does not.
//!
//! - Switching uses the compute time Δt_c of the previous frame, measured
//!   with an injectable [`Clock`]: to quasi-static above `to_static` (95 %)
//!   of the budget, back to dynamic below `to_dynamic` (90 %); in between the
//!   mode is kept (hysteresis).
//! - Never quasi-static when a rod is not held at ≥ 2 points or one point
//!   plus an orientation (the thesis' rule), when the rigid modes are not
//!   all held (the check of `relax`), or when the static system is singular.
//! - Time step: Δt = (l_free / l_initial) Δt0 (IV.15), l_free the longest
//!   stretch of rod between constrained abscissae (or ends), l_initial the
//!   longest rod's rest length at creation.
//! - Velocity hand-over: a quasi-static frame sets V = Δq / Δt (the thesis'
//!   Δq/Δt_c; a frame lasts Δt of simulated time), so dynamics resume with
//!   the motion the static frames had.
//! - Incomplete Newton: a static frame moves by `newton_fraction` (1/3) of
//!   the Newton increment. On the transition from dynamic, the first static
//!   frame moves no further than the last dynamic frame did (or 1e-4 of the
//!   length, from rest) and the allowed motion doubles per frame until the
//!   Newton step fits, so switching never makes the trajectory jump.
use super::assemble::{assemble, Regime};
use super::{definedness, post_solve, solve, StepReport};
use crate::error::{Error, Result};
use crate::world::{Event, World};
use serde::{Deserialize, Serialize};

/// A monotonic clock in seconds. [`WallClock`] in production; tests inject
/// a scripted one to make switching deterministic.
pub trait Clock {
    fn now(&mut self) -> f64;
}

/// The process' monotonic wall clock.
#[derive(Debug)]
pub struct WallClock(std::time::Instant);

impl Default for WallClock {
    fn default() -> Self {
        WallClock(std::time::Instant::now())
    }
}

impl Clock for WallClock {
    fn now(&mut self) -> f64 {
        self.0.elapsed().as_secs_f64()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct QuasiDynamicParameters {
    /// Time step of the free configuration Δt0 (time unit).
    pub dt0: f64,
    /// Wall-clock seconds a frame may take. None: real time, the budget is
    /// the frame's Δt (the thesis' setting, with time unit = second).
    pub time_budget: Option<f64>,
    /// Fractions of the budget that switch to quasi-static (0.95) and back
    /// to dynamic (0.90); to_dynamic ≤ to_static.
    pub to_static: f64,
    pub to_dynamic: f64,
    /// Fraction of the Newton increment taken per static frame (1/3).
    pub newton_fraction: f64,
    /// Scale Δt with the free length (IV.15).
    pub scale_with_free_length: bool,
}

impl Default for QuasiDynamicParameters {
    fn default() -> Self {
        QuasiDynamicParameters {
            dt0: 1e-3,
            time_budget: None,
            to_static: 0.95,
            to_dynamic: 0.90,
            newton_fraction: 1.0 / 3.0,
            scale_with_free_length: true,
        }
    }
}

impl QuasiDynamicParameters {
    pub fn validate(&self) -> Result<()> {
        crate::error::positive("dt0", self.dt0)?;
        if let Some(b) = self.time_budget {
            crate::error::positive("time_budget", b)?;
        }
        crate::error::positive("to_static", self.to_static)?;
        crate::error::positive("to_dynamic", self.to_dynamic)?;
        if self.to_dynamic > self.to_static {
            return Err(Error::input(format!(
                "to_dynamic ({}) must not exceed to_static ({}) (hysteresis)",
                self.to_dynamic, self.to_static
            )));
        }
        if !(self.newton_fraction > 0.0 && self.newton_fraction <= 1.0) {
            return Err(Error::input(format!("newton_fraction must be in (0, 1], got {}", self.newton_fraction)));
        }
        Ok(())
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    Dynamic,
    QuasiStatic,
}

/// What one frame did.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrameReport {
    pub mode: Mode,
    /// The mode changed at this frame.
    pub switched: bool,
    /// Quasi-static was wanted but refused: the world is not statically
    /// defined, or its static system was singular.
    pub static_refused: bool,
    /// Why it was refused (the message of the definedness check or solve).
    pub refusal: Option<String>,
    /// Simulated time step of the frame (time unit) and the free length
    /// it was scaled with (length unit).
    pub dt: f64,
    pub free_length: f64,
    /// Compute time of this frame (seconds, from the clock) and what is left
    /// of the budget (negative: late). A real-time caller sleeps `slack`.
    pub compute_time: f64,
    pub slack: f64,
    /// Largest control-point displacement of the frame (length unit).
    pub motion: f64,
    pub events: Vec<Event>,
}

/// The quasi-dynamic driver of a world (algorithm 11).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct QuasiDynamic {
    pub params: QuasiDynamicParameters,
    mode: Mode,
    /// Δt_c of the last frame (seconds); starts at 0.9 Δt0 as in the thesis.
    compute_time: f64,
    initial_length: f64,
    last_motion: f64,
    /// Largest motion allowed to the next static frame (transition ramp).
    ramp: Option<f64>,
}

impl QuasiDynamic {
    /// Starts in dynamic mode; l_initial is the longest rod's rest length now.
    pub fn new(world: &World, params: QuasiDynamicParameters) -> Result<Self> {
        params.validate()?;
        let initial_length = world.rods().map(|(_, r)| r.rest_length()).fold(0.0, f64::max);
        if !(initial_length > 0.0) {
            return Err(Error::input("quasi-dynamic simulation needs at least one rod"));
        }
        Ok(QuasiDynamic {
            params,
            mode: Mode::Dynamic,
            compute_time: 0.9 * params.dt0,
            initial_length,
            last_motion: 0.0,
            ramp: None,
        })
    }

    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Advances the world by one frame.
    pub fn step(&mut self, world: &mut World, clock: &mut dyn Clock) -> Result<FrameReport> {
        self.params.validate()?;
        let t0 = clock.now();
        let free_length = free_length(world)?;
        let dt = if self.params.scale_with_free_length {
            // Bounded below so that a densely constrained rod still advances.
            self.params.dt0 * (free_length / self.initial_length).clamp(1e-3, 1.0)
        } else {
            self.params.dt0
        };
        let budget = self.params.time_budget.unwrap_or(dt);
        let wanted = if self.compute_time > self.params.to_static * budget {
            Mode::QuasiStatic
        } else if self.compute_time < self.params.to_dynamic * budget {
            Mode::Dynamic
        } else {
            self.mode
        };
        let previous = self.mode;
        let mut refusal = None;
        let mut outcome = None;
        if wanted == Mode::QuasiStatic {
            if previous == Mode::Dynamic {
                // From rest there is no motion to match: start the ramp at
                // 1e-4 of the length, so it still leaves rest smoothly.
                self.ramp = Some(self.last_motion.max(1e-4 * self.initial_length));
            }
            match static_frame(world, dt, self.params.newton_fraction, self.ramp) {
                Ok((motion, capped, events)) => {
                    self.ramp = if capped { self.ramp.map(|r| 2.0 * r) } else { None };
                    outcome = Some((Mode::QuasiStatic, motion, events));
                }
                // Not statically defined / singular: stay dynamic (algorithm 11).
                Err(e @ Error::Singular { .. }) => refusal = Some(e.to_string()),
                Err(e) => return Err(e),
            }
        }
        let (mode, motion, events) = match outcome {
            Some(o) => o,
            None => {
                let before = all_coordinates(world);
                world.params.dt = dt;
                let r: StepReport = world.step()?;
                (Mode::Dynamic, position_change(world, &before), r.events)
            }
        };
        self.mode = mode;
        self.last_motion = motion;
        self.compute_time = clock.now() - t0;
        Ok(FrameReport {
            mode,
            switched: mode != previous,
            static_refused: refusal.is_some(),
            refusal,
            dt,
            free_length,
            compute_time: self.compute_time,
            slack: budget - self.compute_time,
            motion,
            events,
        })
    }
}

/// One quasi-static frame: a fraction of the Newton increment, capped at
/// `cap` (length unit) if given; velocities V = Δq / dt. Returns the
/// motion, whether the cap bound it, and the events. Error (Singular)
/// when the world is not statically defined.
fn static_frame(world: &mut World, dt: f64, fraction: f64, cap: Option<f64>) -> Result<(f64, bool, Vec<Event>)> {
    super::beads::static_load(world);
    assemble(world, Regime::Statics { bead_unknowns: false })?;
    definedness::check_anchored(world)?;
    definedness::check_statically_defined(world, false)?;
    if world.detectors.is_empty() && world.contacts.is_empty() {
        solve::solve(world)?;
    } else {
        // Contacts: the active set settled around the solve.
        solve::assemble_and_solve(world, Regime::Statics { bead_unknowns: false })?;
    }
    let full = world.ws.layout.cp_index.iter().zip(world.rods.iter()).fold(0.0f64, |m, (cps, (_, rod))| {
        cps.iter().fold(m, |m, &g| (0..3.min(rod.dofs())).fold(m, |m, a| m.max(world.ws.sys.sol[g + a].abs())))
    });
    let mut scale = fraction;
    let mut capped = false;
    // With contact detection a frame moves no point farther than the
    // detectors' margin (see `statics::contact_reach`).
    let cap = match (cap, super::statics::contact_reach(world)) {
        (Some(c), Some(m)) => Some(c.min(m)),
        (c, m) => c.or(m),
    };
    if let Some(c) = cap {
        if full * scale > c {
            scale = if full > 0.0 { c / full } else { 0.0 };
            capped = true;
        }
    }
    let (motion, _) = solve::commit(world, scale, Some(1.0 / dt), None)?;
    world.beads.iter_mut().for_each(|(_, b)| {
        b.velocity = 0.0;
        b.carried = None;
    });
    world.time += dt;
    world.steps += 1;
    let mut events = Vec::new();
    post_solve::run(world, None, &mut events)?;
    Ok((motion, capped, events))
}

/// Coordinates of every rod (flat, in rod order).
fn all_coordinates(world: &World) -> Vec<f64> {
    world.rods.iter().flat_map(|(_, r)| r.coords().to_vec()).collect()
}

/// Largest position change since `before` (same rods, same order).
fn position_change(world: &World, before: &[f64]) -> f64 {
    let now = all_coordinates(world);
    if now.len() != before.len() {
        return f64::NAN; // a rupture changed the rods: no comparison
    }
    let mut m = 0.0f64;
    let mut k = 0;
    for (_, r) in world.rods.iter() {
        let n = r.coords().len();
        for i in 0..n {
            if i % r.dofs() < 3 {
                m = m.max((now[k + i] - before[k + i]).abs());
            }
        }
        k += n;
    }
    m
}

/// Longest stretch of rest arc length between the constrained abscissae
/// of a rod (or its ends), over all rods (IV.15).
pub fn free_length(world: &World) -> Result<f64> {
    let mut longest = 0.0f64;
    for (h, rod) in world.rods() {
        let mut cuts: Vec<f64> = Vec::new();
        for (_, c) in world.constraints() {
            let sides = [c.rod, c.other.unwrap_or(c.rod)];
            c.kind.visit_abscissae(&mut |side, u| {
                let s = if c.other.is_none() { 0 } else { side.min(1) as usize };
                if sides[s] == h {
                    cuts.push(u);
                }
            });
        }
        longest = longest.max(rod.longest_free_arc(&mut cuts)?);
    }
    Ok(longest)
}
