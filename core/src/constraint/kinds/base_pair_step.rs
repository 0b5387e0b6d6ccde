//! Base-pair step (the stacking of a double helix, SPEC §9.1): a compliant
//! six-row link between two consecutive base pairs i, i+1 of two strands,
//! rods a and b, read from the positions of four pairs i−1 … i+2 (a point
//! of each strand per pair). Each pair j carries a frame: x along its rung
//! b − a; z the local helix axis, the difference of the neighbouring rung
//! midpoints m_{j+1} − m_{j−1} made ⟂ x (see [`axis`]); y = z × x; origin
//! the rung's midpoint moved by `axis_offset` along y, onto the helix
//! axis. The frames come from the pairs' points only, not from the
//! strands' tangents: those follow the helix's inclination, so twisting or
//! stretching the duplex would tilt every frame and read as roll and
//! slide. A missing neighbour (the duplex's ends) is given as the pair
//! itself. The rows are the step's strains against its rest — the
//! translation of pair i+1's origin, read in the step's mid frame (shift,
//! slide, rise), and the small-rotation vector of the relative rotation
//! (tilt, roll, twist: ½ vee(E − Eᵀ) of E = R₀ᵀ F_iᵀ F_{i+1}) — weighted by
//! the square root of the step's stiffness (with a rise–twist coupling),
//! so that the constraint added with compliance 1 stores ½ eᵀ K e, a
//! rigid-base-pair stacking energy (Olson et al. PNAS 1998) without new
//! unknowns. The exact Jacobian comes from the chain rule through the
//! frames' construction ([`strains_jacobian`]), checked against
//! forward-mode dual numbers over the 24 inputs (the eight points).
use crate::constraint::catalogue::{FieldInfo, FieldType::*, KindInfo};
use crate::constraint::{finite3, ConstraintLaw, Reaction, Row, Side, MAX_ENTRIES};
use crate::error::{Error, Result};
use crate::rod::Rod;
use nalgebra::{Matrix3, RealField, SMatrix, Vector3};
use serde::{Deserialize, Serialize};

/// Stacking between base pair (ua, ub) and the next one (ua_next,
/// ub_next), framed with the help of the pair before (ua_prev, ub_prev)
/// and the one after (ua_after, ub_after): six compliant rows, energy
/// ½ eᵀ K e / compliance with e the step's strains from its rest (length
/// for shift, slide, rise; rad for tilt, roll, twist) and K diagonal but
/// for the rise–twist coupling `twist_stretch`. Add it with compliance 1
/// for the stiffness given.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BasePairStep {
    /// Pair i−1 (pair i again at the duplex's start).
    pub ua_prev: f64,
    pub ub_prev: f64,
    pub ua: f64,
    pub ub: f64,
    pub ua_next: f64,
    pub ub_next: f64,
    /// Pair i+2 (pair i+1 again at the duplex's end).
    pub ua_after: f64,
    pub ub_after: f64,
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
    /// Frames built axis first ([`stagger_free_axis`], x the rung made ⟂
    /// to it), blind to a pair's stagger (its two points
    /// sliding along the axis): for rungs that resist stagger themselves
    /// ([`super::PairStagger`]). False: x the rung, z the axis made ⟂ x
    /// (the stacking then resists stagger through shift and roll).
    #[serde(default)]
    pub stagger_free: bool,
    /// μ of [`stagger_free_axis`] for pairs i and i+1 (stagger-free
    /// frames; set at rest by [`BasePairStep::free_of_stagger`]).
    #[serde(default)]
    pub axis_mu: [f64; 2],
}


/// Unit rung of each of the four pairs, from the points [a, b] × 4.
fn rungs<T: RealField + Copy>(p: &[Vector3<T>; 8]) -> [Vector3<T>; 4] {
    [0, 1, 2, 3].map(|j| (p[2 * j + 1] - p[2 * j]).normalize())
}

/// Rung midpoints of the four pairs.
fn midpoints<T: RealField + Copy>(p: &[Vector3<T>; 8]) -> [Vector3<T>; 4] {
    let half = T::from_subset(&0.5);
    [0, 1, 2, 3].map(|j| (p[2 * j] + p[2 * j + 1]) * half)
}

/// The helix axis direction (unnormalised, before removing its rung
/// component) at pair j = 1 (pair i) or 2 (pair i+1): the central
/// difference of the rung midpoints m_{j+1} − m_{j−1}; at an end of the
/// duplex (its missing neighbour given as itself) the one-sided
/// second-order difference. The midpoints lie off the axis by R cos(φ/2)
/// along y, turning with the twist: on a straight helix their difference
/// is 2h z minus a multiple of the rung x, exactly removed by making it
/// ⟂ x; on a uniformly bent one it follows the axis to first order in the
/// curvature. (Cross products of neighbouring rungs, the first choice,
/// wobble with the helix phase when the duplex bends: its bending came
/// out 1.7× too stiff.) Public so that measurements of a duplex (the
/// builders' elasticity probe) frame its pairs by the same rule.
pub fn axis<T: RealField + Copy>(m: &[Vector3<T>; 4], j: usize, ends: [bool; 2]) -> Vector3<T> {
    debug_assert!(j == 1 || j == 2, "the axis rule frames pairs 1 and 2 of the four");
    let a = axis_coefficients(j, ends);
    (0..4).fold(Vector3::zeros(), |c, i| if a[i] == 0.0 { c } else { c + m[i] * T::from_subset(&a[i]) })
}

/// The coefficients of the rung midpoints m_0 … m_3 in [`axis`].
fn axis_coefficients(j: usize, ends: [bool; 2]) -> [f64; 4] {
    match (j, ends) {
        (1, [true, _]) => [0.0, -3.0, 4.0, -1.0],
        (2, [_, true]) => [1.0, -4.0, 3.0, 0.0],
        (1, _) => [-1.0, 0.0, 1.0, 0.0],
        _ => [0.0, -1.0, 0.0, 1.0],
    }
}

/// The helix axis direction (unnormalised) at a pair, blind to stagger:
/// c₀ + μ n̂ × c₀, with c₀ = m_last − m_first the difference of two rung
/// midpoints and n̂ = c₀ × p / |c₀ × p|, p = r_first + r_last the sum of
/// those two pairs' rungs (the pair's neighbours; at a duplex's end the
/// pair itself and its one neighbour). On a straight helix c₀ = 2h ẑ + α x̂
/// leans (the midpoints lie off the axis) along x̂, the rung direction
/// halfway between the two pairs, which p follows: the plane of c₀ and p
/// contains the axis. A stagger — a pair's two points sliding along ẑ in
/// opposite senses — moves no midpoint and tilts a rung within a plane
/// (ẑ, its own x̂), leaving the plane of c₀ and p in place to first order;
/// μ ([`axis_mu`]) turns c₀ in that plane by the rest angle that makes the
/// axis ⟂ the pair's rung. Bending and turning carry it along; stretching
/// and twisting change the lean's angle (α/2h), which μ keeps at rest: a
/// coupling the calibration measures with the rest (about 1.3 nm of
/// axis-read stagger per nm of rise and 0.6 nm per rad of twist).
pub fn stagger_free_axis<T: RealField + Copy>(c0: &Vector3<T>, p: &Vector3<T>, mu: f64) -> Vector3<T> {
    *c0 + c0.cross(p).normalize().cross(c0) * T::from_subset(&mu)
}

/// μ that makes [`stagger_free_axis`] (c₀, p) ⟂ the rung `x` (at rest).
pub fn axis_mu(c0: &Vector3<f64>, p: &Vector3<f64>, x: &Vector3<f64>) -> Result<f64> {
    let n = c0.cross(p);
    if !(n.norm() > 1e-9 * c0.norm() * p.norm()) {
        return Err(Error::singular("helix axis: the midpoints run along the rungs (no helix to read an axis from)"));
    }
    let s = n.normalize().cross(c0);
    if !(s.dot(x).abs() > 1e-12 * c0.norm() * x.norm()) {
        return Err(Error::singular("helix axis: no rotation in the rungs' plane makes the axis ⟂ the rung"));
    }
    Ok(-c0.dot(x) / s.dot(x))
}

/// The two of the four pairs whose midpoints and rungs give pair j's
/// stagger-free axis: its neighbours, or at a duplex's end itself and
/// its one neighbour.
fn free_axis_pairs(j: usize, ends: [bool; 2]) -> (usize, usize) {
    match j {
        1 => (if ends[0] { 1 } else { 0 }, 2),
        _ => (1, if ends[1] { 2 } else { 3 }),
    }
}

/// c₀ and p of pair j's stagger-free axis, from the eight points.
fn free_axis_inputs<T: RealField + Copy>(p: &[Vector3<T>; 8], j: usize, ends: [bool; 2]) -> (Vector3<T>, Vector3<T>) {
    let (f, l) = free_axis_pairs(j, ends);
    let half = T::from_subset(&0.5);
    ((p[2 * l] + p[2 * l + 1] - p[2 * f] - p[2 * f + 1]) * half, p[2 * f + 1] - p[2 * f] + p[2 * l + 1] - p[2 * l])
}

/// Pair j's frame (columns x, y, z) and origin, j = 1 (pair i) or 2
/// (pair i+1); `lambda`: the stagger-free rule's μ per pair (None: rung
/// first).
fn pair_frame<T: RealField + Copy>(p: &[Vector3<T>; 8], x: &[Vector3<T>; 4], m: &[Vector3<T>; 4], j: usize, ends: [bool; 2], offset: f64, lambda: Option<[f64; 2]>) -> (Matrix3<T>, Vector3<T>) {
    let (x, z) = match lambda {
        None => {
            let c = axis(m, j, ends);
            (x[j], (c - x[j] * x[j].dot(&c)).normalize())
        }
        Some(mu) => {
            let (c0, plane) = free_axis_inputs(p, j, ends);
            let z = stagger_free_axis(&c0, &plane, mu[j - 1]).normalize();
            ((x[j] - z * z.dot(&x[j])).normalize(), z)
        }
    };
    let y = z.cross(&x);
    (Matrix3::from_columns(&[x, y, z]), m[j] + y * T::from_subset(&offset))
}

/// The step's mid frame, halfway between pair i's and pair i+1's (to
/// first order in their relative rotation about anything but z, exactly
/// about z): the step's translation is read in it, so that a uniform bend
/// is no shear (read in pair i's frame, the rise would lean by half the
/// step's bend into shift and slide).
fn mid_frame<T: RealField + Copy>(f0: &Matrix3<T>, f1: &Matrix3<T>) -> Matrix3<T> {
    let z = (f0.column(2) + f1.column(2)).normalize();
    let x = f0.column(0) + f1.column(0);
    let x = (x - z * z.dot(&x)).normalize();
    Matrix3::from_columns(&[x, z.cross(&x), z])
}

/// The step's frames and origins from the eight points [a, b] of pairs
/// i−1 … i+2.
fn frames<T: RealField + Copy>(p: &[Vector3<T>; 8], ends: [bool; 2], offset: f64, lambda: Option<[f64; 2]>) -> [(Matrix3<T>, Vector3<T>); 2] {
    let (x, m) = (rungs(p), midpoints(p));
    [pair_frame(p, &x, &m, 1, ends, offset, lambda), pair_frame(p, &x, &m, 2, ends, offset, lambda)]
}

/// The step's translation (in its mid frame) and relative rotation.
fn step<T: RealField + Copy>(p: &[Vector3<T>; 8], ends: [bool; 2], offset: f64, lambda: Option<[f64; 2]>) -> (Vector3<T>, Matrix3<T>) {
    let [(f0, o0), (f1, o1)] = frames(p, ends, offset, lambda);
    (mid_frame(&f0, &f1).transpose() * (o1 - o0), f0.transpose() * f1)
}

/// The six strains (shift, slide, rise, tilt, roll, twist) of the step
/// given the eight points and the rest (translation, rotation).
fn strains<T: RealField + Copy>(p: &[Vector3<T>; 8], ends: [bool; 2], offset: f64, lambda: Option<[f64; 2]>, d0: &Vector3<f64>, r0: &Matrix3<f64>) -> [T; 6] {
    let (d, r) = step(p, ends, offset, lambda);
    let e = r0.transpose().map(|v| T::from_subset(&v)) * r;
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

/// Jacobian of a 3-vector with respect to the 24 inputs (the 8 points).
pub(crate) type J3 = SMatrix<f64, 3, 24>;
pub(crate) type J1 = SMatrix<f64, 1, 24>;

/// The Jacobian of input point k (of the eight) scaled by w.
pub(crate) fn select(k: usize, w: f64) -> J3 {
    let mut j = J3::zeros();
    for a in 0..3 {
        j[(a, 3 * k + a)] = w;
    }
    j
}

/// [`stagger_free_axis`] and its Jacobian from c₀'s and p's.
pub(crate) fn stagger_free_axis_jacobian(c0: &Vector3<f64>, jc0: &J3, p: &Vector3<f64>, jp: &J3, mu: f64) -> (Vector3<f64>, J3) {
    let (n, jn) = cross(c0, jc0, p, jp);
    let (n, jn) = unit(&n, &jn);
    let (s, js) = cross(&n, &jn, c0, jc0);
    (c0 + s * mu, jc0 + js * mu)
}

/// Unit vector v/|v| and its Jacobian from v's.
pub(crate) fn unit(v: &Vector3<f64>, jv: &J3) -> (Vector3<f64>, J3) {
    let n = v.norm();
    let u = v / n;
    (u, (Matrix3::identity() - u * u.transpose()) * jv / n)
}

/// w − u (u·w) for a unit u, and its Jacobian.
pub(crate) fn reject(w: &Vector3<f64>, jw: &J3, u: &Vector3<f64>, ju: &J3) -> (Vector3<f64>, J3) {
    let uw = u.dot(w);
    (w - u * uw, jw - u * (u.transpose() * jw + w.transpose() * ju) - ju * uw)
}

/// a × b and its Jacobian.
pub(crate) fn cross(a: &Vector3<f64>, ja: &J3, b: &Vector3<f64>, jb: &J3) -> (Vector3<f64>, J3) {
    (a.cross(b), a.cross_matrix() * jb - b.cross_matrix() * ja)
}

/// [`strains`] and their exact Jacobian with respect to the eight points,
/// by the chain rule through the frames' construction (the same steps as
/// [`frames`], [`mid_frame`] and [`step`]; a unit test compares it with
/// forward-mode dual numbers). Allocation-free, no 24-wide dual numbers.
fn strains_jacobian(p: &[Vector3<f64>; 8], ends: [bool; 2], offset: f64, lambda: Option<[f64; 2]>, d0: &Vector3<f64>, r0: &Matrix3<f64>) -> ([f64; 6], [J1; 6]) {
    let m: [Vector3<f64>; 4] = [0, 1, 2, 3].map(|j| (p[2 * j] + p[2 * j + 1]) * 0.5);
    let jm: [J3; 4] = [0, 1, 2, 3].map(|j| select(2 * j, 0.5) + select(2 * j + 1, 0.5));
    // Pair frames j = 1, 2: columns (x, y, z) with Jacobians, and origins.
    let mut f = [[Vector3::zeros(); 3]; 2];
    let mut jf = [[J3::zeros(); 3]; 2];
    let mut o = [Vector3::zeros(); 2];
    let mut jo = [J3::zeros(); 2];
    for (s, j) in [1usize, 2].into_iter().enumerate() {
        let (xr, jxr) = unit(&(p[2 * j + 1] - p[2 * j]), &(select(2 * j + 1, 1.0) - select(2 * j, 1.0)));
        let a = axis_coefficients(j, ends);
        let (mut c, mut jc) = (Vector3::zeros(), J3::zeros());
        for i in 0..4 {
            if a[i] != 0.0 {
                c += m[i] * a[i];
                jc += jm[i] * a[i];
            }
        }
        let ((x, jx), (z, jz)) = match lambda {
            None => {
                let (w, jw) = reject(&c, &jc, &xr, &jxr);
                ((xr, jxr), unit(&w, &jw))
            }
            Some(mu) => {
                let (fp, lp) = free_axis_pairs(j, ends);
                let (c0, plane) = free_axis_inputs(p, j, ends);
                let jc0 = jm[lp] - jm[fp];
                let jp = select(2 * fp + 1, 1.0) - select(2 * fp, 1.0) + select(2 * lp + 1, 1.0) - select(2 * lp, 1.0);
                let (c, jc) = stagger_free_axis_jacobian(&c0, &jc0, &plane, &jp, mu[j - 1]);
                let (z, jz) = unit(&c, &jc);
                let (w, jw) = reject(&xr, &jxr, &z, &jz);
                (unit(&w, &jw), (z, jz))
            }
        };
        let (y, jy) = cross(&z, &jz, &x, &jx);
        o[s] = m[j] + y * offset;
        jo[s] = jm[j] + jy * offset;
        f[s] = [x, y, z];
        jf[s] = [jx, jy, jz];
    }
    // Mid frame.
    let (zm, jzm) = unit(&(f[0][2] + f[1][2]), &(jf[0][2] + jf[1][2]));
    let (v, jv) = reject(&(f[0][0] + f[1][0]), &(jf[0][0] + jf[1][0]), &zm, &jzm);
    let (xm, jxm) = unit(&v, &jv);
    let (ym, jym) = cross(&zm, &jzm, &xm, &jxm);
    let (dl, jdl) = (o[1] - o[0], jo[1] - jo[0]);
    let mut g = [0.0; 6];
    let mut jg = [J1::zeros(); 6];
    for (a, (col, jcol)) in [(xm, jxm), (ym, jym), (zm, jzm)].iter().enumerate() {
        g[a] = col.dot(&dl) - d0[a];
        jg[a] = col.transpose() * jdl + dl.transpose() * jcol;
    }
    // R = F0ᵀ F1, E = R0ᵀ R; rows: ½ vee(E − Eᵀ).
    let mut r = Matrix3::zeros();
    let mut jr = [[J1::zeros(); 3]; 3];
    for a in 0..3 {
        for b in 0..3 {
            r[(a, b)] = f[0][a].dot(&f[1][b]);
            jr[a][b] = f[0][a].transpose() * jf[1][b] + f[1][b].transpose() * jf[0][a];
        }
    }
    let e = r0.transpose() * r;
    let je = |a: usize, b: usize| (0..3).fold(J1::zeros(), |acc, c| acc + jr[c][b] * r0[(c, a)]);
    for (k, (a, b)) in [(2, 1), (0, 2), (1, 0)].into_iter().enumerate() {
        g[3 + k] = 0.5 * (e[(a, b)] - e[(b, a)]);
        jg[3 + k] = (je(a, b) - je(b, a)) * 0.5;
    }
    (g, jg)
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

/// Per side, the control points that (at most eight) points (side, u) move
/// (nonzero position weights: a point at a knot moves three) with, per
/// row, the summed coefficients of the rows' gradient `grad` over the
/// points' 24 coordinates (at most 6 rows).
pub(crate) fn control_points(rods: &[&Rod], points: &[(usize, f64)], grad: &[[f64; 24]]) -> Result<([[(usize, [[f64; 3]; 6]); 16]; 2], [usize; 2])> {
    let mut cps = [[(usize::MAX, [[0.0; 3]; 6]); 16]; 2];
    let mut len = [0usize; 2];
    for (k, &(side, u)) in points.iter().enumerate() {
        let (ctrl, b) = rods[side].basis_at(u)?;
        for j in 0..4 {
            if b[0][j] == 0.0 {
                continue;
            }
            let slot = match cps[side][..len[side]].iter().position(|c| c.0 == ctrl[j]) {
                Some(s) => s,
                None => {
                    len[side] += 1;
                    cps[side][len[side] - 1].0 = ctrl[j];
                    len[side] - 1
                }
            };
            for (r, g) in grad.iter().enumerate() {
                for a in 0..3 {
                    cps[side][slot].1[r][a] += g[3 * k + a] * b[0][j];
                }
            }
        }
    }
    Ok((cps, len))
}

/// Rows from their values `g` and gradients `grad` over the points'
/// coordinates (gathered per control point by [`control_points`]).
pub(crate) fn point_rows(rods: &[&Rod], points: &[(usize, f64)], grad: &[[f64; 24]], g: &[f64], rows: &mut [Row]) -> Result<()> {
    let (cps, len) = control_points(rods, points, grad)?;
    for (r, row) in rows.iter_mut().enumerate().take(grad.len()) {
        for side in 0..2 {
            let dofs = rods[side].dofs();
            for (cp, c) in &cps[side][..len[side]] {
                for a in 0..3 {
                    row.push_on(side as Side, cp * dofs + a, c[r][a]);
                }
            }
        }
        row.rhs = -g[r];
    }
    Ok(())
}

/// Resultant on strand a (the even points: a, b alternate) of the rows'
/// forces λ · gradient, reduced to its first point (a rigid motion moves
/// a point by ω × (p − p₀)).
pub(crate) fn strand_a_resultant(points: &[Vector3<f64>], grad: &[[f64; 24]], lambda: &[f64]) -> Reaction {
    let (mut f, mut m) = (Vector3::zeros(), Vector3::zeros());
    for (gr, l) in grad.iter().zip(lambda) {
        for k in (0..points.len()).step_by(2) {
            let g = Vector3::new(gr[3 * k], gr[3 * k + 1], gr[3 * k + 2]) * *l;
            f += g;
            m += (points[k] - points[0]).cross(&g);
        }
    }
    Reaction { force: f.into(), torque: m.into() }
}

/// Value and gradient (24 inputs) of the weighted rows.
struct Eval {
    g: [f64; 6],
    grad: [[f64; 24]; 6],
    inputs: [Vector3<f64>; 8],
}

impl BasePairStep {
    /// The eight abscissae with their side, in input order (pairs i−1 … i+2).
    fn points(&self) -> [(usize, f64); 8] {
        [
            (0, self.ua_prev),
            (1, self.ub_prev),
            (0, self.ua),
            (1, self.ub),
            (0, self.ua_next),
            (1, self.ub_next),
            (0, self.ua_after),
            (1, self.ub_after),
        ]
    }

    /// Whether pair i is the first (no pair before) and pair i+1 the last.
    fn ends(&self) -> [bool; 2] {
        [self.ua_prev == self.ua && self.ub_prev == self.ub, self.ua_after == self.ua_next && self.ub_after == self.ub_next]
    }

    /// λ of the stagger-free frames (None: rung-first frames).
    fn lambda(&self) -> Option<[f64; 2]> {
        self.stagger_free.then_some(self.axis_mu)
    }

    fn inputs(&self, rods: &[&Rod]) -> Result<[Vector3<f64>; 8]> {
        let mut p = [Vector3::zeros(); 8];
        for (k, (side, u)) in self.points().into_iter().enumerate() {
            let v = rods[side].eval(u, 0)?;
            p[k] = Vector3::new(v[0], v[1], v[2]);
        }
        // Every pair needs a rung, and pairs i, i+1 an axis off their rung.
        for j in 0..4 {
            if !((p[2 * j + 1] - p[2 * j]).norm() > 0.0) {
                return Err(Error::singular("base-pair step: a pair's two points coincide"));
            }
        }
        let (x, m) = (rungs(&p), midpoints(&p));
        for j in [1, 2] {
            let c = match self.lambda() {
                None => axis(&m, j, self.ends()),
                Some(mu) => {
                    let (c0, plane) = free_axis_inputs(&p, j, self.ends());
                    if !(c0.cross(&plane).norm() > 1e-9 * c0.norm() * plane.norm()) {
                        return Err(Error::singular("base-pair step: the rung midpoints run along the rungs (no helix axis)"));
                    }
                    stagger_free_axis(&c0, &plane, mu[j - 1])
                }
            };
            if (c - x[j] * x[j].dot(&c)).norm() < 1e-9 || (self.stagger_free && (x[j] - c * x[j].dot(&c) / c.norm_squared()).norm() < 1e-9) {
                return Err(Error::singular("base-pair step: the helix axis runs along a rung (no frame)"));
            }
        }
        // The mid frame needs the two axes and the two rungs off antiparallel.
        let [(f0, _), (f1, _)] = frames(&p, self.ends(), self.axis_offset, self.lambda());
        let z = f0.column(2) + f1.column(2);
        let xm = f0.column(0) + f1.column(0);
        if z.norm() < 1e-9 || (xm - z * z.dot(&xm) / z.norm_squared()).norm() < 1e-9 {
            return Err(Error::singular("base-pair step: the two pairs' frames are turned half a turn apart (no mid frame)"));
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
        let (e, je) = strains_jacobian(&inputs, self.ends(), self.axis_offset, self.lambda(), &Vector3::from(self.rest_shift), &rotation(&self.rest_rotation));
        let w = self.weights();
        let mut out = Eval { g: [0.0; 6], grad: [[0.0; 24]; 6], inputs };
        for r in 0..6 {
            for c in 0..6 {
                if w[r][c] == 0.0 {
                    continue;
                }
                out.g[r] += w[r][c] * e[c];
                for i in 0..24 {
                    out.grad[r][i] += w[r][c] * je[c][i];
                }
            }
        }
        Ok(out)
    }

    /// A step at rest in the rods' current shape (the builder's use):
    /// abscissae of pairs i−1 … i+2 on strand a (`ua`) and strand b (`ub`).
    pub fn at_rest(rods: &[&Rod], ua: [f64; 4], ub: [f64; 4], axis_offset: f64, translation_stiffness: [f64; 3], rotation_stiffness: [f64; 3], twist_stretch: f64) -> Result<BasePairStep> {
        let mut s = BasePairStep {
            ua_prev: ua[0],
            ub_prev: ub[0],
            ua: ua[1],
            ub: ub[1],
            ua_next: ua[2],
            ub_next: ub[2],
            ua_after: ua[3],
            ub_after: ub[3],
            axis_offset,
            rest_shift: [0.0; 3],
            rest_rotation: [0.0; 3],
            translation_stiffness,
            rotation_stiffness,
            twist_stretch,
            stagger_free: false,
            axis_mu: [0.0; 2],
        };
        s.set_rest(rods)?;
        Ok(s)
    }

    /// The same step with stagger-free frames (see `stagger_free`), λ and
    /// rest set from the rods' current shape.
    pub fn free_of_stagger(mut self, rods: &[&Rod]) -> Result<BasePairStep> {
        let mut p = [Vector3::zeros(); 8];
        for (k, (side, u)) in self.points().into_iter().enumerate() {
            p[k] = rods[side].position(u)?;
        }
        let x = rungs(&p);
        for j in [1, 2] {
            let (c0, plane) = free_axis_inputs(&p, j, self.ends());
            self.axis_mu[j - 1] = axis_mu(&c0, &plane, &x[j])?;
        }
        self.stagger_free = true;
        self.set_rest(rods)?;
        Ok(self)
    }

    /// Rest shift and rotation = the step in the rods' current shape.
    fn set_rest(&mut self, rods: &[&Rod]) -> Result<()> {
        let p = self.inputs(rods)?;
        let (d, r) = step(&p, self.ends(), self.axis_offset, self.lambda());
        self.rest_shift = d.into();
        self.rest_rotation = rotation_vector(&r).into();
        Ok(())
    }

    /// The six strains (shift, slide, rise in length; tilt, roll, twist in
    /// rad) of the step now, from its rest.
    pub fn strains(&self, rods: &[&Rod]) -> Result<[f64; 6]> {
        let p = self.inputs(rods)?;
        Ok(strains(&p, self.ends(), self.axis_offset, self.lambda(), &Vector3::from(self.rest_shift), &rotation(&self.rest_rotation)))
    }

}

impl ConstraintLaw for BasePairStep {
    const INFO: KindInfo = KindInfo {
        name: "BasePairStep",
        helper: "base_pair_step",
        rods: 2,
        doc: "Stacking of a double helix between base pair (ua on strand a, ub on strand b) and the next (ua_next, \
              ub_next), the pairs before (ua_prev, ub_prev) and after (ua_after, ub_after) giving the helix axis \
              (at an end: the end pair again): six rows, the step's shift, slide, rise (length) and tilt, roll, twist \
              (rad) from their rest, weighted so that with compliance 1 the energy is ½ eᵀKe (K: the stiffnesses, \
              rise–twist coupled by `twist_stretch`). Strand b runs antiparallel to a. Multipliers: the weighted rows' \
              forces.",
        fields: &[
            FieldInfo::new("ua_prev", Abscissa, "u", "pair i−1 on strand a (pair i at the start)"),
            FieldInfo::new("ub_prev", Abscissa, "u", "pair i−1 on strand b (pair i at the start)"),
            FieldInfo::new("ua", Abscissa, "u", "pair i on strand a"),
            FieldInfo::new("ub", Abscissa, "u", "pair i on strand b"),
            FieldInfo::new("ua_next", Abscissa, "u", "pair i+1 on strand a"),
            FieldInfo::new("ub_next", Abscissa, "u", "pair i+1 on strand b"),
            FieldInfo::new("ua_after", Abscissa, "u", "pair i+2 on strand a (pair i+1 at the end)"),
            FieldInfo::new("ub_after", Abscissa, "u", "pair i+2 on strand b (pair i+1 at the end)"),
            FieldInfo::new("axis_offset", Scalar, "length", "the pair's origin: rung midpoint + axis_offset along y (onto the helix axis)").default("0.0"),
            FieldInfo::new("rest_shift", Vec3, "length", "pair i+1's origin in pair i's frame at rest"),
            FieldInfo::new("rest_rotation", Vec3, "rad", "rotation vector from pair i's frame to pair i+1's at rest"),
            FieldInfo::new("translation_stiffness", Vec3, "force/length", "shift, slide, rise stiffness (> 0)"),
            FieldInfo::new("rotation_stiffness", Vec3, "force·length/rad²", "tilt, roll, twist stiffness (> 0)"),
            FieldInfo::new("twist_stretch", Scalar, "force/rad", "rise–twist coupling (< 0: overwinds when stretched)").default("0.0"),
            FieldInfo::new("stagger_free", Flag, "", "frames built axis first (the midpoint difference turned in the plane of the rung), blind to a pair's stagger (for rungs that resist it: PairStagger)").default("false"),
            FieldInfo::new("axis_mu", Vec2, "", "μ of the stagger-free helix-axis rule for pairs i and i+1 (set at rest)").default("[0, 0]"),
        ],
    };
    fn n_rows(&self) -> usize {
        6
    }
    fn visit_abscissae(&self, f: &mut dyn FnMut(Side, f64)) {
        for (side, u) in self.points() {
            f(side as Side, u);
        }
    }
    fn visit_abscissae_mut(&mut self, f: &mut dyn FnMut(Side, &mut f64)) {
        f(0, &mut self.ua_prev);
        f(1, &mut self.ub_prev);
        f(0, &mut self.ua);
        f(1, &mut self.ub);
        f(0, &mut self.ua_next);
        f(1, &mut self.ub_next);
        f(0, &mut self.ua_after);
        f(1, &mut self.ub_after);
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
        crate::error::finite("base-pair step axis_mu", self.axis_mu[0])?;
        crate::error::finite("base-pair step axis_mu", self.axis_mu[1])?;
        if self.twist_stretch.powi(2) >= self.translation_stiffness[2] * self.rotation_stiffness[2] {
            return Err(Error::invalid(
                "base-pair step twist_stretch",
                format!("{} (rise {} , twist {})", self.twist_stretch, self.translation_stiffness[2], self.rotation_stiffness[2]),
                "twist_stretch² < rise stiffness × twist stiffness (a positive-definite step)",
            ));
        }
        // Every row's entries must fit: the four pairs' spline supports overlap.
        let (_, len) = control_points(rods, &self.points(), &[[0.0; 24]; 6])?;
        if 3 * (len[0] + len[1]) > MAX_ENTRIES {
            return Err(Error::invalid(
                "base-pair step abscissae",
                "pairs i−1 … i+2 far apart along a strand",
                format!("consecutive pairs (at most {} control points moved on both strands)", MAX_ENTRIES / 3),
            ));
        }
        Ok(())
    }
    fn linearize(&self, rods: &[&Rod], rows: &mut [Row]) -> Result<()> {
        let ev = self.eval(rods)?;
        point_rows(rods, &self.points(), &ev.grad, &ev.g, rows)
    }
    /// Resultant on strand a of the weighted rows' forces, reduced to its
    /// first point (`ua_prev`): through its four points (a rigid motion
    /// moves a point by ω × (a − p)).
    fn reaction(&self, rods: &[&Rod], lambda: &[f64]) -> Result<Reaction> {
        let ev = self.eval(rods)?;
        Ok(strand_a_resultant(&ev.inputs, &ev.grad, lambda))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::DualSVec64;

    /// The chain-rule Jacobian equals forward-mode automatic
    /// differentiation (num-dual) on deformed steps, at the ends and inside.
    #[test]
    fn jacobian_matches_dual_numbers() {
        type D = DualSVec64<24>;
        // A helix (radius 1, rise 0.34, 10.5 bp/turn, phase 127°) with a
        // fixed pseudo-random perturbation (no RNG: a deterministic sine).
        let point = |k: usize, side: usize| {
            let t = 2.0 * std::f64::consts::PI * k as f64 / 10.5 + side as f64 * 2.23;
            let q = (k * 2 + side) as f64;
            Vector3::new(t.cos() + 0.05 * (1.7 * q).sin(), t.sin() + 0.05 * (2.3 * q).cos(), 0.34 * k as f64 + 0.03 * (0.7 * q).sin())
        };
        let r0 = rotation(&[0.02, -0.01, 0.6]);
        let d0 = Vector3::new(0.01, -0.02, 0.34);
        for (ends, lambda) in [[false, false], [true, false], [false, true], [true, true]].into_iter().flat_map(|e| [(e, None), (e, Some([-0.74, -0.7]))]) {
            let ks = [if ends[0] { 1 } else { 0 }, 1, 2, if ends[1] { 2 } else { 3 }];
            let mut p = [Vector3::zeros(); 8];
            for (j, &k) in ks.iter().enumerate() {
                p[2 * j] = point(k, 0);
                p[2 * j + 1] = point(k, 1);
            }
            let (g, jg) = strains_jacobian(&p, ends, 0.6, lambda, &d0, &r0);
            let mut pd = [Vector3::<D>::zeros(); 8];
            for (k, v) in p.iter().enumerate() {
                for a in 0..3 {
                    pd[k][a] = D::from_re(v[a]).derivative(3 * k + a);
                }
            }
            let e = strains(&pd, ends, 0.6, lambda, &d0, &r0);
            for r in 0..6 {
                assert!((g[r] - e[r].re).abs() < 1e-13, "value of row {r} at ends {ends:?}, λ {lambda:?}");
                let d = e[r].eps.0.unwrap_or_default();
                for i in 0..24 {
                    assert!((jg[r][i] - d[i]).abs() < 1e-12 * (1.0 + d[i].abs()), "∂row {r}/∂input {i} at ends {ends:?}, λ {lambda:?}: {} vs {}", jg[r][i], d[i]);
                }
            }
        }
    }

    /// Stagger-free frames do not see a pair's stagger (its two points
    /// sliding by ±d/2 along the helix axis) to first order, where the
    /// rung-first frames read it as shift and roll.
    #[test]
    fn stagger_free_frames_ignore_a_pairs_stagger() {
        let helix = |k: usize, side: usize| {
            let t = 2.0 * std::f64::consts::PI * k as f64 / 10.5 + side as f64 * 2.2176;
            Vector3::new(t.cos(), t.sin(), 0.34 * k as f64)
        };
        // Inside, and at either end (the missing neighbour given as the pair).
        for ends in [[false, false], [true, false], [false, true]] {
            let ks = [if ends[0] { 1 } else { 0 }, 1, 2, if ends[1] { 2 } else { 3 }];
            let mut p = [Vector3::zeros(); 8];
            for (slot, &k) in ks.iter().enumerate() {
                p[2 * slot] = helix(k, 0);
                p[2 * slot + 1] = helix(k, 1);
            }
            let x = rungs(&p);
            let mu = [1, 2].map(|j| {
                let (c0, plane) = free_axis_inputs(&p, j, ends);
                axis_mu(&c0, &plane, &x[j]).unwrap() // an exact helix: never singular
            });
            // At rest the stagger-free axes are the helix axis.
            for j in [1, 2] {
                let (c0, plane) = free_axis_inputs(&p, j, ends);
                assert!((stagger_free_axis(&c0, &plane, mu[j - 1]).normalize() - Vector3::z()).norm() < 1e-12, "pair {j} at ends {ends:?}");
            }
            let d = 1e-4;
            for lambda in [None, Some(mu)] {
                let (d0, r) = step(&p, ends, 0.45, lambda);
                let r0 = rotation(&rotation_vector(&r).into());
                for j in [1, 2] {
                    // Pair j's points, wherever they appear among the eight.
                    let mut q = p;
                    for (slot, &k) in ks.iter().enumerate() {
                        if k == ks[j] {
                            q[2 * slot].z += d / 2.0;
                            q[2 * slot + 1].z -= d / 2.0;
                        }
                    }
                    let e = strains(&q, ends, 0.45, lambda, &d0, &r0);
                    let worst = e.iter().fold(0.0f64, |w, v| w.max(v.abs()));
                    match lambda {
                        Some(_) => assert!(worst < 1e-3 * d, "stagger-free: strain {worst:e} for a stagger {d:e} of pair {j} at ends {ends:?}"),
                        None => assert!(worst > 0.1 * d, "rung-first: strain {worst:e} for a stagger {d:e} of pair {j} at ends {ends:?}"),
                    }
                }
            }
        }
    }
}
