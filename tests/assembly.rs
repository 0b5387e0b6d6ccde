//! Assemblies (SPEC §9.0): a structure described as data, inserted in one
//! batch (everything checked first, nothing added on error), queried by
//! group; break policies by tension; a JSON round trip that rebuilds the
//! same world.
mod common;
use common::steel_rod;
use nalgebra::Vector3;
use strandkit::prelude::*;
use strandkit::Event;

const N_RUNGS: usize = 19;

/// Two parallel rails 0.5 m apart, rail a clamped at its start and pinned
/// at its end, rail b free and held by `N_RUNGS` rungs labelled "rung[i]"
/// (relative positions: r_b = r_a + 0.5 y, so tension pulls b towards a);
/// rail b's rest direction reversed when `antiparallel`. A point load
/// `pull` at the free end of rail b, labelled "pull".
fn ladder(antiparallel: bool, pull: [f64; 3], breaking: Option<Breaking>) -> Assembly {
    let mut asm = Assembly::new();
    let a = asm.add_rod(steel_rod(Vector3::zeros(), Vector3::new(2.0, 0.0, 0.0), 21, false), Some("rail[0]"));
    let (b0, b1) = (Vector3::new(0.0, 0.5, 0.0), Vector3::new(2.0, 0.5, 0.0));
    let b = asm.add_rod(if antiparallel { steel_rod(b1, b0, 21, false) } else { steel_rod(b0, b1, 21, false) }, Some("rail[1]"));
    let (u0, u1) = asm.rods[a].rod.domain();
    asm.constrain(a, Position { u: u0, axes: [true, true, true, false], target: [0.0; 4] }).label("clamp[0]");
    asm.constrain(a, Tangent { u: u0, direction: [1.0, 0.0, 0.0] }).label("clamp[1]");
    asm.constrain(a, Position { u: u1, axes: [false, true, true, false], target: [2.0, 0.0, 0.0, 0.0] }).label("pin");
    for i in 0..N_RUNGS {
        let u = u0 + (u1 - u0) * (i as f64 + 0.5) / N_RUNGS as f64;
        let ub = if antiparallel { u0 + u1 - u } else { u };
        let rung = RelativePosition { ua: u, ub, axes: [true, true, true, false], offset: [0.0, -0.5, 0.0, 0.0] };
        // Compliant rungs (1e7 N/m) share the load by their stiffness; hard
        // rungs at every segment would leave its split to the rails' bending.
        let c = asm.link(a, b, rung).compliance(1e-7).label(format!("rung[{i}]"));
        if let Some(br) = breaking {
            c.breaks(br.force, br.policy);
        }
    }
    let tip = if antiparallel { u0 } else { u1 };
    asm.add_load(b, PointForce { rod: RodHandle { index: 0, generation: 0 }, u: tip, force: pull }, Some("pull"));
    asm
}

/// The rungs hold rail b: at equilibrium the forces they exert on rail a,
/// read from the group, add up to the load on rail b — in both directions
/// of rail b, with the same narrow band.
#[test]
fn inserted_ladder_balances_its_load_through_the_group() {
    let pull = [300.0, 2000.0, -500.0];
    let mut bands = Vec::new();
    for antiparallel in [false, true] {
        let mut w = World::new(IntegrationParameters::default());
        let ins = w.insert(&ladder(antiparallel, pull, None)).unwrap();
        assert_eq!((ins.rods.len(), ins.constraints.len(), ins.loads.len()), (2, 3 + N_RUNGS, 1));
        w.relax().unwrap();
        let rungs = w.group_constraints("rung").unwrap();
        assert_eq!(rungs.len(), N_RUNGS);
        assert_eq!(rungs[7].label, "rung[7]");
        let total = rungs.iter().fold(Vector3::zeros(), |s, r| s + Vector3::from(r.force));
        // The force on rail a is −(force on rail b) = the load on b.
        let err = (total - Vector3::from(pull)).norm() / Vector3::from(pull).norm();
        println!("antiparallel {antiparallel}: bandwidth {}, Σ rung forces {total:?} vs load {pull:?} ({err:.1e})", ins.bandwidth);
        assert!(err < 1e-8, "rung forces {total:?} vs load {pull:?}");
        // The group's forces are the reactions of the handles.
        for r in &rungs {
            assert_eq!(w.reaction(r.constraint).unwrap().force, r.force);
            assert!(r.alive && r.broken.is_none());
            assert_eq!(r.tension, w.tension(r.constraint).unwrap());
        }
        // One exact label.
        assert_eq!(w.group_constraints("rung[3]").unwrap().len(), 1);
        bands.push(ins.bandwidth);
    }
    assert!(bands[0] <= 40 && bands[1] <= 40, "bandwidths {bands:?}");
}

/// Rungs that break in tension only: a load pulling rail b away breaks
/// them, reported by label at the equilibrium; pushing it towards rail a
/// breaks none, while the same push breaks rungs measured by magnitude.
#[test]
fn tension_only_rungs_break_under_tension_and_not_under_compression() {
    let run = |per_length: f64, policy: BreakPolicy| {
        let mut asm = ladder(false, [0.0; 3], Some(Breaking::new(400.0, policy)));
        // About 10 kN over 19 rungs: ≈ 530 N each.
        asm.add_load(1, Distributed { rod: RodHandle { index: 0, generation: 0 }, force_per_length: [0.0, per_length, 0.0] }, None);
        let mut w = World::new(IntegrationParameters::default());
        w.insert(&asm).unwrap();
        let events = w.relax().unwrap().events;
        let broken: Vec<(String, f64)> = events
            .iter()
            .filter_map(|e| match e {
                Event::ConstraintBroken { label, force, policy: p, .. } => {
                    assert_eq!(*p, policy);
                    Some((label.clone().unwrap(), *force))
                }
                _ => None,
            })
            .collect();
        let flags: Vec<bool> = w.group_constraints("rung").unwrap().iter().map(|r| r.broken.is_some()).collect();
        (broken, flags, w)
    };
    let (broken, flags, w) = run(5000.0, BreakPolicy::Tension);
    println!("pulled: {} rungs broke: {broken:?}", broken.len());
    assert!(broken.len() >= N_RUNGS / 2, "530 N of tension breaks 400 N rungs");
    for (label, force) in &broken {
        assert!(*force > 400.0);
        let i: usize = label.trim_start_matches("rung[").trim_end_matches(']').parse().unwrap();
        assert!(flags[i], "{label} broken but not flagged");
        let st = &w.group_constraints(label).unwrap()[0];
        assert!(!st.alive && st.broken.unwrap().force == *force && st.position.is_none());
    }
    assert_eq!(flags.iter().filter(|f| **f).count(), broken.len());
    let (broken, _, _) = run(-5000.0, BreakPolicy::Tension);
    assert!(broken.is_empty(), "compressed tension-only rungs broke: {broken:?}");
    let (broken, _, _) = run(-5000.0, BreakPolicy::Compression);
    assert!(broken.len() >= N_RUNGS / 2, "compression breaks compression-only rungs: {broken:?}");
    let (broken, _, _) = run(-5000.0, BreakPolicy::Magnitude);
    assert!(broken.len() >= N_RUNGS / 2, "compressed rungs measured by magnitude must break");
}

/// An Assembly written to JSON and read back is the same Assembly, and
/// inserting either builds the same world.
#[test]
fn json_round_trip_rebuilds_the_same_world() {
    let asm = ladder(true, [1.0, 2.0, 3.0], Some(Breaking::new(5.0, BreakPolicy::Tension)));
    let text = asm.to_json().unwrap();
    let back = Assembly::from_json(&text).unwrap();
    assert_eq!(back.to_json().unwrap(), text);
    let (mut w1, mut w2) = (World::new(IntegrationParameters::default()), World::new(IntegrationParameters::default()));
    w1.insert(&asm).unwrap();
    w2.insert(&back).unwrap();
    w1.step().unwrap();
    w2.step().unwrap();
    assert_eq!(w1.to_json().unwrap(), w2.to_json().unwrap());
}

/// A bad part anywhere refuses the whole assembly, names it, and leaves
/// the world exactly as it was.
#[test]
fn a_bad_assembly_changes_nothing() {
    let mut w = World::new(IntegrationParameters::default());
    w.insert(&ladder(false, [0.0; 3], None)).unwrap();
    w.step().unwrap();
    let before = w.to_json().unwrap();
    let cases: Vec<(&str, Assembly)> = vec![
        ("abscissa outside", {
            let mut a = ladder(false, [0.0; 3], None);
            a.link(0, 1, RelativeDistance { ua: 99.0, ub: 1.0, distance: 0.5 });
            a
        }),
        ("rod index", {
            let mut a = ladder(false, [0.0; 3], None);
            a.link(0, 7, RelativeDistance { ua: 1.0, ub: 1.0, distance: 0.5 });
            a
        }),
        ("linearly dependent", {
            // A plane through the clamp point, normal x: the clamp's x row again.
            let mut a = ladder(false, [0.0; 3], None);
            let (u0, _) = a.rods[0].rod.domain();
            a.constrain(0, Plane { u: u0, origin: [0.0; 3], normal: [1.0, 0.0, 0.0] });
            a
        }),
        ("label", {
            let mut a = ladder(false, [0.0; 3], None);
            a.constraints[3].label = Some("bad label[".into());
            a
        }),
        ("break force", {
            let mut a = ladder(false, [0.0; 3], None);
            a.constraints[4].breaking = Some(Breaking::new(-1.0, BreakPolicy::Magnitude));
            a
        }),
        ("tension policy", {
            let mut a = ladder(false, [0.0; 3], None);
            a.constraints[0].breaking = Some(Breaking::new(1.0, BreakPolicy::Tension));
            a
        }),
        ("bead", {
            let mut a = ladder(false, [0.0; 3], None);
            a.add_bead(1, 0.5, -1.0, 0.0, 0.0, Some("bead[0]"));
            a
        }),
    ];
    for (what, asm) in cases {
        let e = w.insert(&asm).unwrap_err();
        println!("{what}: {e}");
        assert!(matches!(e, Error::InvalidInput { .. } | Error::InvalidHandle { .. }), "{what}: {e:?}");
        assert_eq!(w.to_json().unwrap(), before, "{what}: the world changed");
    }
}
