//! Issue "Show 7": bad input gives a clear error, never a panic or NaN.
//! Every case runs under `catch_unwind`, matches the `Error` variant and
//! checks that the message names the problem.

use strandkit::prelude::*;
use nalgebra::Vector3;
use std::panic::{catch_unwind, AssertUnwindSafe};
use strandkit::rod::RodShape;
use strandkit::spline::KnotKind;

/// Runs `f`, asserting that it neither panics nor succeeds; returns the error.
fn err_of<T: std::fmt::Debug>(what: &str, f: impl FnOnce() -> Result<T>) -> Error {
    match catch_unwind(AssertUnwindSafe(f)) {
        Err(_) => panic!("{what}: panicked instead of returning an error"),
        Ok(Ok(v)) => panic!("{what}: accepted, got {v:?}"),
        Ok(Err(e)) => e,
    }
}

/// Runs `f`, asserting that it neither panics nor fails.
fn ok_of<T>(what: &str, f: impl FnOnce() -> Result<T>) -> T {
    match catch_unwind(AssertUnwindSafe(f)) {
        Err(_) => panic!("{what}: panicked"),
        Ok(Err(e)) => panic!("{what}: unexpected error {e}"),
        Ok(Ok(v)) => v,
    }
}

/// Asserts the variant and that the message contains every `words` (case-insensitive).
fn expect(e: &Error, variant: &str, words: &[&str]) {
    let v = e.kind();
    assert_eq!(v, variant, "wrong error variant: {e}");
    let msg = e.to_string().to_lowercase();
    for w in words {
        assert!(msg.contains(&w.to_lowercase()), "message {msg:?} does not mention {w:?}");
    }
}

fn mat() -> Material {
    Material::new("test", 1e7, 0.3, 1000.0).unwrap()
}
fn circle() -> Section {
    Section::circle(0.01).unwrap()
}
fn straight_builder(roll: bool) -> RodBuilder {
    RodBuilder::straight(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0))
        .control_points(8)
        .with_roll(roll)
        .section(circle())
        .material(mat())
}
fn world_with_rod(roll: bool) -> (World, RodHandle) {
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(straight_builder(roll).build().unwrap());
    (w, h)
}
fn pts(n: usize) -> Vec<Vector3<f64>> {
    (0..n).map(|i| Vector3::new(i as f64 * 0.1, 0.01 * (i as f64).sin(), 0.0)).collect()
}
fn pos(u: f64, axes: [bool; 4], target: [f64; 4]) -> ConstraintKind {
    ConstraintKind::Position(Position { u, axes, target })
}
const X: [bool; 4] = [true, false, false, false];
const XYZ: [bool; 4] = [true, true, true, false];

// ---------------------------------------------------------------- coordinates

#[test]
fn nan_control_point_coordinate() {
    let mut p = pts(6);
    p[2].y = f64::NAN;
    let e = err_of("NaN control point", || {
        RodBuilder::new(RodShape::ControlPoints(p)).section(circle()).material(mat()).build()
    });
    expect(&e, "InvalidInput", &["control point 2", "non-finite", "nan"]);
    // Through a rod's set_coords as well (the rod keeps its coordinates).
    let mut rod = straight_builder(true).build().unwrap();
    let mut q = rod.coords().to_vec();
    let before = q.clone();
    q[9] = f64::NAN;
    let e = err_of("set_coords NaN", || rod.set_coords(&q));
    expect(&e, "InvalidInput", &["coordinates", "value 9", "not finite"]);
    assert_eq!(rod.coords(), &before[..], "a rejected set_coords changed the rod");
    // And as a straight-rod end point.
    let e = err_of("NaN straight start", || {
        RodBuilder::straight(Vector3::new(0.0, f64::NAN, 0.0), Vector3::x()).section(circle()).material(mat()).build()
    });
    expect(&e, "InvalidInput", &["start", "finite"]);
}

#[test]
fn infinite_control_point_coordinate() {
    let mut p = pts(6);
    p[5].z = f64::INFINITY;
    let e = err_of("infinite control point", || {
        RodBuilder::new(RodShape::ControlPoints(p)).section(circle()).material(mat()).build()
    });
    expect(&e, "InvalidInput", &["control point 5", "non-finite", "inf"]);
    let mut rod = straight_builder(false).build().unwrap();
    let mut v = vec![0.0; rod.coords().len()];
    v[4] = f64::NEG_INFINITY;
    let e = err_of("infinite velocity", || rod.set_velocities(&v));
    expect(&e, "InvalidInput", &["velocities", "not finite"]);
    let e = err_of("infinite straight end", || {
        RodBuilder::straight(Vector3::zeros(), Vector3::new(f64::INFINITY, 0.0, 0.0))
            .section(circle())
            .material(mat())
            .build()
    });
    expect(&e, "InvalidInput", &["end", "finite"]);
    // Interpolated shapes too.
    let mut p = pts(6);
    p[1].x = f64::INFINITY;
    let e = err_of("infinite interpolation point", || {
        RodBuilder::new(RodShape::ThroughPoints(p)).section(circle()).material(mat()).build()
    });
    assert!(matches!(e, Error::InvalidInput { .. }), "got {e}");
    assert!(e.to_string().to_lowercase().contains("finite") || e.to_string().contains("inf"), "{e}");
}

// ---------------------------------------------------------------- sections

#[test]
fn negative_radius() {
    let e = err_of("negative radius", || Section::circle(-0.01));
    expect(&e, "InvalidInput", &["radius", "> 0", "-0.01"]);
    // A section built by hand bypasses the constructor: the rod builder still refuses it.
    let e = err_of("rod with negative radius", || {
        straight_builder(true).section(Section::Circle { radius: -0.01 }).build()
    });
    expect(&e, "InvalidInput", &["radius", "-0.01"]);
    // One bad radius among varying sections.
    let mut secs = vec![circle(); 8];
    secs[3] = Section::Circle { radius: -0.02 };
    let e = err_of("varying sections, one negative", || straight_builder(true).sections(secs).build());
    expect(&e, "InvalidInput", &["radius", "-0.02"]);
}

#[test]
fn zero_radius() {
    let e = err_of("zero radius", || Section::circle(0.0));
    expect(&e, "InvalidInput", &["radius", "> 0", "got 0"]);
    let e = err_of("rod with zero radius", || straight_builder(false).section(Section::Circle { radius: 0.0 }).build());
    expect(&e, "InvalidInput", &["radius"]);
    let e = err_of("tube with zero inner radius", || Section::tube(0.02, 0.0));
    expect(&e, "InvalidInput", &["inner_radius"]);
}

#[test]
fn too_few_control_points() {
    for kind in [KnotKind::Clamped, KnotKind::Uniform, KnotKind::Periodic] {
        let e = err_of("3 control points", || straight_builder(true).knots(kind).control_points(3).build());
        expect(&e, "InvalidInput", &["at least 4 control points", "got 3"]);
    }
    let e = err_of("3 explicit control points", || {
        RodBuilder::new(RodShape::ControlPoints(pts(3))).section(circle()).material(mat()).build()
    });
    expect(&e, "InvalidInput", &["at least 4", "got 3"]);
    let e = err_of("3 interpolation points", || {
        RodBuilder::new(RodShape::ThroughPoints(pts(3))).section(circle()).material(mat()).build()
    });
    expect(&e, "InvalidInput", &["at least 4", "got 3"]);
    let e = err_of("0 control points", || straight_builder(true).control_points(0).build());
    expect(&e, "InvalidInput", &["at least 4", "got 0"]);
}

// ---------------------------------------------------------------- constraints

#[test]
fn constraint_abscissa_outside_rod() {
    let (mut w, h) = world_with_rod(true);
    let (a, b) = w.rod(h).unwrap().domain();
    for u in [b + 0.5, a - 1e-3 * (b - a), 1e9] {
        let e = err_of("u beyond the domain", || w.add_constraint(h, pos(u, X, [0.0; 4]), 0.0));
        expect(&e, "InvalidInput", &["outside", "domain", &format!("{u}")]);
    }
    let e = err_of("tangent beyond the domain", || {
        w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: b + 1.0, direction: [1.0, 0.0, 0.0] }), 0.0)
    });
    expect(&e, "InvalidInput", &["outside"]);
    // Nothing was added: the free rod still steps.
    ok_of("step after rejected constraints", || w.step());
}

#[test]
fn constraint_abscissa_nan() {
    let (mut w, h) = world_with_rod(true);
    let e = err_of("NaN u", || w.add_constraint(h, pos(f64::NAN, X, [0.0; 4]), 0.0));
    expect(&e, "InvalidInput", &["abscissa", "finite", "nan"]);
    let e = err_of("infinite u", || w.add_constraint(h, pos(f64::INFINITY, X, [0.0; 4]), 0.0));
    expect(&e, "InvalidInput", &["abscissa", "finite"]);
    // Periodic rods wrap finite u but still refuse NaN.
    let mut w2 = World::new(IntegrationParameters::default());
    let ring = RodBuilder::curve(1.0, |s| {
        let p = 2.0 * std::f64::consts::PI * s;
        Vector3::new(p.cos(), p.sin(), 0.0) / (2.0 * std::f64::consts::PI)
    })
    .knots(KnotKind::Periodic)
    .control_points(10)
    .section(circle())
    .material(mat())
    .build()
    .unwrap();
    let hr = w2.add_rod(ring);
    let e = err_of("NaN u on a ring", || w2.add_constraint(hr, pos(f64::NAN, X, [0.0; 4]), 0.0));
    expect(&e, "InvalidInput", &["nan"]);
    // Loads too.
    let e = err_of("NaN load u", || w.add_load(Load::PointForce(PointForce { rod: h, u: f64::NAN, force: [0.0, 1.0, 0.0] })));
    expect(&e, "InvalidInput", &["nan"]);
    let e = err_of("load u outside", || w.add_load(Load::PointForce(PointForce { rod: h, u: 100.0, force: [0.0, 1.0, 0.0] })));
    expect(&e, "InvalidInput", &["outside"]);
}

#[test]
fn non_finite_constraint_target() {
    let (mut w, h) = world_with_rod(true);
    let e = err_of("NaN target", || w.add_constraint(h, pos(0.0, XYZ, [0.0, f64::NAN, 0.0, 0.0]), 0.0));
    expect(&e, "InvalidInput", &["target", "finite"]);
    let e = err_of("NaN compliance", || w.add_constraint(h, pos(0.0, X, [0.0; 4]), f64::NAN));
    expect(&e, "InvalidInput", &["compliance"]);
    let e = err_of("negative compliance", || w.add_constraint(h, pos(0.0, X, [0.0; 4]), -1.0));
    expect(&e, "InvalidInput", &["compliance", ">= 0"]);
    let e = err_of("no axis", || w.add_constraint(h, pos(0.0, [false; 4], [0.0; 4]), 0.0));
    expect(&e, "InvalidInput", &["axes", "none selected"]);
}

#[test]
fn duplicate_constraint() {
    let (mut w, h) = world_with_rod(true);
    let first = ok_of("first x constraint", || w.add_constraint(h, pos(1.0, X, [0.1, 0.0, 0.0, 0.0]), 0.0));
    let e = err_of("same axis twice", || w.add_constraint(h, pos(1.0, X, [0.1, 0.0, 0.0, 0.0]), 0.0));
    expect(&e, "InvalidInput", &["duplicate", &format!("constraint {}", first.index)]);
    let e = err_of("compliant duplicate", || w.add_constraint(h, pos(1.0, X, [0.1, 0.0, 0.0, 0.0]), 1e-3));
    expect(&e, "InvalidInput", &["duplicate"]);
    let t = ConstraintKind::Tangent(Tangent { u: 0.0, direction: [1.0, 0.0, 0.0] });
    ok_of("tangent", || w.add_constraint(h, t.clone(), 0.0));
    let e = err_of("tangent twice", || w.add_constraint(h, t.clone(), 0.0));
    expect(&e, "InvalidInput", &["duplicate"]);
}

#[test]
fn contradictory_constraints_same_abscissa() {
    let (mut w, h) = world_with_rod(true);
    ok_of("x and y at u = 2", || w.add_constraint(h, pos(2.0, [true, true, false, false], [0.4, 0.0, 0.0, 0.0]), 0.0));
    // Different targets on overlapping axes (y): a duplicate.
    let e = err_of("overlapping axes, other target", || {
        w.add_constraint(h, pos(2.0, [false, true, true, false], [0.0, 0.3, 0.0, 0.0]), 0.0)
    });
    expect(&e, "InvalidInput", &["duplicate"]);
    // Disjoint axes at the same abscissa are fine, and so is the same axis elsewhere.
    ok_of("z at u = 2", || w.add_constraint(h, pos(2.0, [false, false, true, false], [0.0; 4]), 0.0));
    ok_of("x at u = 3", || w.add_constraint(h, pos(3.0, X, [0.6, 0.0, 0.0, 0.0]), 0.0));
}

/// Linearly dependent constraints (5 x-rows on a 4-control-point rod) are
/// rejected when added, consistent or contradictory, at dyadic and generic
/// abscissae, for soft and stiff rods; the world keeps the 4 independent
/// ones and steps normally (SPEC §5: detected and reported, never a
/// singular matrix or garbage multipliers).
#[test]
fn linearly_dependent_constraints_are_rejected() {
    for young in [1e7, 2e11] {
        for ss in [[0.0, 0.25, 0.5, 0.75, 1.0], [0.0, 0.1, 0.37, 0.61, 0.9], [0.05, 0.3, 0.33, 0.7, 0.95]] {
            for offset in [0.0, 1e-3] {
                let (mut w, cs, last) = five_x_constraints(young, ss, offset);
                let e = last.expect_err("fifth, dependent x-row accepted");
                expect(&e, "InvalidInput", &["linearly dependent", "constraints"]);
                assert_eq!(cs.len(), 4);
                catch_unwind(AssertUnwindSafe(|| w.step())).expect("step panicked").expect("4 independent rows");
                for c in &cs {
                    assert!(w.constraint(*c).unwrap().multipliers[0].abs() < 1e-6);
                }
            }
        }
    }
}

fn five_x_constraints(young: f64, ss: [f64; 5], offset: f64) -> (World, Vec<ConstraintHandle>, strandkit::Result<ConstraintHandle>) {
    let rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(1.0, 0.3, 0.0))
        .control_points(4)
        .section(circle())
        .material(Material::new("t", young, 0.3, 1000.0).unwrap())
        .build()
        .unwrap();
    let (a, b) = rod.domain();
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(rod);
    let mut cs = Vec::new();
    let mut last = None;
    for (k, s) in ss.iter().enumerate() {
        let u = a + s * (b - a);
        let x = w.rod(h).unwrap().position(u).unwrap().x + if k == 4 { offset } else { 0.0 };
        let r = w.add_constraint(h, pos(u, X, [x, 0.0, 0.0, 0.0]), 0.0);
        if k < 4 {
            cs.push(r.unwrap());
        } else {
            last = Some(r);
        }
    }
    (w, cs, last.unwrap())
}

// ---------------------------------------------------------------- statics

#[test]
fn relax_free_rod_is_singular() {
    for roll in [true, false] {
        let (mut w, h) = world_with_rod(roll);
        let q0 = w.rod(h).unwrap().coords().to_vec();
        let e = err_of("relax of a free rod", || w.relax());
        expect(&e, "Singular", &["not statically defined", "translation"]);
        assert_eq!(w.rod(h).unwrap().coords(), &q0[..], "failed relax moved the rod");
    }
}

fn held_at_one_point(roll: bool) -> (World, RodHandle) {
    let (mut w, h) = world_with_rod(roll);
    let axes = if roll { [true; 4] } else { XYZ };
    w.add_constraint(h, pos(0.0, axes, [0.0; 4]), 0.0).unwrap();
    w.add_load(Load::PointForce(PointForce { rod: h, u: w.rod(h).unwrap().domain().1, force: [0.0, -1.0, 0.0] })).unwrap();
    (w, h)
}

#[test]
fn relax_rod_held_at_one_point_is_singular() {
    for roll in [true, false] {
        let (mut w, h) = held_at_one_point(roll);
        let q0 = w.rod(h).unwrap().coords().to_vec();
        let e = err_of("relax of a rod held at one point", || w.relax());
        println!("roll={roll}: {e}");
        expect(&e, "Singular", &["not statically defined", "held by no constraint"]);
        assert_eq!(w.rod(h).unwrap().coords(), &q0[..], "failed relax moved the rod");
    }
    // Position + tangent on a 4-dof straight rod: only the uniform roll is free
    // (the straight rod's roll has no stiffness), and with a roll clamp it is fine.
    let (mut w, h) = world_with_rod(true);
    w.add_constraint(h, pos(0.0, XYZ, [0.0; 4]), 0.0).unwrap();
    w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: 0.0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    let e = err_of("position + tangent, roll free", || w.relax());
    expect(&e, "Singular", &["not statically defined", "roll"]);
    w.add_constraint(h, pos(0.0, [false, false, false, true], [0.0; 4]), 0.0).unwrap();
    ok_of("fully clamped", || w.relax());
}

/// The free motion of a straight rod (along x) held at its start is a
/// rotation about y or z through the held point; the message should name a
/// rotation, not a translation (which the position constraint does hold).
#[test]
fn relax_rod_held_at_one_point_names_rotation() {
    for roll in [true, false] {
        let (mut w, _) = held_at_one_point(roll);
        let e = err_of("relax of a rod held at one point", || w.relax());
        expect(&e, "Singular", &["not statically defined", "rotation"]);
        assert!(!e.to_string().contains("translation"), "names a held translation: {e}");
    }
}

// ---------------------------------------------------------------- handles

#[test]
fn removed_rod_handle() {
    let (mut w, h) = world_with_rod(true);
    let c = w.add_constraint(h, pos(0.0, X, [0.0; 4]), 0.0).unwrap();
    let l = w.add_load(Load::Distributed(Distributed { rod: h, force_per_length: [0.0, 0.0, -1.0] })).unwrap();
    ok_of("remove rod", || w.remove_rod(h));
    expect(&err_of("rod()", || w.rod(h)), "InvalidHandle", &["rod", "does not exist"]);
    expect(&err_of("rod_mut()", || w.rod_mut(h).map(|_| ())), "InvalidHandle", &["rod"]);
    expect(&err_of("remove_rod twice", || w.remove_rod(h)), "InvalidHandle", &["rod"]);
    expect(&err_of("constraint on removed rod", || w.add_constraint(h, pos(0.0, X, [0.0; 4]), 0.0)), "InvalidHandle", &["rod"]);
    // Its constraint and load went with it.
    expect(&err_of("its constraint", || w.constraint(c).map(|_| ())), "InvalidHandle", &["constraint"]);
    expect(&err_of("its load", || w.remove_load(l)), "InvalidHandle", &["load"]);
    // A new rod reuses the slot with a new generation: the old handle stays dead.
    let h2 = w.add_rod(straight_builder(true).build().unwrap());
    assert_eq!(h2.index, h.index);
    assert_ne!(h2, h);
    expect(&err_of("stale rod handle", || w.rod(h)), "InvalidHandle", &["rod"]);
    ok_of("step without the removed rod", || w.step());
}

#[test]
fn removed_constraint_handle() {
    let (mut w, h) = world_with_rod(true);
    let c = w.add_constraint(h, pos(0.0, X, [0.0; 4]), 0.0).unwrap();
    ok_of("remove constraint", || w.remove_constraint(c));
    expect(&err_of("constraint()", || w.constraint(c).map(|_| ())), "InvalidHandle", &["constraint", "does not exist"]);
    expect(&err_of("remove twice", || w.remove_constraint(c)), "InvalidHandle", &["constraint"]);
    expect(&err_of("reaction()", || w.reaction(c)), "InvalidHandle", &["constraint"]);
    expect(&err_of("set_constraint()", || w.set_constraint(c, pos(0.0, X, [1.0; 4]))), "InvalidHandle", &["constraint"]);
    // The same kind can be added again (no stale duplicate).
    let c2 = ok_of("re-add", || w.add_constraint(h, pos(0.0, X, [0.0; 4]), 0.0));
    assert_ne!(c2, c);
    expect(&err_of("stale constraint handle", || w.reaction(c)), "InvalidHandle", &["constraint"]);
}

#[test]
fn removed_load_handle() {
    let (mut w, h) = world_with_rod(true);
    let l = w.add_load(Load::PointForce(PointForce { rod: h, u: 1.0, force: [0.0, 1.0, 0.0] })).unwrap();
    ok_of("remove load", || w.remove_load(l));
    expect(&err_of("remove twice", || w.remove_load(l)), "InvalidHandle", &["load", "does not exist"]);
    expect(
        &err_of("set_load()", || w.set_load(l, Load::PointForce(PointForce { rod: h, u: 1.0, force: [0.0; 3] }))),
        "InvalidHandle",
        &["load"],
    );
}

#[test]
fn load_on_removed_rod() {
    let (mut w, h) = world_with_rod(false);
    w.remove_rod(h).unwrap();
    for load in [
        Load::PointForce(PointForce { rod: h, u: 1.0, force: [0.0, 1.0, 0.0] }),
        Load::Distributed(Distributed { rod: h, force_per_length: [0.0, 0.0, -9.81] }),
    ] {
        let e = err_of("load on removed rod", || w.add_load(load.clone()));
        expect(&e, "InvalidHandle", &["rod", "does not exist"]);
    }
    // Moving a live load onto a removed rod is refused too.
    let h2 = w.add_rod(straight_builder(false).build().unwrap());
    let l = w.add_load(Load::PointForce(PointForce { rod: h2, u: 1.0, force: [0.0, 1.0, 0.0] })).unwrap();
    let e = err_of("set_load onto removed rod", || w.set_load(l, Load::PointForce(PointForce { rod: h, u: 1.0, force: [0.0; 3] })));
    expect(&e, "InvalidHandle", &["rod"]);
    let e = err_of("NaN load", || w.add_load(Load::PointForce(PointForce { rod: h2, u: 1.0, force: [f64::NAN, 0.0, 0.0] })));
    expect(&e, "InvalidInput", &["point force", "finite"]);
}

// ---------------------------------------------------------------- parameters

#[test]
fn nan_dt_is_an_error_from_step() {
    for dt in [f64::NAN, 0.0, -1e-3, f64::INFINITY] {
        let (mut w, h) = world_with_rod(true);
        let q0 = w.rod(h).unwrap().coords().to_vec();
        w.params.dt = dt;
        let e = err_of("bad dt", || w.step());
        expect(&e, "InvalidInput", &["dt", "finite and > 0"]);
        assert_eq!(w.rod(h).unwrap().coords(), &q0[..]);
        assert_eq!(w.time(), 0.0, "a failed step advanced time");
        assert_eq!(w.n_steps(), 0);
    }
    let (mut w, _) = world_with_rod(true);
    w.params.gravity = [0.0, f64::NAN, 0.0];
    expect(&err_of("NaN gravity", || w.step()), "InvalidInput", &["gravity", "finite"]);
}

#[test]
fn poisson_ratio_above_half() {
    let e = err_of("Poisson 0.6", || Material::new("bad", 1e9, 0.6, 1000.0));
    expect(&e, "InvalidInput", &["poisson", "0.6"]);
    for nu in [-1.0, f64::NAN] {
        let e = err_of("Poisson out of range", || Material::new("bad", 1e9, nu, 1000.0));
        expect(&e, "InvalidInput", &["poisson"]);
    }
    // A hand-built material bypasses Material::new: the rod refuses it.
    let m = Material { poisson: 0.6, ..mat() };
    let e = err_of("rod with Poisson 0.6", || straight_builder(true).material(m).build());
    expect(&e, "InvalidInput", &["poisson", "0.6"]);
    let e = err_of("negative Young", || Material::new("bad", -1.0, 0.3, 1000.0));
    expect(&e, "InvalidInput", &["young"]);
    ok_of("Poisson 0.5 is allowed", || Material::new("rubber", 1e6, 0.5, 1000.0));
}

#[test]
fn tangent_with_zero_direction() {
    let (mut w, h) = world_with_rod(true);
    let e = err_of("zero tangent", || w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: 0.0, direction: [0.0; 3] }), 0.0));
    expect(&e, "InvalidInput", &["tangent direction", "non-zero"]);
    let e = err_of("NaN tangent", || {
        w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: 0.0, direction: [f64::NAN, 1.0, 0.0] }), 0.0)
    });
    expect(&e, "InvalidInput", &["tangent direction", "finite"]);
    // Also through set_constraint on a valid tangent.
    let c = w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: 0.0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    let e = err_of("set zero tangent", || w.set_constraint(c, ConstraintKind::Tangent(Tangent { u: 0.0, direction: [0.0; 3] })));
    expect(&e, "InvalidInput", &["tangent direction"]);
    let e = err_of("zero roll reference", || {
        w.add_constraint(h, ConstraintKind::MaterialRoll(MaterialRoll { u: 0.0, reference: [0.0; 3], angle: 0.0 }), 0.0)
    });
    expect(&e, "InvalidInput", &["reference", "non-zero"]);
}

#[test]
fn roll_constraint_on_rod_without_roll() {
    let (mut w, h) = world_with_rod(false);
    let e = err_of("position roll on 3 dofs", || w.add_constraint(h, pos(0.0, [false, false, false, true], [0.0; 4]), 0.0));
    expect(&e, "InvalidInput", &["roll", "no roll coordinate"]);
    let e = err_of("all 4 axes on 3 dofs", || w.add_constraint(h, pos(0.0, [true; 4], [0.0; 4]), 0.0));
    expect(&e, "InvalidInput", &["roll", "no roll coordinate"]);
    let e = err_of("material roll on 3 dofs", || {
        w.add_constraint(h, ConstraintKind::MaterialRoll(MaterialRoll { u: 0.0, reference: [0.0, 1.0, 0.0], angle: 0.0 }), 0.0)
    });
    expect(&e, "InvalidInput", &["material roll", "no roll coordinate"]);
    let e = err_of("point torque on 3 dofs", || w.add_load(Load::PointTorque(PointTorque { rod: h, u: 0.5, torque: 1.0 })));
    expect(&e, "InvalidInput", &["torque", "no roll coordinate"]);
    let e = err_of("roll angles on 3 dofs", || straight_builder(false).roll(vec![0.0; 8]).build());
    expect(&e, "InvalidInput", &["roll", "no roll coordinate"]);
}

/// MaterialRoll on a straight rod: the Frenet frame is undefined, so the
/// constraint must fail with a clear error when it is used, not give NaN.
#[test]
fn material_roll_on_straight_rod() {
    // The Frenet model measures roll from the Frenet normal, undefined on a
    // straight rod (the reference model's transported director is not).
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(straight_builder(true).options(RodOptions { model: FrameModel::Frenet, ..Default::default() }).build().unwrap());
    let e = err_of("material roll on a straight rod", || {
        w.add_constraint(h, ConstraintKind::MaterialRoll(MaterialRoll { u: 0.0, reference: [0.0, 1.0, 0.0], angle: 0.0 }), 0.0)
    });
    expect(&e, "Singular", &["material roll", "straight"]);
    assert!(w.rod(h).unwrap().coords().iter().all(|x| x.is_finite()));
}

#[test]
fn samples_per_segment_zero() {
    for n in [0usize, 9, 1000] {
        let o = RodOptions { samples_per_segment: n, ..Default::default() };
        let e = err_of("bad samples_per_segment", || straight_builder(true).options(o).build());
        expect(&e, "InvalidInput", &["samples_per_segment", &format!("got {n}")]);
    }
    let o = RodOptions { samples_per_segment: 1, ..Default::default() };
    ok_of("1 sample per segment", || straight_builder(true).options(o).build());
}

#[test]
fn other_bad_rod_options() {
    for (o, word) in [
        (RodOptions { drag: -1.0, ..Default::default() }, "drag"),
        (RodOptions { drag: f64::NAN, ..Default::default() }, "drag"),
        (RodOptions { curvature_threshold: f64::NAN, ..Default::default() }, "curvature_threshold"),
        (RodOptions { curvature_threshold: -1.0, ..Default::default() }, "curvature_threshold"),
    ] {
        let e = err_of("bad option", || straight_builder(true).options(o).build());
        expect(&e, "InvalidInput", &[word]);
    }
    let e = err_of("no material", || RodBuilder::straight(Vector3::zeros(), Vector3::x()).section(circle()).build());
    expect(&e, "InvalidInput", &["material"]);
    let e = err_of("no section", || RodBuilder::straight(Vector3::zeros(), Vector3::x()).material(mat()).build());
    expect(&e, "InvalidInput", &["section"]);
    let e = err_of("degenerate straight rod", || {
        RodBuilder::straight(Vector3::x(), Vector3::x()).section(circle()).material(mat()).build()
    });
    expect(&e, "InvalidInput", &["coincide"]);
    let e = err_of("wrong number of sections", || straight_builder(true).sections(vec![circle(); 5]).build());
    expect(&e, "InvalidInput", &["section", "got 5"]);
}
