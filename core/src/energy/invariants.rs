//! The local derivative vector d = (r', r'', r''', θ, θ') ∈ R¹¹ (SPEC §2) and
//! the five scalar invariants every energy density is written in:
//!
//!   a  = r'·r'            (squared parametric speed)
//!   c2 = |r' × r''|²      (κ² |r'|⁶)
//!   p  = (r' × r'')·r'''  (the numerator of the Frenet torsion)
//!   θ, θ'                 (roll and its parametric derivative)
//!
//! W(d) = F(a, c2, p, θ, θ'), so ∇W = Σ F_k ∇q_k and
//! ∇²W = Σ F_k ∇²q_k + Jᵀ F_qq J with J = ∂q/∂d (5×11). The q_k are
//! polynomials whose gradients and Hessians are written here in closed form;
//! this replaces the factorised (and misprinted) II.84–II.101.
use nalgebra::{SMatrix, SVector, Vector3};

pub type Vec11 = SVector<f64, 11>;
pub type Mat11 = SMatrix<f64, 11, 11>;
pub type Vec5 = SVector<f64, 5>;
pub type Mat5 = SMatrix<f64, 5, 5>;

/// Slots of d: r' at 0..3, r'' at 3..6, r''' at 6..9, θ at 9, θ' at 10.
pub const R1: usize = 0;
pub const R2: usize = 3;
pub const R3: usize = 6;
pub const TH: usize = 9;
pub const TH1: usize = 10;
/// Indices of the invariants in F's argument vector.
pub const QA: usize = 0;
pub const QC2: usize = 1;
pub const QP: usize = 2;
pub const QTH: usize = 3;
pub const QTH1: usize = 4;

/// d at one sample. Derivatives are with respect to the spline parameter u.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalState {
    pub r1: Vector3<f64>,
    pub r2: Vector3<f64>,
    pub r3: Vector3<f64>,
    pub th: f64,
    pub th1: f64,
}

impl LocalState {
    pub fn from_vec(d: &Vec11) -> Self {
        LocalState {
            r1: d.fixed_rows::<3>(R1).into(),
            r2: d.fixed_rows::<3>(R2).into(),
            r3: d.fixed_rows::<3>(R3).into(),
            th: d[TH],
            th1: d[TH1],
        }
    }
    pub fn to_vec(&self) -> Vec11 {
        let mut d = Vec11::zeros();
        d.fixed_rows_mut::<3>(R1).copy_from(&self.r1);
        d.fixed_rows_mut::<3>(R2).copy_from(&self.r2);
        d.fixed_rows_mut::<3>(R3).copy_from(&self.r3);
        d[TH] = self.th;
        d[TH1] = self.th1;
        d
    }
    /// C = r' × r'' (the unnormalised binormal).
    pub fn cross(&self) -> Vector3<f64> {
        self.r1.cross(&self.r2)
    }
    /// (a, c2, p, θ, θ').
    pub fn invariants(&self) -> Vec5 {
        let c = self.cross();
        Vec5::new(self.r1.norm_squared(), c.norm_squared(), c.dot(&self.r3), self.th, self.th1)
    }

    /// J = ∂q/∂d, 5×11 (rows: a, c2, p, θ, θ').
    pub fn jacobian(&self) -> SMatrix<f64, 5, 11> {
        let c = self.cross();
        let mut j = SMatrix::<f64, 5, 11>::zeros();
        set3(&mut j, QA, R1, &(2.0 * self.r1));
        // dc2 = 2C·(dr'×r'' + r'×dr'') = 2 dr'·(r''×C) + 2 dr''·(C×r')
        set3(&mut j, QC2, R1, &(2.0 * self.r2.cross(&c)));
        set3(&mut j, QC2, R2, &(2.0 * c.cross(&self.r1)));
        // p = det[r', r'', r''']
        set3(&mut j, QP, R1, &self.r2.cross(&self.r3));
        set3(&mut j, QP, R2, &self.r3.cross(&self.r1));
        set3(&mut j, QP, R3, &c);
        j[(QTH, TH)] = 1.0;
        j[(QTH1, TH1)] = 1.0;
        j
    }
}

fn set3(j: &mut SMatrix<f64, 5, 11>, row: usize, col: usize, v: &Vector3<f64>) {
    for k in 0..3 {
        j[(row, col + k)] = v[k];
    }
}

/// κ² = c2 a⁻³ (frame-free) and its derivatives in the invariants a, c2
/// (∂²/∂c2² is zero).
#[derive(Clone, Copy, Debug)]
pub struct Curvature2 {
    pub v: f64,
    pub a: f64,
    pub c: f64,
    pub aa: f64,
    pub ac: f64,
}

#[inline(always)]
pub fn curvature_squared(q: &Vec5) -> Curvature2 {
    let ia = 1.0 / q[QA];
    let ia3 = ia * ia * ia;
    let v = q[QC2] * ia3;
    Curvature2 { v, a: -3.0 * v * ia, c: ia3, aa: 12.0 * v * ia * ia, ac: -3.0 * ia3 * ia }
}

/// Value, gradient and Hessian of W(d) from F's derivatives with respect to
/// the invariants: the chain rule of the module doc, ∇W = Jᵀ F_q and
/// ∇²W = Σ_k F_k ∇²q_k + Jᵀ F_qq J. `grad` and `hess` are overwritten.
///
/// J = ∂q/∂d is sparse: per position slot r′, r″, r‴ it has the 3-vector
/// rows of (a, c2, p), (c2, p), (p) (see [`LocalState::jacobian`]) and θ,
/// θ′ are unit rows, so M = F_qq J and the upper half of Jᵀ M are formed
/// slot by slot (≈ 250 multiply-adds instead of ≈ 880 dense); the ∇²q_k
/// are isotropic, rank-one and cross-product 3×3 blocks added in closed
/// form. Unrolled scalar code on plain arrays: this runs at every sample
/// of every step.
pub fn compose(s: &LocalState, fq: &Vec5, fqq: &Mat5, grad: &mut Vec11, hess: &mut Mat11) {
    compose_up_to(s, fq, fqq, grad, hess, 3);
}

/// [`compose`] for an energy that uses r′ … r^(np) only (np = 1: a alone,
/// 2: a and c2, 3: all): the Jacobian blocks of the unused invariants,
/// whose derivatives are zero, are skipped (their entries are written 0).
pub fn compose_up_to(s: &LocalState, fq: &Vec5, fqq: &Mat5, grad: &mut Vec11, hess: &mut Mat11, np: usize) {
    // Compiled per np: fixed loop bounds keep the loops unrolled.
    match np {
        0 | 1 => compose_n::<1>(s, fq, fqq, grad, hess),
        2 => compose_n::<2>(s, fq, fqq, grad, hess),
        _ => compose_n::<3>(s, fq, fqq, grad, hess),
    }
}

/// The non-zero 3-vector blocks of J per position slot: (invariant, ∂q/∂slot).
type SlotRows = [[(usize, [f64; 3]); 3]; 3];

#[inline(always)]
fn arr(v: Vector3<f64>) -> [f64; 3] {
    [v[0], v[1], v[2]]
}

#[inline(always)]
fn compose_n<const NP: usize>(s: &LocalState, fq: &Vec5, fqq: &Mat5, grad: &mut Vec11, hess: &mut Mat11) {
    let (r1, r2, r3) = (&s.r1, &s.r2, &s.r3);
    let c = r1.cross(r2);
    let z = [0.0; 3];
    // rows[slot][..count(slot)]: slot 0 (r′) is touched by a, c2, p; slot 1
    // (r″) by c2, p; slot 2 (r‴) by p; only those below NP exist.
    let (vc1, vc2) = if NP >= 2 { (arr(2.0 * r2.cross(&c)), arr(2.0 * c.cross(r1))) } else { (z, z) };
    let (vp1, vp2, vp3) = if NP >= 3 { (arr(r2.cross(r3)), arr(r3.cross(r1)), arr(c)) } else { (z, z, z) };
    let rows: SlotRows = [
        [(QA, arr(2.0 * r1)), (QC2, vc1), (QP, vp1)],
        [(QC2, vc2), (QP, vp2), (QP, z)],
        [(QP, vp3), (QP, z), (QP, z)],
    ];
    // Rows of J touching slot `sl` (a compile-time count once NP is fixed).
    let count = |sl: usize| NP.saturating_sub(sl);
    let f: [f64; 5] = [fq[0], fq[1], fq[2], fq[3], fq[4]];
    let ff = |k: usize, l: usize| fqq[(k, l)];
    // ∇W = Jᵀ F_q.
    let mut g = [0.0f64; 11];
    for sl in 0..NP {
        for &(k, v) in &rows[sl][..count(sl)] {
            for a in 0..3 {
                g[3 * sl + a] += f[k] * v[a];
            }
        }
    }
    g[TH] = f[QTH];
    g[TH1] = f[QTH1];
    // M = F_qq J (5 × 11).
    let mut m = [[0.0f64; 11]; 5];
    for (k, mk) in m.iter_mut().enumerate() {
        for sl in 0..NP {
            for &(l, v) in &rows[sl][..count(sl)] {
                let fl = ff(k, l);
                for a in 0..3 {
                    mk[3 * sl + a] += fl * v[a];
                }
            }
        }
        mk[TH] = ff(k, QTH);
        mk[TH1] = ff(k, QTH1);
    }
    // Upper half of Jᵀ M: row (sl, a) is Σ_k J[k][(sl, a)] M[k].
    let mut h = [[0.0f64; 11]; 11];
    for sl in 0..NP {
        for a in 0..3 {
            let i = 3 * sl + a;
            let hi = &mut h[i];
            for &(k, v) in &rows[sl][..count(sl)] {
                let x = v[a];
                for j in i..11 {
                    hi[j] += x * m[k][j];
                }
            }
        }
    }
    h[TH][TH] = m[QTH][TH];
    h[TH][TH1] = m[QTH][TH1];
    h[TH1][TH1] = m[QTH1][TH1];
    // Σ_k F_k ∇²q_k. ∇²a = 2 I on r′.
    let fa = f[QA];
    for a in 0..3 {
        h[R1 + a][R1 + a] += 2.0 * fa;
    }
    if NP >= 2 {
        // ∇²c2 from c2 = |r′|²|r″|² − (r′·r″)²:
        //   (r′,r′) 2|r″|² I − 2 r″r″ᵀ, (r″,r″) 2|r′|² I − 2 r′r′ᵀ,
        //   (r′,r″) 4 r′r″ᵀ − 2 r″r′ᵀ − 2 (r′·r″) I.
        let fc = f[QC2];
        let (n1, n2, d12) = (r1.norm_squared(), r2.norm_squared(), r1.dot(r2));
        for a in 0..3 {
            for b in a..3 {
                let e = if a == b { 1.0 } else { 0.0 };
                h[R1 + a][R1 + b] += 2.0 * fc * (n2 * e - r2[a] * r2[b]);
                h[R2 + a][R2 + b] += 2.0 * fc * (n1 * e - r1[a] * r1[b]);
            }
            for b in 0..3 {
                let e = if a == b { 1.0 } else { 0.0 };
                h[R1 + a][R2 + b] += fc * (4.0 * r1[a] * r2[b] - 2.0 * r2[a] * r1[b] - 2.0 * d12 * e);
            }
        }
    }
    if NP >= 3 {
        // ∇²p: ∂²p/∂r′∂r″ = −[r‴]×, ∂²p/∂r′∂r‴ = [r″]×, ∂²p/∂r″∂r‴ = −[r′]×.
        let fp = f[QP];
        add_cross(&mut h, R1, R2, r3, -fp);
        add_cross(&mut h, R1, R3, r2, fp);
        add_cross(&mut h, R2, R3, r1, -fp);
    }
    // Write out, mirroring the upper half (the unused slots stay 0).
    grad.as_mut_slice().copy_from_slice(&g);
    let hs = hess.as_mut_slice();
    for i in 0..11 {
        hs[11 * i + i] = h[i][i];
        for j in i + 1..11 {
            hs[11 * j + i] = h[i][j];
            hs[11 * i + j] = h[i][j];
        }
    }
}

/// h[(ro + a, co + b)] += s [v]×_(a,b) on a block above the diagonal.
#[inline(always)]
fn add_cross(h: &mut [[f64; 11]; 11], ro: usize, co: usize, v: &Vector3<f64>, s: f64) {
    let (x, y, z) = (s * v[0], s * v[1], s * v[2]);
    h[ro][co + 1] -= z;
    h[ro][co + 2] += y;
    h[ro + 1][co] += z;
    h[ro + 1][co + 2] -= x;
    h[ro + 2][co] -= y;
    h[ro + 2][co + 1] += x;
}
