//! Issue 3, bad input: each case a clear error, never a panic.
use strandkit::prelude::*;
use nalgebra::Vector3;

fn world_with_two_rods() -> (World, RodHandle, RodHandle) {
    let mk = |y: f64| {
        RodBuilder::straight(Vector3::new(0.0, y, 0.0), Vector3::new(1.0, y, 0.0))
            .control_points(8)
            .section(Section::circle(0.01).unwrap())
            .material(Material::new("m", 1e9, 0.3, 1000.0).unwrap())
            .build()
            .unwrap()
    };
    let mut w = World::new(IntegrationParameters::default());
    let a = w.add_rod(mk(0.0));
    let b = w.add_rod(mk(0.5));
    (w, a, b)
}

fn msg(r: Result<ConstraintHandle>) -> String {
    match r {
        Err(e) => e.to_string(),
        Ok(h) => panic!("accepted: {h:?}"),
    }
}

#[test]
fn abscissa_outside_the_rod() {
    let (mut w, a, b) = world_with_two_rods();
    let m = msg(w.add_constraint(a, ConstraintKind::Distance(Distance { u: 99.0, point: [0.0; 3], distance: 1.0 }), 0.0));
    assert!(m.contains("outside the rod's parameter domain"), "{m}");
    let m = msg(w.add_constraint(a, ConstraintKind::SlidingPoint(SlidingPoint { u: -1.0, point: [0.0; 3], friction: 0.0 }), 0.0));
    assert!(m.contains("outside"), "{m}");
    let m = msg(w.add_link(a, b, ConstraintKind::RelativeDistance(RelativeDistance { ua: 0.0, ub: f64::NAN, distance: 0.5 }), 0.0));
    assert!(m.contains("ub") && m.contains("finite"), "{m}");
    let m = msg(w.add_link(a, b, ConstraintKind::Contact(Contact { ua: 0.0, ub: 42.0, distance: 0.5 }), 0.0));
    assert!(m.contains("outside"), "{m}");
}

#[test]
fn constraint_on_a_removed_rod() {
    let (mut w, a, b) = world_with_two_rods();
    w.remove_rod(b).unwrap();
    let m = msg(w.add_link(a, b, ConstraintKind::RelativePosition(RelativePosition { ua: 0.0, ub: 0.0, axes: [true; 4], offset: [0.0; 4] }), 0.0));
    assert!(m.contains("does not exist"), "{m}");
    let m = msg(w.add_constraint(b, ConstraintKind::Plane(Plane { u: 0.0, origin: [0.0; 3], normal: [0.0, 0.0, 1.0] }), 0.0));
    assert!(m.contains("does not exist"), "{m}");
    assert!(w.add_bead(b, 0.0, 1.0, 0.0, 0.0).is_err());
}

#[test]
fn duplicate_constraints() {
    let (mut w, a, b) = world_with_two_rods();
    let plane = ConstraintKind::Plane(Plane { u: 1.0, origin: [0.0; 3], normal: [0.0, 0.0, 1.0] });
    w.add_constraint(a, plane.clone(), 0.0).unwrap();
    // Two planes at one abscissa are legitimate (an axis) unless their rows
    // coincide: then the dependence check names the repeated constraint.
    let m = msg(w.add_constraint(a, plane, 0.0));
    assert!(m.contains("linearly dependent") && m.contains("[0]"), "{m}");
    let link = ConstraintKind::RelativeDistance(RelativeDistance { ua: 2.0, ub: 2.0, distance: 0.5 });
    w.add_link(a, b, link.clone(), 0.0).unwrap();
    let m = msg(w.add_link(a, b, link, 0.0));
    assert!(m.contains("duplicate"), "{m}");
}

#[test]
fn zero_length_distances() {
    let (mut w, a, b) = world_with_two_rods();
    let m = msg(w.add_constraint(a, ConstraintKind::Distance(Distance { u: 0.0, point: [0.0, 1.0, 0.0], distance: 0.0 }), 0.0));
    assert!(m.contains("distance") && m.contains("> 0"), "{m}");
    let m = msg(w.add_link(a, b, ConstraintKind::RelativeDistance(RelativeDistance { ua: 0.0, ub: 0.0, distance: 0.0 }), 0.0));
    assert!(m.contains("Position"), "{m}");
    // A distance anchor on the rod itself has no direction.
    let m = msg(w.add_constraint(a, ConstraintKind::Distance(Distance { u: 0.0, point: [0.0, 0.0, 0.0], distance: 0.3 }), 0.0));
    assert!(m.contains("coincides"), "{m}");
}

#[test]
fn unsatisfiable_combination_is_rejected() {
    // A point pinned (x, y, z) and also asked to stay 1 m from an anchor
    // 2 m away: the distance row depends on the position rows.
    let (mut w, a, _) = world_with_two_rods();
    w.add_constraint(a, ConstraintKind::Position(Position { u: 0.0, axes: [true, true, true, false], target: [0.0; 4] }), 0.0).unwrap();
    let m = msg(w.add_constraint(a, ConstraintKind::Distance(Distance { u: 0.0, point: [2.0, 0.0, 0.0], distance: 1.0 }), 0.0));
    assert!(m.contains("linearly dependent"), "{m}");
    // Kinds that link two rods go through add_link, and one-rod kinds do not.
    let m = msg(w.add_constraint(a, ConstraintKind::RelativeDistance(RelativeDistance { ua: 0.0, ub: 0.0, distance: 1.0 }), 0.0));
    assert!(m.contains("add_link"), "{m}");
}
