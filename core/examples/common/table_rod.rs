#![allow(dead_code)] // shared by several examples, each uses a part
//! The rod of thesis table IV.1 as the benchmarks use it (SPEC §11): a 4 m
//! steel rod, R = 5 cm, 5 Gauss points per segment, free and pre-deformed
//! for the dynamic rows, clamped and tip-loaded for the static row.
use strandkit_core::prelude::*;
use nalgebra::Vector3;
use strandkit_core::energy::EnergyTerms;

pub const LENGTH: f64 = 4.0;
pub const RADIUS: f64 = 0.05;

pub fn steel() -> Material {
    Material::new("steel", 200e9, 0.3, 7800.0).unwrap()
}

pub fn rod(n: usize, terms: EnergyTerms, drag: f64, material: Material) -> Rod {
    RodBuilder::straight(Vector3::zeros(), Vector3::new(LENGTH, 0.0, 0.0))
        .control_points(n)
        .section(section())
        .material(material)
        .options(RodOptions { samples_per_segment: 5, terms, drag, model: model(), ..Default::default() })
        .build()
        .unwrap()
}

/// The section: the table's circle, or with `--section ellipse` an
/// ellipse of the same area (semi-axes 1.25 R and 0.8 R: EI1 ≠ EI2, so
/// neither frame model can write bending in the invariants alone).
pub fn section() -> Section {
    match std::env::args().skip_while(|a| a != "--section").nth(1).as_deref() {
        Some("ellipse") => Section::ellipse(1.25 * RADIUS, 0.8 * RADIUS).unwrap(),
        _ => Section::circle(RADIUS).unwrap(),
    }
}

/// The frame model named by `--model frenet|reference` on the command
/// line (default: Frenet, the thesis table's model; the rods' default is
/// the reference-frame model).
pub fn model() -> strandkit_core::FrameModel {
    match std::env::args().skip_while(|a| a != "--model").nth(1).as_deref() {
        Some("reference") => strandkit_core::FrameModel::Reference,
        _ => strandkit_core::FrameModel::Frenet,
    }
}

/// Smooth 3-D pre-deformation (1 mm bend in y, 0.5 mm in z, 5 mrad roll).
/// (10× larger — 1 cm, 5 mm, 0.05 rad — makes the 40000-cp full-twist rod
/// diverge within 4 steps, see BENCHMARKS.md; ≤ 20000 cp are fine.)
pub fn deformed(q: &[f64]) -> Vec<f64> {
    let mut q = q.to_vec();
    let pi = std::f64::consts::PI;
    for c in q.chunks_exact_mut(4) {
        let s = c[0] / LENGTH;
        c[1] += 0.001 * (pi * s).sin();
        c[2] += 0.0005 * (2.0 * pi * s).sin();
        c[3] += 0.005 * (pi * s).sin();
    }
    q
}

/// Free pre-deformed rod, dt = 1e-3: (world, rod, initial coordinates).
pub fn dynamic_world(r: Rod, parallel: bool) -> (World, RodHandle, Vec<f64>) {
    let q0 = deformed(r.coords());
    let mut world = World::new(IntegrationParameters { dt: 1e-3, parallel, ..Default::default() });
    let h = world.add_rod(r);
    world.rod_mut(h).unwrap().set_coords(&q0).unwrap();
    (world, h, q0)
}

/// Clamped rod with a tip load, dt = 1e6 (the static row).
pub fn static_world(r: Rod) -> (World, RodHandle, Vec<f64>) {
    let (u0, u1) = r.domain();
    let q0 = r.coords().to_vec();
    let mut world = World::new(IntegrationParameters { dt: 1e6, parallel: false, ..Default::default() });
    let h = world.add_rod(r);
    world.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true; 4], target: [0.0; 4] }), 0.0).unwrap();
    world.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    world.add_load(Load::PointForce(PointForce { rod: h, u: u1, force: [0.0, -100.0, 50.0] })).unwrap();
    (world, h, q0)
}

/// Back to the initial coordinates, at rest.
pub fn reset(w: &mut World, h: RodHandle, q0: &[f64]) {
    let r = w.rod_mut(h).unwrap();
    r.set_coords(q0).unwrap();
    r.set_velocities(&vec![0.0; q0.len()]).unwrap();
}
