//! Snapshots (serde JSON) reload bit-for-bit: a world saved mid-run and
//! reloaded continues exactly like the uninterrupted run.
mod common;
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
    assert!(matches!(strandkit::World::load(&path), Err(strandkit::Error::Io(_))));
    std::fs::remove_dir_all(&dir).ok();
}
