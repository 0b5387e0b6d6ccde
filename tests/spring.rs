//! Particles on a spring (issue 12, SPEC §9.4, thesis fig. III.17):
//! the helical spring against Castigliano's theorem for a curved rod, a
//! bead on a rigid helix against its closed-form motion, and the thesis'
//! scene (beads stretch the spring, leave it in order, the spring springs
//! back).
use nalgebra::Vector3;
use strandkit::prelude::*;
use strandkit::Event;
use strandkit_builders::{beads_on_spring, BeadsOnSpring};

const G: f64 = 9.81;

fn world(dt: f64, g: f64) -> World {
    World::new(IntegrationParameters { dt, gravity: [0.0, -g, 0.0], relax_max_iterations: 500, ..Default::default() })
}

fn env_usize(k: &str, d: usize) -> usize {
    std::env::var(k).ok().and_then(|v| v.parse().ok()).unwrap_or(d)
}

/// Castigliano (Maxwell–Mohr) for a rod loaded at its free end by F: the
/// end moves along F̂ by (1/F) ∫ (|M⊥|²/EI + (M·t)²/GJ + (F·t)²/EA) ds,
/// M(s) = (r(ℓ) − r(s)) × F — the linear Kirchhoff response of any curved
/// rod, computed here on the exact helix by Simpson's rule (independent of
/// the engine: no spline, no frame model).
fn castigliano(p: &BeadsOnSpring, f: Vector3<f64>) -> f64 {
    let r = p.wire_radius;
    let area = std::f64::consts::PI * r * r;
    let ei = p.young_modulus * area * r * r / 4.0;
    let gj = p.young_modulus / (2.0 * (1.0 + p.poisson_ratio)) * area * r * r / 2.0;
    let ea = p.young_modulus * area;
    let l = p.wire_length();
    let end = p.centreline(l);
    let n = 20_000;
    let h = l / n as f64;
    let mut sum = 0.0;
    for k in 0..=n {
        let s = k as f64 * h;
        let t = (p.centreline(s + 1e-6) - p.centreline(s - 1e-6)).normalize();
        let m = (end - p.centreline(s)).cross(&f);
        let mt = m.dot(&t);
        let integrand = (m.norm_squared() - mt * mt) / ei + mt * mt / gj + f.dot(&t).powi(2) / ea;
        let w = if k == 0 || k == n { 1.0 } else if k % 2 == 1 { 4.0 } else { 2.0 };
        sum += w * integrand;
    }
    sum * h / 3.0 / f.norm()
}

/// The spring hanging from its clamp, weightless, pulled at its free end
/// by a small force (1 mN: the end moves ~2e-3 of the spring's height, so
/// the linear reference holds to ~0.1 %): the end's displacement along
/// the force, down the axis and sideways, converges to Castigliano as the
/// spline follows the helix better — within 0.5 % with 121 control points
/// (30 per turn), 2 % with the default 61 (15 per turn); the thesis' 31
/// (7.5 per turn) are 5–6 % short down the axis and 28–30 % sideways (Frenet
/// model – reference model), which is why the builder's default has 61.
/// In both frame models. The vertical number is about 1.9× the
/// textbook close-coiled 1/k, which ignores that the load hangs off the
/// axis (it also bends the spring as a whole).
#[test]
fn spring_end_compliance_matches_castigliano() {
    // Both frame models (the wire has roll; the reference model is the default).
    for model in [FrameModel::Reference, FrameModel::Frenet] {
        let mut last = [f64::INFINITY; 2];
        for (ncp, tol) in [(31, f64::INFINITY), (61, 0.02), (env_usize("NCP", 121), 0.005)] {
            let p = BeadsOnSpring { n_beads: 0, control_points: ncp, model, ..Default::default() };
            for (k, dir) in [Vector3::new(0.0, -1.0, 0.0), Vector3::new(1.0, 0.0, 0.0)].into_iter().enumerate() {
                let f: Vector3<f64> = 1e-3 * dir;
                let (asm, lay) = beads_on_spring(&p).unwrap();
                let mut w = world(1e-3, 0.0);
                let ins = w.insert(&asm).unwrap();
                let h = ins.rods[lay.spring];
                let (_, u1) = w.rod(h).unwrap().domain();
                let before = w.rod(h).unwrap().position(u1).unwrap();
                w.add_load(Load::PointForce(PointForce { rod: h, u: u1, force: f.into() })).unwrap();
                let rep = w.relax().unwrap();
                let moved = (w.rod(h).unwrap().position(u1).unwrap() - before).dot(&dir);
                let reference = castigliano(&p, f);
                let err = (moved / reference - 1.0).abs();
                println!(
                    "{model:?}, {ncp} cp, F along {:?}: end moved {moved:.6e} m, Castigliano {reference:.6e} m ({:.3} %), 1/k·F = {:.4e} m, {} iterations",
                    dir.as_slice(),
                    100.0 * err,
                    1e-3 / lay.close_coiled_rate,
                    rep.iterations
                );
                assert!(err < tol, "{model:?}, {ncp} cp: end compliance off by {:.3} %", 100.0 * err);
                assert!(err < last[k], "{model:?}, {ncp} cp: no closer than with fewer control points");
                last[k] = err;
            }
        }
    }
}

/// A frictionless bead on a rigid helix (a thick steel wire, 1 g bead):
/// it slides with the constant acceleration g sin α along the wire, α the
/// helix angle — arc length ½ g sin α t² after 0.3 s within 1 % (implicit
/// Euler's own error is 1/n = 0.3 %). With viscous friction c it reaches
/// the terminal speed m g sin α / c within 1 %.
#[test]
fn bead_on_a_rigid_helix_moves_as_the_closed_form() {
    for friction in [0.0, 0.05] {
        let p = BeadsOnSpring { wire_radius: 4e-3, pitch: 0.03, n_beads: 1, bead_mass: 1e-3, friction, ..Default::default() };
        let (asm, lay) = beads_on_spring(&p).unwrap();
        let mut w = world(1e-3, G);
        let ins = w.insert(&asm).unwrap();
        // Let the heavy spring settle under its own weight first.
        let b = ins.beads[0];
        w.set_bead_fixed(b, true).unwrap();
        w.relax().unwrap();
        w.set_bead_fixed(b, false).unwrap();
        let h = ins.rods[lay.spring];
        let s0 = w.rod(h).unwrap().rest_arc_length(w.bead(b).unwrap().u).unwrap();
        let sin_a = lay.helix_angle.sin();
        let steps = 300;
        for _ in 0..steps {
            w.step().unwrap();
        }
        let t = steps as f64 * 1e-3;
        let bead = w.bead(b).unwrap();
        let s = w.rod(h).unwrap().rest_arc_length(bead.u).unwrap() - s0;
        if friction == 0.0 {
            let reference = 0.5 * G * sin_a * t * t;
            let err = (s / reference - 1.0).abs();
            println!("frictionless: slid {s:.6} m in {t} s, ½ g sin α t² = {reference:.6} m ({:.3} %)", 100.0 * err);
            assert!(err < 0.01, "slid {s} vs {reference}");
        } else {
            let reference = 1e-3 * G * sin_a / friction;
            let err = (bead.velocity / reference - 1.0).abs();
            println!("friction {friction}: speed {:.6} m/s, m g sin α / c = {reference:.6} m/s ({:.3} %)", bead.velocity, 100.0 * err);
            assert!(err < 0.01, "speed {} vs {reference}", bead.velocity);
        }
    }
}

/// The thesis' scene (default parameters, dt = 1 ms): the beads slide
/// down and stretch the spring — the free end drops by at least the
/// static extension their weight gives at the end (Castigliano, 1/2 of it
/// at least while they are on) — they leave the wire in order (4
/// `BeadLeft` events, bead[0] first), never closer than 2r, and once they
/// are gone the spring comes back to its unloaded equilibrium (within 2 %
/// of the stretch) by 4 s.
#[test]
fn beads_stretch_the_spring_and_leave() {
    let p = BeadsOnSpring::default();
    let (asm, lay) = beads_on_spring(&p).unwrap();
    let mut w = world(1e-3, G);
    let ins = w.insert(&asm).unwrap();
    let h = ins.rods[lay.spring];
    let (_, u1) = w.rod(h).unwrap().domain();
    // Unloaded equilibrium (own weight): the reference height of the end.
    let mut unloaded = world(1e-3, G);
    let (asm0, _) = beads_on_spring(&BeadsOnSpring { n_beads: 0, ..p.clone() }).unwrap();
    let i0 = unloaded.insert(&asm0).unwrap();
    unloaded.relax().unwrap();
    let rest_end = unloaded.rod(i0.rods[0]).unwrap().position(u1).unwrap();
    let static_drop = castigliano(&p, Vector3::new(0.0, -1.0, 0.0)) * p.n_beads as f64 * p.bead_mass * G;
    let mut left = Vec::new();
    let mut max_drop: f64 = 0.0;
    let mut min_gap = f64::INFINITY;
    for _ in 0..4000 {
        let rep = w.step().unwrap();
        for e in &rep.events {
            if let Event::BeadLeft { bead, time } = e {
                left.push((ins.beads.iter().position(|b| b == bead).unwrap(), *time));
            }
        }
        let end = w.rod(h).unwrap().position(u1).unwrap();
        max_drop = max_drop.max(rest_end.y - end.y);
        let mut s: Vec<f64> = w.beads().map(|(_, b)| w.rod(h).unwrap().rest_arc_length(b.u).unwrap()).collect();
        s.sort_by(f64::total_cmp);
        for pair in s.windows(2) {
            min_gap = min_gap.min(pair[1] - pair[0]);
        }
    }
    let end = w.rod(h).unwrap().position(u1).unwrap();
    let back = (end - rest_end).norm();
    println!(
        "beads left at {:?}; max drop of the end {max_drop:.4} m (static, all beads at the end: {static_drop:.4} m); \
         min gap {min_gap:.4} m (2r = {}); 4 s: {back:.2e} m from the unloaded equilibrium",
        left,
        2.0 * p.bead_radius
    );
    assert_eq!(left.iter().map(|l| l.0).collect::<Vec<_>>(), (0..p.n_beads).collect::<Vec<_>>(), "all beads leave, in order");
    assert!(max_drop > 0.5 * static_drop, "the beads stretch the spring: drop {max_drop} vs static {static_drop}");
    assert!(min_gap >= 2.0 * p.bead_radius * (1.0 - 1e-3), "beads overlapped: {min_gap}");
    assert!(back < 0.02 * static_drop, "spring not back: {back} m vs stretch {static_drop}");
}

/// Bad input: a clear error naming the argument, nothing built.
#[test]
fn spring_bad_input() {
    let d = BeadsOnSpring::default();
    let cases: Vec<(BeadsOnSpring, &str)> = vec![
        (BeadsOnSpring { coil_radius: 0.0, ..d.clone() }, "coil_radius"),
        (BeadsOnSpring { pitch: -0.01, ..d.clone() }, "pitch"),
        (BeadsOnSpring { pitch: 5e-4, ..d.clone() }, "pitch"),
        (BeadsOnSpring { turns: f64::NAN, ..d.clone() }, "turns"),
        (BeadsOnSpring { turns: 1e9, ..d.clone() }, "turns"),
        (BeadsOnSpring { wire_radius: 0.05, ..d.clone() }, "wire_radius"),
        (BeadsOnSpring { young_modulus: -1.0, ..d.clone() }, "young_modulus"),
        (BeadsOnSpring { poisson_ratio: 0.5, ..d.clone() }, "poisson_ratio"),
        (BeadsOnSpring { density: 0.0, ..d.clone() }, "density"),
        (BeadsOnSpring { bead_mass: 0.0, ..d.clone() }, "bead_mass"),
        (BeadsOnSpring { bead_radius: -1.0, ..d.clone() }, "bead_radius"),
        (BeadsOnSpring { bead_spacing: 0.001, ..d.clone() }, "bead_spacing"),
        (BeadsOnSpring { n_beads: 100, ..d.clone() }, "n_beads"),
        (BeadsOnSpring { n_beads: usize::MAX, ..d.clone() }, "n_beads"),
        (BeadsOnSpring { friction: -0.1, ..d.clone() }, "friction"),
        (BeadsOnSpring { control_points: 10, ..d.clone() }, "control_points"),
        (BeadsOnSpring { control_points: usize::MAX, ..d.clone() }, "control_points"),
        (BeadsOnSpring { top: [0.0, f64::INFINITY, 0.0], ..d.clone() }, "top"),
    ];
    for (p, name) in cases {
        let e = beads_on_spring(&p).expect_err(name).to_string();
        assert!(e.contains(name), "{name}: {e}");
    }
}
