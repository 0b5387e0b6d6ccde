//! Equal offsets: two point pairs of rods a and b keep the same offset,
//! (r_a(ua) − r_b(ub)) − (r_a(va) − r_b(vb)) = 0 on x, y, z, whatever that
//! offset is. Tied at as many pairs as rod b has control points (matching
//! abscissae, each to one reference pair), rod b is rod a translated by a
//! free vector: the
//! periodic image of a knit cell (SPEC §9.3), whose period the equilibrium
//! then chooses. Linear in q; side 0 is rod a, side 1 rod b.
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{ConstraintLaw, Reaction, Row, Side};
use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// r_a(ua) − r_b(ub) = r_a(va) − r_b(vb) (3 rows, x, y, z). Multiplier λ:
/// the force on rod a at `ua` (−λ at `va`; rod b the opposite of both).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EqualOffsets {
    pub ua: f64,
    pub ub: f64,
    pub va: f64,
    pub vb: f64,
}

impl EqualOffsets {
    /// The four points with their side and the sign of their term.
    fn terms(&self) -> [(Side, f64, f64); 4] {
        [(0, self.ua, 1.0), (1, self.ub, -1.0), (0, self.va, -1.0), (1, self.vb, 1.0)]
    }
}

impl ConstraintLaw for EqualOffsets {
    const INFO: KindInfo = KindInfo {
        name: "EqualOffsets",
        helper: "equal_offsets",
        rods: 2,
        doc: "Two point pairs (rods a and b of World.add_link) keep the same offset, whatever it is: \
              r_a(ua) − r_b(ub) = r_a(va) − r_b(vb). At rod b's control points, each against one pair, it makes rod b a \
              translated copy of rod a (a periodic image). Multiplier: force on rod a at ua (the opposite at va; \
              rod b gets the opposite of both).",
        fields: &[
            FieldInfo::new("ua", Abscissa, "u", "first pair: abscissa on rod a"),
            FieldInfo::new("ub", Abscissa, "u", "first pair: abscissa on rod b"),
            FieldInfo::new("va", Abscissa, "u", "second pair: abscissa on rod a"),
            FieldInfo::new("vb", Abscissa, "u", "second pair: abscissa on rod b"),
        ],
    };
    fn n_rows(&self) -> usize {
        3
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        f(0, self.ua);
        f(1, self.ub);
        f(0, self.va);
        f(1, self.vb);
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.ua);
        f(1, &mut self.ub);
        f(0, &mut self.va);
        f(1, &mut self.vb);
    }
    fn validate(&self, _rods: &[&Rod]) -> Result<()> {
        // The same two pairs: rows 0 = 0, dependent on everything.
        if self.ua == self.va && self.ub == self.vb {
            return Err(Error::invalid("equal offsets", format!("pairs ({}, {}) twice", self.ua, self.ub), "two different point pairs"));
        }
        Ok(())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let mut g = Vector3::zeros();
        for (side, u, sign) in self.terms() {
            let rod = rods[side as usize];
            g += rod.position(u)? * sign;
            let (ctrl, b) = rod.basis_at(u)?;
            for (a, row) in rows.iter_mut().enumerate().take(3) {
                for j in 0..4 {
                    row.push_on(side, ctrl[j] * rod.dofs() + a, sign * b[0][j]);
                }
            }
        }
        for (a, row) in rows.iter_mut().enumerate().take(3) {
            row.rhs = -g[a];
        }
        Ok(())
    }
    /// No net force on rod a (λ at ua, −λ at va): the couple's moment about
    /// r_a(ua).
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        let l = Vector3::new(lambda[0], lambda[1], lambda[2]);
        let arm = rods[0].position(self.va)? - rods[0].position(self.ua)?;
        Ok(Reaction { force: [0.0; 3], torque: arm.cross(&-l).into() })
    }
    fn duplicates(&self, other: &Self) -> bool {
        let same = |x: f64, y: f64| (x - y).abs() <= 1e-12 * (1.0 + x.abs());
        let direct = same(self.ua, other.ua) && same(self.ub, other.ub) && same(self.va, other.va) && same(self.vb, other.vb);
        let swapped = same(self.ua, other.va) && same(self.ub, other.vb) && same(self.va, other.ua) && same(self.vb, other.ub);
        direct || swapped
    }
}
