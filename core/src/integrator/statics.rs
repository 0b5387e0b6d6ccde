//! Quasi-static equilibrium (II.83): K ΔX = F + P iterated to equilibrium.
//! K is indefinite under compression and large rotations defeat plain
//! Newton, so the solve is a pseudo-transient continuation: each iterate
//! solves (K + M/h²) ΔX = F + P (an implicit Euler step from rest), accepted
//! when the potential energy U − Fᵀq does not rise (or while constraints are
//! still being reached), h ×4 after an accepted step and ÷4 after a rejected
//! one; once M/h² is negligible the iteration is Newton's method, and
//! convergence is declared on the Newton increment.
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
        // Statically defined? (rigid-body modes not held by constraints nor by stiffness)
        self.assemble(Coefficients { mass: 0.0, drag: 0.0, momentum: 0.0 })?;
        self.check_statically_defined()?;
        let h0 = self.pseudo_time_scale();
        let mut h = h0;
        let mut report = RelaxReport::default();
        let mut potential = self.potential();
        for _ in 0..self.params.relax_max_iterations {
            let newton = h > 1e6 * h0;
            let m = if newton { 0.0 } else { 1.0 / (h * h) };
            self.assemble(Coefficients { mass: m, drag: 0.0, momentum: 0.0 })?;
            let violation = self.violation();
            let saved: Vec<Vec<f64>> = self.rods.iter().map(|(_, r)| r.q.clone()).collect();
            let saved_kinds: Vec<_> = self.constraints.iter().map(|(_, c)| c.kind.clone()).collect();
            let solved = self.solve_system();
            report.iterations += 1;
            if let Err(e) = solved {
                if newton {
                    h = h0 * 1e5; // fall back to continuation
                    report.rejected += 1;
                    continue;
                }
                return Err(e);
            }
            let (dx, dth) = self.apply_solution(1.0, None);
            if !self.ws.left.is_empty() {
                // A slider left its rod: the configuration changed, start anew.
                report.events.extend(self.drop_departed_sliders());
                potential = self.potential();
                continue;
            }
            let trial = self.potential();
            if std::env::var_os("STRANDKIT_DEBUG").is_some() {
                eprintln!("relax it {} h {h:.3e} newton {newton} dx {dx:.3e} dth {dth:.3e} viol {violation:.3e} pot {potential:.9e} -> {trial:.9e}", report.iterations);
            }
            // Energy comparisons are meaningless at round-off level: a step
            // below the tolerance is accepted as is.
            // Otherwise a step must halve the constraint violation, or lower
            // the potential without increasing the violation.
            let tiny = dx <= tol * length && dth <= tol;
            let vtrial = self.constraint_violation()?;
            let floor = tol * length;
            let accept = trial.is_finite()
                && (tiny
                    || (violation > floor && vtrial <= 0.5 * violation)
                    || (trial <= potential + 1e-11 * potential.abs() && vtrial <= violation.max(tol.sqrt() * length)));
            if !accept {
                for ((_, r), q) in self.rods.iter_mut().zip(saved) {
                    r.q = q;
                }
                for ((_, c), k) in self.constraints.iter_mut().zip(saved_kinds) {
                    c.kind = k;
                }
                self.ws.left.clear();
                report.rejected += 1;
                h = if newton { h0 * 1e5 } else { h / 4.0 };
                if h < 1e-8 * h0 {
                    return Err(Error::NoConvergence(format!(
                        "relax: no descent step found after {} iterations (potential {potential:.6e})",
                        report.iterations
                    )));
                }
                continue;
            }
            potential = trial;
            report.increment = dx;
            report.violation = violation;
            if newton && dx <= tol * length && dth <= tol && violation <= tol * length {
                report.potential = potential;
                report.bandwidth = self.ws.layout.bandwidth;
                report.n_unknowns = self.ws.layout.n;
                report.events.extend(self.break_constraints()?);
                return Ok(report);
            }
            h *= 4.0;
        }
        Err(Error::NoConvergence(format!(
            "relax: not converged after {} iterations (last increment {:.3e}, violation {:.3e})",
            report.iterations, report.increment, report.violation
        )))
    }

    /// h such that M/h² is comparable to K on the diagonal.
    fn pseudo_time_scale(&self) -> f64 {
        let (mut m, mut k) = (0.0f64, 0.0f64);
        for (r, (_, rod)) in self.rods.iter().enumerate() {
            for blk in &rod.cache.seg_mass {
                m = m.max(blk[1][1]);
            }
            for i in 0..rod.n_ctrl() {
                let g = self.ws.layout.cp_index[r][i];
                k = k.max(self.ws.sys.band.get(g, g));
            }
        }
        if m > 0.0 && k > 0.0 {
            (m / k).sqrt()
        } else {
            1.0
        }
    }
}
