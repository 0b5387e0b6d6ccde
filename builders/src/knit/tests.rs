use super::*;
use strandkit_core::ConstraintKind;

fn small(pattern: Pattern, wales: usize, courses: usize) -> Fabric {
    Fabric { grid: StitchGrid::new(pattern, wales, courses).unwrap(), ..Fabric::default() }
}

/// Rest arc length between two abscissae of a rod (m), by Gauss sums on a fine grid.
fn arc(rod: &Rod, a: f64, b: f64) -> f64 {
    let n = 400;
    (0..n)
        .map(|k| {
            let (u0, u1) = (a + (b - a) * k as f64 / n as f64, a + (b - a) * (k + 1) as f64 / n as f64);
            (rod.position(u1).unwrap() - rod.position(u0).unwrap()).norm()
        })
        .sum()
}

#[test]
fn loops_have_the_requested_length() {
    for (f, tol) in [
        (small(Pattern::Jersey, 5, 4), 5e-3),
        (Fabric { continuous: false, ..small(Pattern::Seed, 5, 4) }, 5e-3),
        (Fabric { boundary: Boundary::Periodic, continuous: false, ..small(Pattern::Rib1x1, 6, 3) }, 5e-3),
        (Fabric { spacing: Some([1.6e-3, 1.1e-3]), loop_length: 6e-3, ..small(Pattern::Garter, 4, 4) }, 5e-3),
    ] {
        let (asm, lay) = fabric(&f).unwrap();
        assert!((lay.loop_length - f.loop_length).abs() < 1e-4 * f.loop_length, "built {} vs {}", lay.loop_length, f.loop_length);
        let mean: f64 = lay.loops.iter().map(|l| arc(&asm.rods[lay.yarns[l.rod]].rod, l.u_start, l.u_end)).sum::<f64>() / lay.loops.len() as f64;
        assert!((mean - f.loop_length).abs() < tol * f.loop_length, "{:?}: built loops {mean} vs {}", f.grid.rows()[0], f.loop_length);
        // Naturally straight yarn: the knitted shape stores bending energy,
        // at least that of its loops' curvature 2π/ℓ on average.
        let b = f.yarn.bending();
        let floor = 0.5 * b * (TAU / f.loop_length).powi(2) * f.loop_length * lay.loops.len() as f64;
        let energy: f64 = asm.rods.iter().map(|r| r.rod.elastic_energy()).sum();
        assert!(energy > floor, "{energy} J vs the loops' {floor} J");
    }
}

/// Smallest distance between yarn centrelines, points closer than 4 radii
/// along a yarn excluded, over 2r — measured on the built rods.
fn built_clearance(asm: &Assembly, r: f64) -> f64 {
    let mut samples: Vec<(usize, f64, Vector3<f64>)> = Vec::new();
    for (k, a) in asm.rods.iter().enumerate() {
        let (u0, u1) = a.rod.domain();
        let n = (a.rod.rest_length() / (0.25 * r)).ceil() as usize;
        let mut s = 0.0;
        let mut prev = a.rod.position(u0).unwrap();
        for q in 0..n {
            let p = a.rod.position(u0 + (u1 - u0) * q as f64 / n as f64).unwrap();
            s += (p - prev).norm();
            prev = p;
            samples.push((k, s, p));
        }
    }
    let mut best = f64::INFINITY;
    for (x, a) in samples.iter().enumerate() {
        for b in &samples[x + 1..] {
            if a.0 == b.0 && (a.1 - b.1).abs() < 4.0 * r {
                continue;
            }
            best = best.min((a.2 - b.2).norm());
        }
    }
    best / (2.0 * r)
}

#[test]
fn yarns_do_not_overlap_as_built() {
    for f in [small(Pattern::Jersey, 4, 4), Fabric { continuous: false, ..small(Pattern::Rib2x2, 4, 3) }, small(Pattern::Garter, 3, 4)] {
        let (asm, lay) = fabric(&f).unwrap();
        let c = built_clearance(&asm, f.yarn.radius);
        assert!(c >= 1.0, "built clearance {c} (model {})", lay.clearance);
    }
}

/// Crossings in the (x, y) projection of two polylines, with z_a − z_b at each.
fn crossings(a: &[Vector3<f64>], b: &[Vector3<f64>]) -> Vec<f64> {
    let mut out = Vec::new();
    for p in a.windows(2) {
        for q in b.windows(2) {
            let (d1, d2) = (p[1] - p[0], q[1] - q[0]);
            let den = d1.x * d2.y - d1.y * d2.x;
            if den.abs() < 1e-30 {
                continue;
            }
            let w = q[0] - p[0];
            let (s, t) = ((w.x * d2.y - w.y * d2.x) / den, (w.x * d1.y - w.y * d1.x) / den);
            if (0.0..1.0).contains(&s) && (0.0..1.0).contains(&t) {
                out.push((p[0].z + s * d1.z) - (q[0].z + t * d2.z));
            }
        }
    }
    out
}

fn polyline(rod: &Rod, a: f64, b: f64) -> Vec<Vector3<f64>> {
    (0..=200).map(|k| rod.position(a + (b - a) * k as f64 / 200.0).unwrap()).collect()
}

#[test]
fn each_loop_is_pulled_through_the_loop_below_on_its_side() {
    // Seed mixes every neighbour relation: knit over knit, purl over knit, …
    for pattern in [Pattern::Seed, Pattern::Jersey, Pattern::Rib2x2] {
        let f = small(pattern, 4, 4);
        let (asm, lay) = fabric(&f).unwrap();
        let nw = f.grid.wales();
        for j in 0..f.grid.courses() - 1 {
            for i in 0..nw {
                let (below, above) = (&lay.loops[j * nw + i], &lay.loops[(j + 1) * nw + i]);
                let rod = |l: &LoopSpan| &asm.rods[lay.yarns[l.rod]].rod;
                let dz = crossings(&polyline(rod(above), above.u_start, above.u_end), &polyline(rod(below), below.u_start, below.u_end));
                // Along the loop above: its sinker passes the leg below, its
                // legs the head below on the stitch's side, its other
                // sinker the other leg: signs −s, +s, +s, −s.
                let s = f.grid.get(i, j + 1).sign();
                let signs: Vec<f64> = dz.iter().map(|d| d.signum()).collect();
                assert_eq!(signs, vec![-s, s, s, -s], "{pattern:?} loop ({i},{}) over ({i},{j}): dz {dz:?}", j + 1);
                for d in dz {
                    assert!(d.abs() > 1.9 * f.yarn.radius, "{pattern:?} ({i},{j}): crossing at |dz| = {d:e}");
                }
            }
        }
    }
}

#[test]
fn edges_and_tube() {
    let f = Fabric { boundary: Boundary::ClampedEdges, ..small(Pattern::Jersey, 5, 3) };
    let (asm, lay) = fabric(&f).unwrap();
    // The clamps hold the last heads: no bind-off links besides.
    assert_eq!(lay.bind_off.len(), 0);
    assert_eq!(lay.clamps.len(), 2 * 5 + 1);
    // They hold the first sinkers too; the turns and the yarn's ends are tied.
    assert_eq!((lay.cast_on.len(), lay.selvedge.len(), lay.yarn_ends.len()), (0, 2, 2));
    let free = Fabric { boundary: Boundary::Free, ..f.clone() };
    let (fa, fl) = fabric(&free).unwrap();
    assert_eq!((fl.bind_off.len(), fl.cast_on.len(), fl.selvedge.len(), fl.yarn_ends.len()), (4, 5, 2, 2));
    // Every edge link joins the points it names at their distance as built:
    // the cast-on's consecutive sinkers, each turn's ends on its side, each
    // yarn end and the head of its loop.
    let rod = &fa.rods[0].rod;
    let (u0, u1) = rod.domain();
    let at = |i: usize, j: usize| fl.loops[j * 5 + i];
    let expect = |k: usize, ua: f64, ub: f64| {
        let ConstraintKind::RelativeDistance(d) = &fa.constraints[k].kind else { panic!("edge {k} is a distance link") };
        assert_eq!((d.ua, d.ub), (ua, ub), "edge {k}");
        let built = (rod.position(ua).unwrap() - rod.position(ub).unwrap()).norm();
        assert!((d.distance - built).abs() < 1e-15 && built > 0.1 * fl.model.wale_spacing, "edge {k}: {} vs {built}", d.distance);
    };
    for i in 0..4 {
        expect(fl.cast_on[i], at(i, 0).u_start, at(i + 1, 0).u_start);
    }
    expect(fl.cast_on[4], at(4, 0).u_start, at(4, 0).u_end);
    expect(fl.selvedge[0], at(4, 0).u_end, at(4, 1).u_start);
    expect(fl.selvedge[1], at(0, 1).u_end, at(0, 2).u_start);
    expect(fl.yarn_ends[0], u0, at(0, 0).u_head);
    // Three courses: the last runs left to right and ends at wale 4.
    expect(fl.yarn_ends[1], u1, at(4, 2).u_head);
    // Switched off, none of them; one yarn per course has two ends each and no turns.
    let bare = Fabric { cast_on: false, selvedge: false, fasten_ends: false, bind_off: false, ..free.clone() };
    assert_eq!(fabric(&bare).unwrap().0.constraints.len(), 0);
    let courses = fabric(&Fabric { continuous: false, ..free.clone() }).unwrap().1;
    assert_eq!((courses.selvedge.len(), courses.yarn_ends.len()), (0, 6));
    assert_eq!(asm.rods.len(), 1);
    let t = Fabric { boundary: Boundary::Periodic, continuous: false, ..small(Pattern::Jersey, 8, 3) };
    let (asm, lay) = fabric(&t).unwrap();
    assert_eq!(asm.rods.len(), 3);
    assert!(asm.rods.iter().all(|r| r.rod.is_closed()));
    assert_eq!(lay.bind_off.len(), 8);
    // A ring of cast-on links, no sides and no ends.
    assert_eq!((lay.cast_on.len(), lay.selvedge.len(), lay.yarn_ends.len()), (8, 0, 0));
    // The rings' mean radius is the tube's, their loops' depth averaging out.
    let rod = &asm.rods[1].rod;
    let (u0, u1) = rod.domain();
    let mean: f64 = (0..800).map(|k| { let p = rod.position(u0 + (u1 - u0) * k as f64 / 800.0).unwrap(); (p.x * p.x + p.z * p.z).sqrt() }).sum::<f64>() / 800.0;
    assert!((mean - lay.tube_radius).abs() < 0.02 * lay.tube_radius, "{mean} vs {}", lay.tube_radius);
}

/// The cell: one yarn spiralling a course per turn, and its image one
/// period (courses × c) up, tied to it at every Greville abscissa and
/// joined to its end in position and tangent; no edge links.
#[test]
fn the_cell_is_a_spiral_yarn_and_its_image_one_period_up() {
    let f = Fabric { boundary: Boundary::Cell, ..small(Pattern::Jersey, 8, 3) };
    let (asm, lay) = fabric(&f).unwrap();
    let (yarn, image) = (&asm.rods[lay.yarns[0]].rod, &asm.rods[lay.image.unwrap()].rod);
    assert_eq!((asm.rods.len(), lay.yarns.len()), (2, 1));
    assert!(!yarn.is_closed() && !image.is_closed());
    let edges = [&lay.bind_off, &lay.cast_on, &lay.selvedge, &lay.yarn_ends, &lay.clamps];
    assert!(edges.iter().all(|e| e.is_empty()), "a cell has no edge");
    assert_eq!((lay.image_ties.len(), lay.junction.len()), (yarn.n_ctrl() - 1, 2));
    assert_eq!(asm.constraints.len(), yarn.n_ctrl() + 1);
    // Every control point one period up, and the image starts where the yarn ends.
    let period = Vector3::new(0.0, 3.0 * lay.model.course_spacing, 0.0);
    let (q, qi) = (yarn.coords(), image.coords());
    for k in 0..yarn.n_ctrl() {
        let d = Vector3::from_fn(|i, _| qi[k * yarn.dofs() + i] - q[k * yarn.dofs() + i]);
        assert!((d - period).norm() < 1e-15 * period.norm().max(1.0) + 1e-15, "control point {k}: {d:?}");
    }
    let ((u0, u1), r) = (yarn.domain(), f.yarn.radius);
    assert!((yarn.position(u1).unwrap() - image.position(u0).unwrap()).norm() < 1e-6 * r);
    let bend = yarn.tangent(u1).unwrap().angle(&image.tangent(u0).unwrap());
    assert!(bend < 0.05, "the yarn runs on into its image: the tangents {bend} rad apart");
    // The spiral rises a course per turn: loop (i, j) is loop (i, 0) moved
    // j courses up (to 0.06 c: the heads' marks drift along the yarn).
    let head = |l: &LoopSpan| yarn.position(l.u_head).unwrap();
    for (k, l) in lay.loops.iter().enumerate().skip(8) {
        let rise = head(l) - head(&lay.loops[k % 8]);
        let want = (k / 8) as f64 * lay.model.course_spacing;
        assert!((rise - Vector3::new(0.0, want, 0.0)).norm() < 0.1 * lay.model.course_spacing, "loop {k}: {rise:?}");
    }
    // Half the modulus and density each: the two count the yarn once.
    let full = f.yarn.material().unwrap();
    for rod in [yarn, image] {
        assert_eq!((rod.material().young, rod.material().density), (0.5 * full.young, 0.5 * full.density));
    }
    let (ey, ei) = (yarn.elastic_energy(), image.elastic_energy());
    assert!((ey - ei).abs() < 1e-9 * ey, "a translated copy has the same energy: {ey} vs {ei}");
}

#[test]
fn bad_fabrics_are_refused_before_building() {
    let d = Fabric::default();
    let cases: Vec<(Fabric, &str)> = vec![
        (Fabric { loop_length: 1e-3, ..d.clone() }, "loop_length"),
        (Fabric { loop_length: f64::NAN, ..d.clone() }, "loop_length"),
        (Fabric { loop_length: -5e-3, ..d.clone() }, "loop_length"),
        (Fabric { yarn: Yarn { radius: f64::INFINITY, ..d.yarn.clone() }, ..d.clone() }, "radius"),
        (Fabric { spacing: Some([f64::NAN, 1e-3]), ..d.clone() }, "wale spacing"),
        (Fabric { spacing: Some([1e-4, 1e-4]), ..d.clone() }, "loop_length"),
        (Fabric { boundary: Boundary::Periodic, ..d.clone() }, "continuous"),
        (Fabric { control_points_per_loop: 2, ..d.clone() }, "control_points_per_loop"),
        (Fabric { control_points_per_loop: usize::MAX, ..d.clone() }, "control points"),
        (Fabric { boundary: Boundary::Periodic, continuous: false, ..small(Pattern::Jersey, 2, 3) }, "wales"),
        (Fabric { boundary: Boundary::Cell, continuous: false, ..d.clone() }, "continuous"),
        (Fabric { boundary: Boundary::Cell, ..small(Pattern::Jersey, 2, 3) }, "wales"),
    ];
    for (f, what) in cases {
        let e = fabric(&f).unwrap_err().to_string();
        assert!(e.contains(what), "expected an error naming {what}, got {e}");
    }
    // Tight loops for the yarn: the clearance check (not the rough 16 r bound).
    let tight = Fabric { loop_length: 17.0 * d.yarn.radius, ..d.clone() };
    let e = fabric(&tight).unwrap_err().to_string();
    assert!(e.contains("overlap"), "{e}");
}

