//! Cables (issue 12, SPEC §9.5, thesis III.C.1–2): a cable on clips
//! (capture within the capture radius, release at the clip's force
//! against beam theory, the door scene in equilibrium) and a harness
//! (every branch in force and moment balance under the forces its
//! junctions and connectors report).
use nalgebra::Vector3;
use strandkit::prelude::*;
use strandkit::Event;
use strandkit_builders::{cable_on_clips, harness, BranchEnd, CableOnClips, Harness};

const G: f64 = 9.81;

fn world(g: f64) -> World {
    World::new(IntegrationParameters { dt: 3e-3, gravity: [0.0, -g, 0.0], relax_max_iterations: 500, ..Default::default() })
}

fn v(a: [f64; 3]) -> Vector3<f64> {
    Vector3::from(a)
}

/// A straight 1 m cable along x, clamped at x = 0, clips at x = a, b.
fn straight(a: f64, b: f64, offset: f64, resistance: f64) -> CableOnClips {
    CableOnClips {
        path: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]],
        clip_positions: vec![[a, 0.0, offset], [b, 0.0, 0.0]],
        clip_resistance: resistance,
        // Stiff enough to stay linear under ~1 N (EI = 6.4 N·m²; with
        // 0.64 the membrane tension of the deflected span already moves
        // the reactions by 0.5 % at 0.18 N).
        young_modulus: 1e11,
        control_points: std::env::var("NCP").ok().and_then(|v| v.parse().ok()).unwrap_or(41),
        ..Default::default()
    }
}

/// Reactions of a cantilever (EI, clamped at 0, length L) on simple
/// supports at a and b under a tip force F: the supports' forces (along F)
/// from w(a) = w(b) = 0 with the cantilever's influence function
/// w(x; ξ) = x²(3ξ − x)/6EI (x ≤ ξ), ξ²(3x − ξ)/6EI (x ≥ ξ) — beam theory,
/// independent of the engine.
fn support_reactions(l: f64, a: f64, b: f64, f: f64) -> (f64, f64) {
    let w = |x: f64, xi: f64| if x <= xi { x * x * (3.0 * xi - x) / 6.0 } else { xi * xi * (3.0 * x - xi) / 6.0 };
    // Solve [w(a,a) w(a,b); w(b,a) w(b,b)] [Ra Rb] = −F [w(a,L) w(b,L)].
    let (m11, m12, m21, m22) = (w(a, a), w(a, b), w(b, a), w(b, b));
    let (r1, r2) = (-f * w(a, l), -f * w(b, l));
    let det = m11 * m22 - m12 * m21;
    ((r1 * m22 - m12 * r2) / det, (m11 * r2 - m21 * r1) / det)
}

/// Clips capture a cable passing within their capture radius — wherever
/// it passes, not only at the rod's samples — and pull it to their centre;
/// a clip whose sphere the cable misses stays empty; the builder refuses a
/// clip farther from the laid cable than its radius, naming it.
#[test]
fn clips_capture_within_their_radius() {
    let r = 0.01;
    let p = CableOnClips { clip_positions: vec![], ..straight(0.4, 0.7, 0.0, 1e3) };
    let (asm, lay) = cable_on_clips(&p).unwrap();
    let mut w = world(0.0);
    let ins = w.insert(&asm).unwrap();
    let h = ins.rods[lay.cable];
    let inside = w.add_clip([0.437, 0.0, 0.8 * r], r, [0.0, 0.0, 1.0], 1e3).unwrap();
    // On the far side: the pull towards the first clip takes the cable
    // away from this one.
    let outside = w.add_clip([0.613, 0.0, -1.2 * r], r, [0.0, 0.0, 1.0], 1e3).unwrap();
    // A capture ends a relax with its events; the next one settles.
    let rep = w.relax().unwrap();
    w.relax().unwrap();
    let captured: Vec<_> = rep.events.iter().filter_map(|e| if let Event::ClipCaptured { clip, .. } = e { Some(*clip) } else { None }).collect();
    assert_eq!(captured, vec![inside], "only the clip the cable passes through captures: {:?}", rep.events);
    assert!(w.clip(outside).unwrap().held.is_none());
    let held = w.clip(inside).unwrap().held.expect("held");
    let u = match w.constraint(held.1).unwrap().kind {
        ConstraintKind::Position(ref pos) => pos.u,
        _ => panic!("a clip holds by a position constraint"),
    };
    let d = (w.rod(h).unwrap().position(u).unwrap() - Vector3::new(0.437, 0.0, 0.8 * r)).norm();
    println!("captured at u = {u:.5}; the cable is {d:.2e} m from the clip's centre");
    assert!(d < 1e-9, "the clip holds the cable at its centre: {d}");
    let e = cable_on_clips(&straight(0.4, 0.7, 1.2 * r, 2.0)).unwrap_err().to_string();
    assert!(e.contains("clip_positions[0]"), "{e}");
    let (_, lay) = cable_on_clips(&straight(0.4, 0.7, 0.8 * r, 2.0)).unwrap();
    assert!((lay.clip_distances[0] - 0.8 * r).abs() < 1e-9, "distance {}", lay.clip_distances[0]);
}

/// Pull-out: the cable's free end is pulled along the clips' exit axis
/// (+z) by F growing in 1 % steps (weightless cable). Before any release,
/// both clips' forces match beam theory's support reactions within 0.5 %
/// and the clamp and clips balance F; the clip nearest the tip (the larger
/// reaction) lets go at the first step where its reaction passes its
/// resistance — the event names it and reports that force — and the other
/// clip, now a propped cantilever's support (reaction F(1 + 3(L−a)/2a)
/// beyond its resistance; 1 %: the single span bends more, the membrane
/// tension of the deflected span shows), follows at the next solve at the
/// same load: the cable unzips.
#[test]
fn clips_release_at_their_force() {
    let (l, a, b, resistance) = (1.0, 0.4, 0.7, 2.0);
    let p = straight(a, b, 0.0, resistance);
    let (asm, lay) = cable_on_clips(&p).unwrap();
    let mut w = world(0.0);
    let ins = w.insert(&asm).unwrap();
    w.relax().unwrap();
    let h = ins.rods[lay.cable];
    let (_, u1) = w.rod(h).unwrap().domain();
    let load = w.add_load(Load::PointForce(PointForce { rod: h, u: u1, force: [0.0; 3] })).unwrap();
    let (ra1, rb1) = support_reactions(l, a, b, 1.0);
    let f_release = resistance / rb1.abs();
    println!("beam theory per newton at the tip: Ra = {ra1:.5}, Rb = {rb1:.5}; clip[1] lets go at F = {f_release:.4} N");
    let mut released = Vec::new();
    let mut last_f = 0.0;
    for k in 1..400 {
        let f = 0.01 * k as f64;
        w.set_load(load, Load::PointForce(PointForce { rod: h, u: u1, force: [0.0, 0.0, f] })).unwrap();
        // A release ends a relax with its event: solve again at this load
        // until nothing more happens.
        loop {
            let rep = w.relax().unwrap();
            for e in &rep.events {
                if let Event::ClipReleased { clip, force, .. } = e {
                    let idx = ins.clips.iter().position(|c| c == clip).unwrap();
                    released.push((idx, f, *force));
                }
            }
            if rep.events.is_empty() || released.len() == 2 {
                break;
            }
        }
        if released.is_empty() {
            // Clip forces on the cable (along −z) vs beam theory.
            let force_of = |k: usize| -> Vector3<f64> {
                let (_, con) = w.clip(ins.clips[k]).unwrap().held.unwrap();
                v(w.reaction(con).unwrap().force)
            };
            let (fa, fb) = (force_of(0), force_of(1));
            let (ea, eb) = ((fa.z / (ra1 * f) - 1.0).abs(), (fb.z / (rb1 * f) - 1.0).abs());
            assert!(ea < 5e-3 && eb < 5e-3, "F = {f}: clip forces {:.5} {:.5} vs {:.5} {:.5}", fa.z, fb.z, ra1 * f, rb1 * f);
            let clamp: Vector3<f64> = lay.clamps.iter().map(|&c| v(w.reaction(ins.constraints[c]).unwrap().force)).sum();
            let total = clamp + fa + fb + Vector3::new(0.0, 0.0, f);
            assert!(total.norm() < 1e-6 * f, "F = {f}: forces do not balance: {total:?}");
            last_f = f;
        } else if released.len() == 2 || k > 200 {
            break;
        }
    }
    println!("released (clip, F, reported pull-out force): {released:?}; last F held {last_f}");
    assert_eq!(released.len(), 2, "both clips let go: {released:?}");
    let (first, f1, force1) = released[0];
    assert_eq!(first, 1, "the clip nearest the tip goes first");
    assert!(f1 >= f_release && f1 - 0.01 < f_release, "released at F = {f1}, beam theory {f_release}");
    assert!(force1 > resistance && (force1 / (rb1.abs() * f1) - 1.0).abs() < 5e-3, "reported force {force1}");
    let (second, f2, force2) = released[1];
    let propped = f2 * (1.0 + 3.0 * (l - a) / (2.0 * a));
    assert!(second == 0 && f2 == f1, "the other clip follows at the same load: {released:?}");
    println!("clip[0] then pulled {force2:.4} N, propped cantilever {propped:.4} N");
    assert!((force2 / propped - 1.0).abs() < 0.01, "propped-cantilever reaction {force2} vs {propped}");
}

/// The door scene (default: 18 control points, 4 clips, a connector): the
/// cable is inserted clipped (every clip holds it), stays clipped while it
/// settles, and at equilibrium under gravity the connector and clips carry
/// the cable's weight exactly (force balance within 1e-6).
#[test]
fn door_scene_hangs_on_its_clips() {
    let p = CableOnClips::default();
    let (asm, lay) = cable_on_clips(&p).unwrap();
    println!("door: clips {:?} m from the laid cable", lay.clip_distances);
    let mut w = world(G);
    let ins = w.insert(&asm).unwrap();
    assert!(ins.clips.iter().all(|&c| w.clip(c).unwrap().held.is_some()), "inserted clipped");
    for _ in 0..50 {
        let rep = w.step().unwrap();
        assert!(rep.events.is_empty(), "{:?}", rep.events);
    }
    let rep = w.relax().unwrap();
    assert!(rep.events.is_empty(), "{:?}", rep.events);
    let weight = p.density * std::f64::consts::PI * p.cable_radius.powi(2) * lay.length * G;
    let mut held = Vector3::zeros();
    for &c in &lay.clamps {
        held += v(w.reaction(ins.constraints[c]).unwrap().force);
    }
    for &c in &ins.clips {
        held += v(w.reaction(w.clip(c).unwrap().held.unwrap().1).unwrap().force);
    }
    println!("door: {} iterations; supports carry {:?} N, weight {weight:.6} N", rep.iterations, held.as_slice());
    assert!((held - Vector3::new(0.0, weight, 0.0)).norm() < 1e-6 * weight, "supports {held:?} vs weight {weight}");
}

/// Forces and moments (about the origin) on one rod from a reaction at `u`.
fn wrench(w: &World, rod: RodHandle, u: f64, con: ConstraintHandle, sign: f64) -> (Vector3<f64>, Vector3<f64>) {
    let r = w.reaction(con).unwrap();
    let (f, m) = (sign * v(r.force), sign * v(r.torque));
    (f, w.rod(rod).unwrap().position(u).unwrap().cross(&f) + m)
}

/// The default harness (6 branches of 2.5–6 mm, 2 junctions, 5
/// connectors) relaxed under gravity: every branch is in equilibrium under
/// its weight and the forces and moments its junctions and connector
/// report — force within 1e-6 of its weight, moment within 1e-6 of weight
/// × size — so the junction forces are the forces the branches carry
/// (at each junction they sum to zero: each link puts Λ on one branch and
/// −Λ on the other).
#[test]
fn harness_junction_forces_balance() {
    let p = Harness::default();
    let (asm, lay) = harness(&p).unwrap();
    let mut w = world(G);
    let ins = w.insert(&asm).unwrap();
    let rep = w.relax().unwrap();
    let n = lay.branches.len();
    let mut force = vec![Vector3::zeros(); n];
    let mut moment = vec![Vector3::zeros(); n];
    let end_u = |w: &World, b: usize, e: BranchEnd| {
        let (u0, u1) = w.rod(ins.rods[lay.branches[b]]).unwrap().domain();
        if e == BranchEnd::Start { u0 } else { u1 }
    };
    for links in &lay.junctions {
        for l in links {
            for (end, sign) in [(l.main, 1.0), (l.other, -1.0)] {
                let rod = ins.rods[lay.branches[end.0]];
                let u = end_u(&w, end.0, end.1);
                for c in [l.position, l.orientation] {
                    let (f, m) = wrench(&w, rod, u, ins.constraints[c], sign);
                    force[end.0] += f;
                    moment[end.0] += m;
                }
            }
        }
    }
    for (k, cons) in lay.connectors.iter().enumerate() {
        let (b, e) = p.connectors[k];
        let rod = ins.rods[lay.branches[b]];
        let u = end_u(&w, b, e);
        for &c in cons {
            let (f, m) = wrench(&w, rod, u, ins.constraints[c], 1.0);
            force[b] += f;
            moment[b] += m;
        }
    }
    for b in 0..n {
        let rod = w.rod(ins.rods[lay.branches[b]]).unwrap();
        let mu = p.density * std::f64::consts::PI * p.radii[b].powi(2);
        let l = lay.lengths[b];
        // Weight and its moment: Simpson over rest arc length.
        let m = 2000;
        let mut wm = Vector3::zeros();
        for i in 0..=m {
            let s = l * i as f64 / m as f64;
            let x = rod.position(rod.u_at_rest_arc_length(s).unwrap()).unwrap();
            let c = if i == 0 || i == m { 1.0 } else if i % 2 == 1 { 4.0 } else { 2.0 };
            wm += c * x.cross(&Vector3::new(0.0, -mu * G, 0.0));
        }
        wm *= l / m as f64 / 3.0;
        let weight = mu * l * G;
        let size = p.branches[b].iter().map(|x| v(*x).norm()).fold(0.0, f64::max).max(l);
        let fres = force[b] + Vector3::new(0.0, -weight, 0.0);
        let mres = moment[b] + wm;
        println!(
            "branch[{b}] (r = {} mm): weight {weight:.4e} N, force residual {:.2e} N, moment residual {:.2e} N·m",
            1e3 * p.radii[b],
            fres.norm(),
            mres.norm()
        );
        assert!(fres.norm() < 1e-6 * weight, "branch[{b}] force residual {fres:?}");
        assert!(mres.norm() < 1e-6 * weight * size, "branch[{b}] moment residual {mres:?}");
    }
    println!("harness: {} iterations, {} multipliers", rep.iterations, w.constraints().map(|(_, c)| c.kind.n_rows()).sum::<usize>());
}

/// Bad input: a clear error naming the argument, nothing built.
#[test]
fn cables_bad_input() {
    let d = CableOnClips::default();
    let cases: Vec<(CableOnClips, &str)> = vec![
        (CableOnClips { path: vec![[0.0; 3]], ..d.clone() }, "path"),
        (CableOnClips { path: vec![[0.0; 3], [0.0; 3]], ..d.clone() }, "path[1]"),
        (CableOnClips { path: vec![[0.0; 3], [f64::NAN, 0.0, 0.0]], ..d.clone() }, "path[1]"),
        (CableOnClips { clip_positions: vec![[5.0, 5.0, 5.0]], ..d.clone() }, "clip_positions[0]"),
        (CableOnClips { clip_positions: vec![[0.2, 1.0, 0.0], [f64::INFINITY, 0.0, 0.0]], ..d.clone() }, "clip_positions[1]"),
        (CableOnClips { clip_radius: 0.0, ..d.clone() }, "clip_radius"),
        (CableOnClips { bend_radius: -1.0, ..d.clone() }, "bend_radius"),
        (CableOnClips { clip_axis: [0.0; 3], ..d.clone() }, "clip_axis"),
        (CableOnClips { clip_resistance: -1.0, ..d.clone() }, "clip_resistance"),
        (CableOnClips { cable_radius: -0.003, ..d.clone() }, "cable_radius"),
        (CableOnClips { young_modulus: 0.0, ..d.clone() }, "young_modulus"),
        (CableOnClips { density: f64::NAN, ..d.clone() }, "density"),
        (CableOnClips { control_points: 2, ..d.clone() }, "control points"),
        (CableOnClips { control_points: usize::MAX, ..d.clone() }, "control_points"),
    ];
    for (p, name) in cases {
        let e = cable_on_clips(&p).expect_err(name).to_string();
        assert!(e.contains(name), "{name}: {e}");
    }
    use BranchEnd::*;
    let h = Harness::default();
    let mut disconnected = h.clone();
    disconnected.junctions[1].truncate(3); // branch 5 hangs alone
    let mut far = h.clone();
    far.branches[3][0] = [0.5, 0.01, 0.0];
    let mut reversed = h.clone();
    reversed.branches[4].reverse();
    reversed.junctions[1][2] = (4, End);
    reversed.connectors[3] = (4, Start);
    let mut twice = h.clone();
    twice.connectors.push((0, Start));
    let mut bent = h.clone();
    bent.branches[4][1] = [0.6, 0.05, 0.0];
    let cases: Vec<(Harness, &str)> = vec![
        (Harness { branches: vec![], radii: vec![], junctions: vec![], connectors: vec![], ..h.clone() }, "branches"),
        (Harness { radii: vec![0.003; 5], ..h.clone() }, "radii"),
        (Harness { radii: vec![0.006, 0.0035, -0.0035, 0.004, 0.003, 0.0025], ..h.clone() }, "radii[2]"),
        (Harness { junctions: vec![vec![(0, Start)]], ..h.clone() }, "junctions[0]"),
        (Harness { junctions: vec![vec![(0, Start), (9, End)]], ..h.clone() }, "junctions[0]"),
        (disconnected, "junctions"),
        (far, "junctions[1]"),
        (reversed, "other way round"),
        (twice, "connectors[5]"),
        (bent, "junctions[1]"),
        (Harness { control_points_per_metre: f64::INFINITY, ..h.clone() }, "control_points_per_metre"),
        (Harness { control_points_per_metre: 1e12, ..h.clone() }, "control_points_per_metre"),
        (Harness { young_modulus: -1.0, ..h.clone() }, "young_modulus"),
        (Harness { bend_radius: 0.0, ..h.clone() }, "bend_radius"),
    ];
    for (p, name) in cases {
        let e = harness(&p).expect_err(name).to_string();
        println!("{name}: {e}");
        assert!(e.contains(name), "{name}: {e}");
    }
}
