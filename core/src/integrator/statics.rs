//! Quasi-static equilibrium (II.83): K ΔX = F + P iterated to equilibrium.
//! K is indefinite under compression and large rotations defeat plain
//! Newton, so each iterate solves the damped system (K + λ D) ΔX = F + P
//! with D = |diag K| (Levenberg–Marquardt; the thesis' "incomplete Newton"
//! is a fixed damping), accepted when the potential energy U − Fᵀq does not
//! rise (or while constraints are still being reached); λ ÷4 after an
//! accepted step and ×4 after a rejected one. Once λ is negligible the
//! iteration is Newton's method, and convergence is declared on the Newton
//! increment. A mass-based damping (pseudo-transient continuation, M/h²)
//! was tried first: it stalls when the mass is very unevenly distributed,
//! e.g. a bead on a light string.
use super::RelaxReport;
use crate::error::{Error, Result};
use crate::system::Coefficients;
use crate::world::World;

impl World {
    /// Moves the world to static equilibrium under its loads and
    /// constraints (velocities are zeroed). Errors when a rod is not
    /// statically defined or when the iteration does not converge.
    pub fn relax(&mut self) -> Result<RelaxReport> {
        let tol = self.params.relax_tolerance;
        let length = self.rods.iter().map(|(_, r)| r.rest_length()).fold(0.0, f64::max);
        for (_, r) in self.rods.iter_mut() {
            r.v.iter_mut().for_each(|v| *v = 0.0);
        }
        self.beads_static_load();
        // Statically defined? (rigid-body modes not held by constraints nor by stiffness)
        self.assemble(Coefficients { mass: 0.0, drag: 0.0, momentum: 0.0 })?;
        self.check_statically_defined()?;
        let mut lambda: f64 = 1.0;
        let mut report = RelaxReport::default();
        let mut potential = self.potential();
        for _ in 0..self.params.relax_max_iterations {
            let newton = lambda < 1e-9;
            self.assemble_with(Coefficients { mass: 0.0, drag: 0.0, momentum: 0.0 }, true)?;
            if !newton {
                let layout = std::mem::take(&mut self.ws.layout);
                self.ws.sys.damp(&layout, lambda);
                self.ws.layout = layout;
            }
            let violation = self.violation();
            let saved: Vec<Vec<f64>> = self.rods.iter().map(|(_, r)| r.q.clone()).collect();
            let saved_beads: Vec<f64> = self.beads.iter().map(|(_, b)| b.u).collect();
            let saved_kinds: Vec<_> = self.constraints.iter().map(|(_, c)| c.kind.clone()).collect();
            let solved = self.solve_system();
            report.iterations += 1;
            if let Err(e) = solved {
                if lambda < 1e6 {
                    lambda = (lambda * 4.0).max(1e-6); // singular K: damp more
                    report.rejected += 1;
                    continue;
                }
                return Err(e);
            }
            let (dx, dth) = self.apply_solution(1.0, None);
            let n_cons = self.ws.layout.row_index.len() - self.beads.len();
            let du: Vec<f64> = (0..self.beads.len()).map(|j| self.ws.sys.sol[self.ws.layout.extra_index[n_cons + j]]).collect();
            let dbead = self.beads_apply(&du)?;
            if !self.ws.left.is_empty() {
                // A slider left its rod: the configuration changed, start anew.
                report.events.extend(self.drop_departed_sliders());
                potential = self.potential();
                continue;
            }
            let trial = self.potential() + self.beads_potential_correction()?;
            let vtrial = self.constraint_violation()?;
            if std::env::var_os("STRANDKIT_DEBUG").is_some() {
                eprintln!("relax it {} λ {lambda:.3e} newton {newton} dx {dx:.3e} dth {dth:.3e} viol {violation:.3e} vtrial {vtrial:.3e} pot {potential:.9e} -> {trial:.9e}", report.iterations);
            }
            // Energy comparisons are meaningless at round-off level: a step
            // below the tolerance is accepted as is.
            // Otherwise a step must halve the constraint violation, or lower
            // the potential without increasing the violation.
            let tiny = dx <= tol * length && dth <= tol && dbead <= tol * 1e3;
            let accept = trial.is_finite()
                && (tiny
                    || (violation > 1e-5 * tol * length && vtrial <= 0.5 * violation)
                    || (trial <= potential + 1e-11 * potential.abs() && vtrial <= violation.max(tol.sqrt() * length)));
            if !accept {
                for ((_, r), q) in self.rods.iter_mut().zip(saved) {
                    r.q = q;
                }
                for ((_, c), k) in self.constraints.iter_mut().zip(saved_kinds) {
                    c.kind = k;
                }
                for ((_, b), u) in self.beads.iter_mut().zip(saved_beads) {
                    b.u = u;
                }
                self.ws.left.clear();
                report.rejected += 1;
                lambda = (lambda * 4.0).max(1e-6);
                if lambda > 1e8 {
                    return Err(Error::not_converged(
                        report.iterations,
                        report.violation.max(report.increment),
                        format!("relax: no descent step found (potential {potential:.6e})"),
                    ));
                }
                continue;
            }
            potential = trial;
            report.increment = dx;
            report.violation = violation;
            if newton && dx <= tol * length && dth <= tol && violation <= tol * length && dbead <= tol * 1e3 {
                // Plastic flow at this equilibrium moves it: relax again
                // until the offsets stop moving (or a rupture ends the solve).
                let inelastic = self.inelastic_update(&mut report.events)?;
                report.plastic_samples += inelastic.yielded;
                if std::env::var_os("STRANDKIT_DEBUG").is_some() {
                    eprintln!("relax plastic: {} samples, max increment {:.3e}", inelastic.yielded, inelastic.max_increment);
                }
                // Stop when the flow has converged, or when it stagnates: a
                // rod at yield all along (uniform moment) has an indeterminate
                // plastic distribution, and the rounds then trade a constant
                // small increment between samples (reported, not an error).
                let stagnant = inelastic.max_increment > 0.99 * report.plastic_increment && report.plastic_increment > 0.0;
                report.plastic_increment = inelastic.max_increment;
                if inelastic.max_increment > self.params.plastic_tolerance && !inelastic.ruptured && !stagnant {
                    potential = self.potential();
                    lambda = 1e-6;
                    continue;
                }
                report.potential = potential;
                report.bandwidth = self.ws.layout.bandwidth;
                report.n_unknowns = self.ws.layout.n;
                report.events.extend(self.break_constraints()?);
                report.events.extend(self.update_clips()?);
                return Ok(report);
            }
            lambda /= 4.0;
        }
        Err(Error::not_converged(
            report.iterations,
            report.violation.max(report.increment),
            format!("relax: last increment {:.3e}, violation {:.3e}", report.increment, report.violation),
        ))
    }
}
