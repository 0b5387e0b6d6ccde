//! Stretch energy (II.56–II.57 corrected): ε = |r'|/|r0'| − 1,
//! W_s = ½ EA (ε − ε_p)², as a function of the invariant a = |r'|².
use super::invariants::{Mat11, Mat5, Vec5, QA, R1};
use super::SampleConsts;
use nalgebra::Vector3;

/// Adds F_s's derivatives with respect to the invariants; returns W_s.
#[inline(always)]
pub fn add(q: &Vec5, c: &SampleConsts, fq: &mut Vec5, fqq: &mut Mat5) -> f64 {
    let a = q[QA];
    let s = a.sqrt();
    // Two reciprocals instead of four divisions (this runs at every sample).
    let (il0, is) = (1.0 / c.speed0, 1.0 / s);
    let e = s * il0 - 1.0 - c.eps_p;
    // dε/da = 1/(2 s l0), d²ε/da² = −1/(4 l0 s³)
    let de = 0.5 * is * il0;
    fq[QA] += c.ea * e * de;
    fqq[(QA, QA)] += c.ea * (de * de - 0.5 * e * de * is * is);
    0.5 * c.ea * e * e
}

/// Engineering stretch strain ε = |r'|/|r0'| − 1.
pub fn strain(q: &Vec5, c: &SampleConsts) -> f64 {
    q[QA].sqrt() / c.speed0 - 1.0
}

/// Leaves out of `hess` (a sample's Hessian in d) the transverse stiffness
/// of a compressed sample, 2 W_a (I − r̂′r̂′ᵀ) with W_a = ∂W_s/∂a < 0:
/// compression's negative geometric stiffness. A linearised implicit step
/// is one solve with M/h² + K; where that term outweighed the mass the step
/// leapt along it. Leaving it out adds K′ − K ≥ 0 to the matrix, a little
/// numerical damping of the sideways motion of compressed samples (which
/// is why thermal steps keep the exact term). Measured: a string under
/// heavy sliding beads, whose 16-point spline carries quadrature-level
/// compressions of ±0.5 %, took a step that put 930 J into it; the falling
/// rope bridge diverged under a 1e-10 relative change of its time step.
/// Left out everywhere, not only past a threshold: with the exact term
/// kept below ten times the compression the inertia holds at the grid
/// scale, the bridge diverged too. The force is untouched, so buckling
/// still grows (its driving term is then explicit); statics (but for
/// relax's mixed prediction, [`mixed_geometric_stiffness`]) and the
/// Newton iterations of the second-order schemes keep the exact Hessian.
#[inline(always)]
pub fn leave_out_compression(r1: &Vector3<f64>, c: &SampleConsts, hess: &mut Mat11) {
    let a = r1.norm_squared();
    // ε < 0 ⟺ |r′| < l0 (1 + ε_p): tested without the root (most samples).
    let rest = c.speed0 * (1.0 + c.eps_p);
    if !(rest > 0.0 && a < rest * rest) {
        return;
    }
    let s = a.sqrt();
    let e = s / c.speed0 - 1.0 - c.eps_p;
    // W_a = EA e dε/da, dε/da = 1/(2 s l0).
    let wa = c.ea * e * 0.5 / (s * c.speed0);
    // `hess` is stored whole (symmetric).
    for i in 0..3 {
        for j in 0..3 {
            let transverse = if i == j { 1.0 } else { 0.0 } - r1[i] * r1[j] / a;
            hess[(R1 + i, R1 + j)] -= 2.0 * wa * transverse;
        }
    }
}

/// Mixed-integration-point stiffness (Magisano, Leonetti & Garcea,
/// CMAME 313 (2017) 986): in a Newton iteration the transverse
/// (geometric) stretch stiffness EA ε/(l0 |r′|) (I − r̂′r̂′ᵀ) takes the
/// strain predicted linearly from the previous iterate, ε̃ = t·r′/l0 − 1 −
/// ε_p (t: that iterate's unit tangent), instead of the strain at r′. A
/// step that turns a sample by θ stretches it by θ²/2 to second order;
/// with EA ≫ EI/L² that spurious tension then stiffens the next
/// iteration's sideways motion and the iteration crawls (membrane locking
/// of the iteration, not of the equilibrium: ε̃ − ε = O(|Δr′|²), so the
/// fixed point and the quadratic convergence are kept).
#[inline(always)]
pub fn mixed_geometric_stiffness(r1: &Vector3<f64>, t: &[f64; 3], c: &SampleConsts, hess: &mut Mat11) {
    let a = r1.norm_squared();
    if !(a > 0.0 && c.speed0 > 0.0) || *t == [0.0; 3] {
        return; // no tangent to predict from: the exact stiffness stays
    }
    let s = a.sqrt();
    // ε̃ − ε = (t·r′ − |r′|)/l0 ≤ 0.
    let shift = c.ea * (Vector3::from(*t).dot(r1) - s) / (c.speed0 * c.speed0 * s);
    for i in 0..3 {
        for j in 0..3 {
            let transverse = if i == j { 1.0 } else { 0.0 } - r1[i] * r1[j] / a;
            hess[(R1 + i, R1 + j)] += shift * transverse;
        }
    }
}

/// The mixed merit's stretch density less the exact one: with ε̃ the strain
/// predicted linearly from the tangent t (as above), the Hellinger–Reissner
/// density σ̃ε − σ̃²/(2EA), σ̃ = EA ε̃, is ½EAε² − ½EA(ε − ε̃)²; this returns
/// −½EA((|r′| − t·r′)/l0)². Zero at the iterate where t was taken, of
/// second order in the step, so the merit's slope there is the energy's.
#[inline(always)]
pub fn mixed_merit_shift(r1: &Vector3<f64>, t: &[f64; 3], c: &SampleConsts) -> f64 {
    if *t == [0.0; 3] || !(c.speed0 > 0.0) {
        return 0.0;
    }
    let d = (r1.norm() - Vector3::from(*t).dot(r1)) / c.speed0;
    -0.5 * c.ea * d * d
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::invariants::{LocalState, Vec11};
    use crate::energy::{density, EnergyTerms, FrameModel, FrameState};

    fn stretch_hessian(r1: Vector3<f64>, c: &SampleConsts) -> Mat11 {
        let mut d = Vec11::zeros();
        d.fixed_rows_mut::<3>(R1).copy_from(&r1);
        let terms = EnergyTerms { stretch: true, bend: false, twist: false };
        density(&LocalState::from_vec(&d), c, &FrameState::None, terms, FrameModel::Frenet, true).hess
    }

    /// The mixed stiffness takes the strain predicted from a tangent t:
    /// with t along r′ it is the exact Hessian; with t turned by φ its
    /// transverse eigenvalue is EA ε̃/(l0 |r′|), ε̃ = cos φ |r′|/l0 − 1 − ε_p
    /// (twice), and the axial one is unchanged. The merit's shift is
    /// −½EA(|r′|(1 − cos φ)/l0)², and zero with a zero gradient (central
    /// differences) where t is the tangent.
    #[test]
    fn mixed_stiffness_and_merit_take_the_predicted_strain() {
        let c = SampleConsts { ea: 600.0, speed0: 0.04, eps_p: 0.003, ..Default::default() };
        let dir = Vector3::new(0.6, -0.48, 0.64);
        let r1 = dir * (c.speed0 * 1.01);
        let s = r1.norm();
        let exact = stretch_hessian(r1, &c);
        let mut same = exact;
        mixed_geometric_stiffness(&r1, &dir.into(), &c, &mut same);
        assert!((same - exact).norm() < 1e-12 * exact.norm(), "t along r′ changes nothing");
        assert_eq!(mixed_merit_shift(&r1, &dir.into(), &c), 0.0);
        // Its gradient in r′ vanishes there.
        let h = 1e-6 * s;
        for i in 0..3 {
            let mut e = Vector3::zeros();
            e[i] = h;
            let g = (mixed_merit_shift(&(r1 + e), &dir.into(), &c) - mixed_merit_shift(&(r1 - e), &dir.into(), &c)) / (2.0 * h);
            assert!(g.abs() < 1e-9 * c.ea / c.speed0, "merit gradient {g}");
        }
        // t turned by φ about an axis normal to r′.
        let axis = dir.cross(&Vector3::new(0.0, 0.0, 1.0)).normalize();
        for phi in [0.05f64, 0.4, 1.0] {
            let t = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), phi) * dir;
            let mut mixed = exact;
            mixed_geometric_stiffness(&r1, &t.into(), &c, &mut mixed);
            let block = |h: &Mat11| h.fixed_view::<3, 3>(R1, R1).into_owned();
            let mut ev: Vec<f64> = block(&mixed).symmetric_eigenvalues().iter().copied().collect();
            ev.sort_by(f64::total_cmp);
            let predicted = phi.cos() * s / c.speed0 - 1.0 - c.eps_p;
            let transverse = c.ea * predicted / (c.speed0 * s);
            let axial = c.ea / (c.speed0 * c.speed0);
            for k in 0..2 {
                assert!((ev[k] - transverse).abs() < 1e-9 * axial, "φ {phi}: transverse {} vs {transverse}", ev[k]);
            }
            assert!((ev[2] - axial).abs() < 1e-9 * axial, "φ {phi}: axial {} vs {axial}", ev[2]);
            let d = s * (1.0 - phi.cos()) / c.speed0;
            let shift = mixed_merit_shift(&r1, &t.into(), &c);
            assert!((shift + 0.5 * c.ea * d * d).abs() < 1e-12 * c.ea * d * d, "φ {phi}: shift {shift}");
        }
    }

    /// Compressed 1 %: the exact stretch Hessian in r′ has the transverse
    /// eigenvalue 2 W_a < 0 (twice), the step's has 0 there and the same
    /// axial one; stretched 1 %, both are the same matrix.
    #[test]
    fn compression_leaves_a_positive_step_matrix_and_tension_is_untouched() {
        let c = SampleConsts { ea: 600.0, speed0: 0.04, ..Default::default() };
        let dir = Vector3::new(0.6, -0.48, 0.64);
        for (stretch, compressed) in [(0.99, true), (1.01, false)] {
            let r1 = dir * (c.speed0 * stretch);
            let exact = stretch_hessian(r1, &c);
            let mut step = exact;
            leave_out_compression(&r1, &c, &mut step);
            let eigen = |h: &Mat11| {
                let mut ev: Vec<f64> = h.fixed_view::<3, 3>(R1, R1).into_owned().symmetric_eigenvalues().iter().copied().collect();
                ev.sort_by(f64::total_cmp);
                ev
            };
            let (ev_exact, ev_step) = (eigen(&exact), eigen(&step));
            // W_a = EA ε /(2 |r′| l0), ε = stretch − 1.
            let wa = c.ea * (stretch - 1.0) * 0.5 / (c.speed0 * stretch * c.speed0);
            if compressed {
                for k in 0..2 {
                    assert!((ev_exact[k] - 2.0 * wa).abs() < 1e-9 * wa.abs(), "exact transverse {} vs {}", ev_exact[k], 2.0 * wa);
                    assert!(ev_step[k].abs() < 1e-9 * wa.abs(), "step transverse {}", ev_step[k]);
                }
                assert!((ev_step[2] - ev_exact[2]).abs() < 1e-12 * ev_exact[2], "axial unchanged");
            } else {
                assert_eq!(step, exact);
            }
        }
        // A plastic offset ε_p = 2 %: |r′| = 1.01 l0 is compressed against
        // the plastic rest length (ε − ε_p = −1 %), so the term goes; at
        // 1.03 l0 it is stretched and stays.
        let c = SampleConsts { eps_p: 0.02, ..c };
        for (stretch, compressed) in [(1.01, true), (1.03, false)] {
            let r1 = dir * (c.speed0 * stretch);
            let exact = stretch_hessian(r1, &c);
            let mut step = exact;
            leave_out_compression(&r1, &c, &mut step);
            let wa = c.ea * (stretch - 1.0 - c.eps_p) * 0.5 / (c.speed0 * stretch * c.speed0);
            let removed = (exact - step).fixed_view::<3, 3>(R1, R1).into_owned();
            let expected = if compressed { (nalgebra::Matrix3::identity() - dir * dir.transpose()) * (2.0 * wa) } else { nalgebra::Matrix3::zeros() };
            assert!((removed - expected).norm() < 1e-9 * (2.0 * wa).abs().max(1e-300), "removed {removed} vs {expected}");
            assert_eq!(compressed, removed.norm() > 0.0);
        }
    }
}
