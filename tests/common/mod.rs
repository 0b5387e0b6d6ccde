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

/// The pre-deformed, spinning free rod of the energy tests (rubber, 1 m,
/// r = 1 cm, 15 control points): bent in y and z, moving and spinning (and
/// twisted and rolling when `roll`).
pub fn spinning_free_rod(roll: bool) -> strandkit::Rod {
    let mut rod = strandkit::RodBuilder::straight(nalgebra::Vector3::zeros(), nalgebra::Vector3::new(1.0, 0.0, 0.0))
        .control_points(15)
        .with_roll(roll)
        .section(strandkit::Section::circle(0.01).unwrap())
        .material(strandkit::Material::new("rubber", 1e6, 0.45, 1000.0).unwrap())
        .build()
        .unwrap();
    let d = rod.dofs();
    let mut q = rod.coords().to_vec();
    let mut v = vec![0.0; q.len()];
    for i in 0..rod.n_ctrl() {
        let x = q[i * d];
        q[i * d + 1] = 0.05 * (3.0 * x).sin();
        q[i * d + 2] = 0.03 * (5.0 * x).cos();
        if d == 4 {
            q[i * d + 3] = 0.2 * x;
            v[i * d + 3] = 0.5;
        }
        v[i * d] = 0.1;
        v[i * d + 1] = 0.3 * (x - 0.5);
        v[i * d + 2] = -0.2;
    }
    rod.set_coords(&q).unwrap();
    rod.set_velocities(&v).unwrap();
    rod
}
