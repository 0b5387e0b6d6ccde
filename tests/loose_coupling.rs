//! Loose coupling with an external mechanical model (III.A.5.b): solve the
//! constrained rods, hand the multipliers to the other model as forces, let
//! it move, feed its motion back as the constraint target. Here the other
//! model is a linear spring (stiffness k_e) holding the tip of a loaded
//! cantilever; the coupled iteration converges to the monolithic run (the
//! same rod with the spring inside the solve as a compliant constraint,
//! C = 1/k_e), and both to linear theory y_tip = −F / (3EI/L³ + k_e).
use strandkit::prelude::*;
use nalgebra::Vector3;

#[test]
fn four_step_protocol_converges_to_the_coupled_equilibrium() {
    let rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0))
        .control_points(12)
        .section(Section::circle(0.01).unwrap())
        .material(Material::new("steel", 200e9, 0.3, 7800.0).unwrap())
        .build()
        .unwrap();
    let ei = 200e9 * std::f64::consts::PI * 1e-8 / 4.0;
    let k_beam = 3.0 * ei; // L = 1
    let k_e = 0.5 * k_beam;
    let f = 20.0;
    let mut w = World::new(IntegrationParameters::default());
    let rest = rod.coords().to_vec();
    let h = w.add_rod(rod);
    let (u0, u1) = w.rod(h).unwrap().domain();
    w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true; 4], target: [0.0; 4] }), 0.0).unwrap();
    w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    w.add_load(Load::PointForce(PointForce { rod: h, u: u1, force: [0.0, -f, 0.0] })).unwrap();
    let tip = |y: f64| ConstraintKind::Position(Position { u: u1, axes: [false, true, false, false], target: [0.0, y, 0.0, 0.0] });
    let link = w.add_constraint(h, tip(0.0), 0.0).unwrap();
    let mut y_e = 0.0; // the external model's attachment point
    for it in 0..60 {
        // 1. solve the constrained rod; 2. multiplier out: the rod pulls the
        // external point with −Λ; 3. the external spring moves to balance
        // it; 4. imposed motion in. The exchange map has slope −k_beam/k_e
        // (−2 here), so it needs under-relaxation ω < 2/(1 + k_beam/k_e):
        // ω = 0.3 contracts by 0.1 per exchange (ω = 0.7 diverges).
        w.relax().unwrap();
        let lam = w.reaction(link).unwrap().force[1];
        let y_new = -lam / k_e;
        let step = 0.3 * (y_new - y_e);
        y_e += step;
        w.set_constraint(link, tip(y_e)).unwrap();
        if step.abs() < 1e-13 {
            println!("converged after {it} exchanges");
            break;
        }
    }
    w.relax().unwrap();
    let y = w.rod(h).unwrap().position(u1).unwrap().y;
    // The monolithic run: the spring as a compliant tip constraint.
    let mut m = World::new(IntegrationParameters::default());
    let hm = m.add_rod(w.rod(h).unwrap().clone());
    m.rod_mut(hm).unwrap().set_coords(&rest).unwrap();
    m.add_constraint(hm, ConstraintKind::Position(Position { u: u0, axes: [true; 4], target: [0.0; 4] }), 0.0).unwrap();
    m.add_constraint(hm, ConstraintKind::Tangent(Tangent { u: u0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    m.add_load(Load::PointForce(PointForce { rod: hm, u: u1, force: [0.0, -f, 0.0] })).unwrap();
    m.add_constraint(hm, tip(0.0), 1.0 / k_e).unwrap();
    m.relax().unwrap();
    let monolithic = m.rod(hm).unwrap().position(u1).unwrap().y;
    let linear = -f / (k_beam + k_e);
    println!("coupled tip {y:.9e}, monolithic {monolithic:.9e}, linear theory {linear:.6e}");
    assert!((y - monolithic).abs() < 1e-8 * monolithic.abs(), "coupled vs monolithic");
    assert!((monolithic - linear).abs() < 2e-3 * linear.abs(), "monolithic vs linear theory");
}
