//! Scenario builders shared by the validation tests (SPEC §10).
#![allow(dead_code)]
pub mod scenarios;
pub use scenarios::Cantilever;
#[allow(unused_imports)]
pub use scenarios::CANTILEVER_REFERENCES;
use strandkit::{RodHandle, World};

pub fn cantilever(n_ctrl: usize, samples: usize, force: [f64; 3]) -> Cantilever {
    scenarios::cantilever(n_ctrl, samples, force).unwrap()
}

pub fn tip(world: &World, rod: RodHandle) -> (nalgebra::Vector3<f64>, f64) {
    scenarios::tip(world, rod).unwrap()
}

/// A straight steel rod (E = 200 GPa, R = 5 cm) from `a` to `b`.
pub fn steel_rod(a: nalgebra::Vector3<f64>, b: nalgebra::Vector3<f64>, n: usize, roll: bool) -> strandkit::Rod {
    strandkit::RodBuilder::straight(a, b)
        .control_points(n)
        .with_roll(roll)
        .section(strandkit::Section::circle(0.05).unwrap())
        .material(strandkit::Material::new("steel", 200e9, 0.3, 7800.0).unwrap())
        .build()
        .unwrap()
}

/// Bends a straight rod without roll (along x, length `len`) into a
/// sagging arc spanning `span`: y = −0.3 sin(π s), a start for hanging
/// strings (the rest shape stays straight).
pub fn sag(rod: &mut strandkit::Rod, len: f64, span: f64) {
    let q: Vec<f64> = rod
        .coords()
        .chunks(3)
        .flat_map(|p| {
            let s = p[0] / len;
            [s * span, -0.3 * (std::f64::consts::PI * s).sin(), 0.0]
        })
        .collect();
    rod.set_coords(&q).unwrap();
}
