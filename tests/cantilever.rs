//! SPEC §10 cantilever with a vertical tip load (elastica references by
//! shooting): tip angle within 0.5 %, tip position within 0.5 % of L with
//! ≤ 20 control points; clamp multipliers equal the reactions (0.1 %).
mod common;
use common::*;

const REFS: [(f64, f64, f64, f64); 5] = [
    (1e4, 0.08129, 3.9930, 0.2166),
    (5e4, 0.38540, 3.8422, 1.0140),
    (1e5, 0.67964, 3.5129, 1.7388),
    (2e5, 1.02631, 2.8979, 2.4945),
    (5e5, 1.37952, 1.9635, 3.1491),
];

#[test]
fn cantilever_matches_elastica_references() {
    for &(f, angle, x, y) in &REFS {
        let mut c = cantilever(20, 5, [0.0, -f, 0.0]);
        let rep = c.world.relax().unwrap();
        let (p, a) = tip(&c.world, c.rod);
        let (ea, ex, ey) = ((-a - angle).abs() / angle, (p.x - x).abs() / 4.0, (-p.y - y).abs() / 4.0);
        println!("F={f:.0e}: angle {:.5} (ref {angle}, {:.3}%), tip ({:.4}, {:.4}) (ref ({x}, {y}); err {:.3}%/{:.3}% of L), {} iterations",
            -a, 100.0 * ea, p.x, -p.y, 100.0 * ex, 100.0 * ey, rep.iterations);
        assert!(ea < 5e-3, "tip angle error {ea}");
        assert!(ex < 5e-3 && ey < 5e-3, "tip position error {ex} {ey}");
        // Reactions: force +F along y, moment about z = F · x_tip.
        let rf = c.world.reaction(c.clamp).unwrap();
        let rm = c.world.reaction(c.clamp_tangent).unwrap();
        let (fy, mz) = (rf.force[1], rm.torque[2]);
        println!("   reaction force {:?}, moment {:?}", rf.force, rm.torque);
        assert!((fy - f).abs() < 1e-3 * f && rf.force[0].abs() < 1e-3 * f);
        assert!((mz - f * p.x).abs() < 1e-3 * f * p.x, "moment {mz} vs {}", f * p.x);
    }
}
