//! Coplanar relative clamp (III.61–III.65): r_a(ua) − r_b(ub) =
//! α0 r_a'(ua) + α1 r_b'(ub), α fixed from the geometry when it is made
//! (`World::add_coplanar_clamp`). Linear in q. Unlike its name in the
//! thesis it is a hinge, not a weld: it keeps the two tangent lines meeting
//! at a common point P = r_a − α0 r_a' = r_b + α1 r_b', and rod b may rotate
//! about P. Λ is the force on rod a, applied at P.
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{Anchoring, ConstraintLaw, Reaction, Row, Side};
use crate::error::Result;
use crate::rod::Rod;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// r_a(ua) − r_b(ub) = α0 r_a'(ua) + α1 r_b'(ub) (a hinge at the common
/// point of the two tangent lines). Multiplier: force on rod a (at that
/// point, hence the moment −α0 r_a' × Λ about r_a(ua)).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CoplanarClamp {
    pub ua: f64,
    pub ub: f64,
    pub alpha: [f64; 2],
}

impl ConstraintLaw for CoplanarClamp {
    const INFO: KindInfo = KindInfo {
        name: "CoplanarClamp",
        helper: "coplanar_clamp",
        rods: 2,
        doc: "Coplanar relative clamp (III.61): r_a(ua) − r_b(ub) = alpha[0] r_a'(ua) + alpha[1] r_b'(ub) \
              (u-parameter units); World.add_coplanar_clamp solves alpha from the geometry. A hinge at the \
              common point of the two tangent lines. Multiplier: force on rod a.",
        fields: &[
            FieldInfo::new("ua", Abscissa, "u", "abscissa on rod a"),
            FieldInfo::new("ub", Abscissa, "u", "abscissa on rod b"),
            FieldInfo::new("alpha", Vec2, "u", "coefficients of the two tangents"),
        ],
    };
    fn n_rows(&self) -> usize {
        3
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        f(0, self.ua);
        f(1, self.ub);
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.ua);
        f(1, &mut self.ub);
    }
    fn validate(&self, _rods: &[&Rod]) -> Result<()> {
        crate::error::finite("coplanar clamp alpha", self.alpha[0])?;
        crate::error::finite("coplanar clamp alpha", self.alpha[1]).map(|_| ())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let (ca, ba) = rods[0].basis_at(self.ua)?;
        let (cb, bb) = rods[1].basis_at(self.ub)?;
        let (pa, pb) = (rods[0].eval(self.ua, 0)?, rods[1].eval(self.ub, 0)?);
        let (ta, tb) = (rods[0].eval(self.ua, 1)?, rods[1].eval(self.ub, 1)?);
        let alpha = self.alpha;
        for (a, row) in rows.iter_mut().enumerate().take(3) {
            for j in 0..4 {
                row.push_on(0, ca[j] * rods[0].dofs() + a, ba[0][j] - alpha[0] * ba[1][j]);
                row.push_on(1, cb[j] * rods[1].dofs() + a, -bb[0][j] - alpha[1] * bb[1][j]);
            }
            row.rhs = -(pa[a] - pb[a] - alpha[0] * ta[a] - alpha[1] * tb[a]);
        }
        Ok(())
    }
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        let f = Vector3::new(lambda[0], lambda[1], lambda[2]);
        let d = rods[0].eval(self.ua, 1)?;
        let arm = -self.alpha[0] * Vector3::new(d[0], d[1], d[2]);
        Ok(Reaction { force: f.into(), torque: arm.cross(&f).into() })
    }
    fn anchoring(&self) -> Anchoring {
        Anchoring::PointViaPeer
    }
}
