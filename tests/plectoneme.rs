//! Issue 14's plectoneme, with issue 15's self-contact: a straight rod
//! (reference-frame model) under tension F, L√(F/B) = 20, its far end
//! sliding along the axis and turned at a steady rate, stays straight past
//! M_c = 2√(BF) (dynamic loading overshoots it), snaps into a loop, and
//! then winds a plectoneme held open by self-contact: the extension falls
//! linearly with the turns while the torque stays on a plateau below M_c.
use nalgebra::Vector3;
use strandkit::energy::FrameModel;
use strandkit::prelude::*;
use strandkit::RodContacts;

#[test]
fn plectoneme_extension_falls_linearly_and_torque_plateaus() {
    let (len, r, e, nu) = (1.0f64, 0.002f64, 1e7f64, 0.5f64);
    let b = e * std::f64::consts::PI * r.powi(4) / 4.0;
    let force = 400.0 * b / (len * len);
    let rod = RodBuilder::straight(Vector3::zeros(), Vector3::new(len, 0.0, 0.0))
        .control_points(80)
        .with_roll(true)
        .section(Section::circle(r).unwrap())
        .material(Material::new("rubber", e, nu, 1000.0).unwrap())
        .options(RodOptions { model: FrameModel::Reference, drag: 0.05, ..Default::default() })
        .build()
        .unwrap();
    let (u0, u1) = rod.domain();
    let mut w = World::new(IntegrationParameters { dt: 1e-3, ..Default::default() });
    let h = w.add_rod(rod);
    w.add_constraint(h, ConstraintKind::Position(Position { u: u0, axes: [true; 4], target: [0.0; 4] }), 0.0).unwrap();
    w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u0, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    let end = w.add_constraint(h, ConstraintKind::Position(Position { u: u1, axes: [false, true, true, true], target: [0.0; 4] }), 0.0).unwrap();
    w.add_constraint(h, ConstraintKind::Tangent(Tangent { u: u1, direction: [1.0, 0.0, 0.0] }), 0.0).unwrap();
    w.add_load(Load::PointForce(PointForce { rod: h, u: u1, force: [force, 0.0, 0.0] })).unwrap();
    w.add_contact_detector(RodContacts::new(10.0 * r, true, false).unwrap()).unwrap();
    // Perturb slightly off the axis so that the buckling has a direction.
    let rod = w.rod_mut(h).unwrap();
    let mut q = rod.coords().to_vec();
    for (i, c) in q.chunks_mut(4).enumerate() {
        c[1] += 1e-6 * (i as f64 * 0.7).sin();
    }
    rod.set_coords(&q).unwrap();
    let steps_per_turn = 800;
    // The snap's turn (11–12 with dynamic loading) changes with round-off
    // (a bifurcation: the 1e-6 m imperfection only orients it), and the
    // plectoneme reaches the clamps 4–6 turns after it, the extension then
    // no longer falling linearly: the linear stretch is measured from 1.0
    // to 2.5 turns after the snap (beyond, the growth depends on round-off:
    // relative changes of F by 1e-12 moved the extension 3.5 turns after
    // the snap by up to 14 %, and the old window's linearity by 0.5–1.8×
    // its bound; within 1.0–2.5 turns the runs agreed within 2 %, their
    // fits' worst deviations at 57–80 % of the bound below: the early
    // plectoneme grows a little faster). Before the knot work (rows slid to where
    // the strands sag most) it fell 5.3 cm per turn at a 9.9e-4 N m
    // plateau; now 5.5–6.2 cm at 9.1–9.4e-4 N m (the strands held a little
    // farther apart).
    let turns = 20;
    let m_c = 2.0 * (b * force).sqrt();
    let mut table: Vec<(f64, f64, f64, f64)> = Vec::new(); // turns, extension (m), torque (N m), closest approach (m)
    println!("turns  extension(m)  torque(N m)  contacts  closest/2r");
    for k in 1..=turns * steps_per_turn {
        let phi = std::f64::consts::TAU * k as f64 / steps_per_turn as f64;
        w.set_constraint(end, ConstraintKind::Position(Position { u: u1, axes: [false, true, true, true], target: [0.0, 0.0, 0.0, phi] })).unwrap();
        w.step().unwrap();
        let snapped = table.iter().find(|r| r.1 < 0.99 * len).map(|r| r.0);
        if snapped.is_some_and(|t| k as f64 / steps_per_turn as f64 > t + 2.5) {
            break;
        }
        if k % (steps_per_turn / 2) == 0 {
            let rod = w.rod(h).unwrap();
            let x = rod.position(u1).unwrap().x;
            let torque = w.reaction(end).unwrap().torque[0].abs();
            // Closest approach of stretches more than 5 % of the rod apart along it.
            let p = rod.sample_points();
            let n = p.len();
            let gap = (0..n).flat_map(|i| (i + n / 20..n).map(move |j| (i, j))).map(|(i, j)| (p[i] - p[j]).norm()).fold(f64::INFINITY, f64::min);
            println!("{:5.1}  {x:.6}  {torque:.5e}  {:3}  {:.4}", k as f64 / steps_per_turn as f64, w.contacts().active().count(), gap / (2.0 * r));
            table.push((k as f64 / steps_per_turn as f64, x, torque, gap));
        }
    }
    // Straight until the torque passed M_c (dynamic loading overshoots it).
    let buckled = table.iter().position(|&(_, x, _, _)| x < 0.99 * len).expect("the rod should buckle");
    let m_before = table[buckled - 1].2;
    println!("2√(BF) = {m_c:.5e} N m; straight up to {:.5e} N m at {} turns", m_before, table[buckled - 1].0);
    assert!(m_before > 0.97 * m_c, "buckled at {m_before} below M_c {m_c}");
    // The plectoneme, 1.0 to 2.5 turns after the snap: strands one diameter
    // apart (to the sag of the spline between contact rows), extension
    // linear in the turns (least squares), torque on a plateau below M_c.
    let post: Vec<_> = table.iter().filter(|r| r.0 >= table[buckled].0 + 1.0 && r.0 <= table[buckled].0 + 2.5).copied().collect();
    let closest = post.iter().map(|r| r.3).fold(f64::INFINITY, f64::min);
    println!("closest approach in the plectoneme {:.4} diameters", closest / (2.0 * r));
    assert!(closest > 0.9 * 2.0 * r, "the strands interpenetrate: {closest} for a diameter {}", 2.0 * r);
    let n = post.len() as f64;
    let (mt, mx) = (post.iter().map(|r| r.0).sum::<f64>() / n, post.iter().map(|r| r.1).sum::<f64>() / n);
    let slope = post.iter().map(|r| (r.0 - mt) * (r.1 - mx)).sum::<f64>() / post.iter().map(|r| (r.0 - mt).powi(2)).sum::<f64>();
    let worst = post.iter().map(|r| (r.1 - (mx + slope * (r.0 - mt))).abs()).fold(0.0f64, f64::max);
    let tm = post.iter().map(|r| r.2).sum::<f64>() / n;
    let spread = post.iter().map(|r| (r.2 / tm - 1.0).abs()).fold(0.0f64, f64::max);
    println!("plectoneme ({} points from {} turns): extension {slope:.4e} m per turn, worst deviation from the line {worst:.2e} m; torque {tm:.4e} N m ± {:.1} %", post.len(), post[0].0, 100.0 * spread);
    assert!(slope < 0.0, "the extension should fall with the turns");
    assert!(worst < 0.05 * slope.abs() * (post[post.len() - 1].0 - post[0].0), "extension not linear: worst deviation {worst}");
    assert!(spread < 0.1 && tm < m_c, "torque should plateau below M_c: {tm} ± {spread}");
}
