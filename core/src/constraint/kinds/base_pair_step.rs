//! Base-pair step (the stacking of a double helix, SPEC §9.1): a compliant
//! six-row link between two consecutive base pairs of two strands, rods a
//! and b. Each pair (a point of each strand) carries a frame:
//! x along the rung b − a, z the mean strand direction t_a − t_b
//! (strand b runs antiparallel) made ⟂ x, y = z × x, origin the rung's
//! midpoint moved by `axis_offset` along y — onto the helix axis, so that
//! the step strains are those of the duplex's axis (measured from the
//! off-axis midpoints, twisting the duplex would also shear its steps). The rows are the step's strains against its rest — the
//! translation of pair i+1's origin in pair i's frame (shift, slide, rise)
//! and the small-rotation vector of the relative rotation (tilt, roll,
//! twist: ½ vee(E − Eᵀ) of E = R₀ᵀ F_iᵀ F_{i+1}) — weighted by the square
//! root of the step's stiffness (with a rise–twist coupling), so that the
//! constraint added with compliance 1 stores ½ eᵀ K e, a rigid-base-pair
//! stacking energy (Olson et al. PNAS 1998) without new unknowns. The exact
//! Jacobian comes from forward-mode dual numbers over the 24 inputs
//! (positions and first derivatives at the four abscissae).
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{finite3, ConstraintLaw, Reaction, Row, Side, MAX_ENTRIES};
use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::{Matrix3, RealField, Vector3};
use num_dual::DualSVec64;
use serde::{Deserialize, Serialize};

/// Stacking between base pair (ua, ub) and the next one (ua_next,
/// ub_next): six compliant rows, energy ½ eᵀ K e / compliance with e the
/// step's strains from its rest (length for shift, slide, rise; rad for
/// tilt, roll, twist) and K diagonal but for the rise–twist coupling
/// `twist_stretch`. Add it with compliance 1 for the stiffness given.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BasePairStep {
    pub ua: f64,
    pub ub: f64,
    pub ua_next: f64,
    pub ub_next: f64,
    /// The pair's origin: the rung midpoint + axis_offset · y (length; a
    /// double helix of radius R and strand phase φ: R cos(φ/2)).
    #[serde(default)]
    pub axis_offset: f64,
    /// Pair i+1's origin in pair i's frame at rest (length).
    pub rest_shift: [f64; 3],
    /// Rotation vector (rad) of pair i+1's frame relative to pair i's at rest.
    pub rest_rotation: [f64; 3],
    /// Shift, slide, rise stiffness (force / length).
    pub translation_stiffness: [f64; 3],
    /// Tilt, roll, twist stiffness (force × length / rad²).
    pub rotation_stiffness: [f64; 3],
    /// Rise–twist coupling (force / rad); < 0: the step overwinds when
    /// stretched, as DNA does.
    #[serde(default)]
    pub twist_stretch: f64,
}

type D = DualSVec64<24>;

/// A pair's frame (columns x, y, z) and origin from the strands' points and
/// derivatives.
fn pair_frame<T: RealField + Copy>(a: Vector3<T>, da: Vector3<T>, b: Vector3<T>, db: Vector3<T>, offset: f64) -> (Matrix3<T>, Vector3<T>) {
    let x = (b - a).normalize();
    let v = da.normalize() - db.normalize();
    let z = (v - x * x.dot(&v)).normalize();
    let y = z.cross(&x);
    let half = T::from_subset(&0.5);
    (Matrix3::from_columns(&[x, y, z]), (a + b) * half + y * T::from_subset(&offset))
}

/// The six strains (shift, slide, rise, tilt, roll, twist) of the step
/// given the eight input vectors [a, a′, b, b′, a_next, a′_next, b_next,
/// b′_next] and the rest (translation, rotation).
fn strains<T: RealField + Copy>(p: &[Vector3<T>; 8], offset: f64, d0: &Vector3<f64>, r0: &Matrix3<f64>) -> [T; 6] {
    let (f0, o0) = pair_frame(p[0], p[1], p[2], p[3], offset);
    let (f1, o1) = pair_frame(p[4], p[5], p[6], p[7], offset);
    let d = f0.transpose() * (o1 - o0);
    let e = r0.transpose().map(|v| T::from_subset(&v)) * f0.transpose() * f1;
    let half = T::from_subset(&0.5);
    [
        d.x - T::from_subset(&d0.x),
        d.y - T::from_subset(&d0.y),
        d.z - T::from_subset(&d0.z),
        (e[(2, 1)] - e[(1, 2)]) * half,
        (e[(0, 2)] - e[(2, 0)]) * half,
        (e[(1, 0)] - e[(0, 1)]) * half,
    ]
}

/// exp of a rotation vector (Rodrigues).
fn rotation(w: &[f64; 3]) -> Matrix3<f64> {
    let w = Vector3::from(*w);
    let t = w.norm();
    let k = w.cross_matrix();
    if t < 1e-8 {
        return Matrix3::identity() + k + k * k * 0.5;
    }
    Matrix3::identity() + k * (t.sin() / t) + k * k * ((1.0 - t.cos()) / (t * t))
}

/// Rotation vector of a rotation matrix (log map), angle in [0, π].
fn rotation_vector(r: &Matrix3<f64>) -> Vector3<f64> {
    let c = ((r.trace() - 1.0) * 0.5).clamp(-1.0, 1.0);
    let t = c.acos();
    let s = Vector3::new(r[(2, 1)] - r[(1, 2)], r[(0, 2)] - r[(2, 0)], r[(1, 0)] - r[(0, 1)]) * 0.5;
    if t < 1e-6 {
        return s;
    }
    if t < std::f64::consts::PI - 1e-6 {
        return s * (t / t.sin());
    }
    // Near π: the axis is the column of (R + I)/2 with the largest diagonal.
    let m = (r + Matrix3::identity()) * 0.5;
    let i = (0..3).max_by(|&i, &j| m[(i, i)].total_cmp(&m[(j, j)])).unwrap_or(0); // 3 candidates: never empty
    m.column(i).normalize() * t
}

/// Value and gradient (24 inputs) of the weighted rows.
struct Eval {
    g: [f64; 6],
    grad: [[f64; 24]; 6],
    inputs: [Vector3<f64>; 8],
}

impl BasePairStep {
    /// The four abscissae with their side, in input order.
    fn points(&self) -> [(usize, f64); 4] {
        [(0, self.ua), (1, self.ub), (0, self.ua_next), (1, self.ub_next)]
    }

    fn inputs(&self, rods: &[&Rod]) -> Result<[Vector3<f64>; 8]> {
        let mut p = [Vector3::zeros(); 8];
        for (k, (side, u)) in self.points().into_iter().enumerate() {
            for d in 0..2 {
                let v = rods[side].eval(u, d)?;
                p[2 * k + d] = Vector3::new(v[0], v[1], v[2]);
            }
        }
        // The frames need a rung, tangents and a mean direction off the rung.
        for k in [0, 4] {
            let x = p[k + 2] - p[k];
            let (ta, tb) = (p[k + 1].norm(), p[k + 3].norm());
            if !(x.norm() > 0.0 && ta > 0.0 && tb > 0.0) {
                return Err(Error::singular("base-pair step: a pair's two points coincide or a strand has a zero tangent"));
            }
            let v = p[k + 1] / ta - p[k + 3] / tb;
            let xh = x.normalize();
            if (v - xh * xh.dot(&v)).norm() < 1e-9 {
                return Err(Error::singular("base-pair step: the strands run along the rung"));
            }
        }
        Ok(p)
    }

    /// The lower-triangular weights W with WᵀW = K (rise–twist coupled).
    fn weights(&self) -> [[f64; 6]; 6] {
        let (kt, kr) = (self.translation_stiffness, self.rotation_stiffness);
        let mut w = [[0.0; 6]; 6];
        w[0][0] = kt[0].sqrt();
        w[1][1] = kt[1].sqrt();
        w[2][2] = kt[2].sqrt();
        w[2][5] = self.twist_stretch / kt[2].sqrt();
        w[3][3] = kr[0].sqrt();
        w[4][4] = kr[1].sqrt();
        w[5][5] = (kr[2] - self.twist_stretch * self.twist_stretch / kt[2]).max(0.0).sqrt();
        w
    }

    fn eval(&self, rods: &[&Rod]) -> Result<Eval> {
        let inputs = self.inputs(rods)?;
        let mut p = [Vector3::<D>::zeros(); 8];
        for (k, v) in inputs.iter().enumerate() {
            for a in 0..3 {
                p[k][a] = D::from_re(v[a]).derivative(3 * k + a);
            }
        }
        let e = strains(&p, self.axis_offset, &Vector3::from(self.rest_shift), &rotation(&self.rest_rotation));
        let w = self.weights();
        let mut out = Eval { g: [0.0; 6], grad: [[0.0; 24]; 6], inputs };
        for r in 0..6 {
            for (c, ec) in e.iter().enumerate() {
                if w[r][c] == 0.0 {
                    continue;
                }
                out.g[r] += w[r][c] * ec.re;
                if let Some(d) = &ec.eps.0 {
                    for i in 0..24 {
                        out.grad[r][i] += w[r][c] * d[i];
                    }
                }
            }
        }
        Ok(out)
    }

    /// A step at rest in the rods' current shape (the builder's use).
    pub fn at_rest(rods: &[&Rod], ua: [f64; 2], ub: [f64; 2], axis_offset: f64, translation_stiffness: [f64; 3], rotation_stiffness: [f64; 3], twist_stretch: f64) -> Result<BasePairStep> {
        let mut s = BasePairStep {
            ua: ua[0],
            ub: ub[0],
            ua_next: ua[1],
            ub_next: ub[1],
            axis_offset,
            rest_shift: [0.0; 3],
            rest_rotation: [0.0; 3],
            translation_stiffness,
            rotation_stiffness,
            twist_stretch,
        };
        let p = s.inputs(rods)?;
        let (f0, o0) = pair_frame(p[0], p[1], p[2], p[3], axis_offset);
        let (f1, o1) = pair_frame(p[4], p[5], p[6], p[7], axis_offset);
        s.rest_shift = (f0.transpose() * (o1 - o0)).into();
        s.rest_rotation = rotation_vector(&(f0.transpose() * f1)).into();
        Ok(s)
    }

    /// The six strains (shift, slide, rise in length; tilt, roll, twist in
    /// rad) of the step now, from its rest.
    pub fn strains(&self, rods: &[&Rod]) -> Result<[f64; 6]> {
        let p = self.inputs(rods)?;
        Ok(strains(&p, self.axis_offset, &Vector3::from(self.rest_shift), &rotation(&self.rest_rotation)))
    }
}

impl ConstraintLaw for BasePairStep {
    const INFO: KindInfo = KindInfo {
        name: "BasePairStep",
        helper: "base_pair_step",
        rods: 2,
        doc: "Stacking of a double helix between base pair (ua on strand a, ub on strand b) and the next (ua_next, \
              ub_next): six rows, the step's shift, slide, rise (length) and tilt, roll, twist (rad) from their rest, \
              weighted so that with compliance 1 the energy is ½ eᵀKe (K: the stiffnesses, rise–twist coupled by \
              `twist_stretch`). Strand b runs antiparallel to a. Multipliers: the weighted rows' forces.",
        fields: &[
            FieldInfo::new("ua", Abscissa, "u", "pair i on strand a"),
            FieldInfo::new("ub", Abscissa, "u", "pair i on strand b"),
            FieldInfo::new("ua_next", Abscissa, "u", "pair i+1 on strand a"),
            FieldInfo::new("ub_next", Abscissa, "u", "pair i+1 on strand b"),
            FieldInfo::new("axis_offset", Scalar, "length", "the pair's origin: rung midpoint + axis_offset along y (onto the helix axis)").default("0.0"),
            FieldInfo::new("rest_shift", Vec3, "length", "pair i+1's origin in pair i's frame at rest"),
            FieldInfo::new("rest_rotation", Vec3, "rad", "rotation vector from pair i's frame to pair i+1's at rest"),
            FieldInfo::new("translation_stiffness", Vec3, "force/length", "shift, slide, rise stiffness (> 0)"),
            FieldInfo::new("rotation_stiffness", Vec3, "force·length/rad²", "tilt, roll, twist stiffness (> 0)"),
            FieldInfo::new("twist_stretch", Scalar, "force/rad", "rise–twist coupling (< 0: overwinds when stretched)").default("0.0"),
        ],
    };
    fn n_rows(&self) -> usize {
        6
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        f(0, self.ua);
        f(1, self.ub);
        f(0, self.ua_next);
        f(1, self.ub_next);
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.ua);
        f(1, &mut self.ub);
        f(0, &mut self.ua_next);
        f(1, &mut self.ub_next);
    }
    fn validate(&self, rods: &[&Rod]) -> Result<()> {
        finite3(&self.rest_shift, "base-pair step rest shift")?;
        crate::error::finite("base-pair step axis_offset", self.axis_offset)?;
        finite3(&self.rest_rotation, "base-pair step rest rotation")?;
        for (what, k) in [("translation", self.translation_stiffness), ("rotation", self.rotation_stiffness)] {
            for v in k {
                crate::error::positive(&format!("base-pair step {what} stiffness"), v)?;
            }
        }
        crate::error::finite("base-pair step twist_stretch", self.twist_stretch)?;
        if self.twist_stretch.powi(2) >= self.translation_stiffness[2] * self.rotation_stiffness[2] {
            return Err(Error::invalid(
                "base-pair step twist_stretch",
                format!("{} (rise {} , twist {})", self.twist_stretch, self.translation_stiffness[2], self.rotation_stiffness[2]),
                "twist_stretch² < rise stiffness × twist stiffness (a positive-definite step)",
            ));
        }
        // Every row's entries must fit: the two pairs' spline supports overlap.
        let mut n = 0;
        for side in 0..2 {
            let mut cps: Vec<usize> = Vec::with_capacity(8);
            for (s, u) in self.points() {
                if s == side {
                    cps.extend(rods[side].basis_at(u)?.0);
                }
            }
            cps.sort_unstable();
            cps.dedup();
            n += 3 * cps.len();
        }
        if n > MAX_ENTRIES {
            return Err(Error::invalid(
                "base-pair step abscissae",
                "pairs i and i+1 far apart along a strand",
                "consecutive pairs (each strand's two abscissae within 4 spline segments)",
            ));
        }
        Ok(())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let ev = self.eval(rods)?;
        // Per side, the control points touched and their summed coefficients.
        let mut cps: [[(usize, [[f64; 3]; 6]); 8]; 2] = [[(usize::MAX, [[0.0; 3]; 6]); 8]; 2];
        let mut len = [0usize; 2];
        for (k, (side, u)) in self.points().into_iter().enumerate() {
            let (ctrl, b) = rods[side].basis_at(u)?;
            for j in 0..4 {
                let slot = match cps[side][..len[side]].iter().position(|c| c.0 == ctrl[j]) {
                    Some(s) => s,
                    None => {
                        len[side] += 1;
                        cps[side][len[side] - 1].0 = ctrl[j];
                        len[side] - 1
                    }
                };
                for r in 0..6 {
                    for a in 0..3 {
                        cps[side][slot].1[r][a] += ev.grad[r][3 * (2 * k) + a] * b[0][j] + ev.grad[r][3 * (2 * k + 1) + a] * b[1][j];
                    }
                }
            }
        }
        for (r, row) in rows.iter_mut().enumerate().take(6) {
            for side in 0..2 {
                let dofs = rods[side].dofs();
                for (cp, c) in &cps[side][..len[side]] {
                    for a in 0..3 {
                        row.push_on(side as Side, cp * dofs + a, c[r][a]);
                    }
                }
            }
            row.rhs = -ev.g[r];
        }
        Ok(())
    }
    /// Resultant on strand a of the weighted rows' forces, reduced to its
    /// point at `ua`: through the inputs a, a′ at both pairs (a rigid motion
    /// moves a point by ω × (a − p) and a derivative by ω × a′).
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        let ev = self.eval(rods)?;
        let p = ev.inputs[0];
        let (mut f, mut m) = (Vector3::zeros(), Vector3::zeros());
        for (r, l) in lambda.iter().enumerate().take(6) {
            let g = |i: usize| Vector3::new(ev.grad[r][3 * i], ev.grad[r][3 * i + 1], ev.grad[r][3 * i + 2]) * *l;
            for (pos, der) in [(0, 1), (4, 5)] {
                f += g(pos);
                m += (ev.inputs[pos] - p).cross(&g(pos)) + ev.inputs[der].cross(&g(der));
            }
        }
        Ok(Reaction { force: f.into(), torque: m.into() })
    }
}
