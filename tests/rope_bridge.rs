//! Rope bridge builder (issue 12, SPEC §9.2) against closed forms: the
//! funicular polygon of equal plank loads (nodes on the parabola
//! y = −4d x(S−x)/S², Σ H = w S²/(8d)), the catenary of a bare rope
//! (sag and end tension), and a plank breaking once under a walker.
use nalgebra::Vector3;
use strandkit::prelude::*;
use strandkit::Event;
use strandkit_builders::curves::Catenary;
use strandkit_builders::{rope_bridge, PlankModel, Rope, RopeBridge};

const G: f64 = 9.81;

fn world() -> World {
    World::new(IntegrationParameters { gravity: [0.0, -G, 0.0], relax_max_iterations: 500, ..Default::default() })
}

/// A light (1 g/m), stiff (EA = 1e9 N), flexible (EI = 1e-4 N·m²) rope
/// carrying 9 planks of 5 kg: the floor ropes' stations lie on the
/// parabola of sag d within 0.1 % of d, and the ropes' horizontal tensions
/// add up to w S²/(8d), w = m g / Δ, within 0.1 %. Both plank models.
/// The exact shape has a kink at each plank, which a cubic spline rounds
/// over ~2 control-point spacings: the error falls at first order (Body
/// model: 4.5e-3 d at 80 control points per rope, 2.2e-3 at 160, 5.6e-4
/// at 320, 3.2e-4 at 480), hence 480 here.
#[test]
fn planks_hang_the_floor_on_the_parabola() {
    for model in [PlankModel::Body, PlankModel::Link] {
        let p = RopeBridge {
            span: 10.0,
            n_planks: 9,
            plank_mass: 5.0,
            sag: 1.0,
            rope: Rope { linear_density: 1e-3, axial_stiffness: 1e9, bending_stiffness: 1e-4 },
            plank_model: model,
            handrail_height: 0.0,
            rope_control_points: Some(480),
            ..Default::default()
        };
        let (asm, layout) = rope_bridge(&p).unwrap();
        let mut w = world();
        let ins = w.insert(&asm).unwrap();
        let rep = w.relax().unwrap();
        let floor = ins.rods[layout.ropes[0]];
        let mut worst: f64 = 0.0;
        for &u in &layout.stations {
            let x = w.rod(floor).unwrap().position(u).unwrap();
            let y = -4.0 * p.sag * x.x * (p.span - x.x) / (p.span * p.span);
            worst = worst.max((x.y - y).abs() / p.sag);
        }
        let spacing = p.span / (p.n_planks + 1) as f64;
        let w_line = p.plank_mass * G / spacing;
        let h_expected = w_line * p.span * p.span / (8.0 * p.sag);
        let anchors = w.group_constraints("anchor").unwrap();
        // Each rope's end anchors pull its ends outwards: H is the x-reaction.
        let h_total: f64 = anchors.iter().filter(|a| a.label.ends_with(",0]")).map(|a| a.force[0].abs()).sum();
        println!("{model:?}: {} iterations; worst station off the parabola {worst:.2e} d; ΣH {h_total:.3} N vs wS²/8d {h_expected:.3} N", rep.iterations);
        assert!(worst < 1e-3, "{model:?}: station off by {worst} d");
        assert!((h_total / h_expected - 1.0).abs() < 1e-3, "{model:?}: ΣH {h_total} vs {h_expected}");
    }
}

/// A bridge without planks or handrails is two bare ropes: each hangs on
/// the catenary (SPEC §10 scene: span 1 m, length 1.2 m, 1 N/m). Sag and
/// end tension within 0.1 % of the exact catenary (a = 0.46954 m; sag
/// off by 1.2e-3 at 40 control points, 2e-5 at 80).
#[test]
fn a_bare_rope_is_the_catenary() {
    let exact = Catenary::with_length(1.0, 1.2).unwrap();
    let p = RopeBridge {
        span: 1.0,
        n_planks: 0,
        sag: exact.sag(),
        handrail_height: 0.0,
        rope: Rope { linear_density: 1.0 / G, axial_stiffness: 1e7, bending_stiffness: 1e-6 },
        rope_control_points: Some(80),
        ..Default::default()
    };
    let (asm, layout) = rope_bridge(&p).unwrap();
    assert!((asm.rods[0].rod.rest_length() - 1.2).abs() < 1e-9);
    let mut w = world();
    let ins = w.insert(&asm).unwrap();
    w.relax().unwrap();
    let rope = w.rod(ins.rods[layout.ropes[0]]).unwrap();
    let (u0, u1) = rope.domain();
    let sag = -rope.position(0.5 * (u0 + u1)).unwrap().y;
    let t_end = Vector3::from(w.group_constraints("anchor").unwrap()[0].force).norm();
    let t_exact = exact.a * (0.5 / exact.a).cosh(); // w a cosh(S/2a), w = 1 N/m
    println!("a = {:.6} m; sag {sag:.6} vs {:.6}; end tension {t_end:.6} vs {t_exact:.6}", exact.a, exact.sag());
    assert!((sag / exact.sag() - 1.0).abs() < 1e-3);
    assert!((t_end / t_exact - 1.0).abs() < 1e-3);
}

/// A walker's weight ramped up on plank 4: its pins break once each, at the
/// first step whose reaction passes the break force (the step before was
/// below it), with events naming "plank[4]"; no other plank breaks, and
/// the world keeps stepping.
#[test]
fn a_plank_breaks_once_when_its_force_passes_the_threshold() {
    let p = RopeBridge { plank_break_force: Some(300.0), ..Default::default() };
    let (asm, layout) = rope_bridge(&p).unwrap();
    let mut w = world();
    w.params.dt = 1e-3;
    let ins = w.insert(&asm).unwrap();
    w.relax().unwrap();
    let plank = ins.rods[layout.planks[4]];
    let (a, b) = w.rod(plank).unwrap().domain();
    let load = w.add_load(Load::PointForce(PointForce { rod: plank, u: 0.5 * (a + b), force: [0.0; 3] })).unwrap();
    let mut last: Vec<f64> = Vec::new();
    let mut breaks = Vec::new();
    for k in 0..400 {
        let f = -2000.0 * (k as f64 + 1.0) * w.params.dt; // 2 kN/s
        w.set_load(load, Load::PointForce(PointForce { rod: plank, u: 0.5 * (a + b), force: [0.0, f, 0.0] })).unwrap();
        let rep = w.step().unwrap();
        for e in &rep.events {
            if let Event::ConstraintBroken { label, force, .. } = e {
                breaks.push((k, label.clone(), *force, last.clone()));
            }
        }
        last = w.group_constraints("plank[4]").unwrap().iter().map(|s| Vector3::from(s.force).norm()).collect();
    }
    assert!(!breaks.is_empty(), "plank 4 never broke");
    for (k, label, force, before) in &breaks {
        println!("step {k}: {label:?} broke at {force:.1} N (pins before: {before:?})");
        assert_eq!(label.as_deref(), Some("plank[4]"));
        assert!(*force >= 300.0);
        assert!(before.iter().all(|&f| f < 300.0), "a pin was above the threshold a step earlier: {before:?}");
    }
    assert!(breaks.len() <= 2, "each pin breaks once");
    let states = w.group_constraints("plank").unwrap();
    assert!(states.iter().filter(|s| s.broken.is_some()).all(|s| s.label == "plank[4]"));
}

/// Bad input: a clear error naming the argument, nothing built.
#[test]
fn bad_bridges_are_refused() {
    let bad = |p: RopeBridge, what: &str| {
        let e = rope_bridge(&p).expect_err(what);
        assert!(e.to_string().contains(what), "{what}: {e}");
    };
    bad(RopeBridge { span: -1.0, ..Default::default() }, "span");
    bad(RopeBridge { sag: 0.0, ..Default::default() }, "sag");
    bad(RopeBridge { plank_mass: f64::NAN, ..Default::default() }, "plank_mass");
    bad(RopeBridge { n_planks: 60, ..Default::default() }, "n_planks");
    bad(RopeBridge { n_planks: 1 << 40, ..Default::default() }, "n_planks");
    bad(RopeBridge { rope: Rope { linear_density: -1.0, ..Default::default() }, ..Default::default() }, "linear_density");
    bad(RopeBridge { plank_break_force: Some(0.0), ..Default::default() }, "plank_break_force");
    bad(RopeBridge { width: f64::INFINITY, ..Default::default() }, "width");
}
