//! Clips (III.A.5.a, algorithms 4–5): capture of a rod entering the clip
//! sphere, release when the pull-out force exceeds the clip's resistance.
use strandkit::prelude::*;
use nalgebra::Vector3;
use strandkit::*;

/// A 1 m steel cantilever passes through a clip at mid-span (exit axis +y):
/// the clip captures it; an upward tip force F then pulls on the clip with
/// the propped-cantilever reaction F (1 + 3b/2a) = 2.5 F, so a clip of
/// resistance 990 N lets go at the first load increment above 396 N (400 N
/// with 20 N steps), and the tip jumps up once free.
#[test]
fn clip_captures_and_releases_at_its_resistance() {
    let rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0))
        .control_points(21)
        .section(Section::circle(0.02).unwrap())
        .material(Material::new("steel", 200e9, 0.3, 7800.0).unwrap())
        .build()
        .unwrap();
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(rod);
    let (u0, u1) = w.rod(h).unwrap().domain();
    w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true; 4], target: [0.0; 4] }), 0.0).unwrap();
    w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    let clip = w.add_clip([0.5, 0.0, 0.0], 0.02, [0.0, 1.0, 0.0], 990.0).unwrap();
    let rep = w.relax().unwrap();
    assert!(matches!(rep.events.as_slice(), [Event::ClipCaptured { .. }]), "captured: {:?}", rep.events);
    assert!(w.clip(clip).unwrap().held.is_some());
    let load = w.add_load(Load::PointForce(PointForce { rod: h, u: u1, force: [0.0; 3] })).unwrap();
    let mut tip_before = 0.0;
    for k in 1..100 {
        let f = 20.0 * k as f64;
        w.set_load(load, Load::PointForce(PointForce { rod: h, u: u1, force: [0.0, f, 0.0] })).unwrap();
        let rep = w.relax().unwrap();
        if let Some(Event::ClipReleased { force, .. }) = rep.events.first() {
            println!("released at F = {f} N with pull-out {force:.1} N (2.5 F = {})", 2.5 * f);
            assert_eq!(f, 400.0, "released at the first increment with 2.5 F > 990 N");
            assert!((force - 2.5 * f).abs() < 0.01 * 2.5 * f, "pull-out {force} vs 2.5 F");
            assert!(w.clip(clip).unwrap().held.is_none());
            // Free now: the next solve lets the tip rise much further.
            w.relax().unwrap();
            let tip = w.rod(h).unwrap().position(u1).unwrap().y;
            assert!(tip > 3.0 * tip_before, "tip {tip} vs held {tip_before}");
            return;
        }
        tip_before = w.rod(h).unwrap().position(u1).unwrap().y;
    }
    panic!("the clip never released");
}
