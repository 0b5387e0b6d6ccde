//! A rod's viscous drag (III.10, SPEC §3): its own coefficients plus the
//! resistive-force drag of the world's fluid. Per unit rest length the
//! force is −(c_t I + c_a t tᵀ) v: c_t = own + γ_⊥ on every axis and c_a =
//! γ_∥ − γ_⊥ = −γ_⊥/2 along the tangent t (resistive-force theory: a rod
//! slides along itself twice as easily), so D = Σ_g G_g ⊗ (c_t I + c_a t_g
//! t_gᵀ) over the Gauss samples g, G_g their 4×4 blocks of `seg_bb`. On the
//! roll, c_θ ∫ b_k b_l ds0 + 4πη ∫ r² b_k b_l ds0. The tangents are frozen
//! at the start of each dynamic step (`freeze_drag_frame`): D is constant
//! over a step, as the Itô noise needs (which makes the anisotropic part
//! first order in h even under the trapezoidal rule). r is the section's hydrodynamic
//! radius (a tube's outer radius, else that of the circle of equal area).
use super::Rod;
use crate::error::{Error, Result};
use std::f64::consts::PI;

/// Drag coefficients of one rod in a fluid.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Drag {
    /// On each position axis: force per velocity per length.
    pub trans: f64,
    /// Added along the tangent (γ_∥ − γ_⊥ ≤ 0; 0 for isotropic drag).
    pub axial: f64,
    /// On the roll, times ∫ b b ds0: torque per angular velocity per length.
    pub roll: f64,
    /// On the roll, times ∫ r² b b ds0 (4πη).
    pub roll_r2: f64,
}

/// Resistive-force theory for a slender rod of length `length` and radius
/// `radius` in a fluid of viscosity `eta` (SPEC §3): (γ_⊥, γ_∥, γ_θ) =
/// (4πη/(ln(L/r) + ½), γ_⊥/2, 4πηr²) per unit length, SPEC §3's
/// approximations (slender-body theory's γ_∥ is 2πη/(ln(L/r) − ½), 16 %
/// above γ_⊥/2 at L/r = 1000): force per velocity per length, and torque
/// per angular velocity per length.
pub fn resistive_force(eta: f64, radius: f64, length: f64) -> Result<[f64; 3]> {
    crate::error::non_negative("viscosity", eta)?;
    crate::error::positive("radius", radius)?;
    crate::error::positive("length", length)?;
    let log = (length / radius).ln() + 0.5;
    // Slender-body theory needs L ≫ r; below L = 2r (log < 1.19) the
    // formula is meaningless (and negative below L = r e^{−½}).
    if length < 2.0 * radius {
        return Err(Error::invalid("rod length / radius (resistive-force drag)", length / radius, "≥ 2 (a slender rod)"));
    }
    let perp = 4.0 * PI * eta / log;
    Ok([perp, 0.5 * perp, 4.0 * PI * eta * radius * radius])
}

/// One segment's drag blocks: 4×4 on each position axis (`trans`), on
/// the roll, and the tangential part's 3×3 blocks `axial[k][l]` (zero for
/// isotropic drag).
pub(crate) struct SegDrag {
    pub trans: [[f64; 4]; 4],
    pub roll: [[f64; 4]; 4],
    pub axial: Option<[[[[f64; 3]; 3]; 4]; 4]>,
}

impl Rod {
    /// The drag of this rod in a fluid of viscosity `eta` (0: its own only),
    /// with resistive-force theory's anisotropy (γ_∥ = γ_⊥/2).
    pub fn drag(&self, eta: f64) -> Result<Drag> {
        let own = Drag { trans: self.opts.drag, axial: 0.0, roll: if self.dofs == 4 { self.opts.roll_drag } else { 0.0 }, roll_r2: 0.0 };
        if eta == 0.0 {
            return Ok(own);
        }
        let radius = self.cache.mean_r2.sqrt();
        let [perp, par, _] = resistive_force(eta, radius, self.rest_length())?;
        let roll_r2 = if self.dofs == 4 { 4.0 * PI * eta } else { 0.0 };
        Ok(Drag { trans: own.trans + perp, axial: par - perp, roll_r2, ..own })
    }

    /// Freezes the unit tangent at every Gauss sample (the anisotropic
    /// drag's directions for the coming step). Allocation-free once sized.
    pub(crate) fn freeze_drag_frame(&mut self) {
        let mut frame = std::mem::take(&mut self.drag_frame);
        frame.clear();
        frame.extend((0..self.cache.samples.len()).map(|g| self.current_tangent(g)));
        self.drag_frame = frame;
    }

    /// Unit tangent at Gauss sample `g` of the current shape (zero where
    /// the current one vanishes: the drag there is γ_⊥ on every axis).
    fn current_tangent(&self, g: usize) -> [f64; 3] {
        let smp = &self.cache.samples[g];
        let r1 = super::samples::local_state(&self.q, self.dofs, &self.cache.seg_ctrl[smp.seg], &smp.basis).r1;
        let n = r1.norm();
        if n > 0.0 && n.is_finite() {
            (r1 / n).into()
        } else {
            [0.0; 3]
        }
    }

    /// The frozen tangent at sample `g` (the current one before any step).
    pub(crate) fn drag_tangent(&self, g: usize) -> [f64; 3] {
        if self.drag_frame.len() == self.cache.samples.len() {
            self.drag_frame[g]
        } else {
            self.current_tangent(g)
        }
    }

    /// Sample `g`'s factors of its `seg_bb` block, G_g = u uᵀ + v vᵀ:
    /// u = √w b, v = √w ℓ²/|r0′|² b″ (the sampling inertia's share; zero
    /// without `sampling_length`).
    pub(crate) fn drag_factors(&self, g: usize) -> ([f64; 4], [f64; 4]) {
        let smp = &self.cache.samples[g];
        let sw = smp.w.sqrt();
        let l2 = (self.opts.sampling_length / smp.consts.speed0).powi(2);
        (smp.basis[0].map(|b| sw * b), smp.basis[2].map(|b| sw * l2 * b))
    }

    /// y = D x with the drag matrix of `drag` (III.10).
    pub fn drag_times(&self, drag: &Drag, x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        let d = self.dofs;
        for (seg, ctrl) in self.cache.seg_ctrl.iter().enumerate() {
            let (bb, r2) = (&self.cache.seg_bb[seg], &self.cache.seg_r2bb[seg]);
            for k in 0..4 {
                for l in 0..4 {
                    for a in 0..3 {
                        y[ctrl[k] * d + a] += drag.trans * bb[k][l] * x[ctrl[l] * d + a];
                    }
                    if d == 4 {
                        y[ctrl[k] * d + 3] += (drag.roll * bb[k][l] + drag.roll_r2 * r2[k][l]) * x[ctrl[l] * d + 3];
                    }
                }
            }
        }
        if drag.axial == 0.0 {
            return;
        }
        // c_a Σ_g (u uᵀ + v vᵀ) ⊗ t tᵀ: per factor f, c_a f_k t (t · Σ_l f_l x_l).
        for (g, smp) in self.cache.samples.iter().enumerate() {
            let ctrl = &self.cache.seg_ctrl[smp.seg];
            let t = self.drag_tangent(g);
            let (u, v) = self.drag_factors(g);
            for f in [u, v] {
                let tx: f64 = (0..4).map(|l| f[l] * (0..3).map(|a| t[a] * x[ctrl[l] * d + a]).sum::<f64>()).sum();
                for k in 0..4 {
                    for a in 0..3 {
                        y[ctrl[k] * d + a] += drag.axial * f[k] * t[a] * tx;
                    }
                }
            }
        }
    }

    /// Segment `seg`'s drag block on the roll.
    pub(crate) fn seg_roll_drag(&self, drag: &Drag, seg: usize) -> [[f64; 4]; 4] {
        let (bb, r2) = (&self.cache.seg_bb[seg], &self.cache.seg_r2bb[seg]);
        let mut r = [[0.0; 4]; 4];
        for k in 0..4 {
            for l in 0..4 {
                r[k][l] = drag.roll * bb[k][l] + drag.roll_r2 * r2[k][l];
            }
        }
        r
    }

    /// Segment `seg`'s drag blocks.
    pub(crate) fn seg_drag(&self, drag: &Drag, seg: usize) -> SegDrag {
        let bb = &self.cache.seg_bb[seg];
        let t = bb.map(|row| row.map(|x| drag.trans * x));
        let r = self.seg_roll_drag(drag, seg);
        let axial = (drag.axial != 0.0).then(|| {
            let mut a = [[[[0.0; 3]; 3]; 4]; 4];
            for g in self.cache.seg_start[seg]..self.cache.seg_start[seg + 1] {
                let tg = self.drag_tangent(g);
                let (u, v) = self.drag_factors(g);
                for k in 0..4 {
                    for l in 0..4 {
                        let c = drag.axial * (u[k] * u[l] + v[k] * v[l]);
                        for (i, row) in a[k][l].iter_mut().enumerate() {
                            for (j, x) in row.iter_mut().enumerate() {
                                *x += c * tg[i] * tg[j];
                            }
                        }
                    }
                }
            }
            a
        });
        SegDrag { trans: t, roll: r, axial }
    }
}
