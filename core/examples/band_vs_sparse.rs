//! Band LU vs faer sparse (regularised LDLᵀ / LU) on KKT-like matrices, single
//! thread (SPEC §5). Derives the rule encoded in `linalg::sparse::prefer_sparse`.
//!
//!   cargo run --release -p strandkit-core --example band_vs_sparse [-- quick]
//!
//! Structures (symmetric saddle-point [A Lᵀ; L −C], 3 coordinates per control
//! point, cubic coupling over ±3 control points, C = 0):
//! * `chain m`: m interleaved rods (SPEC §5 ordering), a one-row link between
//!   neighbouring rods at every control point and a constraint on rod 0 every
//!   third point; half-bandwidth ≈ 12 m, band density ≈ 1/m.
//! * `grid nx`: a woven fabric, nx crossings per row, each with a weft point, a
//!   warp point and a 3-row pin between them, ordered row by row; half-bandwidth
//!   ≈ 27 nx (warp coupling over ±3 rows), the band is wide but sparse.
//!
//! Times are medians; "band" = BandLu::factor + solve_refined (1 refinement
//! step, as `KktSystem::solve` does), "sparse" = SparseLu::factor (values into
//! the reused symbolic factorisation, probe check) + solve_in_place (with
//! refinement). "symb" is the one-off first factor (symbolic analysis included).
use std::time::Instant;
use strandkit_core::linalg::band::{solve_refined, BandLu, BandMatrix};
use strandkit_core::linalg::sparse::{prefer_sparse, SparseLu, SparseMethod};
use strandkit_core::linalg::synthetic::{chain_kkt, grid_kkt, Lcg};

fn chain(rng: &mut Lcg, n_target: usize, m: usize) -> BandMatrix {
    let per = 3 * m + (m - 1);
    let k_pts = (3 * n_target / (3 * per + 1)).max(4);
    chain_kkt(rng, k_pts, m).0.band()
}

fn grid(rng: &mut Lcg, n_target: usize, nx: usize) -> BandMatrix {
    let ny = (n_target / (9 * nx)).max(4);
    grid_kkt(rng, nx, ny, 0.0).0.band()
}

/// Median wall time (s) of `f`, at least 3 runs, more while under ~0.6 s total (max 9).
fn median(mut f: impl FnMut()) -> f64 {
    let mut t = Vec::new();
    let start = Instant::now();
    while t.len() < 3 || (t.len() < 9 && start.elapsed().as_secs_f64() < 0.6) {
        let s = Instant::now();
        f();
        t.push(s.elapsed().as_secs_f64());
    }
    t.sort_by(|a, b| a.partial_cmp(b).unwrap());
    t[t.len() / 2]
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

fn main() {
    let quick = std::env::args().any(|a| a == "quick");
    let sizes: &[usize] = if quick { &[2000, 6000] } else { &[500, 2000, 6000, 20000] };
    let mut cases: Vec<(&str, usize)> = Vec::new();
    for m in [1, 2, 3, 4, 5, 10, 21] {
        cases.push(("chain", m));
    }
    for nx in [1, 2, 4, 9] {
        cases.push(("grid", nx));
    }
    println!(
        "{:<9} {:>6} {:>4} {:>6} {:>9} {:>9} {:>9} {:>9} {:>7} {:>7}  {:>6} {:>5}",
        "structure", "n", "bw", "nnz/n", "band ms", "ldlt ms", "lu ms", "symb ms", "band/sp", "fill/bd", "choose", "rule"
    );
    let mut rng = Lcg(42);
    for &(kind, p) in &cases {
        for &n_target in sizes {
            let a = if kind == "chain" { chain(&mut rng, n_target, p) } else { grid(&mut rng, n_target, p) };
            let n = a.n();
            let bw = a.kl();
            let b: Vec<f64> = (0..n).map(|_| rng.next()).collect();

            let mut lu = BandLu::new();
            let mut xb = vec![0.0; n];
            let mut work = Vec::new();
            let t_band = median(|| {
                lu.factor(&a).unwrap();
                solve_refined(&a, &lu, &b, &mut xb, &mut work, 1).unwrap();
            });

            let mut times = Vec::new();
            let mut sp_first = 0.0;
            let mut fill = 0usize;
            let mut pattern = 0usize;
            for method in [SparseMethod::Auto, SparseMethod::Lu] {
                let mut sp = SparseLu::with_method(method);
                let s = Instant::now();
                sp.factor(&a).unwrap();
                let first = s.elapsed().as_secs_f64();
                if method == SparseMethod::Auto {
                    sp_first = first;
                    fill = sp.factor_nnz().unwrap_or(0);
                    pattern = sp.pattern_nnz();
                }
                let mut x = b.clone();
                let t = median(|| {
                    sp.factor(&a).unwrap();
                    x.copy_from_slice(&b);
                    sp.solve_in_place(&mut x).unwrap();
                });
                assert_eq!(sp.symbolic_count(), 1);
                let d = x.iter().zip(&xb).fold(0.0f64, |m, (p, q)| m.max((p - q).abs())) / inf_norm(&xb);
                assert!(d < 1e-9, "{kind} {p} n={n}: sparse {method:?} differs from band by {d:e}");
                times.push(t);
            }
            let best = times[0].min(times[1]);
            println!(
                "{:<9} {:>6} {:>4} {:>6.1} {:>9.2} {:>9.2} {:>9.2} {:>9.2} {:>7.2} {:>7.2}  {:>6} {:>5}",
                format!("{kind} {p}"),
                n,
                bw,
                pattern as f64 / n as f64,
                t_band * 1e3,
                times[0] * 1e3,
                times[1] * 1e3,
                sp_first * 1e3,
                t_band / times[0],
                // L entries of LDLᵀ vs the band LU's storage of L and U (n (2 kl + ku + 1)).
                fill as f64 / (n * (3 * bw + 1)) as f64,
                if t_band <= best { "band" } else if times[0] <= times[1] { "ldlt" } else { "lu" },
                if prefer_sparse(n, bw) { "sp" } else { "band" },
            );
        }
    }
}
