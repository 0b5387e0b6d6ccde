//! Bad input to plasticity, rupture, Poisson and quasi-dynamics: a clear
//! error each, never a panic.
use nalgebra::Vector3;
use std::panic::{catch_unwind, AssertUnwindSafe};
use strandkit::energy::Strains;
use strandkit::material::StrainLimits;
use strandkit::*;

fn err_of<T>(what: &str, f: impl FnOnce() -> Result<T>) -> String {
    match catch_unwind(AssertUnwindSafe(f)) {
        Err(_) => panic!("{what}: panicked instead of returning an error"),
        Ok(Ok(_)) => panic!("{what}: accepted"),
        Ok(Err(e)) => e.to_string(),
    }
}

fn expect(what: &str, msg: String, words: &[&str]) {
    for w in words {
        assert!(msg.contains(w), "{what}: message {msg:?} does not mention {w:?}");
    }
}

fn rod(poisson: bool) -> Rod {
    RodBuilder::straight(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0))
        .control_points(6)
        .section(Section::circle(0.01).unwrap())
        .material(Material::new("m", 1e6, 0.5, 1000.0).unwrap())
        .options(RodOptions { poisson_update: poisson, ..Default::default() })
        .build()
        .unwrap()
}

#[test]
fn quasi_dynamic_parameters_are_validated() {
    let mut w = World::new(IntegrationParameters::default());
    expect("empty world", err_of("empty", || QuasiDynamic::new(&w, QuasiDynamicParameters::default())), &["at least one rod"]);
    w.add_rod(rod(false));
    let bad = [
        (QuasiDynamicParameters { dt0: 0.0, ..Default::default() }, "dt0"),
        (QuasiDynamicParameters { dt0: f64::NAN, ..Default::default() }, "dt0"),
        (QuasiDynamicParameters { time_budget: Some(-1.0), ..Default::default() }, "time_budget"),
        (QuasiDynamicParameters { to_static: 0.8, to_dynamic: 0.9, ..Default::default() }, "hysteresis"),
        (QuasiDynamicParameters { newton_fraction: 0.0, ..Default::default() }, "newton_fraction"),
        (QuasiDynamicParameters { newton_fraction: 1.5, ..Default::default() }, "newton_fraction"),
    ];
    for (p, word) in bad {
        expect(word, err_of(word, || QuasiDynamic::new(&w, p)), &[word]);
    }
    w.params.plastic_tolerance = 0.0;
    expect("plastic_tolerance", err_of("tol", || w.step()), &["plastic_tolerance"]);
}

#[test]
fn plastic_offsets_and_limits_are_validated() {
    let mut r = rod(false);
    let n = r.sample_params().len();
    expect("length", err_of("len", || r.set_plastic_offsets(&vec![Strains::default(); n - 1])), &["one per sample"]);
    let mut p = vec![Strains::default(); n];
    p[3].kappa1 = f64::NAN;
    expect("nan", err_of("nan", || r.set_plastic_offsets(&p)), &["sample 3", "not finite"]);
    let y = StrainLimits::symmetric(0.01, 1.0, 1.0).unwrap();
    let inside = StrainLimits::symmetric(0.005, 1.0, 1.0).unwrap();
    expect("order", err_of("order", || r.set_strain_limits(Some(y), Some(inside))), &["rupture_limits", "beyond"]);
}

#[test]
fn cut_outside_the_rod_is_an_error() {
    let r = rod(false);
    let (a, b) = r.domain();
    for u in [a - 1.0, b + 0.5, f64::NAN, a, b] {
        err_of("cut", || r.cut_at(u));
    }
}

#[test]
fn poisson_update_that_would_invert_the_section_is_an_error() {
    let mut r = rod(true);
    let q: Vec<f64> = r.rest_coords().iter().enumerate().map(|(i, x)| if i % 4 == 0 { 3.5 * x } else { *x }).collect();
    r.set_coords(&q).unwrap();
    expect("poisson", err_of("poisson", || r.update_poisson()), &["non-positive section size"]);
}
