//! Scenario builders shared by the validation tests (SPEC §10).
#![allow(dead_code)]
use strandkit::builders::scenarios;
pub use strandkit::builders::scenarios::Cantilever;
#[allow(unused_imports)]
pub use strandkit::builders::scenarios::CANTILEVER_REFERENCES;
use strandkit::{RodHandle, World};

pub fn cantilever(n_ctrl: usize, samples: usize, force: [f64; 3]) -> Cantilever {
    scenarios::cantilever(n_ctrl, samples, force).unwrap()
}

pub fn tip(world: &World, rod: RodHandle) -> (nalgebra::Vector3<f64>, f64) {
    scenarios::tip(world, rod).unwrap()
}
