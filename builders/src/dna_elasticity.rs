//! Zero-temperature elastic constants of a built duplex (issue 17): pair 0
//! held, small loads on the last pair — an axial force, a twisting couple,
//! a bending couple —, relaxed each time; the stretch modulus S, twist–
//! stretch coupling g and twist stiffness C from the 2×2 compliance of
//! (strain, twist) to (force, torque), the bending stiffness B from the
//! curvature under the couple. Everything is read on the duplex axis over
//! the pairs at least a turn away from either end.
//!
//! The axis point of a pair is its rung midpoint moved by R cos(φ/2)
//! toward the axis (along ẑ × x̂, ẑ the mean strand direction ⟂ the rung).
use crate::dna::{duplex, Duplex, DuplexLayout};
use nalgebra::Vector3;
use strandkit_core::constraint::kinds::{Position, Tangent};
use strandkit_core::force::PointForce;
use strandkit_core::world::{IntegrationParameters, World};
use strandkit_core::{Error, Inserted, Result};

/// What [`zero_temperature_elasticity`] measured (pN, nm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    /// Stretch modulus at free twist (pN).
    pub stretch_modulus: f64,
    /// Twist–stretch coupling (pN·nm; < 0: overwinds when stretched).
    pub twist_stretch: f64,
    /// Twist stiffness C at fixed extension (pN·nm²).
    pub twist_stiffness: f64,
    /// Bending stiffness B (pN·nm²).
    pub bending_stiffness: f64,
    /// The compliance [[ε/F, ε/M], [τ/F, τ/M]] (1/pN, 1/(pN·nm),
    /// rad/(nm·pN), rad/(nm·pN·nm)); symmetric for a conservative model.
    pub compliance: [[f64; 2]; 2],
}

/// Axis point and rung of pair k (nm).
pub fn pair_axis(w: &World, ins: &Inserted, l: &DuplexLayout, k: usize) -> Result<(Vector3<f64>, Vector3<f64>)> {
    let (ra, rb) = (w.rod(ins.rods[l.strands[0]])?, w.rod(ins.rods[l.strands[1]])?);
    let (ua, ub) = (l.abscissae[0][k], l.abscissae[1][l.partner[k]]);
    let (a, b) = (ra.position(ua)?, rb.position(ub)?);
    let x = (b - a).normalize();
    let v = ra.tangent(ua)? - rb.tangent(ub)?;
    let z = (v - x * x.dot(&v)).normalize();
    let offset = 0.5 * l.rung_length / (0.5 * l.phase).tan(); // R cos(φ/2)
    Ok(((a + b) * 0.5 + z.cross(&x) * offset, b - a))
}

/// The duplex relaxed with forces `fa`, `fb` (pN) on the last pair's
/// nucleotides of strands a and b; pair 0 held (strand a clamped, strand
/// b's height and tangent: the rung already fixes its distance to a).
fn loaded(p: &Duplex, fa: Vector3<f64>, fb: Vector3<f64>) -> Result<(World, Inserted, DuplexLayout)> {
    let (asm, l) = duplex(p)?;
    let mut w = World::new(IntegrationParameters { relax_max_iterations: 200, ..Default::default() });
    let ins = w.insert(&asm)?;
    let (ra, rb) = (ins.rods[l.strands[0]], ins.rods[l.strands[1]]);
    let n = l.partner.len();
    w.clamp(ra, l.abscissae[0][0], 0.0)?;
    let ub = l.abscissae[1][n - 1];
    let (pb, tb) = (w.rod(rb)?.position(ub)?, w.rod(rb)?.tangent(ub)?);
    w.add_constraint(rb, Position { u: ub, axes: [false, false, true, false], target: [0.0, 0.0, pb.z, 0.0] }, 0.0)?;
    w.add_constraint(rb, Tangent { u: ub, direction: tb.into() }, 0.0)?;
    w.add_load(PointForce { rod: ra, u: l.abscissae[0][n - 1], force: fa.into() }.into())?;
    w.add_load(PointForce { rod: rb, u: l.abscissae[1][0], force: fb.into() }.into())?;
    w.relax()?;
    Ok((w, ins, l))
}

/// Measures S, g, C and B of the duplex `p` (at least 4 turns long) by
/// three relaxations under loads of 1 pN, 1 pN·nm and a 0.2 pN couple.
pub fn zero_temperature_elasticity(p: &Duplex) -> Result<Measured> {
    let (w0, ins0, l) = loaded(p, Vector3::zeros(), Vector3::zeros())?;
    let n = l.partner.len();
    let turn = p.bp_per_turn.ceil() as usize;
    if n < 4 * turn {
        return Err(Error::invalid("duplex length", format!("{n} bp"), format!("at least 4 turns ({} bp)", 4 * turn)));
    }
    let (k1, k2) = (turn, n - 1 - turn);
    let len = (k2 - k1) as f64 * p.rise;
    let z = |w: &World, ins: &Inserted| -> Result<f64> { Ok(pair_axis(w, ins, &l, k2)?.0.z - pair_axis(w, ins, &l, k1)?.0.z) };
    // Rotation of the rung about z from k1 to k2, summed pair by pair.
    let angle = |w: &World, ins: &Inserted| -> Result<f64> {
        let mut tot = 0.0;
        for k in k1..k2 {
            let (x0, x1) = (pair_axis(w, ins, &l, k)?.1, pair_axis(w, ins, &l, k + 1)?.1);
            tot += (x0.x * x1.y - x0.y * x1.x).atan2(x0.x * x1.x + x0.y * x1.y);
        }
        Ok(tot)
    };
    let (z0, t0) = (z(&w0, &ins0)?, angle(&w0, &ins0)?);
    let response = |w: &World, ins: &Inserted| -> Result<(f64, f64)> { Ok(((z(w, ins)? - z0) / z0, (angle(w, ins)? - t0) / len)) };

    let f = 1.0; // pN along the axis, shared by the two nucleotides
    let (w, ins, _) = loaded(p, Vector3::new(0.0, 0.0, f / 2.0), Vector3::new(0.0, 0.0, f / 2.0))?;
    let (eps_f, tau_f) = response(&w, &ins)?;
    let m = 1.0; // pN·nm about the axis: ±M/|x| ⟂ the end rung
    let (_, x) = pair_axis(&w0, &ins0, &l, n - 1)?;
    let y = Vector3::z().cross(&x.normalize()) * (m / x.norm());
    let (w, ins, _) = loaded(p, -y, y)?;
    let (eps_m, tau_m) = response(&w, &ins)?;
    let c = [[eps_f / f, eps_m / m], [tau_f / f, tau_m / m]];
    let det = c[0][0] * c[1][1] - c[0][1] * c[1][0];

    // Bending: ±fb ẑ on the end pair, a couple |x| fb about x̂ × ẑ; κ is
    // the slope of the axis direction's rotation (from rest, about that
    // axis) along the duplex, by least squares over the measured steps.
    let fb = 0.2;
    let (w, ins, _) = loaded(p, Vector3::new(0.0, 0.0, -fb), Vector3::new(0.0, 0.0, fb))?;
    let dir = |w: &World, ins: &Inserted, k: usize| -> Result<Vector3<f64>> { Ok((pair_axis(w, ins, &l, k + 1)?.0 - pair_axis(w, ins, &l, k)?.0).normalize()) };
    let about = x.normalize().cross(&Vector3::z());
    let (mut sx, mut sy, mut sxx, mut sxy, mut cnt) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for k in k1..k2 {
        let th = dir(&w0, &ins0, k)?.cross(&dir(&w, &ins, k)?).dot(&about);
        let s = k as f64 * p.rise;
        sx += s;
        sy += th;
        sxx += s * s;
        sxy += s * th;
        cnt += 1.0;
    }
    let kappa = ((cnt * sxy - sx * sy) / (cnt * sxx - sx * sx)).abs();
    Ok(Measured {
        stretch_modulus: c[1][1] / det,
        twist_stretch: -c[0][1] / det,
        twist_stiffness: c[0][0] / det,
        bending_stiffness: fb * x.norm() / kappa,
        compliance: c,
    })
}
