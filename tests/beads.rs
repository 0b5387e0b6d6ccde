//! Beads (sliding-abscissa particles, SPEC §4 and §9.4).
use nalgebra::Vector3;
use strandkit::*;

/// A light, nearly inextensible string (EA = 1e4 N, 4.5e-7 kg/m) of length
/// `len` between (0,0,0) and (span,0,0), started from a sagging arc. Its
/// bending stiffness EI = `ei` gives the corner under a bead a boundary
/// layer √(EI/T) that the control points must resolve: a spline cannot form
/// the kink of a perfectly flexible string.
fn string(world: &mut World, len: f64, span: f64, n: usize, ei: f64) -> RodHandle {
    let r = (4.0 * ei / 1e4f64).sqrt();
    let e = 1e4 / (std::f64::consts::PI * r * r);
    let mut rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(len, 0.0, 0.0))
        .control_points(n)
        .with_roll(false)
        .section(Section::circle(r).unwrap())
        .material(Material::new("string", e, 0.3, 1.0).unwrap())
        .build()
        .unwrap();
    let q: Vec<f64> = rod
        .coords()
        .chunks(3)
        .flat_map(|p| {
            let s = p[0] / len;
            [s * span, -0.3 * (std::f64::consts::PI * s).sin(), 0.0]
        })
        .collect();
    rod.set_coords(&q).unwrap();
    world.add_rod(rod)
}

/// SPEC §9.4: one frictionless bead (m = 0.1 kg) on a light inextensible
/// string of length 1.2 m between supports 1 m apart at equal height: both
/// halves at θ = 56.44° from the vertical, sag 0.3317 m, tension 0.887 N
/// (within 1 %). The string's bending boundary layer √(EI/T) = 5 mm rounds
/// the corner under the bead over ~3 control-point spacings (with 2 cm the
/// rounding shortened the effective string by 1.3 cm: θ 55.5°, T 0.866 N).
#[test]
fn bead_on_a_string_matches_the_reference() {
    // ~500 damped Newton iterations: the string is nearly a mechanism.
    let params = IntegrationParameters { gravity: [0.0, -9.81, 0.0], relax_max_iterations: 3000, ..Default::default() };
    let mut w = World::new(params);
    let h = string(&mut w, 1.2, 1.0, 721, 2.2e-5);
    let (u0, u1) = w.rod(h).unwrap().domain();
    let xyz = [true, true, true, false];
    let a = w.add_constraint(h, ConstraintKind::Position { u: u0, axes: xyz, target: [0.0; 4] }, 0.0).unwrap();
    let b = w.add_constraint(h, ConstraintKind::Position { u: u1, axes: xyz, target: [1.0, 0.0, 0.0, 0.0] }, 0.0).unwrap();
    // Off-centre start: the bead must find the middle by itself.
    let bead = w.add_bead(h, u0 + 0.4 * (u1 - u0), 0.1, 0.0, 0.0).unwrap();
    let rep = w.relax().unwrap();
    let p = w.bead_position(bead).unwrap();
    let (fa, fb) = (Vector3::from(w.reaction(a).unwrap().force), Vector3::from(w.reaction(b).unwrap().force));
    let theta = (fa.x.abs()).atan2(fa.y.abs()).to_degrees();
    let (sag, t) = (-p.y, fa.norm());
    println!("bead at {p:?}: θ = {theta:.3}° (56.44), sag {sag:.4} (0.3317), T {t:.4} | {:.4} N (0.887); {} iterations", fb.norm(), rep.iterations);
    assert!((theta - 56.44).abs() < 0.01 * 56.44);
    assert!((sag - 0.3317).abs() < 0.01 * 0.3317);
    assert!((t - 0.887).abs() < 0.01 * 0.887 && (fb.norm() - 0.887).abs() < 0.01 * 0.887);
    assert!((p.x - 0.5).abs() < 1e-3, "the bead sits in the middle");
}
