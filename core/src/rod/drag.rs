//! A rod's viscous drag (III.10, SPEC §3): its own coefficients plus the
//! resistive-force drag of the world's fluid, D = c_t ∫ b_k b_l ds0 on each
//! position axis and c_θ ∫ b_k b_l ds0 + 4πη ∫ r² b_k b_l ds0 on the roll.
//! The translational drag is isotropic (γ_⊥ on every axis): resistive-force
//! theory's smaller axial drag γ_∥ ≈ γ_⊥/2 is not modelled, which slows
//! axial motion but leaves every equilibrium (thermal) average unchanged.
//! r is the section's hydrodynamic radius (a tube's outer radius, else
//! that of the circle of equal area).
use super::Rod;
use crate::error::{Error, Result};
use std::f64::consts::PI;

/// Drag coefficients of one rod in a fluid.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Drag {
    /// On each position axis: force per velocity per length.
    pub trans: f64,
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

impl Rod {
    /// The drag of this rod in a fluid of viscosity `eta` (0: its own only).
    pub fn drag(&self, eta: f64) -> Result<Drag> {
        let own = Drag { trans: self.opts.drag, roll: if self.dofs == 4 { self.opts.roll_drag } else { 0.0 }, roll_r2: 0.0 };
        if eta == 0.0 {
            return Ok(own);
        }
        let radius = self.cache.mean_r2.sqrt();
        let [perp, _, _] = resistive_force(eta, radius, self.rest_length())?;
        let roll_r2 = if self.dofs == 4 { 4.0 * PI * eta } else { 0.0 };
        Ok(Drag { trans: own.trans + perp, roll_r2, ..own })
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
    }

    /// Segment `seg`'s drag blocks (4×4 on each position axis, on the roll).
    pub(crate) fn seg_drag(&self, drag: &Drag, seg: usize) -> ([[f64; 4]; 4], [[f64; 4]; 4]) {
        let (bb, r2) = (&self.cache.seg_bb[seg], &self.cache.seg_r2bb[seg]);
        let mut t = [[0.0; 4]; 4];
        let mut r = [[0.0; 4]; 4];
        for k in 0..4 {
            for l in 0..4 {
                t[k][l] = drag.trans * bb[k][l];
                r[k][l] = drag.roll * bb[k][l] + drag.roll_r2 * r2[k][l];
            }
        }
        (t, r)
    }
}
