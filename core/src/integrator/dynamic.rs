//! Linearised implicit Euler (II.77–II.82; V^n is the velocity):
//!   (M/h² + D/h + K^n) ΔX = M V^n / h + F + P^n,   V^{n+1} = ΔX / h,
//! with the constraint rows of SPEC §4 in the same solve.
use super::StepReport;
use crate::error::Result;
use crate::system::Coefficients;
use crate::world::World;

impl World {
    /// Advances the world by one time step `params.dt`.
    pub fn step(&mut self) -> Result<StepReport> {
        let h = self.params.dt;
        self.beads_predict(h)?;
        let energy = self.assemble(Coefficients { mass: 1.0 / (h * h), drag: 1.0 / h, momentum: 1.0 / h })?;
        let residual = self.solve_system()?;
        self.apply_solution(1.0, Some(1.0 / h));
        self.time += h;
        self.steps += 1;
        let mut events = self.drop_departed_sliders();
        events.extend(self.beads_advance(h)?);
        events.extend(self.break_constraints()?);
        events.extend(self.update_clips()?);
        let inelastic = self.inelastic_update(&mut events)?;
        Ok(StepReport {
            time: self.time,
            n_unknowns: self.ws.layout.n,
            n_multipliers: self.ws.layout.n_rows,
            bandwidth: self.ws.layout.bandwidth,
            residual,
            sparse: self.ws.sys.used_sparse,
            ldlt: self.ws.sys.used_ldlt,
            factor_entries: self.ws.sys.factor_entries(),
            elastic_energy: energy,
            plastic_samples: inelastic.yielded,
            events,
        })
    }
}
