//! Snapshots (serde JSON) reload bit-for-bit: a world saved mid-run and
//! reloaded continues exactly like the uninterrupted run.
mod common;
use strandkit::prelude::*;
use common::*;

#[test]
fn snapshot_continues_bit_for_bit() {
    let mut c = cantilever(12, 4, [0.0, -2e4, 0.0]);
    c.world.params.dt = 1e-3;
    c.world.params.gravity = [0.0, -9.81, 0.0];
    for _ in 0..20 {
        c.world.step().unwrap();
    }
    let dir = std::env::temp_dir().join(format!("strandkit-snap-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("world.json");
    c.world.save(&path).unwrap();
    let mut copy = strandkit::World::load(&path).unwrap();
    for _ in 0..30 {
        c.world.step().unwrap();
        copy.step().unwrap();
    }
    let (a, b) = (c.world.rod(c.rod).unwrap(), copy.rod(c.rod).unwrap());
    assert!(a.coords().iter().zip(b.coords()).all(|(x, y)| x.to_bits() == y.to_bits()));
    assert!(a.velocities().iter().zip(b.velocities()).all(|(x, y)| x.to_bits() == y.to_bits()));
    assert_eq!(c.world.time().to_bits(), copy.time().to_bits());
    let (ra, rb) = (c.world.reaction(c.clamp).unwrap(), copy.reaction(c.clamp).unwrap());
    assert_eq!(ra, rb);
    // A truncated file is an error, not a panic.
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, &text[..text.len() / 2]).unwrap();
    assert!(matches!(strandkit::World::load(&path), Err(strandkit::Error::Io { .. })));
    std::fs::remove_dir_all(&dir).ok();
}

/// Plastic offsets, Poisson-updated sections and the quasi-dynamic driver's
/// state survive a snapshot: the reloaded run continues bit for bit.
#[test]
fn snapshot_keeps_plastic_and_poisson_state() {
    use strandkit::material::StrainLimits;
    use strandkit::*;
    let inf = (f64::NEG_INFINITY, f64::INFINITY);
    let m = Material::new("wire", 1e7, 0.3, 8000.0)
        .unwrap()
        .with_yield(StrainLimits { stretch: (-0.002, 0.002), bend: (-0.5, 0.5), twist: inf })
        .unwrap();
    let rod = RodBuilder::straight(nalgebra::Vector3::zeros(), nalgebra::Vector3::new(1.0, 0.0, 0.0))
        .control_points(10)
        .section(Section::circle(0.01).unwrap())
        .material(m)
        .options(RodOptions { poisson_update: true, ..Default::default() })
        .build()
        .unwrap();
    let u0 = rod.domain().0;
    let mut w = World::new(IntegrationParameters { gravity: [0.0, -9.81, 0.0], parallel: false, ..Default::default() });
    let h = w.add_rod(rod);
    w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true; 4], target: [0.0; 4] }), 0.0).unwrap();
    w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    // Frames "take" 2× their budget on a scripted clock, so the driver
    // goes quasi-static deterministically.
    let mut qd = QuasiDynamic::new(&w, QuasiDynamicParameters { time_budget: Some(0.5), ..Default::default() }).unwrap();
    struct Slow(f64, u64);
    impl strandkit::Clock for Slow {
        fn now(&mut self) -> f64 {
            self.1 += 1;
            if self.1 % 2 == 0 {
                self.0 += 1.0;
            }
            self.0
        }
    }
    let (mut clock, mut clock_copy) = (Slow(0.0, 0), Slow(0.0, 0));
    for _ in 0..40 {
        w.step().unwrap();
    }
    assert!(w.rod(h).unwrap().plastic_offsets().iter().any(|p| p.kappa2 != 0.0), "the wire yielded");
    let text = w.to_json().unwrap();
    let mut copy = World::from_json(&text).unwrap();
    let qd_text = serde_json::to_string(&qd).unwrap();
    let mut qd_copy: QuasiDynamic = serde_json::from_str(&qd_text).unwrap();
    for _ in 0..20 {
        w.step().unwrap();
        copy.step().unwrap();
    }
    let (a, b) = (w.rod(h).unwrap(), copy.rod(h).unwrap());
    assert!(a.coords().iter().zip(b.coords()).all(|(x, y)| x.to_bits() == y.to_bits()));
    assert_eq!(a.plastic_offsets(), b.plastic_offsets());
    assert_eq!(a.sections(), b.sections());
    // The driver's state reloads too: the same frames (dynamic, then
    // quasi-static with its ramped cap) give the same bits.
    for _ in 0..4 {
        qd.step(&mut w, &mut clock).unwrap();
        qd_copy.step(&mut copy, &mut clock_copy).unwrap();
    }
    assert_eq!(qd.mode(), strandkit::Mode::QuasiStatic, "the scripted clock drives it quasi-static");
    assert_eq!(qd.mode(), qd_copy.mode());
    let (a, b) = (w.rod(h).unwrap(), copy.rod(h).unwrap());
    assert!(a.coords().iter().zip(b.coords()).all(|(x, y)| x.to_bits() == y.to_bits()));
}
