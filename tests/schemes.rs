//! Issue 13: the second-order schemes (trapezoidal rule, TR-BDF2) beside
//! implicit Euler — energy of a free rod in flight, the cantilever's first
//! mode, order of convergence, the schemes with constraints, beads, clips
//! and quasi-dynamic frames.
mod common;
use nalgebra::Vector3;
use strandkit::prelude::*;
use strandkit::{Mode, QuasiDynamic, QuasiDynamicParameters, Scheme};

/// `common::spinning_free_rod`: (kinetic + elastic) energy after each step.
fn free_rod_energies(scheme: Scheme, roll: bool, dt: f64, steps: usize) -> Vec<f64> {
    let rod = common::spinning_free_rod(roll);
    let mut w = World::new(IntegrationParameters { dt, parallel: false, scheme, ..Default::default() });
    let h = w.add_rod(rod);
    let total = |w: &World| {
        let r = w.rod(h).unwrap();
        r.kinetic_energy() + r.elastic_energy()
    };
    let mut e = vec![total(&w)];
    let mut solves = 0;
    for _ in 0..steps {
        solves += w.step().unwrap().solves;
        e.push(total(&w));
    }
    println!("{scheme:?} dt {dt}: {:.2} solves per step", solves as f64 / steps as f64);
    e
}

/// Issue 13, check 2: a free rod in flight (no damping, no gravity) keeps
/// its energy within 1 % over 1000 steps with the trapezoidal rule
/// (measured 0.30 % at dt = 1e-3 s; 2.8 % at 3e-3 s), where implicit Euler
/// loses 70 % and TR-BDF2, which damps the unresolved modes the initial
/// shape excites, 12 %. (Roll off: with the Frenet model the twist is
/// singular at inflections, which the undamped rule does not survive.)
#[test]
fn free_rod_in_flight_keeps_its_energy_with_the_trapezoidal_rule() {
    let dt = 1e-3;
    let trap = free_rod_energies(Scheme::Trapezoidal, false, dt, 1000);
    let euler = free_rod_energies(Scheme::ImplicitEuler, false, dt, 1000);
    let tb = free_rod_energies(Scheme::TrBdf2, false, dt, 1000);
    let dev = trap.iter().map(|e| (e / trap[0] - 1.0).abs()).fold(0.0, f64::max);
    println!("dt {dt}: trapezoidal max |ΔE|/E0 = {dev:.3e}; kept: implicit Euler {:.3}, TR-BDF2 {:.3}", euler[1000] / euler[0], tb[1000] / tb[0]);
    assert!(dev < 0.01, "trapezoidal energy drift {dev}");
    assert!(euler[1000] < 0.5 * euler[0]);
    assert!(tb.windows(2).all(|w| w[1] <= w[0] * (1.0 + 1e-9)), "TR-BDF2 raised the free rod's energy");
}

/// The SPEC §10 cantilever (steel, L = 4 m, R = 5 cm, clamped) with `n`
/// control points, released from its first Euler–Bernoulli mode shape
/// (1 cm at the tip, no gravity). Returns the world, the rod and ω1 (rad/s).
fn cantilever_in_first_mode(n: usize, scheme: Scheme) -> (World, RodHandle, f64) {
    let (len, r, e, rho) = (4.0f64, 0.05f64, 200e9, 7800.0);
    let bl = 1.875104068711961f64; // first root of cos βL cosh βL = −1
    let sigma = (bl.sinh() - bl.sin()) / (bl.cosh() + bl.cos());
    let phi = move |x: f64| {
        let b = bl * x / len;
        (b.cosh() - b.cos() - sigma * (b.sinh() - b.sin())) / 2.0 // 1 at the tip
    };
    let a = 0.01;
    let shaped = RodBuilder::curve(len, move |x| Vector3::new(x, a * phi(x), 0.0))
        .control_points(n)
        .section(Section::circle(r).unwrap())
        .material(Material::new("steel", e, 0.3, rho).unwrap())
        .build()
        .unwrap();
    let mut c = common::scenarios::cantilever(n, 5, [0.0; 3]).unwrap();
    c.world.params.scheme = scheme;
    c.world.params.parallel = false;
    let rod = c.world.rod_mut(c.rod).unwrap();
    let (dr, ds) = (rod.dofs(), shaped.dofs());
    let mut q = rod.coords().to_vec();
    for i in 0..rod.n_ctrl() {
        for k in 0..3 {
            q[i * dr + k] = shaped.coords()[i * ds + k];
        }
    }
    rod.set_coords(&q).unwrap();
    let (area, inertia) = (std::f64::consts::PI * r * r, std::f64::consts::PI * r.powi(4) / 4.0);
    let omega = bl * bl * (e * inertia / (rho * area * len.powi(4))).sqrt();
    (c.world, c.rod, omega)
}

/// Tip deflection y over `periods` periods of 2π/ω with `per_period` steps
/// each: (period from the zero crossings, amplitude of the first and of
/// the last period).
fn vibrate(w: &mut World, rod: RodHandle, omega: f64, per_period: usize, periods: usize) -> (f64, f64, f64) {
    let period = 2.0 * std::f64::consts::PI / omega;
    let dt = period / per_period as f64;
    w.params.dt = dt;
    let tip_y = |w: &World| {
        let r = w.rod(rod).unwrap();
        r.position(r.domain().1).unwrap().y
    };
    let (mut ys, mut crossings) = (vec![tip_y(w)], Vec::new());
    for _ in 0..per_period * periods {
        w.step().unwrap();
        let (prev, y) = (*ys.last().unwrap(), tip_y(w));
        if prev > 0.0 && y <= 0.0 || prev < 0.0 && y >= 0.0 {
            crossings.push(w.time() - dt * y / (y - prev));
        }
        ys.push(y);
    }
    let measured = 2.0 * (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let amp = |s: &[f64]| s.iter().fold(0.0f64, |m, y| m.max(y.abs()));
    (measured, amp(&ys[..=per_period]), amp(&ys[ys.len() - 1 - per_period..]))
}

/// Issue 13, check 1: at 20 steps per period the trapezoidal rule keeps the
/// first mode's amplitude over 10 periods (≥ 98 %; implicit Euler keeps
/// little) and lengthens its period by the rule's own factor ωh/(2 atan(ωh/2))
/// (0.82 % at 20 steps); at 26 steps the period is within 0.5 % of
/// Euler–Bernoulli. TR-BDF2 at 20 steps keeps ≥ 98 % (99.2 %) with the
/// period within 0.5 % (+0.40 %). The spline model itself (200 steps per
/// period) is within 0.1 % of Euler–Bernoulli (+0.008 %).
#[test]
fn cantilever_first_mode_keeps_its_amplitude_with_the_trapezoidal_rule() {
    let (mut w, rod, omega) = cantilever_in_first_mode(16, Scheme::Trapezoidal);
    let exact = 2.0 * std::f64::consts::PI / omega;
    let (model, a0, a1) = vibrate(&mut w, rod, omega, 200, 3);
    println!("model period {model:.6} s vs Euler–Bernoulli {exact:.6} s ({:+.3} %); amplitude {a0:.5} -> {a1:.5}", 100.0 * (model / exact - 1.0));
    assert!((model / exact - 1.0).abs() < 1e-3);
    for (scheme, per_period) in [(Scheme::Trapezoidal, 20usize), (Scheme::Trapezoidal, 26), (Scheme::TrBdf2, 20), (Scheme::ImplicitEuler, 20)] {
        let (mut w, rod, omega) = cantilever_in_first_mode(16, scheme);
        let (period, a0, a1) = vibrate(&mut w, rod, omega, per_period, 10);
        let wh = 2.0 * std::f64::consts::PI / per_period as f64;
        let rule = wh / (2.0 * (wh / 2.0).atan());
        println!(
            "{scheme:?}, {per_period} steps per period: amplitude kept {:.2} %, period {:+.3} % (Euler–Bernoulli), {:+.3} % (model), rule {:+.3} %",
            100.0 * a1 / a0,
            100.0 * (period / exact - 1.0),
            100.0 * (period / model - 1.0),
            100.0 * (rule - 1.0)
        );
        match scheme {
            Scheme::Trapezoidal => {
                assert!(a1 / a0 >= 0.98, "amplitude kept {}", a1 / a0);
                assert!((period / model / rule - 1.0).abs() < 1e-3, "period {period} vs model {model} × rule {rule}");
                if per_period == 26 {
                    assert!((period / exact - 1.0).abs() < 5e-3);
                }
            }
            Scheme::ImplicitEuler => assert!(a1 / a0 < 0.1, "implicit Euler kept {}", a1 / a0),
            // Both of issue 13's figures at 20 steps per period.
            Scheme::TrBdf2 => assert!(a1 / a0 >= 0.98 && (period / exact - 1.0).abs() < 5e-3, "TR-BDF2: {} {period}", a1 / a0),
        }
    }
}

/// PyElastica's flexible swinging pendulum (examples/FlexibleSwingingPendulumCase):
/// L = 1 m, r = 5 mm, ρ = 1100 kg/m³, E = 5 MPa, hinged at its top,
/// released horizontal under gravity along −x. Tip position after 1 s.
fn flexible_pendulum_tip(scheme: Scheme, dt: f64, n_ctrl: usize) -> Vector3<f64> {
    let rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(0.0, 0.0, 1.0))
        .control_points(n_ctrl)
        .with_roll(false)
        .section(Section::circle(0.005).unwrap())
        .material(Material::new("pendulum", 5e6, 0.499, 1100.0).unwrap())
        .build()
        .unwrap();
    let u0 = rod.domain().0;
    let mut w = World::new(IntegrationParameters { dt, gravity: [-9.80665, 0.0, 0.0], parallel: false, scheme, ..Default::default() });
    let h = w.add_rod(rod);
    w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true, true, true, false], target: [0.0; 4] }), 0.0).unwrap();
    let steps = (1.0 / dt).round() as usize;
    for _ in 0..steps {
        w.step().unwrap();
    }
    let r = w.rod(h).unwrap();
    r.position(r.domain().1).unwrap()
}

/// Issue 13, check 3: at 1 s the trapezoidal rule reaches 2 mm tip
/// accuracy with a step 20× larger than implicit Euler needs. Reference:
/// the same model with the trapezoidal rule at dt = 5e-5 s (4.5e-7 m from
/// dt = 2.5e-5 s). Measured: implicit Euler 2.6 mm at dt = 1e-4 s (it needs
/// ≈ 7e-5 s for 2 mm); trapezoidal 0.18 mm at 1e-3 s, 0.58 mm at 2e-3 s;
/// TR-BDF2 0.09 mm at 1e-3 s, 0.32 mm at 2e-3 s.
#[test]
fn flexible_pendulum_reaches_2_mm_with_a_20x_larger_step() {
    let n = 16;
    let reference = flexible_pendulum_tip(Scheme::Trapezoidal, 5e-5, n);
    let euler = (flexible_pendulum_tip(Scheme::ImplicitEuler, 1e-4, n) - reference).norm();
    let trap10 = (flexible_pendulum_tip(Scheme::Trapezoidal, 1e-3, n) - reference).norm();
    let trap20 = (flexible_pendulum_tip(Scheme::Trapezoidal, 2e-3, n) - reference).norm();
    let trap5 = (flexible_pendulum_tip(Scheme::Trapezoidal, 5e-4, n) - reference).norm();
    let tb20 = (flexible_pendulum_tip(Scheme::TrBdf2, 2e-3, n) - reference).norm();
    let tb10 = (flexible_pendulum_tip(Scheme::TrBdf2, 1e-3, n) - reference).norm();
    println!("TR-BDF2: dt 2e-3 {tb20:.3e} m, 1e-3 {tb10:.3e} m");
    assert!(tb20 < 2e-3 && tb20 / tb10 > 3.0, "TR-BDF2 {tb20} {tb10}");
    println!("tip error at 1 s: implicit Euler dt 1e-4 {euler:.3e} m; trapezoidal dt 2e-3 {trap20:.3e} m, 1e-3 {trap10:.3e} m, 5e-4 {trap5:.3e} m");
    assert!(euler > 2e-3, "implicit Euler already within 2 mm at 1e-4 s: {euler}");
    assert!(trap10 < 5e-4 && trap20 < 2e-3, "trapezoidal {trap10}, {trap20}");
    // Second order: halving the step divides the error by ≈ 4 (3.3–3.4 here).
    assert!(trap20 / trap10 > 3.0 && trap10 / trap5 > 3.0, "order: {trap20} {trap10} {trap5}");
}

/// The builders' scenes step with TR-BDF2 (sliders, clips, relative
/// orientations, many constraints; `adaptive_dt` on) and their mechanical
/// energy (gravity included) ends below where it began, no step raising it
/// by more than 0.5 % of |E0| (measured: bridge 3.7e-2 of 354, harness
/// 1.3e-4 of 0.35; implicit Euler, for comparison, 0, 0). The cable on the
/// door is printed, not asserted: its laid cable starts with ≈ 1 J of local
/// strain, and TR-BDF2 ends that transient above where it began (issue 13
/// notes). The trapezoidal rule is not run here: with curved constraints
/// its undamped constraint chatter blows up (see `Scheme::Trapezoidal`).
/// The scenes with sliding beads (necklace, spring) are refused by both
/// second-order schemes with a clear error, the world unchanged (a bead's
/// abscissa is an unknown of implicit Euler steps only). When the beads'
/// motion was a first-order update beside the step it pumped energy in
/// (this test ran them 300
/// steps, which the necklace survived; over 2000 steps, TR-BDF2: the
/// necklace with 6–14 beads went from −0.01…−0.03 J to 1–45 J before its
/// Newton iterations failed at steps 235–368, one bead alone to 67 J by
/// step 203, the spring to 4.4e-2 J from −3.1e-3 J by step 446; the
/// trapezoidal rule alike; knotted beads and beads of 10 mg stay below
/// their start).
#[test]
fn builder_scenes_step_with_tr_bdf2() {
    use strandkit_builders::{beads_on_spring, cable_on_clips, harness, necklace, rope_bridge, BeadsOnSpring, CableOnClips, Harness, Necklace, RopeBridge};
    let scenes = [
        ("cable on a door", cable_on_clips(&CableOnClips::default()).unwrap().0, 3e-3, false),
        ("rope bridge", rope_bridge(&RopeBridge::default()).unwrap().0, 1e-2, true),
        ("harness", harness(&Harness::default()).unwrap().0, 3e-3, true),
    ];
    for (name, asm, dt, assert) in scenes {
        for scheme in [Scheme::ImplicitEuler, Scheme::TrBdf2] {
            let mut w = World::new(IntegrationParameters { gravity: [0.0, -9.81, 0.0], dt, parallel: false, scheme, adaptive_dt: true, ..Default::default() });
            w.insert(&asm).unwrap();
            let e0 = w.energy().unwrap().total();
            let (mut rise, mut solves, mut prev) = (0.0f64, 0u32, e0);
            for _ in 0..300 {
                solves += w.step().unwrap().solves;
                let e = w.energy().unwrap().total();
                rise = rise.max(e - prev);
                prev = e;
            }
            println!("{name}, {scheme:?}: energy {e0:.4e} -> {prev:.4e} J, largest rise in a step {rise:.2e} J, {:.2} solves per step", solves as f64 / 300.0);
            if assert {
                assert!(prev <= e0 && rise <= 5e-3 * e0.abs(), "{name}, {scheme:?}");
            }
        }
    }
    // Sliding beads: refused by name, the world unchanged; knotted beads step.
    for (name, asm, dt) in [
        ("necklace over a peg", necklace(&Necklace::default()).unwrap().0, 8e-4),
        ("beads on a spring", beads_on_spring(&BeadsOnSpring::default()).unwrap().0, 1e-3),
    ] {
        for scheme in [Scheme::TrBdf2, Scheme::Trapezoidal] {
            let mut w = World::new(IntegrationParameters { gravity: [0.0, -9.81, 0.0], dt, parallel: false, scheme, adaptive_dt: true, ..Default::default() });
            w.insert(&asm).unwrap();
            let state = |w: &World| -> (Vec<f64>, Vec<(f64, f64)>, f64) {
                (w.rods().flat_map(|(_, r)| r.coords().to_vec()).collect(), w.beads().map(|(_, b)| (b.u, b.velocity)).collect(), w.time())
            };
            let before = state(&w);
            let err = w.step().unwrap_err().to_string();
            println!("{name}, {scheme:?}: {err}");
            assert!(err.contains("sliding beads") && err.contains("implicit_euler"), "{name}, {scheme:?}: {err}");
            assert_eq!(state(&w), before, "{name}, {scheme:?}: the world changed");
        }
    }
    let mut w = World::new(IntegrationParameters { gravity: [0.0, -9.81, 0.0], dt: 8e-4, parallel: false, scheme: Scheme::TrBdf2, adaptive_dt: true, ..Default::default() });
    w.insert(&necklace(&Necklace { knotted: true, ..Default::default() }).unwrap().0).unwrap();
    let e0 = w.energy().unwrap().total();
    let mut rise = 0.0f64;
    let mut prev = e0;
    for _ in 0..2000 {
        w.step().unwrap();
        let e = w.energy().unwrap().total();
        rise = rise.max(e - prev);
        prev = e;
    }
    println!("knotted necklace, TR-BDF2, 2000 steps: energy {e0:.4e} -> {prev:.4e} J, largest rise in a step {rise:.2e} J");
    assert!(prev <= e0 && rise <= 5e-3 * e0.abs(), "knotted necklace: {e0} -> {prev}, rise {rise}");
}

/// Quasi-dynamic frames (algorithm 11) with TR-BDF2 as the dynamic scheme:
/// the cantilever under a tip load swings (dynamic frames), switches to
/// quasi-static when the scripted frame cost passes 95 % of the budget,
/// converges to the relaxed tip (1e-4 m), and back to dynamic frames with
/// the V = Δq/Δt hand-over: nothing refused, the motion continuous across
/// both switches (ratio ≤ 1.5).
#[test]
fn quasi_dynamic_frames_run_with_tr_bdf2() {
    struct Clock {
        t: f64,
        calls: usize,
    }
    impl strandkit::Clock for Clock {
        fn now(&mut self) -> f64 {
            if self.calls % 2 == 1 {
                let frame = self.calls / 2;
                // Frames 0–9 cheap, 10–49 over budget, then cheap again.
                self.t += if (10..50).contains(&frame) { 0.01 } else { 0.005 };
            }
            self.calls += 1;
            self.t
        }
    }
    let mut c = common::cantilever(10, 5, [0.0, -1e4, 0.0]);
    let w = &mut c.world;
    w.params.parallel = false;
    w.params.scheme = Scheme::TrBdf2;
    let params = QuasiDynamicParameters { dt0: 1e-3, time_budget: Some(0.01), ..Default::default() };
    let mut qd = QuasiDynamic::new(w, params).unwrap();
    let mut clock = Clock { t: 0.0, calls: 0 };
    let (mut modes, mut motions, mut tip_50) = (Vec::new(), Vec::new(), Vector3::zeros());
    for k in 0..70 {
        let r = qd.step(w, &mut clock).unwrap();
        modes.push(r.mode);
        motions.push(r.motion);
        if k == 50 {
            tip_50 = common::tip(w, c.rod).0;
        }
    }
    assert!(modes[..11].iter().all(|m| *m == Mode::Dynamic) && modes[11..51].iter().all(|m| *m == Mode::QuasiStatic));
    assert!(modes[51..].iter().all(|m| *m == Mode::Dynamic));
    let mut reference = common::cantilever(10, 5, [0.0, -1e4, 0.0]);
    reference.world.relax().unwrap();
    let off = (tip_50 - common::tip(&reference.world, reference.rod).0).norm();
    let (r1, r2) = (motions[11] / motions[10], motions[51] / motions[50]);
    println!("TR-BDF2 quasi-dynamic: tip {off:.2e} m from relaxed after 40 static frames; motion ratios at the switches {r1:.3}, {r2:.3}");
    assert!(off < 1e-4 && r1 <= 1.5 && r2 <= 1.5);
}

/// `common::spinning_free_rod`'s rubber rod, straight along x from the
/// origin (1 m, r = 1 cm, 0.31 kg), moving at (0.1, 0.05, 0) m/s.
fn moving_rubber_rod() -> Rod {
    let mut rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0))
        .control_points(15)
        .with_roll(false)
        .section(Section::circle(0.01).unwrap())
        .material(Material::new("rubber", 1e6, 0.45, 1000.0).unwrap())
        .build()
        .unwrap();
    let v: Vec<f64> = (0..rod.coords().len()).map(|i| [0.1, 0.05, 0.0][i % 3]).collect();
    rod.set_velocities(&v).unwrap();
    rod
}

/// The moving rubber rod tied by its start to a fixed point through a
/// compliant position constraint (α = 3e-3 m/N: a 333 N/m spring, ~33
/// rad/s on the rod's 0.31 kg): it pulls the spring, swings and bends.
/// (kinetic + elastic + ½ α|Λ|²) after each step, Λ the multipliers.
fn rod_on_a_compliant_tie(scheme: Scheme, dt: f64, steps: usize) -> Vec<f64> {
    let rod = moving_rubber_rod();
    let alpha = 3e-3;
    let mut w = World::new(IntegrationParameters { dt, parallel: false, scheme, ..Default::default() });
    let h = w.add_rod(rod);
    let u = w.rod(h).unwrap().domain().0;
    let tie = w.add_constraint(h, strandkit::constraint::kinds::Position { u, axes: [true, true, true, false], target: [0.0; 4] }, alpha).unwrap();
    let total = |w: &World| {
        let r = w.rod(h).unwrap();
        let l = &w.constraint(tie).unwrap().multipliers;
        r.kinetic_energy() + r.elastic_energy() + 0.5 * alpha * l.iter().map(|x| x * x).sum::<f64>()
    };
    let mut e = vec![total(&w)];
    for _ in 0..steps {
        w.step().unwrap();
        e.push(total(&w));
    }
    e
}

/// A compliant constraint is an elastic energy ½ g²/α, and the
/// trapezoidal rule averages its force over the step like the rods' (half
/// at the start, half at the end), so a rod on a compliant tie keeps its
/// energy. Measured over 2000 steps of 1 ms (~10 spring periods):
/// trapezoidal max |ΔE|/E0 7.9e-6 (asserted < 1 %). With the tie's whole
/// force at the step's end, as before, the energy swung between 0.71 and
/// 2.47 E0 (the scheme was neither the trapezoidal rule nor dissipative);
/// implicit Euler keeps 0.354 (asserted < 0.5).
#[test]
fn a_rod_on_a_compliant_tie_keeps_its_energy_with_the_trapezoidal_rule() {
    let trap = rod_on_a_compliant_tie(Scheme::Trapezoidal, 1e-3, 2000);
    let euler = rod_on_a_compliant_tie(Scheme::ImplicitEuler, 1e-3, 2000);
    let dev = trap.iter().map(|e| (e / trap[0] - 1.0).abs()).fold(0.0, f64::max);
    println!("trapezoidal max |ΔE|/E0 = {dev:.3e}; implicit Euler kept {:.3}", euler[2000] / euler[0]);
    assert!(dev < 0.01, "trapezoidal energy drift {dev}");
    assert!(euler[2000] < 0.5 * euler[0]);
}

/// The moving rubber rod pinned by its start (a rigid position
/// constraint): it swings and bends about the pin.
/// Returns the largest pin speed seen after a step and the largest
/// |ΔE|/E0 of kinetic + elastic energy over `steps` trapezoidal steps (E0
/// after the first).
fn pinned_rod_swinging(steps: usize) -> (f64, f64) {
    let rod = moving_rubber_rod();
    let mut w = World::new(IntegrationParameters { dt: 1e-3, parallel: false, scheme: Scheme::Trapezoidal, ..Default::default() });
    let h = w.add_rod(rod);
    let u = w.rod(h).unwrap().domain().0;
    w.add_constraint(h, strandkit::constraint::kinds::Position { u, axes: [true, true, true, false], target: [0.0; 4] }, 0.0).unwrap();
    let energy = |w: &World| {
        let r = w.rod(h).unwrap();
        r.kinetic_energy() + r.elastic_energy()
    };
    // The initial velocity moves the pin: the first step's projection
    // takes that share of E0 away. The energy is followed from after it.
    w.step().unwrap();
    let e0 = energy(&w);
    let (mut speed, mut drift) = (0.0f64, 0.0f64);
    for _ in 1..steps {
        w.step().unwrap();
        let r = w.rod(h).unwrap();
        let (ctrl, b) = r.basis_at(u).unwrap();
        let vel = r.velocities();
        let pin: Vector3<f64> = (0..4).map(|k| Vector3::new(vel[3 * ctrl[k]], vel[3 * ctrl[k] + 1], vel[3 * ctrl[k] + 2]) * b[0][k]).sum();
        speed = speed.max(pin.norm());
        drift = drift.max((energy(&w) / e0 - 1.0).abs());
    }
    (speed, drift)
}

/// The trapezoidal rule holds a rigid constraint on the positions; its end
/// velocity V' = 2ΔX/h − V_n is projected so that the constraint holds on
/// it too (else V' keeps V_n's component along the constraint's normal,
/// flipped each step: under thermal noise a duplex's rigid bonds let the
/// kinetic energy grow without bound). Measured over 2000 steps of 1 ms:
/// the pin's speed after a step at most 1e-31 m/s (asserted < 1e-10; 0.112
/// m/s without the projection, the initial velocity flipping), energy
/// within 9.2e-5 of that after the first step (asserted 1 %; the same
/// without the projection: it takes no energy from a consistent motion).
#[test]
fn a_pinned_point_stays_at_rest_with_the_trapezoidal_rule() {
    let (speed, drift) = pinned_rod_swinging(2000);
    println!("pin speed at most {speed:.2e} m/s; max |ΔE|/E0 {drift:.2e}");
    assert!(speed < 1e-10, "the pin moves at {speed} m/s");
    assert!(drift < 0.01, "energy drift {drift}");
}

/// A DNA-scale rod (A = 50 nm, S = 1100 pN, 7.8 nm on 24 points, clamped
/// at s = 0 and pulled by 5 pN, molecular units, water-like drag 0.1)
/// started with velocities up to 300 nm/ns in a fixed pseudo-random
/// pattern (the thermal speeds of its control points), stepped by the
/// trapezoidal rule at 5 ps, 100 steps, no noise. Its Newton iterations
/// diverge at the third step: the step is refused as NotConverged with
/// the world unchanged (before: 20 iterations, then with `adaptive_dt`
/// the iterates made the clamp's rows singular at step 7, an error not
/// retried). With `adaptive_dt` the run goes through, and the energy
/// (kinetic + elastic − the pull's work) never rises above its start.
/// Then with noise (298 K, seed 1) 100 steps go through too (before:
/// Singular at step 67).
#[test]
fn a_diverging_trapezoidal_newton_is_refused_and_retried_not_singular() {
    use strandkit_builders::dna_harmonic::reference_rod;
    let build = |adaptive: bool, temperature: f64| {
        let mu = 2.0 * 330.0 * 1.6605e-6 / 0.34; // two nucleotides per rise
        let rod = reference_rod(23.0 * 0.34, 24, 50.0, 1100.0, 4.114, mu).unwrap();
        let (u0, u1) = rod.domain();
        let mut w = World::new(IntegrationParameters {
            dt: 0.005,
            scheme: Scheme::Trapezoidal,
            temperature,
            viscosity: 0.1,
            units: strandkit::Units::Molecular,
            seed: 1,
            adaptive_dt: adaptive,
            parallel: false,
            ..Default::default()
        });
        let h = w.add_rod(rod);
        w.clamp(h, u0, 0.0).unwrap();
        w.add_load(strandkit::force::PointForce { rod: h, u: u1, force: [0.0, 0.0, 5.0] }.into()).unwrap();
        if temperature == 0.0 {
            let r = w.rod_mut(h).unwrap();
            let v: Vec<f64> = (0..r.velocities().len()).map(|i| if i < 6 { 0.0 } else { 300.0 * (((i * 7919 + 13) % 17) as f64 / 8.0 - 1.0) }).collect();
            r.set_velocities(&v).unwrap();
        }
        (w, h, u1)
    };
    let energy = |w: &World, h, u1| {
        let r = w.rod(h).unwrap();
        r.kinetic_energy() + r.elastic_energy() - 5.0 * r.position(u1).unwrap().z
    };
    let (mut w, h, _) = build(false, 0.0);
    let (mut before, mut failed) = (Vec::new(), None);
    for s in 0..10 {
        before = w.rod(h).unwrap().coords().to_vec();
        if let Err(e) = w.step() {
            failed = Some((s, e));
            break;
        }
    }
    let (s, err) = failed.expect("a step refused within 10");
    println!("step {s} refused: {err}");
    assert!(matches!(err, Error::NotConverged { .. }), "{err}");
    assert_eq!(w.rod(h).unwrap().coords(), &before[..], "a refused step leaves the world as it was");

    let (mut w, h, u1) = build(true, 0.0);
    let e0 = energy(&w, h, u1);
    let (mut top, mut substeps) = (e0, 0);
    for _ in 0..100 {
        substeps += w.step().unwrap().substeps;
        top = top.max(energy(&w, h, u1));
    }
    println!("adaptive: 100 steps in {substeps} sub-steps; energy {e0:.1} → {:.1}, highest {top:.1} pN nm", energy(&w, h, u1));
    assert!(top <= e0 * (1.0 + 1e-9), "energy rose from {e0} to {top}");

    let (mut w, _, _) = build(true, 298.15);
    let substeps: u32 = (0..100).map(|_| w.step().unwrap().substeps).sum();
    println!("with noise: 100 steps in {substeps} sub-steps");
}
