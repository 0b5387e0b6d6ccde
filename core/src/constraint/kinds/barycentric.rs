//! Barycentric constraint (III.70–III.74): Σ_j a_j q(u_j) = q(driven) on the
//! selected axes of one rod (up to 4 points; weights summing to 1 make it
//! translation invariant). Linear in q. The driven point's entries are
//! tagged side 1 (same rod) so that its reaction, −Λ, can be told from the
//! forces a_j Λ at the weighted points.
use super::position::axes_reaction;
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{ConstraintLaw, Reaction, Row, Side};
use crate::error::{Error, Result};
use crate::rod::Rod;
use serde::{Deserialize, Serialize};

/// Σ a_j q(u_j) = q(`driven`) on the selected `axes` (1 to 4 points
/// (u_j, a_j)). Multiplier: Λ; the force (torque) at the driven point is −Λ.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Barycentric {
    pub points: Vec<(f64, f64)>,
    pub driven: f64,
    pub axes: [bool; 4],
}

impl ConstraintLaw for Barycentric {
    const INFO: KindInfo = KindInfo {
        name: "Barycentric",
        helper: "barycentric",
        rods: 1,
        doc: "Σ a_j q(u_j) = q(driven) on the selected `axes` of one rod, for 1 to 4 `points` (u_j, a_j) \
              (weights summing to 1 make it translation invariant). Reaction: the force at the driven point.",
        fields: &[
            FieldInfo::new("points", WeightedAbscissae, "u, 1", "(abscissa, weight) pairs"),
            FieldInfo::new("driven", Abscissa, "u", "abscissa of the driven point"),
            FieldInfo::new("axes", Axes, "", "constrained axes").default("[true, true, true, false]"),
        ],
    };
    fn n_rows(&self) -> usize {
        self.axes.iter().filter(|a| **a).count()
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        f(1, self.driven);
        self.points.iter().for_each(|p| f(0, p.0));
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(1, &mut self.driven);
        self.points.iter_mut().for_each(|p| f(0, &mut p.0));
    }
    fn validate(&self, rods: &[&Rod]) -> Result<()> {
        if self.points.is_empty() || self.points.len() > 4 {
            return Err(Error::invalid("barycentric constraint points", self.points.len(), "1 to 4 (abscissa, weight) pairs"));
        }
        for (_, a) in &self.points {
            crate::error::finite("barycentric weight", *a)?;
        }
        if !self.axes.iter().any(|a| *a) || (self.axes[3] && rods[0].dofs() == 3) {
            return Err(Error::invalid("barycentric constraint axes", format!("{:?}", self.axes), "at least one axis the rod has"));
        }
        Ok(())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let rod = rods[0];
        let mut r = 0;
        for a in 0..4 {
            if !self.axes[a] {
                continue;
            }
            let mut value = 0.0;
            let terms = self.points.iter().map(|&(u, w)| (0u8, u, w)).chain(std::iter::once((1u8, self.driven, -1.0)));
            for (side, u, w) in terms {
                let (ctrl, b) = rod.basis_at(u)?;
                for k in 0..4 {
                    rows[r].push_on(side, ctrl[k] * rod.dofs() + a, w * b[0][k]);
                }
                value += w * rod.eval(u, 0)?[a];
            }
            rows[r].rhs = -value;
            r += 1;
        }
        Ok(())
    }
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        // Λ multiplies −q(driven): the force at the driven point is −Λ.
        let r = axes_reaction(rods[0], self.driven, &self.axes, lambda)?;
        Ok(Reaction { force: r.force.map(|f| -f), torque: r.torque.map(|t| -t) })
    }
    /// Two of them at one abscissa can be legitimate (two planes make an
    /// axis); only the dependence check rejects repeated rows.
    fn duplicates(&self, _other: &Self) -> bool {
        false
    }
}
