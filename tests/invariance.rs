//! Issue "Show 2": rigid-motion invariance and rest-shape equilibrium.
//!
//! - Rigid translations and rotations (about an arbitrary axis through an
//!   arbitrary point, applied to x, y, z of every control point; θ unchanged)
//!   of a rod in its rest state give zero internal force (max |P| ≤ 1e-10 EA)
//!   and zero energy (≤ 1e-10 × the energy of a bending to curvature 0.01/L),
//!   for straight and helical rest shapes, with and without roll (Frenet
//!   model: see `frenet`).
//! - A helical rest shape is an equilibrium (both models): zero internal
//!   forces at rest, and
//!   `relax()` of the helix clamped at one end (position + roll, tangent,
//!   material roll) without load leaves it unchanged (1e-9 × length).
//! - SPEC §2.2: a straight free rod stays put at rest (both models) and
//!   straight and stable in dynamics.
mod common;

use strandkit::prelude::*;
use nalgebra::{Rotation3, Unit, Vector3};

const E: f64 = 1e7;
const R: f64 = 0.02;

struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

fn material() -> Material {
    Material::new("test", E, 0.3, 1200.0).unwrap()
}
fn ea() -> f64 {
    E * std::f64::consts::PI * R * R
}
fn ei() -> f64 {
    E * std::f64::consts::PI * R.powi(4) / 4.0
}

/// The Frenet model: moving x, y, z rigidly with θ unchanged is a rigid
/// motion of the material frame only where θ is measured from a frame that
/// turns with the curve. (The reference-frame model measures θ from
/// directors carried by the smallest rotation, which a finite rotation
/// does not carry rigidly, and refuses a tangent turned by more than 150°
/// in one assignment.)
fn frenet() -> RodOptions {
    RodOptions { model: FrameModel::Frenet, ..Default::default() }
}

fn straight(roll: bool) -> Rod {
    straight_in(roll, FrameModel::Frenet)
}

fn helix(roll: bool) -> Rod {
    helix_in(roll, FrameModel::Frenet)
}

/// The checks that do not move the rod rigidly hold in both models.
const MODELS: [FrameModel; 2] = [FrameModel::Frenet, FrameModel::Reference];

fn straight_in(roll: bool, model: FrameModel) -> Rod {
    RodBuilder::straight(Vector3::new(0.2, 0.1, -0.3), Vector3::new(1.0, 0.7, 0.2))
        .control_points(12)
        .with_roll(roll)
        .section(Section::circle(R).unwrap())
        .material(material())
        .options(RodOptions { model, ..frenet() })
        .build()
        .unwrap()
}

fn helix_in(roll: bool, model: FrameModel) -> Rod {
    let b = RodBuilder::helix(0.15, 0.1, 2.0)
        .control_points(24)
        .with_roll(roll)
        .section(Section::ellipse(R, 0.7 * R).unwrap())
        .material(material())
        .options(RodOptions { model, ..frenet() });
    // A non-trivial rest roll on the rods that have one.
    let b = if roll { b.roll((0..24).map(|i| 0.2 * (0.5 * i as f64).sin()).collect()) } else { b };
    b.build().unwrap()
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// Energy of bending the rod uniformly to curvature 0.01/L: ½ EI κ² L.
fn energy_scale(rod: &Rod) -> f64 {
    let l = rod.rest_length();
    0.5 * ei() * (0.01 / l).powi(2) * l
}

/// Applies x ↦ R (x − c) + c + t to the positions; θ unchanged.
fn rigid(rod: &Rod, rot: &Rotation3<f64>, centre: Vector3<f64>, t: Vector3<f64>) -> Vec<f64> {
    let d = rod.dofs();
    let mut q = rod.coords().to_vec();
    for i in 0..rod.n_ctrl() {
        let p = Vector3::new(q[i * d], q[i * d + 1], q[i * d + 2]);
        let p = rot * (p - centre) + centre + t;
        q[i * d..i * d + 3].copy_from_slice(p.as_slice());
    }
    q
}

fn motions() -> Vec<(&'static str, Rotation3<f64>, Vector3<f64>, Vector3<f64>)> {
    let axis = Unit::new_normalize(Vector3::new(1.0, 2.0, -0.5));
    let axis2 = Unit::new_normalize(Vector3::new(-0.3, 0.1, 0.9));
    let c = Vector3::new(0.4, -0.1, 0.3);
    vec![
        ("translation", Rotation3::identity(), Vector3::zeros(), Vector3::new(0.3, -1.2, 2.5)),
        ("rotation 0.3 rad", Rotation3::from_axis_angle(&axis, 0.3), c, Vector3::zeros()),
        ("rotation 1.7 rad", Rotation3::from_axis_angle(&axis, 1.7), c, Vector3::zeros()),
        ("rotation pi", Rotation3::from_axis_angle(&axis2, std::f64::consts::PI), c, Vector3::zeros()),
        (
            "rotation + translation",
            Rotation3::from_axis_angle(&axis2, -2.4) * Rotation3::from_axis_angle(&axis, 0.8),
            c,
            Vector3::new(-5.0, 3.0, 1.0),
        ),
    ]
}

fn check_invariance(name: &str, mut rod: Rod) {
    let (fscale, escale) = (ea(), energy_scale(&rod));
    // At rest: zero force and energy.
    let p0 = max_abs(&rod.internal_forces());
    let e0 = rod.elastic_energy();
    assert!(p0 <= 1e-10 * fscale, "{name} at rest: max |P| = {p0:e} (EA = {fscale:e})");
    assert!(e0.abs() <= 1e-10 * escale, "{name} at rest: U = {e0:e} (scale {escale:e})");
    let rest = rod.coords().to_vec();
    for (what, rot, c, t) in motions() {
        let q = rigid(&rod, &rot, c, t);
        rod.set_coords(&q).unwrap();
        let p = max_abs(&rod.internal_forces());
        let e = rod.elastic_energy();
        println!("{name}, {what}: max|P|/EA = {:.2e}, U/scale = {:.2e}", p / fscale, e / escale);
        assert!(p <= 1e-10 * fscale, "{name}, {what}: max |P| = {p:e} (EA = {fscale:e})");
        assert!(e.abs() <= 1e-10 * escale, "{name}, {what}: U = {e:e} (scale {escale:e})");
        // The motion is really rigid and non-trivial.
        assert!(max_abs(&q.iter().zip(&rest).map(|(a, b)| a - b).collect::<Vec<_>>()) > 0.05);
        rod.set_coords(&rest).unwrap();
    }
    // Sanity: the same tolerances do see a small bending.
    let d = rod.dofs();
    let mut q = rest.clone();
    let l = rod.rest_length();
    let n = rod.n_ctrl();
    for i in 0..n {
        let s = i as f64 / (n - 1) as f64;
        // A displacement ⟂ to the chord, quadratic along the rod (amplitude 1e-3 L).
        q[i * d + 2] += 1e-3 * l * 4.0 * s * (1.0 - s);
        q[i * d] -= 0.5e-3 * l * 4.0 * s * (1.0 - s);
    }
    rod.set_coords(&q).unwrap();
    let e = rod.elastic_energy();
    let p = max_abs(&rod.internal_forces());
    assert!(e > 1e-10 * escale && p > 1e-10 * fscale, "{name}: a real bending gives U = {e:e}, max |P| = {p:e}");
}

#[test]
fn straight_with_roll_rigid_motion_invariant() {
    check_invariance("straight, roll", straight(true));
}
#[test]
fn straight_without_roll_rigid_motion_invariant() {
    check_invariance("straight, no roll", straight(false));
}
#[test]
fn helix_with_roll_rigid_motion_invariant() {
    check_invariance("helix, roll", helix(true));
}
#[test]
fn helix_without_roll_rigid_motion_invariant() {
    check_invariance("helix, no roll", helix(false));
}

/// The helical rest shape is an equilibrium also on the bending force scale:
/// max |P| ≤ 1e-9 × EI κ0 / ds (ds = control-point spacing), not only ≤ 1e-10 EA.
#[test]
fn helix_rest_forces_vanish_on_bending_scale() {
    for (roll, model) in [true, false].into_iter().flat_map(|r| MODELS.map(|m| (r, m))) {
        let rod = helix_in(roll, model);
        let (radius, c) = (0.15f64, 0.1 / (2.0 * std::f64::consts::PI));
        let kappa0 = radius / (radius * radius + c * c);
        let ds = rod.rest_length() / rod.n_ctrl() as f64;
        let scale = ei() * kappa0 / ds;
        let p = max_abs(&rod.internal_forces());
        println!("helix roll={roll} {model:?}: max|P| = {p:e}, bending force scale {scale:e}");
        assert!(p <= 1e-9 * scale, "helix roll={roll} {model:?}: rest force {p:e} vs bending scale {scale:e}");
    }
}

/// A helix clamped at its start (position x,y,z,θ + tangent + material roll)
/// with no load: `relax()` converges and leaves it where it is (1e-9 L).
#[test]
fn clamped_helix_relaxes_to_itself() {
    let rod = helix(true);
    let (u0, _) = rod.domain();
    let l = rod.rest_length();
    let p = rod.eval(u0, 0).unwrap();
    let t = rod.tangent(u0).unwrap();
    let s = rod.local_state(u0).unwrap();
    let b = s.r1.cross(&s.r2).normalize();
    let n = b.cross(&t);
    let q0 = rod.coords().to_vec();
    let mut world = World::new(IntegrationParameters::default());
    let h = world.add_rod(rod);
    world.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true; 4], target: p }), 0.0).unwrap();
    world.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: t.into() }), 0.0).unwrap();
    // Reference = Frenet normal: then the material-roll angle is θ(u0).
    let roll = world
        .add_constraint(h, ConstraintKind::MaterialRoll(MaterialRoll { u: u0, reference: n.into(), angle: p[3] }), 0.0)
        .unwrap();
    let rep = world.relax().expect("relax of an unloaded clamped helix");
    let q = world.rod(h).unwrap().coords();
    let dq = max_abs(&q.iter().zip(&q0).map(|(a, b)| a - b).collect::<Vec<_>>());
    println!("clamped helix: {} iterations, max |Δq| = {dq:e} (L = {l})", rep.iterations);
    assert!(dq <= 1e-9 * l, "unloaded clamped helix moved by {dq:e} (L = {l})");
    // And the clamp carries no load (≤ 1e-8 × EI κ0), the rod no force (≤ 1e-8 EA).
    let (radius, c) = (0.15f64, 0.1 / (2.0 * std::f64::consts::PI));
    let kappa0 = radius / (radius * radius + c * c);
    let r = world.reaction(roll).unwrap();
    assert!(max_abs(&r.torque) <= 1e-8 * ei() * kappa0, "material-roll torque {:?}", r.torque);
    assert!(max_abs(&world.rod(h).unwrap().internal_forces()) <= 1e-8 * ea());
}

/// The rotated helix is still an equilibrium of relax() when clamped where it is.
#[test]
fn rotated_clamped_helix_relaxes_to_itself() {
    let mut rod = helix(true);
    let rot = Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::new(0.3, -1.0, 0.4)), 2.1);
    let q = rigid(&rod, &rot, Vector3::new(0.1, 0.2, 0.3), Vector3::new(1.0, -2.0, 0.5));
    rod.set_coords(&q).unwrap();
    let (u0, _) = rod.domain();
    let l = rod.rest_length();
    let p = rod.eval(u0, 0).unwrap();
    let t = rod.tangent(u0).unwrap();
    let s = rod.local_state(u0).unwrap();
    let n = s.r1.cross(&s.r2).normalize().cross(&t);
    let mut world = World::new(IntegrationParameters::default());
    let h = world.add_rod(rod);
    world.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true; 4], target: p }), 0.0).unwrap();
    world.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: t.into() }), 0.0).unwrap();
    world.add_constraint(h, ConstraintKind::MaterialRoll(MaterialRoll { u: u0, reference: n.into(), angle: p[3] }), 0.0).unwrap();
    world.relax().expect("relax of the rotated clamped helix");
    let qa = world.rod(h).unwrap().coords();
    let dq = max_abs(&qa.iter().zip(&q).map(|(a, b)| a - b).collect::<Vec<_>>());
    assert!(dq <= 1e-9 * l, "rotated clamped helix moved by {dq:e} (L = {l})");
}

fn total_energy(w: &World, h: RodHandle) -> f64 {
    let r = w.rod(h).unwrap();
    r.kinetic_energy() + r.elastic_energy()
}

/// SPEC §2.2: a straight free rod at rest stays exactly where it is in
/// dynamics (200 steps, coords within 1e-12 L), with and without roll.
#[test]
fn straight_free_rod_at_rest_stays_put() {
    for (roll, model) in [true, false].into_iter().flat_map(|r| MODELS.map(|m| (r, m))) {
        let rod = straight_in(roll, model);
        let l = rod.rest_length();
        let q0 = rod.coords().to_vec();
        let mut w = World::new(IntegrationParameters::default());
        let h = w.add_rod(rod);
        for _ in 0..200 {
            w.step().unwrap();
        }
        let q = w.rod(h).unwrap().coords();
        let dq = max_abs(&q.iter().zip(&q0).map(|(a, b)| a - b).collect::<Vec<_>>());
        assert!(dq <= 1e-12 * l, "roll={roll} {model:?}: free straight rod at rest drifted by {dq:e}");
    }
}

/// SPEC §2.2: a straight free rod with roll and small random initial
/// velocities stays stable: no NaN, total energy never above 1.01 × its
/// initial value (implicit Euler only dissipates), linear momentum conserved
/// (1e-9 relative, no external force), and it stays nearly straight
/// (distance of the sample points from the initial line ≤ 1e-2 L).
#[test]
fn straight_free_rod_with_random_velocities_is_stable() {
    for roll in [true, false] {
        let rod = straight(roll);
        let l = rod.rest_length();
        let d = rod.dofs();
        let mut rng = Lcg(12345);
        let v: Vec<f64> = (0..rod.coords().len())
            .map(|i| if i % d == 3 { 0.05 * rng.next() } else { 1e-3 * rng.next() })
            .collect();
        let a = rod.position(rod.domain().0).unwrap();
        let dir = (rod.position(rod.domain().1).unwrap() - a).normalize();
        let mut w = World::new(IntegrationParameters { dt: 1e-3, ..Default::default() });
        let h = w.add_rod(rod);
        w.rod_mut(h).unwrap().set_velocities(&v).unwrap();
        let e0 = total_energy(&w, h);
        let p0 = w.rod(h).unwrap().momentum();
        assert!(e0 > 0.0);
        let mut emax = e0;
        for n in 0..200 {
            w.step().unwrap_or_else(|e| panic!("roll={roll}: step {n} failed: {e}"));
            let r = w.rod(h).unwrap();
            assert!(r.coords().iter().chain(r.velocities()).all(|x| x.is_finite()), "roll={roll}: NaN at step {n}");
            let e = total_energy(&w, h);
            emax = emax.max(e);
            assert!(e <= 1.01 * e0, "roll={roll}: energy grew from {e0:e} to {e:e} at step {n}");
            let p = r.momentum();
            assert!((p - p0).norm() <= 1e-9 * p0.norm().max(1e-300), "roll={roll}: momentum {p:?} vs {p0:?} at step {n}");
        }
        let r = w.rod(h).unwrap();
        // Distance from the line through the drifting centroid direction.
        let pts = r.sample_points();
        let c = pts.iter().fold(Vector3::zeros(), |s, p| s + p) / pts.len() as f64;
        let dev = pts.iter().map(|p| ((p - c) - dir * (p - c).dot(&dir)).norm()).fold(0.0, f64::max);
        println!("roll={roll}: energy {e0:.3e} -> {:.3e} (max {emax:.3e}), off-line {:.2e} L", total_energy(&w, h), dev / l);
        assert!(dev <= 1e-2 * l, "roll={roll}: the free straight rod bent by {dev:e}");
    }
}

/// A straight rod clamped at one end (SPEC §10 cantilever) with no load:
/// `relax()` converges and leaves it unchanged (1e-9 L).
#[test]
fn unloaded_cantilever_relaxes_to_itself() {
    let mut c = common::cantilever(20, 5, [0.0; 3]);
    let q0 = c.world.rod(c.rod).unwrap().coords().to_vec();
    c.world.relax().expect("relax of an unloaded cantilever");
    let q = c.world.rod(c.rod).unwrap().coords();
    let dq = max_abs(&q.iter().zip(&q0).map(|(a, b)| a - b).collect::<Vec<_>>());
    assert!(dq <= 1e-9 * 4.0, "unloaded cantilever moved by {dq:e}");
}
