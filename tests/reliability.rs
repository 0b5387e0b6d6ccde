//! Reliability regressions (the defects of `../shared/repro/`): each test
//! asserts the fixed behaviour — a clean typed error, or a correct finite
//! result, with the world left as it was on refusal.
mod common;
use common::steel_rod;
use nalgebra::Vector3;
use strandkit::prelude::*;

/// repro/panic_relax_empty_world.py: relax of a world without rods is a
/// no-op, like step.
#[test]
fn relax_of_an_empty_world_is_a_no_op() {
    let mut w = World::new(IntegrationParameters::default());
    let r = w.relax().expect("empty relax");
    assert_eq!(r.iterations, 0);
    assert_eq!(w.n_rods(), 0);
}

/// repro/relax_refused_zeroes_velocities.py: a relax refused because the
/// rod is not statically defined leaves its velocities as they were.
#[test]
fn refused_relax_keeps_the_velocities() {
    let mut w = World::new(IntegrationParameters::default());
    let h = w.add_rod(steel_rod(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0), 6, true));
    let v: Vec<f64> = (0..w.rod(h).unwrap().velocities().len()).map(|i| 0.01 * (i as f64 + 1.0)).collect();
    w.rod_mut(h).unwrap().set_velocities(&v).unwrap();
    let q0 = w.rod(h).unwrap().coords().to_vec();
    let e = w.relax().expect_err("a free rod has no static equilibrium");
    assert!(matches!(e, Error::Singular { .. }), "{e}");
    assert!(e.to_string().contains("not statically defined"), "{e}");
    assert_eq!(w.rod(h).unwrap().velocities(), &v[..]);
    assert_eq!(w.rod(h).unwrap().coords(), &q0[..]);
}
