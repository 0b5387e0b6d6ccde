//! Issue 15's overhand knot: an open trefoil tied in an elastic rod
//! (straight at rest, no twist), held at one end and pulled at the other by
//! a force F of fixed direction, tightened in steps of F and let settle
//! under drag at each (implicit Euler, frictionless self-contact).
//!
//! The knot's shape is Shastri's polynomial long trefoil
//! (t³ − 3t, t⁴ − 4t², (t⁵ − 10t)/5), t ∈ [−2.3, 2.3], scaled to a length of
//! 1 m: knotted by construction, its strands 2.9 diameters apart at least.
//!
//! Measured: the end shortening Δ (arc length taken up by the knot: the
//! centreline's length less the distance between the ends) and the loop
//! size R = Δ / 2π. In the loose limit (diameter h ≪ R) the loop is a circle
//! whose bending balances the pull, F R² / B → ½ (F Δ² / B → 2π²),
//! raised by the braid where the strands touch by a relative amount of
//! order √(h/R) (Audoly, Clauvelin & Neukirch, PRL 2007); the knots here
//! have √(h/R) = 0.34–0.50, the tightest a loop of 4 diameters.
//!
//! Resolution: 320 control points, segments of 0.63 diameters. With 160
//! (1.25 diameters) the contact rows, at most one per half segment, were
//! too few for the braid: from √(h/R) ≈ 0.5 its rows came and went from
//! step to step, Δ swung by 1–2 % and the surfaces overlapped by up to 20 %
//! of a diameter, and at 0.56 the strands passed through one another. At
//! 0.53 with 320 points the chatter returns under rounding-level changes
//! (overlap up to 10 %), so the levels stop at 0.50.
use nalgebra::Vector3;
use strandkit::prelude::*;
use strandkit::RodContacts;

const R: f64 = 0.0025;
const N_CTRL: usize = 320;

/// Points along the polynomial trefoil, scaled to unit length, with their
/// arc lengths.
fn trefoil() -> (Vec<Vector3<f64>>, Vec<f64>) {
    let n = 20001;
    let p: Vec<Vector3<f64>> = (0..n)
        .map(|k| {
            let t = -2.3 + 4.6 * k as f64 / (n - 1) as f64;
            Vector3::new(t.powi(3) - 3.0 * t, t.powi(4) - 4.0 * t * t, 0.2 * (t.powi(5) - 10.0 * t))
        })
        .collect();
    let mut s = vec![0.0];
    for k in 1..n {
        s.push(s[k - 1] + (p[k] - p[k - 1]).norm());
    }
    let scale = 1.0 / s[n - 1];
    (p.iter().map(|x| x * scale).collect(), s.iter().map(|x| x * scale).collect())
}

/// End shortening Δ (m), and the closest approach (m) of points of the
/// rod more than π diameters apart along it (ten points per segment: the
/// spline between the contact rows, not only at them).
fn measure(rod: &Rod) -> (f64, f64) {
    let (u0, u1) = rod.domain();
    let n = 10 * rod.n_segments();
    let p: Vec<Vector3<f64>> = (0..=n).map(|k| rod.position(u0 + (u1 - u0) * k as f64 / n as f64).unwrap()).collect();
    let mut arc = vec![0.0];
    for k in 1..p.len() {
        arc.push(arc[k - 1] + (p[k] - p[k - 1]).norm());
    }
    let length = arc[p.len() - 1];
    let mut closest = f64::INFINITY;
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            if arc[j] - arc[i] > std::f64::consts::PI * 2.0 * R {
                closest = closest.min((p[i] - p[j]).norm());
            }
        }
    }
    (length - (p[p.len() - 1] - p[0]).norm(), closest)
}

#[test]
fn overhand_knot_tightens_with_force_without_interpenetration() {
    let (pts, arc) = trefoil();
    let shape = {
        let (pts, arc) = (pts.clone(), arc.clone());
        move |s: f64| {
            let k = arc.partition_point(|&x| x < s).clamp(1, arc.len() - 1);
            let w = (s - arc[k - 1]) / (arc[k] - arc[k - 1]);
            pts[k - 1] * (1.0 - w) + pts[k] * w
        }
    };
    let (e, nu) = (1e7, 0.5);
    let material = Material::new("rubber", e, nu, 1000.0).unwrap();
    let b = e * std::f64::consts::PI * R.powi(4) / 4.0;
    let options = RodOptions { drag: 0.2, ..Default::default() };
    let knotted = RodBuilder::curve(1.0, shape).control_points(N_CTRL).with_roll(false).section(Section::circle(R).unwrap()).material(material.clone()).build().unwrap();
    // Straight at rest, knotted now.
    let (a, z) = (pts[0], pts[pts.len() - 1]);
    let pull = (z - a).normalize();
    let mut rod = RodBuilder::straight(a, a + pull).control_points(N_CTRL).with_roll(false).section(Section::circle(R).unwrap()).material(material).options(options).build().unwrap();
    rod.set_coords(knotted.coords()).unwrap();
    let (u0, u1) = rod.domain();
    // No step moves the rod farther than the contact margin (retried in
    // halves when it would), as contact scenes are advised to run.
    let mut w = World::new(IntegrationParameters { dt: 1e-2, adaptive_dt: true, max_move: Some(2.0 * R), ..Default::default() });
    let h = w.add_rod(rod);
    w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true, true, true, false], target: [a.x, a.y, a.z, 0.0] }), 0.0).unwrap();
    let load = w.add_load(Load::PointForce(PointForce { rod: h, u: u1, force: [0.0; 3] })).unwrap();
    w.add_contact_detector(RodContacts::new(2.0 * R, true, false).unwrap()).unwrap();
    let (delta0, closest0) = measure(w.rod(h).unwrap());
    println!("tied: Δ = {delta0:.4} m, closest approach {:.3} diameters", closest0 / (2.0 * R));

    let f0 = 400.0 * b; // N: F R²/B ≈ ½ for R = 3.5 cm
    // Steps of 5 ms: at 10 ms the closest approach in the tighter levels
    // depended on rounding (0.80–0.95 diameters under relative force
    // changes of 1e-12); at 5 ms it stays within 0.93–0.97 (measured with
    // the force or the step changed by 1e-12 and 1e-10).
    let steps = 300;
    let mut rows: Vec<(f64, f64, f64)> = Vec::new(); // F (N), Δ (m), Δ 0.5 s before the end
    let mut closest = f64::INFINITY;
    let mut worst_at = (0, 0);
    for level in 0..6 {
        let f = f0 * 2f64.powf(0.5 * level as f64);
        w.set_load(load, Load::PointForce(PointForce { rod: h, u: u1, force: (pull * f).into() })).unwrap();
        let mut before = 0.0;
        // The tied shape is far from equilibrium and collapses at metres
        // per second onto itself: that first half second at a fifth of the
        // step, so that the motion over a step stays within the margin.
        // Each force step then tightens the knot in a burst: its first 0.1
        // s at 2 ms too (at 5 ms the strands sank 11 % of a diameter into
        // each other there).
        let fine = if level == 0 { 250 } else { 50 };
        for k in 0..fine + steps {
            w.params.dt = if k < fine { 2e-3 } else { 5e-3 };
            w.step().unwrap();
            let (delta, gap) = measure(w.rod(h).unwrap());
            if gap < closest {
                worst_at = (level, k);
            }
            closest = closest.min(gap);
            if k == fine + steps - 101 {
                before = delta;
            }
        }
        let (delta, _) = measure(w.rod(h).unwrap());
        let loop_r = delta / (2.0 * std::f64::consts::PI);
        println!(
            "F = {f:.4} N: Δ = {delta:.5} m (moved {:+.2e} over the last 0.5 s), F R²/B = {:.3}, F Δ²/B = {:.2}, √(h/R) = {:.3}, {} contacts",
            (delta - before) / delta,
            f * loop_r * loop_r / b,
            f * delta * delta / b,
            (2.0 * R / loop_r).sqrt(),
            w.contacts().active().count()
        );
        rows.push((f, delta, before));
    }
    println!("closest approach over every step: {:.4} diameters (force level {}, step {})", closest / (2.0 * R), worst_at.0, worst_at.1);
    // Settled at each force (Δ still within 0.1 % over the last 0.5 s;
    // measured 1.3e-4 at most, at the first level).
    for &(f, d, before) in &rows {
        assert!(((d - before) / d).abs() < 1e-3, "not settled at F = {f}: Δ {before} → {d}");
    }
    // The loop shrinks monotonically as the force grows.
    for pair in rows.windows(2) {
        assert!(pair[1].1 < pair[0].1, "Δ grew with the force: {:?}", pair);
    }
    // No pull-through, and the surfaces never overlap by more than 10 % of
    // the diameter: the spline sags between contact rows, most just after
    // a force step (measured 4–7 % under rounding-level perturbations).
    assert!(closest > 0.9 * 2.0 * R, "closest approach {closest} for a diameter {}", 2.0 * R);
    // Loose-knot scaling Δ ∝ F^(−1/2), raised by the braid: the fitted
    // exponent within 20 % of −½, the prefactor F R²/B above the loose
    // limit ½, growing as the knot tightens, and raised by less than
    // 2√(h/R) of itself (measured 1.26 √(h/R) at the loosest, 1.71–1.72 at
    // the tightest).
    let n = rows.len() as f64;
    let (lf, ld): (Vec<f64>, Vec<f64>) = rows.iter().map(|r| (r.0.ln(), r.1.ln())).unzip();
    let (mf, md) = (lf.iter().sum::<f64>() / n, ld.iter().sum::<f64>() / n);
    let slope = lf.iter().zip(&ld).map(|(x, y)| (x - mf) * (y - md)).sum::<f64>() / lf.iter().map(|x| (x - mf).powi(2)).sum::<f64>();
    let loops: Vec<f64> = rows.iter().map(|r| r.1 / (2.0 * std::f64::consts::PI)).collect();
    let prefactors: Vec<f64> = rows.iter().zip(&loops).map(|(r, l)| r.0 * l * l / b).collect();
    let braid: Vec<f64> = prefactors.iter().zip(&loops).map(|(p, l)| (2.0 * p - 1.0) / (2.0 * R / l).sqrt()).collect();
    println!("Δ ∝ F^{slope:.3}; F R²/B = {prefactors:.3?} (loose limit ½), (2 F R²/B − 1)/√(h/R) = {braid:.2?}");
    assert!((-0.5..-0.4).contains(&slope), "exponent {slope}");
    assert!(prefactors.iter().all(|&p| p > 0.5) && prefactors.windows(2).all(|p| p[1] > p[0]), "prefactors {prefactors:?}");
    assert!(braid.iter().all(|&c| c < 2.0), "raised by more than 2√(h/R): {braid:?}");
}
