//! Poisson contraction of the section (II.59, `RodOptions::poisson_update`):
//! a bar stretched by ε thins to R⁰(1 − νε), its axial force follows the
//! thinner section, and it gets R⁰ back when released.
use strandkit::prelude::*;
use nalgebra::Vector3;

#[test]
fn stretched_bar_thins_by_nu_epsilon_and_recovers() {
    let (r0, nu, e_mod, eps) = (0.01, 0.45, 1e6, 0.05);
    let rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0))
        .control_points(8)
        .with_roll(false)
        .section(Section::circle(r0).unwrap())
        .material(Material::new("rubber", e_mod, nu, 1000.0).unwrap())
        .options(RodOptions { poisson_update: true, ..Default::default() })
        .build()
        .unwrap();
    let (u0, u1) = rod.domain();
    let mass0 = rod.mass();
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(rod);
    let pos = |u: f64, x: f64| ConstraintKind::Position(Position { u, axes: [true, true, true, false], target: [x, 0.0, 0.0, 0.0] });
    w.add_constraint(h, pos(u0, 0.0), 0.0).unwrap();
    w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    let end = w.add_constraint(h, pos(u1, 1.0 + eps), 0.0).unwrap();
    w.relax().unwrap();
    w.relax().unwrap(); // the force of the thinned section
    let rod = w.rod(h).unwrap();
    let want = r0 * (1.0 - nu * eps);
    for s in rod.sections() {
        let Section::Circle { radius } = s else { unreachable!() };
        assert!((radius - want).abs() < 1e-9 * r0, "radius {radius} vs {want}");
    }
    let f = w.reaction(end).unwrap().force[0]; // the end constraint pulls the bar along +x
    let expected = e_mod * std::f64::consts::PI * want * want * eps;
    println!("R = {want:.6e} m (R0 {r0}), axial force {f:.6} N vs E A(ε) ε = {expected:.6} N, mass {} vs {mass0}", rod.mass());
    assert!((f - expected).abs() < 1e-6 * expected);
    assert_eq!(rod.mass(), mass0, "mass is conserved");
    // Released (end pinned back at the rest length): R⁰ again.
    w.set_constraint(end, pos(u1, 1.0)).unwrap();
    w.relax().unwrap();
    for s in w.rod(h).unwrap().sections() {
        let Section::Circle { radius } = s else { unreachable!() };
        assert!((radius - r0).abs() < 1e-12, "radius {radius} after release");
    }
}
