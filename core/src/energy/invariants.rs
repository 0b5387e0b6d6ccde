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
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

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

    /// Adds Σ_k f_k ∇²q_k to `h` (f = ∂F/∂q).
    pub fn add_invariant_hessians(&self, f: &Vec5, h: &mut Mat11) {
        self.add_invariant_hessians_up_to(f, h, 3);
    }

    /// [`Self::add_invariant_hessians`] for an energy that uses r′ … r^(np)
    /// only: f_c2 is zero below np = 2 and f_p below 3, so their blocks
    /// are skipped.
    pub fn add_invariant_hessians_up_to(&self, f: &Vec5, h: &mut Mat11, np: usize) {
        let (r1, r2, r3) = (&self.r1, &self.r2, &self.r3);
        let eye = Matrix3::identity();
        // ∇²a = 2 I on r'.
        let fa = f[QA];
        // ∇²c2 from c2 = |r'|²|r''|² − (r'·r'')².
        let fc = f[QC2];
        if np < 2 {
            add_block(h, R1, R1, &(2.0 * fa * eye));
            return;
        }
        let h11 = (2.0 * fa + 2.0 * fc * r2.norm_squared()) * eye - 2.0 * fc * r2 * r2.transpose();
        let h22 = fc * (2.0 * r1.norm_squared() * eye - 2.0 * r1 * r1.transpose());
        let h12 = fc * (4.0 * r1 * r2.transpose() - 2.0 * r2 * r1.transpose() - 2.0 * r1.dot(r2) * eye);
        if np < 3 {
            add_block(h, R1, R1, &h11);
            add_block(h, R2, R2, &h22);
            add_sym_block(h, R1, R2, &h12);
            return;
        }
        // ∇²p: ∂²p/∂r'∂r'' = −[r''']×, ∂²p/∂r'∂r''' = [r'']×, ∂²p/∂r''∂r''' = −[r']×.
        let fp = f[QP];
        let p12 = -fp * r3.cross_matrix();
        let p13 = fp * r2.cross_matrix();
        let p23 = -fp * r1.cross_matrix();
        add_block(h, R1, R1, &h11);
        add_block(h, R2, R2, &h22);
        add_sym_block(h, R1, R2, &(h12 + p12));
        add_sym_block(h, R1, R3, &p13);
        add_sym_block(h, R2, R3, &p23);
    }
}

fn set3(j: &mut SMatrix<f64, 5, 11>, row: usize, col: usize, v: &Vector3<f64>) {
    for k in 0..3 {
        j[(row, col + k)] = v[k];
    }
}

fn add_block(h: &mut Mat11, r: usize, c: usize, b: &Matrix3<f64>) {
    let mut v = h.fixed_view_mut::<3, 3>(r, c);
    v += b;
}

/// Adds `b` at (r, c) and bᵀ at (c, r).
fn add_sym_block(h: &mut Mat11, r: usize, c: usize, b: &Matrix3<f64>) {
    add_block(h, r, c, b);
    add_block(h, c, r, &b.transpose());
}

/// Value, gradient and Hessian of W(d) from F's derivatives with respect to
/// the invariants: the chain rule of the module doc.
///
/// J = ∂q/∂d is sparse (a depends on r′ only, c2 on r′ and r″, θ and θ′ are
/// unit rows: 20 non-zeros of 55, see [`LocalState::jacobian`]), so
/// Jᵀ F_qq J is formed as M = F_qq J (5 dense rows) and then Jᵀ M, one
/// axpy per non-zero of J: ≈ 320 multiply-adds instead of ≈ 880 dense.
pub fn compose(s: &LocalState, fq: &Vec5, fqq: &Mat5, grad: &mut Vec11, hess: &mut Mat11) {
    compose_up_to(s, fq, fqq, grad, hess, 3);
}

/// [`compose`] for an energy that uses r′ … r^(np) only (np = 1: a alone,
/// 2: a and c2, 3: all): the Jacobian blocks of the unused invariants,
/// whose derivatives are zero, are skipped.
pub fn compose_up_to(s: &LocalState, fq: &Vec5, fqq: &Mat5, grad: &mut Vec11, hess: &mut Mat11, np: usize) {
    // Compiled per np: fixed loop bounds keep the loops unrolled.
    match np {
        0 | 1 => compose_n::<1>(s, fq, fqq, grad, hess),
        2 => compose_n::<2>(s, fq, fqq, grad, hess),
        _ => compose_n::<3>(s, fq, fqq, grad, hess),
    }
}

#[inline(always)]
fn compose_n<const NP: usize>(s: &LocalState, fq: &Vec5, fqq: &Mat5, grad: &mut Vec11, hess: &mut Mat11) {
    let np = NP;
    let c = s.cross();
    // The 3-vector blocks of J: (invariant, first slot, ∂q/∂slot).
    let blocks: [(usize, usize, Vector3<f64>); 6] = [
        (QA, R1, 2.0 * s.r1),
        (QC2, R1, 2.0 * s.r2.cross(&c)),
        (QC2, R2, 2.0 * c.cross(&s.r1)),
        (QP, R1, s.r2.cross(&s.r3)),
        (QP, R2, s.r3.cross(&s.r1)),
        (QP, R3, c),
    ];
    let blocks = &blocks[..[1, 1, 3, 6][np.min(3)]];
    // The unit entries of J: (invariant, slot).
    let units = [(QTH, TH), (QTH1, TH1)];
    for &(k, off, v) in blocks {
        let mut g = grad.fixed_rows_mut::<3>(off);
        g += fq[k] * v;
    }
    for &(k, slot) in &units {
        grad[slot] += fq[k];
    }
    s.add_invariant_hessians_up_to(fq, hess, np);
    // M = F_qq J, row k over the 11 slots.
    let mut m = [[0.0f64; 11]; 5];
    for (k, mk) in m.iter_mut().enumerate() {
        for &(l, off, v) in blocks {
            let f = fqq[(k, l)];
            if f != 0.0 {
                for a in 0..3 {
                    mk[off + a] += f * v[a];
                }
            }
        }
        for &(l, slot) in &units {
            mk[slot] += fqq[(k, l)];
        }
    }
    // Jᵀ M is symmetric: add its row i (Σ_k J[k][i] M[k]) as column i,
    // which is contiguous in nalgebra's column-major storage.
    for &(k, off, v) in blocks {
        for a in 0..3 {
            let mut col = hess.column_mut(off + a);
            for (h, &mv) in col.iter_mut().zip(&m[k]) {
                *h += v[a] * mv;
            }
        }
    }
    for &(k, slot) in &units {
        let mut col = hess.column_mut(slot);
        for (h, &mv) in col.iter_mut().zip(&m[k]) {
            *h += mv;
        }
    }
}
