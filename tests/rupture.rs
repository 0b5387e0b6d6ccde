//! Material rupture (SPEC §6, thesis II.C.2.b, algorithms 2–3): the rod is
//! cut by a knot of multiplicity 4 at its most strained sample; the pieces
//! reproduce the pre-rupture rod exactly and then move independently;
//! constraints and beads follow the piece holding their abscissa.
use strandkit::prelude::*;
use nalgebra::Vector3;
use strandkit::material::StrainLimits;
use strandkit::spline::KnotKind;
use strandkit::*;

const INF: (f64, f64) = (f64::NEG_INFINITY, f64::INFINITY);

/// Max over a fine grid of |piece(u) − rod(u)| (positions, roll, velocities).
fn max_mismatch(rod: &Rod, piece_at: impl Fn(f64) -> (Vec<f64>, Vector3<f64>)) -> f64 {
    let (a, b) = rod.domain();
    let mut worst = 0.0f64;
    for k in 0..=1000 {
        let u = a + (b - a) * k as f64 / 1000.0;
        let (q, v) = piece_at(u);
        let q0 = rod.eval(u, 0).unwrap();
        worst = worst.max((0..rod.dofs()).map(|i| (q[i] - q0[i]).abs()).fold(0.0, f64::max));
        worst = worst.max((v - rod.eval_velocity(u).unwrap()).norm());
    }
    worst
}

fn deformed_helix_in(knots: KnotKind, model: strandkit::energy::FrameModel) -> Rod {
    let mut rod = RodBuilder::helix(0.1, 0.05, 1.5)
        .control_points(24)
        .knots(knots)
        .sections((0..24).map(|i| Section::ellipse(0.004 + 0.0001 * i as f64, 0.003).unwrap()).collect())
        .material(Material::preset("nylon").unwrap())
        .options(RodOptions { model, ..Default::default() })
        .build()
        .unwrap();
    let q: Vec<f64> = rod.coords().iter().enumerate().map(|(i, x)| x + 0.01 * ((i * 7 % 11) as f64 / 11.0 - 0.5)).collect();
    let v: Vec<f64> = (0..q.len()).map(|i| (i * 5 % 13) as f64 / 13.0 - 0.5).collect();
    rod.set_coords(&q).unwrap();
    rod.set_velocities(&v).unwrap();
    rod
}

#[test]
fn cut_pieces_reproduce_the_rod_exactly() {
    cut_open(strandkit::energy::FrameModel::Frenet);
}

/// The reference model: the pieces take the parent's directors and the
/// rest values measured in the parent's rest directors (a helix of
/// elliptic section has rest curvature and twist in both directions), so
/// the cut changes the energy only through the two cut segments' quadrature.
#[test]
fn cut_pieces_reproduce_the_rod_exactly_reference_model() {
    cut_open(strandkit::energy::FrameModel::Reference);
}

fn cut_open(model: strandkit::energy::FrameModel) {
    let rod = deformed_helix_in(KnotKind::Clamped, model);
    let (a, b) = rod.domain();
    let uc = a + 0.37 * (b - a);
    let Cut::Two(p) = rod.cut_at(uc).unwrap() else { panic!("an open rod gives two pieces") };
    let [left, right] = *p;
    assert_eq!(left.domain(), (a, uc));
    assert_eq!(right.domain(), (uc, b));
    let worst = max_mismatch(&rod, |u| {
        let piece = if u <= uc { &left } else { &right };
        (piece.eval(u, 0).unwrap().to_vec(), piece.eval_velocity(u).unwrap())
    });
    println!("open cut: max |piece − rod| over q, θ, v: {worst:.2e}");
    assert!(worst < 1e-12);
    // Rest state and sections carried over: same rest length, same energy
    // density at the unchanged samples.
    let total = left.rest_length() + right.rest_length();
    assert!((total - rod.rest_length()).abs() < 1e-12 * rod.rest_length());
    let e = left.elastic_energy() + right.elastic_energy();
    println!("elastic energy {:.9e} J before, {e:.9e} J after (quadrature of the two cut segments differs)", rod.elastic_energy());
    assert!((e - rod.elastic_energy()).abs() < 1e-3 * rod.elastic_energy());
}

#[test]
fn cut_ring_opens_into_one_rod() {
    let rod = RodBuilder::curve(1.0, |s| {
        let t = 2.0 * std::f64::consts::PI * s;
        Vector3::new(t.cos(), t.sin(), 0.1 * (2.0 * t).sin()) / (2.0 * std::f64::consts::PI)
    })
    .control_points(16)
    .knots(KnotKind::Periodic)
    .section(Section::circle(0.002).unwrap())
    .material(Material::preset("nylon").unwrap())
    .build()
    .unwrap();
    let uc = 5.3;
    let Cut::Opened(open) = rod.cut_at(uc).unwrap() else { panic!("a ring opens into one rod") };
    let n = rod.n_ctrl() as f64;
    let worst = max_mismatch(&rod, |u| {
        let s = (u - uc).rem_euclid(n).min(open.domain().1);
        (open.eval(s, 0).unwrap().to_vec(), open.eval_velocity(s).unwrap())
    });
    println!("ring opened at u = {uc}: max mismatch {worst:.2e}, rest length {} vs {}", open.rest_length(), rod.rest_length());
    assert!(worst < 1e-12);
    assert!((open.rest_length() - rod.rest_length()).abs() < 1e-9);
}

/// A rubber strand with a thin spot, clamped at one end and pulled at the
/// other until it breaks.
fn pulled_strand() -> (World, RodHandle, ConstraintHandle, BeadHandle, BeadHandle) {
    let n = 20;
    let m = Material::new("rubber", 1e6, 0.45, 1000.0)
        .unwrap()
        .with_rupture(StrainLimits { stretch: (-0.5, 0.05), bend: INF, twist: INF })
        .unwrap();
    let sections = (0..n).map(|i| Section::circle(if i == 12 { 0.008 } else { 0.01 }).unwrap()).collect();
    let rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0))
        .control_points(n)
        .with_roll(false)
        .sections(sections)
        .material(m)
        .options(RodOptions { drag: 20.0, ..Default::default() })
        .build()
        .unwrap();
    let (u0, u1) = rod.domain();
    let mut w = World::new(IntegrationParameters { parallel: false, ..Default::default() });
    let h = w.add_rod(rod);
    w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true, true, true, false], target: [0.0; 4] }), 0.0).unwrap();
    w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    let end = w
        .add_constraint(h, ConstraintKind::Position(Position { u: u1, axes: [true, true, true, false], target: [1.0, 0.0, 0.0, 0.0] }), 0.0)
        .unwrap();
    let left = w.add_bead(h, u0 + 0.25 * (u1 - u0), 0.001, 0.0, 0.0).unwrap();
    let right = w.add_bead(h, u0 + 0.85 * (u1 - u0), 0.001, 0.0, 0.0).unwrap();
    (w, h, end, left, right)
}

#[test]
fn pulled_past_rupture_splits_at_the_most_strained_sample() {
    let (mut w, h, end, left_bead, right_bead) = pulled_strand();
    let u1 = w.rod(h).unwrap().domain().1;
    let speed = 0.5; // m/s
    let mut rupture = None;
    for k in 1..=400 {
        let before = w.clone();
        let x = 1.0 + speed * w.params.dt * k as f64;
        w.set_constraint(end, ConstraintKind::Position(Position { u: u1, axes: [true, true, true, false], target: [x, 0.0, 0.0, 0.0] })).unwrap();
        let report = w.step().unwrap();
        if let Some(e) = report.events.iter().find(|e| matches!(e, Event::RodRuptured { .. })) {
            rupture = Some((before, x, e.clone()));
            break;
        }
    }
    let (before, x, event) = rupture.expect("the strand never broke");
    let Event::RodRuptured { rod, new_rod, u, mode, strain, limit, .. } = event else { unreachable!() };
    let new_rod = new_rod.expect("an open rod breaks in two");
    assert_eq!(rod, h);
    assert_eq!(mode, StrainMode::Stretch);
    assert!(strain > limit && limit == 0.05);
    // The same step without rupture limits gives the pre-rupture state.
    let mut reference = before;
    reference.rod_mut(h).unwrap().set_strain_limits(None, None).unwrap();
    reference.set_constraint(end, ConstraintKind::Position(Position { u: u1, axes: [true, true, true, false], target: [x, 0.0, 0.0, 0.0] })).unwrap();
    reference.step().unwrap();
    let ref_rod = reference.rod(h).unwrap();
    let strains = ref_rod.relative_strains();
    let worst = strains.iter().enumerate().max_by(|a, b| a.1.eps.total_cmp(&b.1.eps)).unwrap();
    assert_eq!(ref_rod.sample_params()[worst.0], u, "cut at the most strained sample");
    println!("broke at x = {x:.4} m, u = {u:.4} (most strained sample, ε = {:.4} > 0.05)", worst.1.eps);
    let (a, b) = (w.rod(h).unwrap(), w.rod(new_rod).unwrap());
    let mismatch = max_mismatch(ref_rod, |s| {
        let piece = if s <= u { a } else { b };
        (piece.eval(s, 0).unwrap().to_vec(), piece.eval_velocity(s).unwrap())
    });
    println!("pieces vs pre-rupture rod: {mismatch:.2e} m");
    assert!(mismatch < 1e-12);
    // Attachments follow their abscissa.
    assert_eq!(w.constraint(end).unwrap().rod, new_rod);
    assert_eq!(w.bead(left_bead).unwrap().rod, h);
    assert_eq!(w.bead(right_bead).unwrap().rod, new_rod);
    // Afterwards the pieces move apart: the clamped piece retracts.
    for _ in 0..300 {
        w.step().unwrap();
    }
    let (a, b) = (w.rod(h).unwrap(), w.rod(new_rod).unwrap());
    let gap = (b.position(u).unwrap() - a.position(u).unwrap()).norm();
    let a_strain = a.relative_strains().iter().map(|s| s.eps.abs()).fold(0.0, f64::max);
    println!("after 300 steps: gap at the cut {gap:.4} m, max strain of the clamped piece {a_strain:.2e}");
    assert!(gap > 0.02);
    assert!(a_strain < 0.01);
}

/// A ring (sliding point) just left of the thin spot: after the rupture the
/// clamped piece retracts through it, and the slider that falls off its
/// piece is reported.
#[test]
fn slider_falling_off_a_broken_piece_is_reported() {
    let (mut w, h, end, _, _) = pulled_strand();
    let rod = w.rod(h).unwrap();
    let (u0, u1) = rod.domain();
    // The strand breaks at u ≈ 11.05 (thin control point 12 of 20), about
    // 4 % stretched; the ring sits 5 mm beyond where that point is at rest,
    // so the clamped piece, relaxing to its rest length, slides out of it.
    let at = |x: f64| {
        let (mut a, mut b) = (u0, u1);
        for _ in 0..100 {
            let m = 0.5 * (a + b);
            if rod.position(m).unwrap().x < x { a = m } else { b = m }
        }
        0.5 * (a + b)
    };
    let x = rod.position(11.05).unwrap().x + 0.005;
    let ring = w.add_constraint(h, ConstraintKind::SlidingPoint(SlidingPoint { u: at(x), point: [x, 0.0, 0.0], friction: 0.0 }), 0.0).unwrap();
    let mut broke = None;
    let mut left = None;
    for k in 1..=1500 {
        if broke.is_none() {
            let xe = 1.0 + 0.5 * w.params.dt * k as f64;
            w.set_constraint(end, ConstraintKind::Position(Position { u: u1, axes: [true, true, true, false], target: [xe, 0.0, 0.0, 0.0] })).unwrap();
        }
        for e in w.step().unwrap().events {
            match e {
                Event::RodRuptured { u, .. } => broke = Some(u),
                Event::SliderLeft { constraint, .. } if constraint == ring => left = Some(k),
                _ => {}
            }
        }
        if left.is_some() {
            break;
        }
    }
    let u = broke.expect("the strand never broke");
    let end_x = w.rod(h).unwrap().position(u).unwrap().x;
    println!("ring at x = {x:.4} m; cut at u = {u:.4}; clamped piece's end at x = {end_x:.4}; slider left at step {left:?}");
    assert!(left.is_some(), "the ring never came off the retracting piece");
    assert!(w.constraint(ring).is_err());
}

/// In statics the rupture ends the solve: relax returns the event with
/// the equilibrium reached just before the cut.
#[test]
fn relax_stops_at_a_rupture_and_reports_it() {
    let (mut w, h, end, lb, rb) = pulled_strand();
    w.remove_bead(lb).unwrap();
    w.remove_bead(rb).unwrap();
    let u1 = w.rod(h).unwrap().domain().1;
    let pull = |x: f64| ConstraintKind::Position(Position { u: u1, axes: [true, true, true, false], target: [x, 0.0, 0.0, 0.0] });
    w.set_constraint(end, pull(1.02)).unwrap();
    assert!(w.relax().unwrap().events.is_empty());
    w.set_constraint(end, pull(1.06)).unwrap();
    let r = w.relax().unwrap();
    let ruptures: Vec<_> = r.events.iter().filter(|e| matches!(e, Event::RodRuptured { .. })).collect();
    println!("{:?}", ruptures);
    assert_eq!(ruptures.len(), 1);
    assert_eq!(w.rods().count(), 2);
    // The piece left pinned at the pulled end only can swing freely about
    // it: relax names that free rotation instead of picking one of the
    // neutral equilibria. Held at its cut end across the axis, it unloads.
    let e = w.relax().unwrap_err();
    assert!(matches!(e, Error::Singular { .. }) && e.to_string().contains("rotation about"), "{e}");
    let (piece, _) = w.rods().find(|(p, _)| *p != h).unwrap();
    let cut_end = w.rod(piece).unwrap().domain().0;
    w.add_constraint(piece, Position { u: cut_end, axes: [false, true, true, false], target: [0.0; 4] }, 0.0).unwrap();
    w.relax().unwrap();
    for (_, r) in w.rods() {
        let max = r.relative_strains().iter().map(|s| s.eps.abs()).fold(0.0, f64::max);
        assert!(max < 1e-9, "piece still strained: {max}");
    }
}

/// A ring (periodic rod) that breaks opens into one rod: its handle stays,
/// the event has no second piece, and a bead and a constraint keep their
/// material points (same positions as in a run without rupture).
#[test]
fn broken_ring_opens_and_keeps_its_attachments() {
    let m = Material::new("rubber", 1e6, 0.45, 1000.0)
        .unwrap()
        .with_rupture(StrainLimits { stretch: (-0.5, 0.05), bend: INF, twist: INF })
        .unwrap();
    let ring = RodBuilder::curve(1.0, |s| {
        let t = 2.0 * std::f64::consts::PI * s;
        Vector3::new(t.cos(), t.sin(), 0.0) / (2.0 * std::f64::consts::PI)
    })
    .control_points(16)
    .knots(KnotKind::Periodic)
    .with_roll(false)
    .sections((0..16).map(|i| Section::circle(if i == 5 { 0.004 } else { 0.005 }).unwrap()).collect())
    .material(m)
    .build()
    .unwrap();
    let mut w = World::new(IntegrationParameters { parallel: false, ..Default::default() });
    let h = w.add_rod(ring);
    // Stretched 8 % (the thin spot more): it breaks after the first step.
    let q: Vec<f64> = w.rod(h).unwrap().coords().iter().map(|x| 1.08 * x).collect();
    w.rod_mut(h).unwrap().set_coords(&q).unwrap();
    let bead = w.add_bead(h, 11.3, 1e-3, 0.0, 0.0).unwrap();
    let pin = w.add_constraint(h, ConstraintKind::Position(Position { u: 13.7, axes: [true, true, true, false], target: [0.0; 4] }), 0.0).unwrap();
    let target = w.rod(h).unwrap().position(13.7).unwrap();
    w.set_constraint(pin, ConstraintKind::Position(Position { u: 13.7, axes: [true, true, true, false], target: [target.x, target.y, target.z, 0.0] })).unwrap();
    let mut reference = w.clone();
    reference.rod_mut(h).unwrap().set_strain_limits(None, None).unwrap();
    reference.step().unwrap();
    let report = w.step().unwrap();
    let ev = report.events.iter().find(|e| matches!(e, Event::RodRuptured { .. })).expect("the ring broke");
    let Event::RodRuptured { rod, new_rod, u, .. } = ev else { unreachable!() };
    assert_eq!((*rod, *new_rod), (h, None));
    let opened = w.rod(h).unwrap();
    assert_ne!(opened.knots().kind(), KnotKind::Periodic);
    let db = (w.bead_position(bead).unwrap() - reference.bead_position(bead).unwrap()).norm();
    let c = w.constraint(pin).unwrap().kind.u();
    let dc = (opened.position(c).unwrap() - reference.rod(h).unwrap().position(13.7).unwrap()).norm();
    println!("ring opened at u = {u:.4}: bead moved {db:.2e} m, pin point moved {dc:.2e} m (new abscissa {c:.4})");
    assert!(db < 1e-12 && dc < 1e-12);
}
