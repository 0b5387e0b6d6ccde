//! Poisson contraction of the section (II.59, optional).
//!
//! The thesis updates R ← R (1 − ν ΔL/L) after each step. We use its
//! integrated first-order form R_i = R_i⁰ (1 − ν ε_i) per control point,
//! with ε_i the stretch strain averaged over the control point's support
//! with weights b_i ds0: it agrees with the incremental form to first order
//! in ε, does not drift over many steps, and gives back R⁰ exactly when the
//! rod is unloaded. Every size of the section (radii, widths, wall
//! thicknesses) scales by the same factor (isotropic transverse strain). As
//! in the thesis, the radius change is not differentiated in the
//! equilibrium (its time derivative is neglected), and mass and inertia keep
//! their rest values (the mass of a rod does not change when it is pulled).
use super::{samples, Rod};
use crate::energy;
use crate::error::{Error, Result};

impl Rod {
    /// The factors 1 − ν ε_i per control point at the current stretch, or
    /// an error if one would make a section size non-positive.
    fn poisson_factors(&self) -> Result<Vec<f64>> {
        let n = self.n_ctrl();
        let (mut num, mut den) = (vec![0.0; n], vec![0.0; n]);
        for (i, s) in self.cache.samples.iter().enumerate() {
            let ctrl = &self.cache.seg_ctrl[s.seg];
            let ls = samples::local_state(&self.q, self.dofs, ctrl, &s.basis);
            let eps = energy::strains(&ls, &s.consts, self.frame_state(i), self.opts.model).eps;
            for k in 0..4 {
                num[ctrl[k]] += s.w * s.basis[0][k] * eps;
                den[ctrl[k]] += s.w * s.basis[0][k];
            }
        }
        let nu = self.material.poisson;
        (0..n)
            .map(|i| {
                let eps = if den[i] > 0.0 { num[i] / den[i] } else { 0.0 };
                let f = 1.0 - nu * eps;
                if f > 0.0 {
                    Ok(f)
                } else {
                    Err(Error::input(format!(
                        "Poisson update: stretch strain {eps:.3e} at control point {i} would give a non-positive section size (ν = {nu})"
                    )))
                }
            })
            .collect()
    }

    /// Checks that II.59 can be applied at the current stretch (changes
    /// nothing). Ok at once unless `options().poisson_update`.
    pub fn check_poisson(&self) -> Result<()> {
        if self.opts.poisson_update {
            self.poisson_factors()?;
        }
        Ok(())
    }

    /// Applies II.59 with the current stretch; returns the largest relative
    /// change of a section size. No-op unless `options().poisson_update`;
    /// on error nothing changes.
    pub fn update_poisson(&mut self) -> Result<f64> {
        if !self.opts.poisson_update {
            return Ok(0.0);
        }
        let factors = self.poisson_factors()?;
        if self.rest_sections.is_empty() {
            self.rest_sections = self.sections.clone();
        }
        let mut change = 0.0f64;
        for (i, f) in factors.into_iter().enumerate() {
            let old = self.sections[i].sizes();
            let new = self.rest_sections[i].sizes().map(|x| x * f);
            change = old.iter().zip(&new).filter(|(o, _)| **o > 0.0).fold(change, |c, (o, n)| c.max((n / o - 1.0).abs()));
            self.sections[i] = self.rest_sections[i].with_sizes(new);
        }
        self.cache.refresh_stiffness(&self.sections, self.material.young, self.material.shear_modulus())?;
        Ok(change)
    }
}
