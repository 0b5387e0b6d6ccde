//! The hot path does not allocate: after a warm-up, `World::step` on a
//! constrained rod makes no heap allocation (DEVELOPERS.md standard;
//! serial assembly — rayon's pool bookkeeping is its own).
#[path = "common/alloc_count.rs"]
mod alloc_count;

#[global_allocator]
static A: alloc_count::Counting = alloc_count::Counting;

mod common;

fn allocations_per_step(w: &mut strandkit::World) -> f64 {
    for _ in 0..3 {
        w.step().unwrap();
    }
    let before = alloc_count::on_this_thread();
    for _ in 0..10 {
        w.step().unwrap();
    }
    (alloc_count::on_this_thread() - before) as f64 / 10.0
}

#[test]
fn steps_do_not_allocate() {
    let mut c = common::cantilever(40, 5, [0.0, -1e4, 0.0]);
    c.world.params.parallel = false;
    c.world.params.gravity = [0.0, -9.81, 0.0];
    let n = allocations_per_step(&mut c.world);
    println!("clamped cantilever: {n} heap allocations per step");
    assert_eq!(n, 0.0);
}

/// Yield and rupture limits (the plastic update runs every step, and the
/// wire yields) do not allocate either once the offsets exist.
#[test]
fn plastic_steps_do_not_allocate() {
    use strandkit::material::StrainLimits;
    let mut c = common::cantilever(40, 5, [0.0, -2e5, 0.0]);
    let w = &mut c.world;
    w.params.parallel = false;
    let limits = StrainLimits::symmetric(1e-3, 0.02, 0.05).unwrap();
    let broken = StrainLimits::symmetric(0.5, 50.0, 50.0).unwrap();
    w.rod_mut(c.rod).unwrap().set_strain_limits(Some(limits), Some(broken)).unwrap();
    let n = allocations_per_step(w);
    let yielded = w.rod(c.rod).unwrap().plastic_offsets().iter().filter(|p| p.kappa2 != 0.0).count();
    println!("plastic cantilever ({yielded} samples yielded): {n} heap allocations per step");
    assert!(yielded > 0);
    assert_eq!(n, 0.0);
}

/// The builders' scenes with beads (a necklace whose beads press on each
/// other over a peg, beads sliding down a spring), with clips (the door
/// cable) and on the sparse path (the bridge and the harness: wide
/// systems) step without allocating once warmed up.
#[test]
fn builder_scenes_do_not_allocate() {
    use strandkit::prelude::*;
    use strandkit::Scheme;
    use strandkit_builders::{beads_on_spring, cable_on_clips, harness, necklace, rope_bridge, BeadsOnSpring, CableOnClips, Harness, Necklace, RopeBridge};
    let scenes = [
        ("necklace over a peg", necklace(&Necklace::default()).unwrap().0, 8e-4),
        ("beads on a spring", beads_on_spring(&BeadsOnSpring::default()).unwrap().0, 1e-3),
        ("cable on a door", cable_on_clips(&CableOnClips::default()).unwrap().0, 3e-3),
        ("rope bridge", rope_bridge(&RopeBridge::default()).unwrap().0, 1e-2),
        ("harness", harness(&Harness::default()).unwrap().0, 3e-3),
    ];
    for (name, asm, dt) in scenes {
        // TR-BDF2 too, but for the door, whose start it steps by halving
        // (a world copy per retry; see tests/schemes.rs).
        for scheme in [Scheme::ImplicitEuler, Scheme::TrBdf2] {
            // TR-BDF2 refuses sliding beads (tests/schemes.rs).
            if scheme == Scheme::TrBdf2 && matches!(name, "cable on a door" | "necklace over a peg" | "beads on a spring") {
                continue;
            }
            let mut w = World::new(IntegrationParameters { gravity: [0.0, -9.81, 0.0], dt, parallel: false, scheme, ..Default::default() });
            w.insert(&asm).unwrap();
            // Long enough a warm-up for the necklace's beads to gather.
            for _ in 0..200 {
                w.step().unwrap();
            }
            let n = allocations_per_step(&mut w);
            println!("{name}, {scheme:?}: {n} heap allocations per step");
            assert_eq!(n, 0.0, "{name}, {scheme:?}");
        }
    }
}

/// A DNA duplex (stacking, hydrogen bonds breaking on their tension
/// averaged over 1 ns) steps without allocating once warmed up: the
/// sparse pattern grows over the first steps as couplings that vanish on
/// the exact helix appear, then holds.
#[test]
fn duplex_steps_do_not_allocate() {
    use strandkit::prelude::*;
    use strandkit_builders::dna::{duplex, Duplex};
    let mut p = Duplex::new("GATTACAGATTA");
    p.break_averaging_time = 1.0;
    let (asm, _) = duplex(&p).unwrap();
    let mut w = World::new(IntegrationParameters { dt: 0.01, viscosity: 1.0, units: strandkit::Units::Molecular, parallel: false, ..Default::default() });
    w.insert(&asm).unwrap();
    for _ in 0..200 {
        w.step().unwrap();
    }
    let n = allocations_per_step(&mut w);
    println!("12 bp duplex: {n} heap allocations per step");
    assert_eq!(n, 0.0);
    // The averages are kept (and so went through the recycled buffer).
    assert!(w.constraints().any(|(_, c)| c.break_measure.is_some()));
}

/// A rope falling through a frictionless ring: the slider changes segment
/// every few steps, which places its rows again (a new layout on the same
/// order of control points), and that allocates nothing either.
#[test]
fn a_slider_changing_segment_does_not_allocate() {
    use strandkit::prelude::*;
    use strandkit::*;
    let rope = RodBuilder::straight(nalgebra::Vector3::new(0.0, 0.0, 0.0), nalgebra::Vector3::new(0.0, -2.0, 0.0))
        .control_points(80)
        .with_roll(false)
        .section(Section::circle(0.002).unwrap())
        .material(Material::preset("nylon").unwrap())
        .build()
        .unwrap();
    let mut w = World::new(IntegrationParameters { dt: 1e-3, gravity: [0.0, -9.81, 0.0], parallel: false, ..Default::default() });
    let h = w.add_rod(rope);
    // The ring near the rope's lower end: the rope falls through it.
    let (_, u1) = w.rod(h).unwrap().domain();
    let y = w.rod(h).unwrap().position(u1 - 1.0).unwrap().y;
    let s = w.add_constraint(h, ConstraintKind::SlidingPoint(SlidingPoint { u: u1 - 1.0, point: [0.0, y, 0.0], friction: 0.0 }), 0.0).unwrap();
    let u_of = |w: &World| match w.constraint(s).unwrap().kind {
        ConstraintKind::SlidingPoint(SlidingPoint { u, .. }) => u,
        _ => unreachable!(),
    };
    for _ in 0..150 {
        w.step().unwrap();
    }
    let (before, u_start) = (alloc_count::on_this_thread(), u_of(&w));
    let mut fallbacks = 0;
    for _ in 0..100 {
        let rep = w.step().unwrap();
        fallbacks += rep.fallbacks as usize + usize::from(rep.factorisation != Factorisation::BandLdlt);
    }
    let (n, u_end) = (alloc_count::on_this_thread() - before, u_of(&w));
    let crossed = (u_end.floor() - u_start.floor()).abs();
    println!("slider from u = {u_start:.2} to {u_end:.2} ({crossed} segment changes): {n} heap allocations in 100 steps, {fallbacks} steps off the band LDLᵀ");
    assert!(crossed >= 3.0, "the slider must change segment in the window: {u_start} → {u_end}");
    assert_eq!(n, 0);
    // Its abscissa (no stiffness of its own on a straight rope) is pivoted
    // after its rows and kept out of their scaling: the symmetric
    // factorisation takes it (it declined every step, falling back to the LU).
    assert_eq!(fallbacks, 0);
}

/// Steps with contact, once their active set has settled, allocate
/// nothing: the detected pairs fill the previous detection's buffer, the
/// obstacle's probes and the pair tests' per-block lists are kept, the
/// contact set saved for a refused step is copied into a kept one, and
/// the rows are put in order without a merge buffer. Two scenes with
/// friction: a rod pressed across another (rod–rod detection, sticking
/// pairs), a rope lying on a slope below the friction angle (a plane) and
/// on level ground made of a triangle mesh (its tree searched on a fixed
/// stack); two rods pressed side by side held by distributed rows.
/// (A step whose active set changes rebuilds the ordering and the layout,
/// which allocates: a change of topology.)
#[test]
fn settled_contact_steps_do_not_allocate() {
    use nalgebra::Vector3;
    use strandkit::prelude::*;
    use strandkit::{Obstacle, RodContacts};
    let r = 0.01;
    let steel = Material::new("steel", 2e11, 0.3, 7800.0).unwrap();
    let rod = |a: Vector3<f64>, b: Vector3<f64>, n: usize, m: &Material| {
        RodBuilder::straight(a, b).control_points(n).with_roll(false).section(Section::circle(r).unwrap()).material(m.clone()).build().unwrap()
    };
    // Rod b pressed onto rod a (both held at their ends), μ = 0.4.
    let mut crossed = World::new(IntegrationParameters { dt: 1e-3, parallel: false, ..Default::default() });
    let a = crossed.add_rod(rod(Vector3::new(-0.5, 0.0, 0.0), Vector3::new(0.5, 0.0, 0.0), 10, &steel));
    let b = crossed.add_rod(rod(Vector3::new(0.0, -0.2, 2.0 * r), Vector3::new(0.0, 0.2, 2.0 * r), 10, &steel));
    for (h, axes) in [(a, [true, true, true, false]), (b, [false, true, false, false])] {
        let (u0, u1) = crossed.rod(h).unwrap().domain();
        for u in [u0, u1] {
            let (p, t) = (crossed.rod(h).unwrap().position(u).unwrap(), crossed.rod(h).unwrap().tangent(u).unwrap());
            crossed.add_constraint(h, ConstraintKind::Position(Position { u, axes, target: [p.x, p.y, p.z, 0.0] }), 0.0).unwrap();
            crossed.add_constraint(h, ConstraintKind::Tangent(Tangent { u, direction: t.into() }), 0.0).unwrap();
        }
    }
    let (u0, u1) = crossed.rod(b).unwrap().domain();
    crossed.add_load(Load::PointForce(PointForce { rod: b, u: 0.5 * (u0 + u1), force: [6.0, 0.0, -20.0] })).unwrap();
    crossed.add_contact_detector(RodContacts::new(0.005, false, true).unwrap().with_friction(0.4).unwrap()).unwrap();
    // A nylon rope across a slope at tan α = 0.9 μ, μ = 0.4.
    let alpha = (0.9f64 * 0.4).atan();
    let n = Vector3::new(alpha.sin(), 0.0, alpha.cos());
    let mut slope = World::new(IntegrationParameters { dt: 2e-3, gravity: [0.0, 0.0, -9.81], parallel: false, ..Default::default() });
    slope.add_rod(rod(n * r, n * r + Vector3::new(0.0, 0.5, 0.0), 20, &Material::new("nylon", 3e9, 0.4, 1140.0).unwrap()));
    slope.add_contact_detector(Obstacle::plane([0.0; 3], n.into()).unwrap().with_margin(0.005).unwrap().with_friction(0.4).unwrap()).unwrap();
    // The rope on level ground made of a two-triangle mesh.
    let mut ground = World::new(IntegrationParameters { dt: 2e-3, gravity: [0.0, 0.0, -9.81], parallel: false, ..Default::default() });
    ground.add_rod(rod(Vector3::new(0.0, 0.0, r), Vector3::new(0.0, 0.5, r), 20, &Material::new("nylon", 3e9, 0.4, 1140.0).unwrap()));
    let mesh = strandkit::TriMesh::new(vec![[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]], vec![[0, 1, 2], [0, 2, 3]]).unwrap();
    ground.add_contact_detector(Obstacle::mesh(mesh).unwrap().with_margin(0.005).unwrap().with_friction(0.4).unwrap()).unwrap();
    // Two rods pressed side by side with distributed rows (a penalty row
    // at every capsule, `RodContacts::with_line_stiffness`), with friction
    // (a spring per row, trimmed each step) and a pull along the rods.
    let mut side = World::new(IntegrationParameters { dt: 1e-3, overdamped: true, viscosity: 10.0, parallel: false, ..Default::default() });
    let rubber = Material::new("rubber", 1e7, 0.45, 1000.0).unwrap();
    let lower = side.add_rod(rod(Vector3::zeros(), Vector3::x(), 12, &rubber));
    let upper = side.add_rod(rod(Vector3::new(0.0, 0.0, 2.002 * r), Vector3::new(1.0, 0.0, 2.002 * r), 12, &rubber));
    side.add_load(Load::Distributed(Distributed { rod: lower, force_per_length: [0.0, 0.0, 200.0] })).unwrap();
    side.add_load(Load::Distributed(Distributed { rod: upper, force_per_length: [30.0, 0.0, -200.0] })).unwrap();
    side.add_contact_detector(RodContacts::new(0.25 * r, false, true).unwrap().with_friction(0.3).unwrap().with_line_stiffness(1e6).unwrap()).unwrap();
    for (name, w) in [("rod pressed across a rod", &mut crossed), ("rope on a slope", &mut slope), ("rope on a mesh", &mut ground), ("rods side by side, distributed rows", &mut side)] {
        for _ in 0..200 {
            w.step().unwrap();
        }
        let active = w.contacts().active().count();
        let n = allocations_per_step(w);
        println!("{name} ({active} active pairs): {n} heap allocations per step");
        assert!(active > 0, "{name}: no contact");
        assert_eq!(n, 0.0, "{name}");
    }
}
