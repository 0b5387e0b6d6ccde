//! Equal offsets: two point pairs of rods a and b keep the same offset,
//! (r_a(ua) − r_b(ub)) − (r_a(va) − r_b(vb)) = 0 on x, y, z, whatever that
//! offset is. Tied at as many pairs as rod b has control points, each pair
//! against one reference pair (chained pair to pair, a multiplier carries
//! the sum of the forces along the chain before it: measured on a
//! 192-point ring, a tie in the middle then held only to 3e-6 of its terms
//! and the step was refused as contradictory), rod b is rod a translated
//! by a free vector: a periodic image whose period the equilibrium
//! chooses. (At the knots of a periodic cubic B-spline the collocation
//! matrix, rows 1/6, 4/6, 1/6, has eigenvalues ≥ 1/3: ties at the knots
//! leave exactly the translation free.) Linear in q; side 0 is rod a,
//! side 1 rod b.
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
    fn validate(&self, rods: &[&Rod]) -> Result<()> {
        // The same two pairs, or on one rod two pairs each of one point:
        // rows 0 = 0, dependent on everything.
        let one_rod = std::ptr::eq(rods[0], rods[1]);
        if (self.ua == self.va && self.ub == self.vb) || (one_rod && self.ua == self.ub && self.va == self.vb) {
            return Err(Error::invalid(
                "equal offsets",
                format!("pairs ({}, {}) and ({}, {})", self.ua, self.ub, self.va, self.vb),
                "two different point pairs of two different points each",
            ));
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
        // The same two pairs, in either order (the rows only change sign).
        let swapped = EqualOffsets { ua: other.va, ub: other.vb, va: other.ua, vb: other.ub };
        crate::constraint::same_abscissae(self, other) || crate::constraint::same_abscissae(self, &swapped)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spline::KnotVector;
    use crate::{Material, RodOptions, Section};

    fn ring(n: usize, shift: f64) -> Rod {
        let q: Vec<f64> = (0..n)
            .flat_map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                [a.cos() + 0.1 * (3.0 * a).sin(), shift + 0.2 * (2.0 * a).cos(), a.sin()]
            })
            .collect();
        let m = Material::new("nylon", 3e9, 0.4, 1140.0).unwrap();
        Rod::new(KnotVector::periodic(n).unwrap(), 3, q, vec![Section::circle(0.01).unwrap()], m, RodOptions::default()).unwrap()
    }

    /// Tied at the knots of a closed rod, each pair against the first,
    /// the rows leave the image exactly a translation: rank 3n − 3 on its
    /// coordinates, for even and odd counts.
    #[test]
    fn ties_at_the_knots_leave_a_translation_free() {
        for n in [8, 9, 16] {
            let (a, b) = (ring(n, 0.0), ring(n, 0.5));
            let rods = [&a, &b];
            let mut m = Vec::new();
            for k in 1..n {
                let mut rows = [Row::default(); 3];
                EqualOffsets { ua: k as f64, ub: k as f64, va: 0.0, vb: 0.0 }.linearize(&rods, &mut rows).unwrap();
                for r in &rows {
                    // Translated copies: every row holds as built.
                    assert!(r.rhs.abs() < 1e-14, "{}", r.rhs);
                    let mut dense = vec![0.0; 3 * n];
                    r.entries().iter().filter(|e| e.0 == 1).for_each(|&(_, i, v)| dense[i] += v);
                    m.push(dense);
                }
            }
            assert_eq!(rank(m), 3 * n - 3, "n = {n}");
        }
    }

    /// Pairs that give no rows are refused: the same two pairs, or on one
    /// rod two pairs of one point each (two rods may share abscissae).
    #[test]
    fn pairs_without_rows_are_refused() {
        let (a, b) = (ring(8, 0.0), ring(8, 0.5));
        let refused = |k: EqualOffsets, rods: [&Rod; 2]| matches!(k.validate(&rods), Err(Error::InvalidInput { .. }));
        assert!(refused(EqualOffsets { ua: 1.0, ub: 2.0, va: 1.0, vb: 2.0 }, [&a, &b]));
        assert!(refused(EqualOffsets { ua: 1.0, ub: 1.0, va: 3.0, vb: 3.0 }, [&a, &a]));
        assert!(EqualOffsets { ua: 1.0, ub: 1.0, va: 3.0, vb: 3.0 }.validate(&[&a, &b]).is_ok());
    }

    fn rank(mut m: Vec<Vec<f64>>) -> usize {
        let cols = m[0].len();
        let mut r = 0;
        for c in 0..cols {
            let p = (r..m.len()).max_by(|&x, &y| m[x][c].abs().total_cmp(&m[y][c].abs()));
            let Some(p) = p.filter(|&p| m[p][c].abs() > 1e-10) else { continue };
            m.swap(r, p);
            for k in r + 1..m.len() {
                let f = m[k][c] / m[r][c];
                for x in c..cols {
                    m[k][x] -= f * m[r][x];
                }
            }
            r += 1;
        }
        r
    }
}
