//! The constraint contract: every kind in the registry
//! (`ConstraintKind::CATALOGUE`) is checked, from one table of example
//! instances (single rod, closed rod, two rods, two points of one rod,
//! sliders with their abscissa unknown), for
//! - its Jacobian rows against central finite differences of g(q) (and of
//!   g(u) for a slider's abscissa column), relative error ≤ 1e-6, at a
//!   generic curved, rolled configuration;
//! - the control points it declares touched covering every entry;
//! - its reported force and torque equal to the multipliers mapped through
//!   the Jacobian (the resultant of LᵀΛ on the reaction side's rigid
//!   motions, the moment about the tangent read on the roll coordinate
//!   where the rows touch it), and the two sides of a link balancing;
//! - an exact serde round trip;
//! - clean errors for bad input (abscissa outside the rod, NaN abscissa,
//!   NaN or zero parameters, the wrong number of rods).
//!
//! A kind added to the registry without an entry in `examples` fails
//! `every_registered_kind_has_examples`.
use nalgebra::Vector3;
use strandkit::constraint::{ConstraintKind, Row, Side};
use strandkit::prelude::*;
use strandkit::energy::FrameModel;
use strandkit::spline::KnotVector;

/// Deterministic pseudo-random numbers in [-1, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

fn material() -> Material {
    Material::new("steel", 200e9, 0.3, 7800.0).unwrap()
}

/// A curved, rolled rod of 8 control points: open (clamped knots) or closed.
fn rod(closed: bool, seed: u64, model: FrameModel) -> Rod {
    let n = 8;
    let mut rng = Lcg(seed);
    let mut q = Vec::with_capacity(4 * n);
    for i in 0..n {
        let a = i as f64 / n as f64 * std::f64::consts::TAU;
        let (x, y, z) = if closed { (a.cos(), a.sin(), 0.2 * (2.0 * a).sin()) } else { (i as f64 * 0.3, 0.4 * (1.3 * i as f64).sin(), 0.3 * (0.7 * i as f64).cos()) };
        q.extend([x + 0.05 * rng.next(), y + 0.05 * rng.next(), z + 0.05 * rng.next(), 0.7 * rng.next()]);
    }
    let knots = if closed { KnotVector::periodic(n).unwrap() } else { KnotVector::clamped(n).unwrap() };
    Rod::new(knots, 4, q, vec![Section::circle(0.01).unwrap()], material(), RodOptions { model, ..Default::default() }).unwrap()
}

/// How the example's rods are arranged.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Rods {
    Open,
    Closed,
    /// Two different rods (a relative kind).
    Two,
    /// Two points of one rod (a relative kind).
    SameRod,
}

struct Example {
    rods: Rods,
    kind: ConstraintKind,
}

fn ex(rods: Rods, kind: impl Into<ConstraintKind>) -> Example {
    Example { rods, kind: kind.into() }
}

/// One or more examples per registered kind (abscissae of the 8-point rods:
/// open domain [0, 5], closed [0, 8)).
fn examples(name: &str) -> Vec<Example> {
    use Rods::*;
    let d = [0.3, -0.5, 0.8];
    match name {
        "Position" => vec![
            ex(Open, Position { u: 1.3, axes: [true, false, true, true], target: [0.1, 0.2, 0.3, 0.4] }),
            ex(Closed, Position { u: 7.6, axes: [true; 4], target: [0.0; 4] }),
        ],
        "Tangent" => vec![ex(Open, Tangent { u: 2.2, direction: d }), ex(Closed, Tangent { u: 7.7, direction: d })],
        "MaterialRoll" => vec![
            ex(Open, MaterialRoll { u: 2.4, reference: [0.2, 0.1, 1.0], angle: 0.3 }),
            ex(Closed, MaterialRoll { u: 5.1, reference: [0.0, 0.0, 1.0], angle: -0.4 }),
        ],
        "Distance" => vec![ex(Open, Distance { u: 3.1, point: [0.5, 1.0, -0.5], distance: 0.7 })],
        "Plane" => vec![ex(Closed, Plane { u: 0.4, origin: [0.1, 0.0, 0.0], normal: d })],
        "Axis" => vec![ex(Open, Axis { u: 4.6, origin: [0.0, 0.2, 0.0], direction: d })],
        "Curvature" => vec![ex(Open, Curvature { u: 2.9, target: [0.1, -0.2, 0.05] })],
        "RelativePosition" => vec![
            ex(Two, RelativePosition { ua: 1.1, ub: 6.3, axes: [true, true, false, true], offset: [0.1, 0.2, 0.0, 0.3] }),
            ex(SameRod, RelativePosition { ua: 0.7, ub: 4.2, axes: [true; 4], offset: [0.0; 4] }),
        ],
        "RelativeAxis" => vec![
            ex(Two, RelativeAxis { ua: 2.1, ub: 5.4, offset: [0.1, -0.2, 0.05], direction: d }),
            ex(SameRod, RelativeAxis { ua: 0.9, ub: 3.7, offset: [0.0; 3], direction: d }),
        ],
        "RelativePlane" => vec![
            ex(Two, RelativePlane { ua: 2.1, ub: 5.4, offset: [0.1, -0.2, 0.05], normal: d }),
            ex(SameRod, RelativePlane { ua: 0.9, ub: 3.7, offset: [0.0; 3], normal: d }),
        ],
        "RelativeOrientation" => vec![
            ex(Two, RelativeOrientation { ua: 2.5, ub: 1.5, roll: true }),
            ex(SameRod, RelativeOrientation { ua: 1.0, ub: 1.8, roll: false }),
        ],
        "RelativeDistance" => vec![
            ex(Two, RelativeDistance { ua: 3.3, ub: 0.2, distance: 1.5 }),
            ex(SameRod, RelativeDistance { ua: 0.3, ub: 4.9, distance: 1.0 }),
        ],
        "SlidingPoint" => vec![ex(Open, SlidingPoint { u: 2.7, point: [0.8, 0.1, 0.2], friction: 0.5 })],
        "OrientedSlidingPoint" => vec![ex(Open, OrientedSlidingPoint { u: 3.6, point: [1.0, 0.0, 0.1], direction: d, friction: 0.0 })],
        "EqualOffsets" => vec![
            ex(Two, EqualOffsets { ua: 1.2, ub: 2.3, va: 4.1, vb: 5.4 }),
            ex(SameRod, EqualOffsets { ua: 0.4, ub: 2.6, va: 1.5, vb: 4.1 }),
        ],
        "Contact" => vec![ex(Two, Contact { ua: 2.0, ub: 4.0, distance: 0.02 })],
        "CoplanarClamp" => vec![ex(Two, CoplanarClamp { ua: 4.4, ub: 3.2, alpha: [0.3, -0.2] })],
        "Barycentric" => vec![
            ex(Open, Barycentric { points: vec![(0.5, 0.25), (2.5, 0.5), (4.0, 0.25)], driven: 1.7, axes: [true, true, false, true] }),
            ex(Closed, Barycentric { points: vec![(7.5, 0.6), (1.0, 0.4)], driven: 0.2, axes: [false, true, true, false] }),
        ],
        "BasePairStep" => {
            let step = |[ua_prev, ua, ua_next, ua_after]: [f64; 4], [ub_prev, ub, ub_next, ub_after]: [f64; 4]| BasePairStep {
                ua_prev,
                ub_prev,
                ua,
                ub,
                ua_next,
                ub_next,
                ua_after,
                ub_after,
                axis_offset: 0.3,
                rest_shift: [0.1, -0.05, 0.34],
                rest_rotation: [0.02, -0.03, 0.6],
                translation_stiffness: [900.0, 1100.0, 3000.0],
                rotation_stiffness: [600.0, 650.0, 1200.0],
                twist_stretch: -250.0,
                stagger_free: false,
                axis_mu: [0.0; 2],
            };
            // Stagger-free frames (μ near a B-DNA helix's). Not at an end:
            // on these non-helical rods a rigid end step's rows come out
            // linearly dependent (its frames read three pairs only); the
            // dual-number unit test covers the end rules.
            let free = |b: BasePairStep| BasePairStep { stagger_free: true, axis_mu: [-0.7, -0.5], ..b };
            vec![
                ex(Two, step([1.0, 1.2, 1.9, 2.3], [6.4, 6.1, 5.4, 5.1])),
                ex(SameRod, step([0.2, 0.5, 1.1, 1.4], [4.5, 4.2, 3.6, 3.3])),
                ex(Two, free(step([1.0, 1.2, 1.9, 2.3], [6.4, 6.1, 5.4, 5.1]))),
            ]
        }
        "PairStagger" => {
            let st = |pair: (f64, f64), first: (f64, f64), last: (f64, f64)| PairStagger { ua: pair.0, ub: pair.1, ua_first: first.0, ub_first: first.1, ua_last: last.0, ub_last: last.1, axis_mu: -0.6, rest: 0.05 };
            vec![
                ex(Two, st((1.5, 5.8), (1.0, 6.2), (2.0, 5.3))),
                ex(Two, st((1.0, 6.2), (1.0, 6.2), (2.0, 5.3))),
                ex(SameRod, st((0.8, 4.0), (0.3, 4.5), (1.3, 3.5))),
            ]
        }
        _ => vec![],
    }
}

/// The rods of an example (the same one twice for one-rod kinds and for
/// two points of one rod).
fn rods_for(r: Rods) -> Vec<Rod> {
    rods_with(r, FrameModel::Frenet)
}

/// The rods of an example in a given frame model.
fn rods_with(r: Rods, m: FrameModel) -> Vec<Rod> {
    match r {
        Rods::Open | Rods::SameRod => vec![rod(false, 1, m)],
        Rods::Closed => vec![rod(true, 2, m)],
        Rods::Two => vec![rod(false, 3, m), rod(true, 4, m)],
    }
}

fn pair(rods: &[Rod]) -> [&Rod; 2] {
    [&rods[0], rods.get(1).unwrap_or(&rods[0])]
}

fn linearize(kind: &ConstraintKind, rods: &[Rod]) -> Vec<Row> {
    let n = kind.n_rows();
    let mut rows = vec![Row::default(); n];
    kind.linearize(&pair(rods), &mut rows).unwrap();
    rows
}

/// Which stored rod an entry's side refers to.
fn rod_of(rods: &[Rod], side: Side) -> usize {
    if rods.len() == 2 { side as usize } else { 0 }
}

#[test]
fn every_registered_kind_has_examples() {
    assert!(ConstraintKind::CATALOGUE.len() >= 15);
    for info in ConstraintKind::CATALOGUE {
        let ex = examples(info.name);
        assert!(!ex.is_empty(), "kind {} is registered but has no example in tests/constraint_contract.rs", info.name);
        for e in ex {
            assert_eq!(e.kind.name(), info.name, "example filed under the wrong kind");
            let two = matches!(e.rods, Rods::Two | Rods::SameRod);
            assert_eq!(two, info.rods == 2, "{}: rods of the example vs the catalogue", info.name);
        }
    }
}

#[test]
fn jacobians_match_central_differences() {
    // Both frame models: the kinds that ask the model (material roll,
    // curvature, relative orientation) differ between them. In the
    // reference model a coordinate change transports the directors; the
    // state after +h and back differs at second order only.
    for model in [FrameModel::Frenet, FrameModel::Reference] {
    for info in ConstraintKind::CATALOGUE {
        for e in examples(info.name) {
            let mut rods = rods_with(e.rods, model);
            let mut kind = e.kind.clone();
            kind.validate(&pair(&rods)).unwrap();
            kind.project(&pair(&rods)).unwrap();
            let rows = linearize(&kind, &rods);
            let h = 1e-6;
            let mut worst = 0.0f64;
            for (ri, row) in rows.iter().enumerate() {
                let scale = row.entries().iter().fold(0.0f64, |m, e| m.max(e.2.abs())).max(1e-12);
                // Analytic ∂g/∂q per (stored rod, coordinate), sides summed.
                let mut analytic = std::collections::BTreeMap::new();
                for &(side, i, v) in row.entries().iter().filter(|e| e.0 < 2) {
                    *analytic.entry((rod_of(&rods, side), i)).or_insert(0.0) += v;
                }
                // FD over every coordinate of every stored rod.
                for r in 0..rods.len() {
                    for i in 0..rods[r].coords().len() {
                        let mut g = [0.0; 2];
                        let q0 = rods[r].coords().to_vec();
                        for (k, s) in [1.0, -1.0].into_iter().enumerate() {
                            let mut q = q0.clone();
                            q[i] += s * h;
                            rods[r].set_coords(&q).unwrap();
                            g[k] = -linearize(&kind, &rods)[ri].rhs; // rhs = target − g
                        }
                        rods[r].set_coords(&q0).unwrap();
                        let fd = (g[0] - g[1]) / (2.0 * h);
                        let an = analytic.get(&(r, i)).copied().unwrap_or(0.0);
                        let err = (fd - an).abs() / scale;
                        worst = worst.max(err);
                        assert!(err <= 1e-6, "{} ({:?}) row {ri}, rod {r} coordinate {i}: analytic {an:.9e}, FD {fd:.9e}", info.name, e.rods);
                    }
                }
                // The abscissa column of a slider: ∂g/∂u.
                if let Some(&(_, _, col)) = row.entries().iter().find(|e| e.0 == 2) {
                    let mut g = [0.0; 2];
                    for (k, s) in [1.0, -1.0].into_iter().enumerate() {
                        let mut kk = kind.clone();
                        kk.visit_abscissae_mut(&mut |_, u| *u += s * h);
                        g[k] = -linearize(&kk, &rods)[ri].rhs;
                    }
                    let fd = (g[0] - g[1]) / (2.0 * h);
                    assert!((fd - col).abs() <= 1e-6 * scale.max(col.abs()), "{} abscissa column: {col} vs FD {fd}", info.name);
                }
            }
            println!("{:22} {:?} {model:?}: worst relative Jacobian error {worst:.1e}", info.name, e.rods);
        }
    }
    }
}

#[test]
fn touched_control_points_cover_every_entry() {
    for info in ConstraintKind::CATALOGUE {
        for e in examples(info.name) {
            let rods = rods_for(e.rods);
            let t = e.kind.touched(&pair(&rods)).unwrap();
            for row in linearize(&e.kind, &rods) {
                for &(side, i, _) in row.entries().iter().filter(|e| e.0 < 2) {
                    let r = &pair(&rods)[side as usize];
                    let cp = i / r.dofs();
                    assert!(t.as_slice().iter().any(|&(s, c)| s == side && c == cp), "{}: entry on side {side} control point {cp} not declared", info.name);
                }
            }
        }
    }
}

#[test]
fn reported_reaction_is_the_multipliers_through_the_jacobian() {
    let mut rng = Lcg(77);
    for model in [FrameModel::Frenet, FrameModel::Reference] {
    for info in ConstraintKind::CATALOGUE {
        for e in examples(info.name) {
            let rods = rods_with(e.rods, model);
            let p2 = pair(&rods);
            let rows = linearize(&e.kind, &rods);
            let lambda: Vec<f64> = (0..rows.len()).map(|_| 100.0 * rng.next()).collect();
            // The side and abscissa the reaction is reported at.
            let mut first = None;
            e.kind.visit_abscissae(&mut |s, u| {
                first.get_or_insert((s.min(1), u));
            });
            let (side, u) = first.unwrap();
            let rod = p2[side as usize];
            let p = rod.position(u).unwrap();
            let t = rod.tangent(u).unwrap();
            let d = rod.dofs();
            // Resultant of LᵀΛ on each side: force, moment about p, roll share.
            let (mut f, mut m, mut troll, mut touches_roll): ([Vector3<f64>; 2], Vector3<f64>, f64, bool) = ([Vector3::zeros(); 2], Vector3::zeros(), 0.0, false);
            for (row, l) in rows.iter().zip(&lambda) {
                for &(s, i, v) in row.entries().iter().filter(|e| e.0 < 2) {
                    let r = p2[s as usize];
                    let (cp, a) = (i / r.dofs(), i % r.dofs());
                    if a == 3 {
                        if s == side {
                            troll += v * l;
                            touches_roll = true;
                        }
                        continue;
                    }
                    f[s as usize][a] += v * l;
                    if s == side {
                        let q = r.coords();
                        let qk = Vector3::new(q[cp * d], q[cp * d + 1], q[cp * d + 2]);
                        m += (qk - p).cross(&(Vector3::ith(a, 1.0) * (v * l)));
                    }
                }
            }
            let r = e.kind.reaction(&p2, &lambda).unwrap();
            let (rf, rm) = (Vector3::from(r.force), Vector3::from(r.torque));
            let scale = f[side as usize].norm().max(m.norm()).max(troll.abs()).max(1.0);
            assert!((rf - f[side as usize]).norm() <= 1e-9 * scale, "{} ({:?}): force {rf:?} vs LᵀΛ {:?}", info.name, e.rods, f[side as usize]);
            let expected = if touches_roll { m - t * t.dot(&m) + t * troll } else { m };
            assert!((rm - expected).norm() <= 1e-9 * scale, "{} ({:?}): torque {rm:?} vs LᵀΛ {expected:?}", info.name, e.rods);
            // A link's two sides balance (translation invariance).
            if info.rods == 2 {
                assert!((f[0] + f[1]).norm() <= 1e-9 * scale, "{}: sides do not balance: {:?} {:?}", info.name, f[0], f[1]);
            }
        }
    }
    }
}

#[test]
fn serde_round_trip_is_exact() {
    for info in ConstraintKind::CATALOGUE {
        for e in examples(info.name) {
            let s = serde_json::to_string(&e.kind).unwrap();
            assert!(s.starts_with(&format!("{{\"{}\":", info.name)), "{s}");
            let back: ConstraintKind = serde_json::from_str(&s).unwrap();
            assert_eq!(back, e.kind);
            assert_eq!(serde_json::to_string(&back).unwrap(), s);
            // The catalogue's fields are the serde fields.
            let v: serde_json::Value = serde_json::from_str(&s).unwrap();
            let keys: Vec<&String> = v[info.name].as_object().unwrap().keys().collect();
            let mut names: Vec<&str> = info.fields.iter().map(|f| f.name).collect();
            let mut keys: Vec<&str> = keys.iter().map(|k| k.as_str()).collect();
            names.sort();
            keys.sort();
            assert_eq!(names, keys, "{}: catalogue fields vs serde fields", info.name);
        }
    }
}

/// Variants of a kind with one parameter made NaN (or a direction zero, or
/// a required positive value zero), one at a time. Exhaustive over the
/// kinds: a new kind does not compile here until its bad inputs are listed.
fn bad_parameters(k: &ConstraintKind) -> Vec<ConstraintKind> {
    let nan = f64::NAN;
    let mut out: Vec<ConstraintKind> = Vec::new();
    let mut push = |k: ConstraintKind| out.push(k);
    match k {
        ConstraintKind::Position(p) => {
            let mut q = p.clone();
            q.target[0] = nan;
            q.axes[0] = true;
            push(q.into());
            push(Position { axes: [false; 4], ..p.clone() }.into());
        }
        ConstraintKind::Tangent(t) => {
            push(Tangent { direction: [nan, 0.0, 1.0], ..t.clone() }.into());
            push(Tangent { direction: [0.0; 3], ..t.clone() }.into());
        }
        ConstraintKind::MaterialRoll(m) => {
            push(MaterialRoll { angle: nan, ..m.clone() }.into());
            push(MaterialRoll { reference: [0.0; 3], ..m.clone() }.into());
        }
        ConstraintKind::Distance(d) => {
            push(Distance { distance: 0.0, ..d.clone() }.into());
            push(Distance { point: [nan, 0.0, 0.0], ..d.clone() }.into());
        }
        ConstraintKind::Plane(p) => {
            push(Plane { normal: [0.0; 3], ..p.clone() }.into());
            push(Plane { origin: [0.0, nan, 0.0], ..p.clone() }.into());
        }
        ConstraintKind::Axis(a) => {
            push(Axis { direction: [0.0; 3], ..a.clone() }.into());
            push(Axis { origin: [0.0, 0.0, nan], ..a.clone() }.into());
        }
        ConstraintKind::Curvature(c) => push(Curvature { target: [nan, 0.0, 0.0], ..c.clone() }.into()),
        ConstraintKind::RelativePosition(r) => {
            push(RelativePosition { offset: [nan, 0.0, 0.0, 0.0], ..r.clone() }.into());
            push(RelativePosition { axes: [false; 4], ..r.clone() }.into());
        }
        ConstraintKind::RelativeAxis(r) => {
            push(RelativeAxis { direction: [0.0; 3], ..r.clone() }.into());
            push(RelativeAxis { offset: [0.0, nan, 0.0], ..r.clone() }.into());
        }
        ConstraintKind::RelativePlane(r) => {
            push(RelativePlane { normal: [0.0; 3], ..r.clone() }.into());
            push(RelativePlane { offset: [0.0, nan, 0.0], ..r.clone() }.into());
        }
        ConstraintKind::RelativeOrientation(_) => {} // no parameter beyond abscissae and a flag
        // The same pair twice.
        ConstraintKind::EqualOffsets(e) => push(EqualOffsets { va: e.ua, vb: e.ub, ..e.clone() }.into()),
        ConstraintKind::RelativeDistance(r) => {
            push(RelativeDistance { distance: nan, ..r.clone() }.into());
            push(RelativeDistance { distance: -1.0, ..r.clone() }.into());
        }
        ConstraintKind::SlidingPoint(s) => {
            push(SlidingPoint { point: [nan, 0.0, 0.0], ..s.clone() }.into());
            push(SlidingPoint { friction: -1.0, ..s.clone() }.into());
        }
        ConstraintKind::OrientedSlidingPoint(s) => {
            push(OrientedSlidingPoint { direction: [0.0; 3], ..s.clone() }.into());
            push(OrientedSlidingPoint { friction: nan, ..s.clone() }.into());
        }
        ConstraintKind::Contact(c) => push(Contact { distance: 0.0, ..c.clone() }.into()),
        ConstraintKind::CoplanarClamp(c) => push(CoplanarClamp { alpha: [nan, 0.0], ..c.clone() }.into()),
        ConstraintKind::Barycentric(b) => {
            let mut p = b.points.clone();
            p[0].1 = nan;
            push(Barycentric { points: p, ..b.clone() }.into());
            push(Barycentric { points: vec![], ..b.clone() }.into());
            push(Barycentric { points: vec![(1.0, 0.2); 5], ..b.clone() }.into());
        }
        ConstraintKind::BasePairStep(b) => {
            push(BasePairStep { rest_shift: [nan, 0.0, 0.0], ..b.clone() }.into());
            push(BasePairStep { axis_offset: nan, ..b.clone() }.into());
            push(BasePairStep { rest_rotation: [0.0, nan, 0.0], ..b.clone() }.into());
            push(BasePairStep { translation_stiffness: [1.0, 0.0, 1.0], ..b.clone() }.into());
            push(BasePairStep { rotation_stiffness: [1.0, 1.0, -1.0], ..b.clone() }.into());
            // Not positive definite: coupling² ≥ rise × twist stiffness.
            push(BasePairStep { twist_stretch: 2000.0, ..b.clone() }.into());
            push(BasePairStep { twist_stretch: nan, ..b.clone() }.into());
            push(BasePairStep { axis_mu: [nan, 0.0], ..b.clone() }.into());
        }
        ConstraintKind::PairStagger(s) => {
            push(PairStagger { axis_mu: nan, ..s.clone() }.into());
            push(PairStagger { rest: f64::INFINITY, ..s.clone() }.into());
            // One neighbour twice: no axis.
            push(PairStagger { ua_last: s.ua_first, ub_last: s.ub_first, ..s.clone() }.into());
        }
    }
    out
}

#[test]
fn bad_input_is_a_clean_error() {
    for info in ConstraintKind::CATALOGUE {
        for e in examples(info.name) {
            let rods = rods_for(e.rods);
            let p2 = pair(&rods);
            // Each abscissa outside its rod (a closed rod wraps any finite
            // abscissa), NaN and infinite.
            let mut sides = Vec::new();
            e.kind.visit_abscissae(&mut |s, _| sides.push(s));
            for (which, &s) in sides.iter().enumerate() {
                let closed = p2[s.min(1) as usize].knots().kind() == strandkit::spline::KnotKind::Periodic;
                let bad: &[f64] = if closed { &[f64::NAN, f64::INFINITY] } else { &[1e3, -1e3, f64::NAN, f64::INFINITY] };
                for &bad_u in bad {
                    let mut k = e.kind.clone();
                    let mut j = 0;
                    k.visit_abscissae_mut(&mut |_, u| {
                        if j == which {
                            *u = bad_u;
                        }
                        j += 1;
                    });
                    let r = k.validate(&p2);
                    assert!(matches!(r, Err(Error::InvalidInput { .. })), "{}: abscissa {which} = {bad_u} gave {r:?}", info.name);
                }
            }
            for bad in bad_parameters(&e.kind) {
                let r = bad.validate(&p2);
                assert!(matches!(r, Err(Error::InvalidInput { .. })), "{}: {bad:?} gave {r:?}", info.name);
            }
            // Through the world: wrong arity and a relative kind on one point.
            let mut w = World::new(IntegrationParameters::default());
            let hs: Vec<RodHandle> = rods.iter().map(|r| w.add_rod(r.clone())).collect();
            let (a, b) = (hs[0], *hs.last().unwrap());
            if info.rods == 2 {
                let r = w.add_constraint(a, e.kind.clone(), 0.0);
                assert!(matches!(r, Err(Error::InvalidInput { .. })), "{}: add_constraint on a relative kind gave {r:?}", info.name);
                let mut same = e.kind.clone();
                let mut first = None;
                same.visit_abscissae_mut(&mut |_, u| {
                    let f = *first.get_or_insert(*u);
                    *u = f;
                });
                let r = w.add_link(a, a, same, 0.0);
                assert!(matches!(r, Err(Error::InvalidInput { .. }) | Err(Error::Singular { .. })), "{}: a link from a point to itself gave {r:?}", info.name);
            } else {
                let r = w.add_link(a, b, e.kind.clone(), 0.0);
                assert!(matches!(r, Err(Error::InvalidInput { .. })), "{}: add_link on a one-rod kind gave {r:?}", info.name);
            }
            assert_eq!(w.n_constraints(), 0, "{}: a refused constraint was added", info.name);
            // The valid example goes in.
            let ok = if info.rods == 2 { w.add_link(a, b, e.kind.clone(), 0.0) } else { w.add_constraint(a, e.kind.clone(), 0.0) };
            assert!(ok.is_ok(), "{} ({:?}): {ok:?}", info.name, e.rods);
        }
    }
}
