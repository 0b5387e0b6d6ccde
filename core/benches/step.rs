//! Criterion benchmark of one implicit-Euler step (thesis table IV.1, last
//! row): a free straight steel rod (L = 4 m, circle R = 5 cm, 5 samples per
//! segment, stretch + bend + twist, dt = 1e-3, one thread), smoothly
//! pre-deformed, at 100 and 400 control points.
//!
//!   cargo bench -p strandkit-core --bench step
//!
//! The full table (all rows, 20 … 40000 control points, thesis ratios) is
//! `cargo run --release -p strandkit-core --example bench_table`.
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use nalgebra::Vector3;
use std::hint::black_box;
use strandkit_core::energy::EnergyTerms;
use strandkit_core::*;

fn world(n: usize) -> (World, RodHandle, Vec<f64>) {
    let rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(4.0, 0.0, 0.0))
        .control_points(n)
        .section(Section::circle(0.05).unwrap())
        .material(Material::new("steel", 200e9, 0.3, 7800.0).unwrap())
        .options(RodOptions {
            samples_per_segment: 5,
            terms: EnergyTerms { stretch: true, bend: true, twist: true },
            ..Default::default()
        })
        .build()
        .unwrap();
    let mut q = rod.coords().to_vec();
    let pi = std::f64::consts::PI;
    for c in q.chunks_exact_mut(4) {
        let s = c[0] / 4.0;
        c[1] += 0.001 * (pi * s).sin();
        c[2] += 0.0005 * (2.0 * pi * s).sin();
        c[3] += 0.005 * (pi * s).sin();
    }
    let mut w = World::new(IntegrationParameters { dt: 1e-3, parallel: false, ..Default::default() });
    let h = w.add_rod(rod);
    w.rod_mut(h).unwrap().set_coords(&q).unwrap();
    (w, h, q)
}

fn step(c: &mut Criterion) {
    let mut g = c.benchmark_group("step_stretch_bend_twist_dynamic_1thread");
    g.measurement_time(std::time::Duration::from_secs(8));
    for n in [100usize, 400] {
        let (mut w, h, q0) = world(n);
        let zeros = vec![0.0; q0.len()];
        let mut k = 0usize;
        g.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| {
                // Back to the pre-deformed state now and then (cheap O(n) copy)
                // so the rod never settles to the straight rest shape.
                k += 1;
                if k % 50 == 0 {
                    let r = w.rod_mut(h).unwrap();
                    r.set_coords(&q0).unwrap();
                    r.set_velocities(&zeros).unwrap();
                }
                black_box(w.step().unwrap())
            })
        });
    }
    g.finish();
}

criterion_group!(benches, step);
criterion_main!(benches);
