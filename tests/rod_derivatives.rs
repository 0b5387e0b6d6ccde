//! Whole-rod derivative checks (issue acceptance: "assembled forces equal
//! −dU/dX by finite differences on whole rods"):
//!
//! - `Rod::internal_forces()` equals −∂U/∂q by central differences of
//!   `Rod::elastic_energy()` (max error ≤ 1e-6 × max |P|);
//! - the stiffness summed from the per-segment upper-half blocks of
//!   `Rod::assemble(.., Need::Hessian, ..)` equals the central difference of
//!   −P (max error ≤ 1e-5 × max |K|), and so is symmetric;
//!
//! on rods with and without roll, clamped / uniform / periodic knots,
//! straight, helical and ring rest shapes, one with sections varying along
//! the rod, each pre-deformed by a deterministic pseudo-random displacement.
//!
//! In the Frenet model, and in the reference-frame model (the default for
//! rods with roll) by differences of the energy alone: there `set_coords`
//! carries the directors to the new shape, by the formulas the energy uses,
//! so the energy of a state reached in one move from the base state is the
//! energy at the base state's directors — the function the assembled
//! forces and stiffness differentiate — while a difference of forces would
//! include the transport. Its stiffness is checked against second
//! differences of the energy.

use nalgebra::Vector3;
use strandkit::energy::EnergyTerms;
use strandkit::rod::assemble::{Need, SegBlock};
use strandkit::spline::KnotKind;
use strandkit::*;

/// Deterministic pseudo-random numbers in [-1, 1] (64-bit LCG).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

#[derive(Clone, Copy, Debug)]
enum Shape {
    Straight,
    Helix,
    /// Closed circle of radius 0.3 (for periodic knots).
    Ring,
}

#[derive(Clone, Copy)]
struct Case {
    name: &'static str,
    shape: Shape,
    knots: KnotKind,
    roll: bool,
    varying_section: bool,
    n_ctrl: usize,
    /// Position perturbation (length unit; roll gets 7.5 × this in rad).
    amplitude: f64,
    /// Stretch at the Greville points (`RodOptions::stretch_at_greville`).
    greville: bool,
}

fn material() -> Material {
    // Soft enough that stretch and bend forces are of comparable size.
    Material::new("test", 1e6, 0.3, 1000.0).unwrap()
}

fn build(c: &Case) -> Rod {
    build_in(c, FrameModel::Frenet)
}

fn build_in(c: &Case, model: FrameModel) -> Rod {
    let b = match c.shape {
        Shape::Straight => RodBuilder::straight(Vector3::new(0.1, -0.2, 0.3), Vector3::new(1.1, 0.3, 0.1)),
        Shape::Helix => RodBuilder::helix(0.2, 0.15, 1.5),
        Shape::Ring => RodBuilder::curve(2.0 * std::f64::consts::PI * 0.3, |s| {
            let phi = s / 0.3;
            Vector3::new(0.3 * phi.cos(), 0.3 * phi.sin(), 0.0)
        }),
    };
    let b = b.control_points(c.n_ctrl).knots(c.knots).with_roll(c.roll).material(material());
    let b = b.options(RodOptions { stretch_at_greville: c.greville, model, ..Default::default() });
    let b = if c.varying_section {
        b.sections((0..c.n_ctrl).map(|i| Section::circle(0.02 + 0.003 * (i % 5) as f64).unwrap()).collect())
    } else {
        b.section(Section::circle(0.025).unwrap())
    };
    let b = if c.roll {
        // A non-trivial rest roll as well.
        b.roll((0..c.n_ctrl).map(|i| 0.1 * (i as f64).sin()).collect())
    } else {
        b
    };
    b.build().unwrap()
}

/// Deformed coordinates: positions moved by up to 4 % of the length scale,
/// roll by up to 0.3 rad.
fn deform(rod: &Rod, seed: u64) -> Vec<f64> {
    deform_by(rod, seed, 0.04)
}

fn deform_by(rod: &Rod, seed: u64, amp: f64) -> Vec<f64> {
    let mut rng = Lcg(seed);
    let d = rod.dofs();
    let mut q = rod.coords().to_vec();
    for i in 0..rod.n_ctrl() {
        for a in 0..d {
            q[i * d + a] += if a < 3 { amp * rng.next() } else { 7.5 * amp * rng.next() };
        }
    }
    q
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Dense symmetric stiffness from the segment blocks (upper halves).
fn dense_stiffness(rod: &Rod) -> Vec<Vec<f64>> {
    let (n, d) = (rod.coords().len(), rod.dofs());
    let mut blocks: Vec<SegBlock> = Vec::new();
    rod.assemble(&mut blocks, Need::Hessian, false);
    assert_eq!(blocks.len(), rod.n_segments());
    let mut k = vec![vec![0.0; n]; n];
    for (s, b) in blocks.iter().enumerate() {
        let ctrl = rod.knots().segment_ctrl(s);
        let g = |l: usize| ctrl[l / d] * d + l % d;
        for ci in 0..4 * d {
            for cj in ci..4 * d {
                let h = b.hess[ci * 16 + cj];
                k[g(ci)][g(cj)] += h;
                if ci != cj {
                    k[g(cj)][g(ci)] += h;
                }
            }
        }
    }
    k
}

/// Finite-difference step: small against the length scale of the
/// deformation (the nearly straight cases vary on the perturbation scale).
fn step_for(rod: &Rod, j: usize, amp: f64) -> f64 {
    if j % rod.dofs() == 3 {
        1e-6f64.min(1e-4 * amp)
    } else {
        (1e-6 * rod.rest_length()).min(1e-4 * amp)
    }
}

/// The energy at `q`, reached in one move from `rod`'s state.
fn energy_after_move(rod: &Rod, q: &[f64]) -> f64 {
    let mut r = rod.clone();
    r.set_coords(q).unwrap();
    r.elastic_energy()
}

/// Deforms `rod` by the case's seeded perturbation; returns its coordinates.
fn deformed(rod: &mut Rod, c: &Case) -> Vec<f64> {
    let q0 = deform_by(rod, 0x5eed ^ (c.n_ctrl as u64 * 977), c.amplitude);
    rod.set_coords(&q0).unwrap();
    q0
}

/// Internal forces at `q0` (`rod`'s state) against −∂U/∂q by central
/// differences, to 1e-6 max |P|.
fn assert_forces(rod: &Rod, q0: &[f64], c: &Case, label: &str) {
    let (worst, pmax) = force_error(rod, q0, c.amplitude);
    println!("{}{label}: max|P| = {pmax:.4e}, force error {:.2e} (relative)", c.name, worst / pmax);
    assert!(worst <= 1e-6 * pmax, "{}{label}: internal forces differ from -dU/dq by {worst:e} (max |P| {pmax:e})", c.name);
}

/// The largest |P_j + ∂U/∂q_j| at `q0` (`rod`'s state), the derivative by
/// central differences of [`energy_after_move`], and max |P|.
fn force_error(rod: &Rod, q0: &[f64], amp: f64) -> (f64, f64) {
    let p = rod.internal_forces();
    assert_eq!(p.len(), q0.len());
    let mut q = q0.to_vec();
    let mut worst = 0.0f64;
    for j in 0..q0.len() {
        let h = step_for(rod, j, amp);
        q[j] = q0[j] + h;
        let up = energy_after_move(rod, &q);
        q[j] = q0[j] - h;
        let um = energy_after_move(rod, &q);
        q[j] = q0[j];
        worst = worst.max((p[j] + (up - um) / (2.0 * h)).abs());
    }
    (worst, max_abs(&p))
}

fn check_case(c: &Case) {
    let mut rod = build(c);
    let q0 = deformed(&mut rod, c);
    let n = q0.len();
    let e0 = rod.elastic_energy();
    assert!(e0.is_finite() && e0 > 0.0, "{}: energy of the deformed rod {e0}", c.name);
    println!("{}: U = {e0:.4e}", c.name);

    // Forces against −∂U/∂q.
    assert_forces(&rod, &q0, c, "");
    let mut q = q0.clone();

    // Stiffness against −∂P/∂q.
    let k = dense_stiffness(&rod);
    let kmax = k.iter().map(|r| max_abs(r)).fold(0.0, f64::max);
    let mut worst = 0.0f64;
    let mut worst_roll = 0.0f64;
    for j in 0..n {
        let h = step_for(&rod, j, c.amplitude);
        q[j] = q0[j] + h;
        rod.set_coords(&q).unwrap();
        let pp = rod.internal_forces();
        q[j] = q0[j] - h;
        rod.set_coords(&q).unwrap();
        let pm = rod.internal_forces();
        q[j] = q0[j];
        for i in 0..n {
            let fd = -(pp[i] - pm[i]) / (2.0 * h);
            let err = (k[i][j] - fd).abs();
            worst = worst.max(err);
            if i % rod.dofs() == 3 && j % rod.dofs() == 3 {
                worst_roll = worst_roll.max(err);
            }
        }
    }
    rod.set_coords(&q0).unwrap();
    println!("{}: max|K| = {kmax:.4e}, stiffness error {:.2e} (relative)", c.name, worst / kmax);
    assert!(worst <= 1e-5 * kmax, "{}: stiffness differs from -dP/dq by {worst:e} (max |K| {kmax:e})", c.name);
    if c.roll {
        // The roll–roll block is much smaller than the stretch block: check it
        // against its own scale too.
        let kroll = (0..n)
            .filter(|i| i % 4 == 3)
            .flat_map(|i| (0..n).filter(|j| j % 4 == 3).map(move |j| (i, j)))
            .map(|(i, j)| k[i][j].abs())
            .fold(0.0, f64::max);
        assert!(kroll > 0.0, "{}: no roll stiffness", c.name);
        assert!(
            worst_roll <= 1e-5 * kroll,
            "{}: roll-roll stiffness differs from FD by {worst_roll:e} (max {kroll:e})",
            c.name
        );
    }
}

macro_rules! case_test {
    ($fn:ident, $shape:expr, $knots:expr, $roll:expr, $var:expr, $n:expr, $amp:expr) => {
        #[test]
        fn $fn() {
            check_case(&Case {
                name: stringify!($fn),
                shape: $shape,
                knots: $knots,
                roll: $roll,
                varying_section: $var,
                n_ctrl: $n,
                amplitude: $amp,
                greville: false,
            });
        }
    };
}

/// Greville stretch samples (the energy, forces and stiffness of the
/// stretch-only samples go through the same chain rule).
#[test]
fn helix_clamped_roll_varying_section_greville() {
    greville_case(Case { name: "helix_clamped_roll_varying_section_greville", shape: Shape::Helix, knots: KnotKind::Clamped, roll: true, varying_section: true, n_ctrl: 12, amplitude: 0.04, greville: true });
}
#[test]
fn ring_periodic_no_roll_greville() {
    greville_case(Case { name: "ring_periodic_no_roll_greville", shape: Shape::Ring, knots: KnotKind::Periodic, roll: false, varying_section: false, n_ctrl: 10, amplitude: 0.04, greville: true });
}
#[test]
fn straight_uniform_no_roll_greville() {
    greville_case(Case { name: "straight_uniform_no_roll_greville", shape: Shape::Straight, knots: KnotKind::Uniform, roll: false, varying_section: false, n_ctrl: 8, amplitude: 0.04, greville: true });
}

/// A Greville case, and its energy differs from the Gauss stretch's on the
/// same deformation (so its samples are really in the energy); at rest both are zero.
fn greville_case(c: Case) {
    check_case(&c);
    let (mut a, mut b) = (build(&c), build(&Case { greville: false, ..c }));
    assert!(a.elastic_energy().abs() < 1e-12, "{}: rest energy {}", c.name, a.elastic_energy());
    let q = deform_by(&a, 7, c.amplitude);
    a.set_coords(&q).unwrap();
    b.set_coords(&q).unwrap();
    let (ea, eb) = (a.elastic_energy(), b.elastic_energy());
    assert!((ea - eb).abs() > 1e-3 * eb, "{}: Greville energy {ea} equals the Gauss one {eb}", c.name);
}

case_test!(straight_clamped_roll, Shape::Straight, KnotKind::Clamped, true, false, 9, 0.04);
case_test!(straight_clamped_no_roll, Shape::Straight, KnotKind::Clamped, false, false, 9, 0.04);
case_test!(straight_uniform_roll, Shape::Straight, KnotKind::Uniform, true, false, 8, 0.04);
case_test!(straight_uniform_no_roll, Shape::Straight, KnotKind::Uniform, false, false, 8, 0.04);
case_test!(helix_clamped_roll, Shape::Helix, KnotKind::Clamped, true, false, 12, 0.04);
case_test!(helix_clamped_no_roll, Shape::Helix, KnotKind::Clamped, false, false, 12, 0.04);
case_test!(helix_uniform_roll_varying_section, Shape::Helix, KnotKind::Uniform, true, true, 12, 0.04);
case_test!(helix_uniform_no_roll_varying_section, Shape::Helix, KnotKind::Uniform, false, true, 12, 0.04);
case_test!(ring_periodic_roll, Shape::Ring, KnotKind::Periodic, true, false, 10, 0.04);
case_test!(ring_periodic_no_roll, Shape::Ring, KnotKind::Periodic, false, false, 10, 0.04);
// Nearly straight (curvature ~ 1e-3/L .. 1e-2/L, around the Frenet
// regularisation threshold): the derivatives must stay consistent.
case_test!(nearly_straight_clamped_roll, Shape::Straight, KnotKind::Clamped, true, false, 9, 2e-5);
case_test!(nearly_straight_clamped_no_roll, Shape::Straight, KnotKind::Clamped, false, false, 9, 2e-5);
case_test!(straight_clamped_roll_varying_section, Shape::Straight, KnotKind::Clamped, true, true, 10, 0.04);

/// The reference-frame model (module doc): forces against central
/// differences of the energy (≤ 1e-6 max |P|), the stiffness against
/// second differences (≤ 1e-5 max |K|), every energy from the deformed
/// state moved once.
fn check_reference_case(c: &Case) {
    let mut rod = build_in(c, FrameModel::Reference);
    assert_eq!(rod.options().model, FrameModel::Reference);
    let q0 = deformed(&mut rod, c);
    let n = q0.len();
    let energy = |q: &[f64]| energy_after_move(&rod, q);
    assert_forces(&rod, &q0, c, " (reference)");
    let mut q = q0.clone();
    // Second differences: steps 10× the first differences'. The error
    // scales as h² (measured 4.7e-7, 4.2e-6, 4.7e-5 of max |K| at 10×, 30×,
    // 100× on the straight rod): truncation, not a mismatch.
    let k = dense_stiffness(&rod);
    let kmax = k.iter().map(|r| max_abs(r)).fold(0.0, f64::max);
    let mut worst = 0.0f64;
    for i in 0..n {
        let hi = 10.0 * step_for(&rod, i, c.amplitude);
        for j in i..n {
            let hj = 10.0 * step_for(&rod, j, c.amplitude);
            let mut e = [0.0; 4];
            for (slot, (si, sj)) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)].into_iter().enumerate() {
                q[i] += si * hi;
                q[j] += sj * hj;
                e[slot] = energy(&q);
                q[i] = q0[i];
                q[j] = q0[j];
            }
            let fd = (e[0] - e[1] - e[2] + e[3]) / (4.0 * hi * hj);
            worst = worst.max((k[i][j] - fd).abs());
        }
    }
    println!("{} (reference): max|K| = {kmax:.4e}, stiffness error {:.2e} (relative)", c.name, worst / kmax);
    assert!(worst <= 1e-5 * kmax, "{} (reference): stiffness differs from the energy's second differences by {worst:e} (max |K| {kmax:e})", c.name);
}

#[test]
fn reference_model_whole_rod_derivatives() {
    for (name, shape, knots, varying_section, n_ctrl, amplitude, greville) in [
        ("straight_clamped_roll", Shape::Straight, KnotKind::Clamped, false, 9, 0.04, false),
        ("helix_clamped_roll", Shape::Helix, KnotKind::Clamped, false, 12, 0.04, false),
        ("helix_uniform_roll_varying_section", Shape::Helix, KnotKind::Uniform, true, 12, 0.04, false),
        ("ring_periodic_roll", Shape::Ring, KnotKind::Periodic, false, 10, 0.04, false),
        ("nearly_straight_clamped_roll", Shape::Straight, KnotKind::Clamped, false, 9, 2e-5, false),
        ("helix_clamped_roll_varying_section_greville", Shape::Helix, KnotKind::Clamped, true, 12, 0.04, true),
    ] {
        check_reference_case(&Case { name, shape, knots, roll: true, varying_section, n_ctrl, amplitude, greville });
    }
}

/// A rod without roll carries no twist energy: its energy equals that of the
/// same rod with roll but twist switched off (same positions, rest roll), to
/// 1e-12 relative, whereas with twist on the same deformation stores more.
#[test]
fn no_roll_rod_has_no_twist_energy() {
    let c = Case {
        name: "helix",
        shape: Shape::Helix,
        knots: KnotKind::Clamped,
        roll: false,
        varying_section: false,
        n_ctrl: 12,
        amplitude: 0.04,
        greville: false,
    };
    // The Frenet model, as every rod without roll is (Rod::new).
    let all_on = RodOptions { terms: EnergyTerms { stretch: true, bend: true, twist: true }, model: FrameModel::Frenet, ..Default::default() };
    let no_twist = RodOptions { terms: EnergyTerms { stretch: true, bend: true, twist: false }, model: FrameModel::Frenet, ..Default::default() };
    let sec = Section::circle(0.025).unwrap();
    let mk = |roll: bool, o: RodOptions| {
        RodBuilder::helix(0.2, 0.15, 1.5)
            .control_points(c.n_ctrl)
            .with_roll(roll)
            .section(sec)
            .material(material())
            .options(o)
            .build()
            .unwrap()
    };
    // A rod without roll is measured in the Frenet model whatever its
    // options ask (Rod::new).
    let asked = mk(false, RodOptions { model: FrameModel::Reference, ..all_on });
    assert_eq!(asked.options().model, FrameModel::Frenet);
    assert_eq!(mk(true, RodOptions::default()).options().model, FrameModel::Reference, "the default for rods with roll");
    // Asked for twist, a 3-dof rod still has it off.
    let mut r3 = mk(false, all_on);
    assert!(!r3.options().terms.twist, "3-dof rod reports twist energy on");
    let mut r4_off = mk(true, no_twist);
    let mut r4_on = mk(true, all_on);
    // Deform the centreline (this changes the Frenet torsion) and keep θ at rest.
    let q3 = deform(&r3, 42);
    let mut q4 = r4_on.coords().to_vec();
    for i in 0..r3.n_ctrl() {
        q4[i * 4..i * 4 + 3].copy_from_slice(&q3[i * 3..i * 3 + 3]);
    }
    r3.set_coords(&q3).unwrap();
    r4_off.set_coords(&q4).unwrap();
    r4_on.set_coords(&q4).unwrap();
    let (e3, e_off, e_on) = (r3.elastic_energy(), r4_off.elastic_energy(), r4_on.elastic_energy());
    println!("3-dof {e3:.10e}, 4-dof no twist {e_off:.10e}, 4-dof with twist {e_on:.10e}");
    assert!((e3 - e_off).abs() <= 1e-12 * e_off, "3-dof energy {e3} != stretch+bend energy {e_off}");
    assert!(e_on - e_off > 1e-6 * e_off, "the deformation must twist the rod for this test to mean anything");
}

/// The energy vanishes at rest (≤ 1e-12 × the energy of the deformation used
/// above): sanity of the reference state the derivatives are taken around.
#[test]
fn rest_energy_is_zero() {
    for (shape, knots, roll) in [
        (Shape::Straight, KnotKind::Clamped, true),
        (Shape::Helix, KnotKind::Uniform, false),
        (Shape::Ring, KnotKind::Periodic, true),
    ] {
        let mut rod = build(&Case { name: "rest", shape, knots, roll, varying_section: true, n_ctrl: 10, amplitude: 0.04, greville: false });
        let e = rod.elastic_energy();
        let q = deform(&rod, 7);
        rod.set_coords(&q).unwrap();
        let e_def = rod.elastic_energy();
        assert!(e.abs() <= 1e-12 * e_def, "{shape:?}: rest energy {e} (deformed {e_def})");
    }
}
