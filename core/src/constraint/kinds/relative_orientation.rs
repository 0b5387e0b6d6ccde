//! Relative orientation (III.58): the tangents of rod a at ua and rod b at ub
//! aligned, as two rows g_i = e_i · (t_a × t_b) with (e1, e2) ⟂ m = t_a + t_b
//! (≈ the relative rotation angle about e_i, so Λ is a moment), plus equal
//! roll coordinates when `roll`.
//!
//! The frame (e1, e2) turns with m, and the Jacobian includes it: with
//! w = t_a × t_b = g1 e1 + g2 e2 (w ⟂ m) and α the rotation of the frame
//! about m̂, de1·w = α g2 and de2·w = −α g1, where
//! dα = −(m̂·h)/(|P_m h| |m|) e2·dm for the helper axis h of the frame.
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{perpendicular_frame, tangent_of, Anchoring, ConstraintLaw, Reaction, Row, Side};
use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// Tangents of rod a at ua and rod b at ub aligned (two rows), plus equal
/// roll coordinates when `roll`. Multiplier: the moment on rod a.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RelativeOrientation {
    pub ua: f64,
    pub ub: f64,
    pub roll: bool,
}

/// Gradients of the two tangent rows with respect to r_a' and r_b', and
/// the rows' values.
struct Rows {
    ga: [Vector3<f64>; 2],
    gb: [Vector3<f64>; 2],
    g: [f64; 2],
    ta: Vector3<f64>,
}

impl RelativeOrientation {
    fn rows(&self, rods: &[&Rod]) -> Result<Rows> {
        let (ta, sa) = tangent_of(rods[0], self.ua)?;
        let (tb, sb) = tangent_of(rods[1], self.ub)?;
        let m = ta + tb;
        let mn = m.norm();
        if mn < 1e-6 {
            return Err(Error::singular("relative orientation: the tangents are opposite"));
        }
        let mh = m / mn;
        let (e1, e2, h) = perpendicular_frame(&mh);
        let ph = (h - mh * mh.dot(&h)).norm();
        let pa = Matrix3::identity() - ta * ta.transpose();
        let pb = Matrix3::identity() - tb * tb.transpose();
        let w = ta.cross(&tb);
        let g = [e1.dot(&w), e2.dot(&w)];
        // dα/dr' through dm = dt_a + dt_b (dt = P dr'/|r'|).
        let k = -mh.dot(&h) / (ph * mn);
        let (da, db) = (pa * e2 * (k / sa), pb * e2 * (k / sb));
        let mut out = Rows { ga: [Vector3::zeros(); 2], gb: [Vector3::zeros(); 2], g, ta };
        for (i, (e, c)) in [(e1, g[1]), (e2, -g[0])].into_iter().enumerate() {
            out.ga[i] = pa * tb.cross(&e) / sa + da * c;
            out.gb[i] = pb * e.cross(&ta) / sb + db * c;
        }
        Ok(out)
    }
}

impl ConstraintLaw for RelativeOrientation {
    const INFO: KindInfo = KindInfo {
        name: "RelativeOrientation",
        helper: "relative_orientation",
        rods: 2,
        doc: "Tangents of rod a at ua and rod b at ub aligned (two rows), plus equal roll coordinates when `roll`. \
              Multiplier: the moment on rod a (force × length).",
        fields: &[
            FieldInfo::new("ua", Abscissa, "u", "abscissa on rod a"),
            FieldInfo::new("ub", Abscissa, "u", "abscissa on rod b"),
            FieldInfo::new("roll", Flag, "", "also equal roll coordinates").default("false"),
        ],
    };
    fn n_rows(&self) -> usize {
        2 + usize::from(self.roll)
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        f(0, self.ua);
        f(1, self.ub);
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.ua);
        f(1, &mut self.ub);
    }
    fn validate(&self, rods: &[&Rod]) -> Result<()> {
        if self.roll && (rods[0].dofs() == 3 || rods[1].dofs() == 3) {
            return Err(Error::input("relative orientation roll: a rod has no roll coordinate"));
        }
        Ok(())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let r = self.rows(rods)?;
        let (ca, ba) = rods[0].basis_at(self.ua)?;
        let (cb, bb) = rods[1].basis_at(self.ub)?;
        for i in 0..2 {
            let row = &mut rows[i];
            for j in 0..4 {
                for a in 0..3 {
                    row.push_on(0, ca[j] * rods[0].dofs() + a, ba[1][j] * r.ga[i][a]);
                    row.push_on(1, cb[j] * rods[1].dofs() + a, bb[1][j] * r.gb[i][a]);
                }
            }
            row.rhs = -r.g[i];
        }
        if self.roll {
            let row = &mut rows[2];
            for j in 0..4 {
                row.push_on(0, ca[j] * 4 + 3, ba[0][j]);
                row.push_on(1, cb[j] * 4 + 3, -bb[0][j]);
            }
            row.rhs = -(rods[0].eval(self.ua, 0)?[3] - rods[1].eval(self.ub, 0)?[3]);
        }
        Ok(())
    }
    /// The moment of Σ Λ_i ∂g_i/∂r_a' on rigid rotations of rod a,
    /// r_a' × ∂g/∂r_a' (≈ −Λ1 e1 − Λ2 e2 when aligned), plus the roll
    /// row's torque about t_a.
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        let r = self.rows(rods)?;
        let d = rods[0].eval(self.ua, 1)?;
        let r1 = Vector3::new(d[0], d[1], d[2]);
        let mut m = r1.cross(&(r.ga[0] * lambda[0] + r.ga[1] * lambda[1]));
        if self.roll {
            m += r.ta * lambda[2];
        }
        Ok(Reaction::torque(m))
    }
    fn anchoring(&self) -> Anchoring {
        Anchoring::OrientationViaPeer
    }
}
