//! Twist, writhe, link and the material frame (issue 11, accessors):
//! Călugăreanu–White–Fuller on closed curves, an imposed excess link on a
//! ring against its closed-form twist energy, the opened ring keeping its
//! twist, and the Frenet material frame of a helix against the analytic one.
use nalgebra::Vector3;
use std::f64::consts::PI;
use strandkit::prelude::*;
use strandkit::Cut;
use strandkit::spline::KnotKind;

fn material() -> Material {
    Material::new("m", 1e7, 0.5, 1000.0).unwrap()
}

/// A closed rod through `f(φ)`, φ ∈ [0, 2π), with `n` control points.
fn ring(n: usize, roll: bool, f: impl Fn(f64) -> Vector3<f64> + Send + Sync + 'static) -> Rod {
    RodBuilder::curve(1.0, move |s| f(2.0 * PI * s))
        .knots(KnotKind::Periodic)
        .control_points(n)
        .with_roll(roll)
        .section(Section::circle(0.005).unwrap())
        .material(material())
        .options(frenet())
        .build()
        .unwrap()
}

/// These checks are of the Frenet model's twist (the Frenet ribbon's) and
/// material frame; the reference model's link and twist are checked in
/// `tests/reference_twist.rs`.
fn frenet() -> RodOptions {
    RodOptions { model: FrameModel::Frenet, ..Default::default() }
}

fn circle(n: usize, roll: bool) -> Rod {
    ring(n, roll, |p| Vector3::new(p.cos(), p.sin(), 0.0) / (2.0 * PI))
}

/// Călugăreanu–White–Fuller: for a closed curve without inflection the
/// Frenet ribbon's link Tw + Wr is an integer. Checked on curves whose twist
/// and writhe are each far from integers (a tilted ring, a three-lobed
/// curve, a toroidal helix, a trefoil (2,3) torus knot) — the two computations are
/// independent (one a single integral of the torsion, the other the Gauss
/// double integral), so their sum landing on an integer tests both.
#[test]
fn twist_plus_writhe_is_an_integer_on_closed_curves() {
    let curves: Vec<(&str, Box<dyn Fn(f64) -> Vector3<f64> + Send + Sync>)> = vec![
        ("tilted ring", Box::new(|p: f64| Vector3::new(p.cos(), p.sin() + 0.3 * (2.0 * p).sin(), 0.6 * (2.0 * p).sin() + 0.3 * p.cos()))),
        ("three-lobed", Box::new(|p: f64| Vector3::new(p.cos() + 0.4 * (2.0 * p).cos(), p.sin() - 0.4 * (2.0 * p).sin(), 0.5 * (3.0 * p).sin()))),
        ("toroidal helix", Box::new(|p: f64| Vector3::new((1.0 + 0.3 * (5.0 * p).cos()) * p.cos(), (1.0 + 0.3 * (5.0 * p).cos()) * p.sin(), 0.3 * (5.0 * p).sin()))),
        ("trefoil", Box::new(|p: f64| Vector3::new((2.0 + (3.0 * p).cos()) * (2.0 * p).cos(), (2.0 + (3.0 * p).cos()) * (2.0 * p).sin(), (3.0 * p).sin()))),
    ];
    for (name, f) in curves {
        let rod = ring(320, true, f);
        let (tw, wr) = (rod.twist().unwrap(), rod.writhe().unwrap());
        let lk = tw + wr;
        println!("{name}: Tw {tw:.9} Wr {wr:.9} Lk {lk:.9}");
        // The quadrature converges at second order (the toroidal helix:
        // 1.3e-5 turns off at 160 control points, 3.2e-6 at 320).
        assert!((lk - lk.round()).abs() < 1e-5, "{name}: Tw + Wr = {lk}");
        assert!(wr.abs() > 0.01 && (tw - tw.round()).abs() > 0.01, "{name}: the check needs non-trivial values");
    }
    // A planar ring: no writhe, no twist.
    let flat = circle(40, true);
    assert!(flat.writhe().unwrap().abs() < 1e-12 && flat.twist().unwrap().abs() < 1e-12);
}

/// An excess link ΔLk imposed on a circular ring: twist = ΔLk turns, the
/// link too, and the twist energy is ½ GJ (2π ΔLk / L)² L (closed form;
/// the rest shape carries no other energy). A snapshot keeps it.
#[test]
fn an_imposed_excess_link_twists_the_ring() {
    let mut rod = circle(40, true);
    assert!(rod.elastic_energy() < 1e-15);
    let dlk = 1.5;
    rod.set_excess_link(dlk).unwrap();
    let gj = material().shear_modulus() * PI * 0.005f64.powi(4) / 2.0;
    let l = rod.rest_length();
    let expected = 0.5 * gj * (2.0 * PI * dlk / l).powi(2) * l;
    let e = rod.elastic_energy();
    println!("energy {e:.12e} vs ½GJ(2πΔLk/L)²L = {expected:.12e}");
    assert!((e - expected).abs() < 1e-12 * expected);
    assert!((rod.twist().unwrap() - dlk).abs() < 1e-12 && (rod.link().unwrap() - dlk).abs() < 1e-12);
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(rod);
    let back = World::from_json(&w.to_json().unwrap()).unwrap();
    assert_eq!(back.rod(h).unwrap().excess_link(), dlk);
    assert_eq!(back.rod(h).unwrap().elastic_energy(), w.rod(h).unwrap().elastic_energy());
}

/// Cutting a ring with an excess link opens it into a rod that keeps the
/// link's rest-twist shift (as a plastic ω offset): the cut changes no
/// energy. (Its free ends then let θ unwind the twist; the Frenet model's
/// dynamics of an open, curved, twisted rod is rough — issue 14's model.)
#[test]
fn an_opened_ring_keeps_its_twist_in_the_roll() {
    let mut rod = circle(40, true);
    rod.set_excess_link(2.0).unwrap();
    let e = rod.elastic_energy();
    let (a, b) = rod.domain();
    let Cut::Opened(open) = rod.cut_at(a + 0.3 * (b - a)).unwrap() else { panic!("a ring opens into one rod") };
    assert_eq!(open.excess_link(), 0.0);
    let e_open = open.elastic_energy();
    println!("ring {e:.12e}, opened {e_open:.12e}");
    assert!((e_open - e).abs() < 1e-9 * e);
}

/// Bad input for the link accessors: open rods, rods without roll,
/// non-finite turns — typed errors, the rod unchanged.
#[test]
fn excess_link_refuses_what_it_cannot_mean() {
    let mut open = RodBuilder::straight(Vector3::zeros(), Vector3::x()).control_points(6).section(Section::circle(0.01).unwrap()).material(material()).build().unwrap();
    assert!(matches!(open.set_excess_link(1.0), Err(Error::InvalidInput { .. })));
    assert!(matches!(open.writhe(), Err(Error::InvalidInput { .. })));
    let mut no_roll = circle(20, false);
    assert!(matches!(no_roll.set_excess_link(1.0), Err(Error::InvalidInput { .. })));
    let mut r = circle(20, true);
    assert!(matches!(r.set_excess_link(f64::NAN), Err(Error::InvalidInput { .. })));
    assert_eq!(r.excess_link(), 0.0);
    // A ring with an inflection has no Frenet twist.
    let eight = ring(80, true, |p| Vector3::new(p.sin(), (2.0 * p).sin() * 0.5, 0.0));
    assert!(matches!(eight.twist(), Err(Error::Singular { .. })));
}

/// The Frenet model's material frame on a helix r = (a cos t, a sin t, b t)
/// with uniform roll θ = c: d3 = T, d1 = cos c N + sin c B, d2 = d3 × d1,
/// with N = (−cos t, −sin t, 0) and B = (b sin t, −b cos t, a)/√(a² + b²)
/// (to the spline's fit error); orthonormal to round-off; and undefined on
/// a straight rod (a typed error).
#[test]
fn material_frame_of_a_helix_is_the_rolled_frenet_frame() {
    let (a, pitch, turns, c) = (0.1, 0.05, 2.0, 0.4);
    let b = pitch / (2.0 * PI);
    let n = 60;
    let rod = RodBuilder::helix(a, pitch, turns)
        .control_points(n)
        .with_roll(true)
        .roll(vec![c; n])
        .section(Section::circle(0.005).unwrap())
        .material(material())
        .options(frenet())
        .build()
        .unwrap();
    let (u0, u1) = rod.domain();
    let mut worst: f64 = 0.0;
    for k in 1..20 {
        let u = u0 + (u1 - u0) * k as f64 / 20.0;
        let p = rod.position(u).unwrap();
        let t = p.y.atan2(p.x);
        let s = (a * a + b * b).sqrt();
        let (tt, nn, bb) = (
            Vector3::new(-a * t.sin(), a * t.cos(), b) / s,
            Vector3::new(-t.cos(), -t.sin(), 0.0),
            Vector3::new(b * t.sin(), -b * t.cos(), a) / s,
        );
        let f = rod.material_frame(u).unwrap();
        let d1 = nn * c.cos() + bb * c.sin();
        worst = worst.max((f.d3 - tt).norm()).max((f.d1 - d1).norm()).max((f.d2 - tt.cross(&d1)).norm());
        for (x, y, want) in [(f.d1, f.d1, 1.0), (f.d2, f.d2, 1.0), (f.d3, f.d3, 1.0), (f.d1, f.d2, 0.0), (f.d1, f.d3, 0.0)] {
            assert!((x.dot(&y) - want).abs() < 1e-14);
        }
        assert!((f.d1.cross(&f.d2) - f.d3).norm() < 1e-14);
    }
    println!("helix material frame: worst director error {worst:.2e}");
    assert!(worst < 1e-4, "{worst}");
    let straight = RodBuilder::straight(Vector3::zeros(), Vector3::x()).control_points(6).with_roll(true).section(Section::circle(0.01).unwrap()).material(material()).options(frenet()).build().unwrap();
    assert!(matches!(straight.material_frame(0.5 * (straight.domain().0 + straight.domain().1)), Err(Error::Singular { .. })));
}

