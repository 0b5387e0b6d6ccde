//! A built duplex's exact thermal statistics in the harmonic approximation
//! (issue 17): what a sampler must reproduce, with no sampling. The
//! energy's Hessian at rest — the strands' (central differences of their
//! internal forces) plus each compliant constraint's Gauss–Newton LᵀL/α,
//! exact at rest where the rows vanish — restricted to the null space of
//! the rigid constraints, less the six rigid motions, gives the covariance
//! kT H⁺ of the control points. From it:
//! - each stacking row's ⟨λ²⟩/kT (rows √K e: equipartition gives 1 when
//!   the row is its strains' only stiffness), averaged over the interior;
//! - the kT's each energy holds (tr(H_part C)/kT), which add up to the
//!   freedoms less the rigid motions;
//! - the axis correlation 1 − ⟨z_i·z_{i+k}⟩ = ½ tr(ΔD C ΔDᵀ), z framed as
//!   the stacking frames it ([`crate::dna_elasticity::pair_axis`]'s rule:
//!   the central difference of the rung midpoints made ⟂ the rung), D its
//!   Jacobian by central differences, over the interior.
//!
//! Under a pull ([`tension_tilt`]) the same covariance is taken at the
//! loaded equilibrium, from the whole Lagrangian's Hessian, and gives each
//! pair axis's ⟨θ²⟩ against a plain rod's ([`rod_tension_tilt`]).
use crate::dna::{duplex, Duplex, DuplexLayout, BOLTZMANN};
use nalgebra::{DMatrix, DVector, Vector3};
use strandkit_core::constraint::kinds::base_pair_step::axis;
use strandkit_core::constraint::Row;
use strandkit_core::{ConstraintKind, Error, Result, Rod};

/// Longest duplex analysed (the Hessian is dense: 6 n coordinates).
pub const MAX_HARMONIC_BP: usize = 120;
/// Pairs left out at either end for the interior averages.
const SKIP: usize = 4;

/// What [`harmonic_statistics`] computed (kT = k_B × the duplex's temperature).
#[derive(Clone, Debug, PartialEq)]
pub struct Harmonic {
    /// ⟨row²⟩/kT of the stacking's shift, slide, rise, tilt, roll, twist
    /// rows, averaged over the interior steps.
    pub row_equipartition: [f64; 6],
    /// kT's held by the strands, the stacking, the other compliant
    /// constraints (compliant bonds, staggers).
    pub held: [f64; 3],
    /// Freedoms less the rigid motions (the sum of `held`).
    pub freedoms: usize,
    /// (k in bp, 1 − ⟨z_i·z_{i+k}⟩) over the interior pairs.
    pub axis_decorrelation: Vec<(usize, f64)>,
}

/// Dense rows of a constraint over the two strands' coordinates (`sides`:
/// the offsets of its rods' coordinates), with their right-hand sides.
fn dense_rows(rows: &[Row], sides: [usize; 2], m: usize) -> Vec<(DVector<f64>, f64)> {
    rows.iter()
        .map(|row| {
            let mut v = DVector::zeros(m);
            for &(s, i, x) in row.entries() {
                v[sides[s as usize] + i] += x;
            }
            (v, row.rhs)
        })
        .collect()
}

/// The harmonic statistics of the duplex `p` (at most [`MAX_HARMONIC_BP`]
/// base pairs, at least k + 11 for each k of `ks`: interior pairs 4 from
/// either end).
pub fn harmonic_statistics(p: &Duplex, ks: &[usize]) -> Result<Harmonic> {
    let n = p.sequence.len();
    if n > MAX_HARMONIC_BP {
        return Err(Error::invalid("duplex length", format!("{n} bp"), format!("at most {MAX_HARMONIC_BP} bp (a dense Hessian)")));
    }
    let kt = BOLTZMANN * p.temperature;
    let (asm, l) = duplex(p)?;
    let rods: Vec<Rod> = asm.rods.iter().map(|r| r.rod.clone()).collect();
    let off = vec![0, rods[0].coords().len()];
    let m = off[1] + rods[1].coords().len();
    let terms = asm.constraints.iter().map(|c| Term { kind: c.kind.clone(), sides: [c.rod, c.other.unwrap_or(c.rod)], compliance: c.compliance }).collect();
    let mut sys = Loaded { rods, off, m, terms, load: DVector::zeros(m) };

    // At rest: no load, the rows vanish, the six rigid motions are the
    // zero modes (a seventh is a mechanism).
    let (cov, zero, free) = sys.covariance(kt)?;
    if zero != 6 {
        return Err(Error::singular("harmonic statistics: a soft mode beyond the six rigid motions"));
    }
    let stacking = |t: &Term| t.compliance > 0.0 && t.kind.name() == "BasePairStep";
    let parts = [sys.hessian_of(None, true, &|_| false)?, sys.hessian_of(None, false, &stacking)?, sys.hessian_of(None, false, &|t| t.compliance > 0.0 && !stacking(t))?];
    let held = parts.each_ref().map(|hh| (hh * &cov).trace() / kt);

    let mut stacks = Vec::new();
    for t in sys.terms.iter().filter(|t| stacking(t)) {
        let mut rows = vec![Row::default(); t.kind.n_rows()];
        t.kind.linearize(&[&sys.rods[t.sides[0]], &sys.rods[t.sides[1]]], &mut rows)?;
        stacks.push(dense_rows(&rows, [sys.off[t.sides[0]], sys.off[t.sides[1]]], m));
    }
    let interior: Vec<&Vec<(DVector<f64>, f64)>> = stacks.iter().skip(SKIP).take(stacks.len().saturating_sub(2 * SKIP)).collect();
    let mut row_equipartition = [0.0; 6];
    for (r, out) in row_equipartition.iter_mut().enumerate() {
        *out = interior.iter().map(|rows| (rows[r].0.transpose() * &cov * &rows[r].0)[(0, 0)] / kt).sum::<f64>() / interior.len().max(1) as f64;
    }

    // 1 − ⟨z_i·z_{i+k}⟩ = ½ tr(ΔD C ΔDᵀ), ΔD the rows of pairs i and i + k.
    let d = sys.jacobian(|rods| pair_axes([&rods[0], &rods[1]], &l))?;
    let mut axis_decorrelation = Vec::with_capacity(ks.len());
    for &k in ks {
        let first = interior_pairs(n, k)?;
        let mean = first
            .clone()
            .map(|i| {
                let dd = d.rows(3 * i, 3) - d.rows(3 * (i + k), 3);
                0.5 * (&dd * &cov * dd.transpose()).trace()
            })
            .sum::<f64>()
            / first.len() as f64;
        axis_decorrelation.push((k, mean));
    }
    Ok(Harmonic { row_equipartition, held, freedoms: free - 6, axis_decorrelation })
}

/// The local axis z of pairs 1 … n−2 (unit), as the stacking frames it:
/// the central difference of the neighbouring rung midpoints made ⟂ the
/// pair's rung. `rods`: the strands a and b.
pub fn pair_axes(rods: [&Rod; 2], l: &DuplexLayout) -> Result<Vec<Vector3<f64>>> {
    let n = l.partner.len();
    let mut pts = Vec::with_capacity(n);
    for k in 0..n {
        pts.push((rods[0].position(l.abscissae[0][k])?, rods[1].position(l.abscissae[1][l.partner[k]])?));
    }
    let mid = |k: usize| (pts[k].0 + pts[k].1) * 0.5;
    Ok((1..n.saturating_sub(1))
        .map(|k| {
            let x = (pts[k].1 - pts[k].0).normalize();
            // The stacking's own rule at an interior pair.
            let c = axis(&[mid(k - 1), mid(k), mid(k + 1), mid(k + 1)], 1, [false, false]);
            (c - x * x.dot(&c)).normalize()
        })
        .collect())
}

/// Indices i into [`pair_axes`] whose pair i and i + k are both at least
/// SKIP pairs from either end (the interior averages' range).
pub fn interior_pairs(n: usize, k: usize) -> Result<std::ops::Range<usize>> {
    let end = n.saturating_sub(2).saturating_sub(SKIP + k);
    if k == 0 || end <= SKIP {
        return Err(Error::invalid("axis correlation span", format!("k = {k} bp on {n} bp"), format!("1 ≤ k ≤ n − {} bp", 2 * SKIP + 3)));
    }
    Ok(SKIP..end)
}

/// One energy term of a [`Loaded`] system: a constraint on strand `a` (and
/// `b`), rigid when its compliance is 0.
struct Term {
    kind: ConstraintKind,
    sides: [usize; 2],
    compliance: f64,
}

/// ∇V and the rigid rows as (rhs, sparse (coordinate, value) entries).
type Gradient = (DVector<f64>, Vec<(f64, Vec<(usize, f64)>)>);

/// A system at a loaded equilibrium: rods, constraints, and a dead load
/// (its generalised force, constant).
struct Loaded {
    rods: Vec<Rod>,
    off: Vec<usize>,
    m: usize,
    terms: Vec<Term>,
    load: DVector<f64>,
}

impl Loaded {
    /// Coordinate `col` of the stacked system: (rod, rod-local index).
    fn at(&self, col: usize) -> (usize, usize) {
        let r = self.off.partition_point(|&o| o <= col) - 1;
        (r, col - self.off[r])
    }

    /// ∇V of the elastic and compliant energies less the load (V = U +
    /// Σ g²/2α − F·x; the compliant rows' g = −rhs), and the rigid rows
    /// as sparse (coordinate, value) lists with their λ-weighted sum
    /// Σ λ_r ∇g_r added when `lambda` is given.
    fn gradient(&self, lambda: Option<&[f64]>) -> Result<Gradient> {
        let mut g = self.gradient_of(lambda, true, &|_| true)?;
        g.0 -= &self.load;
        Ok(g)
    }

    /// [`Self::gradient`] of a part, without the load: the strands'
    /// energies if `strands`, and the terms `keep` selects (λ indexes the
    /// kept rigid rows).
    fn gradient_of(&self, lambda: Option<&[f64]>, strands: bool, keep: &dyn Fn(&Term) -> bool) -> Result<Gradient> {
        let mut g = DVector::zeros(self.m);
        if strands {
            for (r, rod) in self.rods.iter().enumerate() {
                for (i, f) in rod.internal_forces().into_iter().enumerate() {
                    g[self.off[r] + i] -= f;
                }
            }
        }
        let mut rigid = Vec::new();
        for t in self.terms.iter().filter(|t| keep(t)) {
            let mut rows = vec![Row::default(); t.kind.n_rows()];
            let pair = [&self.rods[t.sides[0]], &self.rods[t.sides[1]]];
            t.kind.linearize(&pair, &mut rows)?;
            for row in &rows {
                let sparse: Vec<(usize, f64)> = row.entries().iter().map(|&(s, i, x)| (self.off[t.sides[s as usize]] + i, x)).collect();
                if t.compliance == 0.0 {
                    if let Some(l) = lambda {
                        for &(i, x) in &sparse {
                            g[i] -= l[rigid.len()] * x;
                        }
                    }
                    rigid.push((row.rhs, sparse));
                } else {
                    for &(i, x) in &sparse {
                        g[i] -= x * row.rhs / t.compliance;
                    }
                }
            }
        }
        Ok((g, rigid))
    }

    fn set(&mut self, col: usize, v: f64) -> Result<()> {
        let (r, i) = self.at(col);
        let mut q = self.rods[r].coords().to_vec();
        q[i] = v;
        self.rods[r].set_coords(&q)
    }

    fn coord(&self, col: usize) -> f64 {
        let (r, i) = self.at(col);
        self.rods[r].coords()[i]
    }

    /// The rigid rows as a dense matrix R, their values c = −rhs, ∇V.
    fn rigid(&self) -> Result<(DMatrix<f64>, DVector<f64>, DVector<f64>)> {
        let (g, rigid) = self.gradient(None)?;
        let mut r = DMatrix::<f64>::zeros(rigid.len(), self.m);
        for (k, row) in rigid.iter().enumerate() {
            for &(i, x) in &row.1 {
                r[(k, i)] += x;
            }
        }
        Ok((r, DVector::from_iterator(rigid.len(), rigid.iter().map(|row| -row.0)), g))
    }

    /// The Lagrangian's Hessian ∇²V − Σ λ ∇²g by central differences.
    fn hessian(&mut self, lam: &[f64]) -> Result<DMatrix<f64>> {
        self.hessian_of(Some(lam), true, &|_| true)
    }

    /// The Hessian of a part ([`Self::gradient_of`]'s selection).
    fn hessian_of(&mut self, lam: Option<&[f64]>, strands: bool, keep: &dyn Fn(&Term) -> bool) -> Result<DMatrix<f64>> {
        let (m, eps) = (self.m, 1e-6);
        let mut h = DMatrix::<f64>::zeros(m, m);
        for col in 0..m {
            let x0 = self.coord(col);
            self.set(col, x0 + eps)?;
            let gp = self.gradient_of(lam, strands, keep)?.0;
            self.set(col, x0 - eps)?;
            let gm = self.gradient_of(lam, strands, keep)?.0;
            self.set(col, x0)?;
            h.set_column(col, &((gp - gm) / (2.0 * eps)));
        }
        Ok((&h + h.transpose()) * 0.5)
    }

    /// λ fitted to ∇V = Rᵀλ by least squares, and the relative residual.
    fn multipliers(r: &DMatrix<f64>, g: &DVector<f64>) -> Result<(Vec<f64>, f64)> {
        let lambda = (r * r.transpose()).cholesky().ok_or_else(|| Error::singular("tension tilt: dependent rigid rows"))?.solve(&(r * g));
        let residual = (g - r.transpose() * &lambda).norm() / g.norm().max(1e-300);
        Ok((lambda.iter().copied().collect(), residual))
    }

    /// Newton steps on the equilibrium (∇V = Rᵀλ, c = 0) with the whole
    /// Lagrangian's Hessian (relax's matrix lacks the stacking's second
    /// derivatives and stalls near 1e-7 nm). Returns the last residual.
    fn polish(&mut self, steps: usize) -> Result<f64> {
        let m = self.m;
        for _ in 0..steps {
            let (r, c, g) = self.rigid()?;
            let (lam, _) = Self::multipliers(&r, &g)?;
            let h = self.hessian(&lam)?;
            let k = r.nrows();
            let mut a = DMatrix::<f64>::zeros(m + k, m + k);
            a.view_mut((0, 0), (m, m)).copy_from(&h);
            a.view_mut((0, m), (m, k)).copy_from(&r.transpose());
            a.view_mut((m, 0), (k, m)).copy_from(&r);
            let lv = DVector::from_column_slice(&lam);
            let mut b = DVector::<f64>::zeros(m + k);
            b.rows_mut(0, m).copy_from(&(-(&g - r.transpose() * &lv)));
            b.rows_mut(m, k).copy_from(&(-&c));
            let x = a.lu().solve(&b).ok_or_else(|| Error::singular("tension tilt: singular Newton matrix"))?;
            for col in 0..m {
                let v = self.coord(col) + x[col];
                self.set(col, v)?;
            }
        }
        let (r, _, g) = self.rigid()?;
        Ok(Self::multipliers(&r, &g)?.1)
    }

    /// The rigid rows' null space N (orthonormal columns) and the
    /// Lagrangian's Hessian H there, NᵀHN (symmetrised).
    fn reduced_hessian(&mut self) -> Result<(DMatrix<f64>, DMatrix<f64>)> {
        let m = self.m;
        let (r, _, g) = self.rigid()?;
        let (lam, _) = Self::multipliers(&r, &g)?;
        let h = self.hessian(&lam)?;
        let e = (r.transpose() * &r).symmetric_eigen();
        let top = e.eigenvalues.amax();
        let cols: Vec<usize> = (0..m).filter(|&i| e.eigenvalues[i].abs() < 1e-10 * top).collect();
        let basis = DMatrix::from_fn(m, cols.len(), |i, j| e.eigenvectors[(i, cols[j])]);
        let hr = basis.transpose() * &h * &basis;
        Ok(((&hr + hr.transpose()) * 0.5, basis))
    }

    /// Covariance kT H⁺ of the Lagrangian's Hessian on the rigid rows'
    /// null space, its count of zero modes (left out) and the null
    /// space's dimension.
    fn covariance(&mut self, kt: f64) -> Result<(DMatrix<f64>, usize, usize)> {
        let (hr, basis) = self.reduced_hessian()?;
        let e = hr.symmetric_eigen();
        let top = e.eigenvalues.amax();
        if e.eigenvalues.iter().any(|&v| v < -1e-8 * top) {
            return Err(Error::singular("tension tilt: the loaded state is not a minimum (a negative curvature)"));
        }
        let mut cov_r = DMatrix::<f64>::zeros(basis.ncols(), basis.ncols());
        let mut zero = 0;
        for i in 0..e.eigenvalues.len() {
            if e.eigenvalues[i] < 1e-9 * top {
                zero += 1;
                continue;
            }
            let v = e.eigenvectors.column(i);
            cov_r += v * v.transpose() * (kt / e.eigenvalues[i]);
        }
        Ok((&basis * cov_r * basis.transpose(), zero, basis.ncols()))
    }

    /// The stationary position covariance of a linearised stepped sampler
    /// with thermal noise about this equilibrium (steps of `h`, isotropic
    /// drag of viscosity `eta`, the noise's force covariance 2kT D/h), on
    /// the null space. Implicit Euler, with A = M/h² + D/h + K:
    ///   Δy = A⁻¹ (M w/h − K y + f),  y' = y + Δy,  w' = Δy/h.
    /// The trapezoidal rule ([`Stepper`]): A = 2M/h² + D/h + K_a/2 + K_e,
    /// Δy = A⁻¹ (2M w/h − K y + f), w' = 2Δy/h − w, with K_a the averaged
    /// part (all of K, or the strands' own with the constraint terms K_e
    /// held at the step's end, as `held_at_end` stacking is). Averaged
    /// whole it is Gibbs-exact for a harmonic system: the recursion's check.
    /// S = Φ S Φᵀ + G (2kT D/h) Gᵀ by doubling.
    fn stepped_covariance(&mut self, kt: f64, h: f64, eta: f64, stepper: Stepper) -> Result<DMatrix<f64>> {
        let (k, basis) = self.reduced_hessian()?;
        let k_end = match stepper {
            Stepper::TrapezoidalHeld => {
                let strands = self.hessian_of(None, true, &|_| false)?;
                &k - basis.transpose() * strands * &basis
            }
            _ => DMatrix::zeros(k.nrows(), k.ncols()),
        };
        let trapezoidal = stepper != Stepper::ImplicitEuler;
        let n = basis.ncols();
        let (mut mm, mut dd) = (DMatrix::<f64>::zeros(self.m, n), DMatrix::<f64>::zeros(self.m, n));
        let drags: Vec<_> = self.rods.iter().map(|rod| Ok(strandkit_core::rod::drag::Drag { axial: 0.0, ..rod.drag(eta)? })).collect::<Result<_>>()?;
        for j in 0..n {
            for (r, rod) in self.rods.iter().enumerate() {
                let len = rod.coords().len();
                let x: Vec<f64> = (0..len).map(|i| basis[(self.off[r] + i, j)]).collect();
                let (mut y, mut z) = (vec![0.0; len], vec![0.0; len]);
                rod.mass_times(&x, &mut y);
                rod.drag_times(&drags[r], &x, &mut z);
                for i in 0..len {
                    mm[(self.off[r] + i, j)] = y[i];
                    dd[(self.off[r] + i, j)] = z[i];
                }
            }
        }
        let (m, d) = (basis.transpose() * mm, basis.transpose() * dd);
        let (cm, ck) = if trapezoidal { (2.0, 0.5) } else { (1.0, 1.0) };
        let a = &m * (cm / (h * h)) + &d / h + (&k - &k_end) * ck + &k_end;
        let ai = a.try_inverse().ok_or_else(|| Error::singular("stepped covariance: singular step matrix"))?;
        let eye = DMatrix::<f64>::identity(n, n);
        let dy_y = -(&ai * &k);
        let dy_w = &ai * &m * (cm / h);
        let mut phi = DMatrix::<f64>::zeros(2 * n, 2 * n);
        phi.view_mut((0, 0), (n, n)).copy_from(&(&eye + &dy_y));
        phi.view_mut((0, n), (n, n)).copy_from(&dy_w);
        let (wy, ww) = if trapezoidal { (&dy_y * (2.0 / h), &dy_w * (2.0 / h) - &eye) } else { (&dy_y / h, &dy_w / h) };
        phi.view_mut((n, 0), (n, n)).copy_from(&wy);
        phi.view_mut((n, n), (n, n)).copy_from(&ww);
        let mut g = DMatrix::<f64>::zeros(2 * n, n);
        g.view_mut((0, 0), (n, n)).copy_from(&ai);
        g.view_mut((n, 0), (n, n)).copy_from(&(&ai * if trapezoidal { 2.0 / h } else { 1.0 / h }));
        // S = Σ Φᵏ Q Φᵏᵀ by doubling (the slowest mode sets the count).
        let mut sum = &g * (&d * (2.0 * kt / h)) * g.transpose();
        let mut p = phi;
        for _ in 0..60 {
            let next = &sum + &p * &sum * p.transpose();
            let change = (&next - &sum).amax() / next.amax().max(1e-300);
            sum = next;
            p = &p * &p;
            if change < 1e-13 {
                let cy = sum.view((0, 0), (n, n)).into_owned();
                return Ok(&basis * cy * basis.transpose());
            }
        }
        Err(Error::NotConverged { iterations: 60, residual: f64::NAN, detail: "stepped covariance: the doubling did not converge (an undamped mode?)".into() })
    }

    /// The Jacobian D (3 rows per vector) of `axes` by central
    /// differences.
    fn jacobian(&mut self, axes: impl Fn(&[Rod]) -> Result<Vec<Vector3<f64>>>) -> Result<DMatrix<f64>> {
        let n = axes(&self.rods)?.len();
        let mut d = DMatrix::<f64>::zeros(3 * n, self.m);
        let eps = 1e-6;
        for col in 0..self.m {
            let x0 = self.coord(col);
            self.set(col, x0 + eps)?;
            let zp = axes(&self.rods)?;
            self.set(col, x0 - eps)?;
            let zm = axes(&self.rods)?;
            self.set(col, x0)?;
            for k in 0..n {
                for a in 0..3 {
                    d[(3 * k + a, col)] = (zp[k][a] - zm[k][a]) / (2.0 * eps);
                }
            }
        }
        Ok(d)
    }

    /// ⟨|δa|²⟩ = tr(D C Dᵀ) of each unit vector of `axes`.
    fn spread(&mut self, cov: &DMatrix<f64>, axes: impl Fn(&[Rod]) -> Result<Vec<Vector3<f64>>>) -> Result<Vec<f64>> {
        let d = self.jacobian(axes)?;
        let dc = &d * cov;
        Ok((0..d.nrows() / 3).map(|k| (0..3).map(|a| dc.row(3 * k + a).dot(&d.row(3 * k + a))).sum()).collect())
    }
}

/// A stepped sampler of [`tension_tilt_stepped`] and
/// [`rod_tension_tilt_stepped`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stepper {
    /// Implicit Euler: every force at the step's end.
    ImplicitEuler,
    /// Everything averaged over the step (Gibbs-exact when harmonic).
    Trapezoidal,
    /// The strands averaged, the constraint terms (compliant stacking and
    /// bonds, rigid rows' curvature) held at the step's end: the
    /// trapezoidal rule with `held_at_end` stacking, the duplex's default.
    TrapezoidalHeld,
}

/// What [`tension_tilt`] computed.
#[derive(Clone, Debug, PartialEq)]
pub struct TensionTilt {
    /// The pull (pN).
    pub force: f64,
    /// ⟨θ²⟩ of each pair's axis (pairs 1 … n − 2; rad²).
    pub tilt: Vec<f64>,
    /// Each pair's axis at the loaded equilibrium (pairs 1 … n − 2).
    pub axes: Vec<Vector3<f64>>,
    /// kT/√(B F) (rad²), a long worm-like chain's ⟨θ²⟩ under the pull,
    /// B = A kT with the duplex's target A.
    pub worm_like_chain: f64,
    /// |∇V − Rᵀλ| / |∇V| at the loaded equilibrium found.
    pub residual: f64,
    /// Modes of zero stiffness left out (none with pair 0 held as here).
    pub zero_modes: usize,
}

/// The duplex `p` held at pair 0 and pulled by `force` (pN, half on each
/// strand's end) along its axis, relaxed, then its harmonic thermal tilt:
/// ⟨θ²⟩ of each pair's axis, whose interior sum × rise / 2 is the
/// entropic shortening a worm-like chain would have (kT/(2√(BF)) of the
/// length). The Hessian is the whole Lagrangian's, stacking and rigid
/// bonds' curvature included (a loaded state, unlike
/// [`harmonic_statistics`]'s at rest).
pub fn tension_tilt(p: &Duplex, force: f64) -> Result<TensionTilt> {
    let kt = BOLTZMANN * p.temperature;
    let (mut sys, l, residual) = loaded_duplex(p, force)?;
    let (cov, zero_modes, _) = sys.covariance(kt)?;
    let tilt = sys.spread(&cov, |rods| pair_axes([&rods[0], &rods[1]], &l))?;
    let axes = pair_axes([&sys.rods[0], &sys.rods[1]], &l)?;
    let b = p.elasticity.bending_persistence * kt;
    Ok(TensionTilt { force, tilt, axes, worm_like_chain: kt / (b * force).sqrt(), residual, zero_modes })
}

/// [`tension_tilt`]'s ⟨θ²⟩ as a stepped sampler reads it: the harmonic
/// stationary covariance of a linearised stepped sampler ([`Stepper`])
/// with thermal noise, steps of `h` ns, isotropic drag of viscosity
/// `eta` (pN·ns/nm²), the strands' own masses. Pairs 1 … n − 2.
pub fn tension_tilt_stepped(p: &Duplex, force: f64, h: f64, eta: f64, stepper: Stepper) -> Result<Vec<f64>> {
    positive(&[("time step", h), ("viscosity", eta)])?;
    let (mut sys, l, _) = loaded_duplex(p, force)?;
    let cov = sys.stepped_covariance(BOLTZMANN * p.temperature, h, eta, stepper)?;
    sys.spread(&cov, |rods| pair_axes([&rods[0], &rods[1]], &l))
}

/// The duplex `p` held at pair 0 and pulled by `force` along its axis, at
/// its loaded equilibrium (see [`tension_tilt`]); the last relative residual.
fn loaded_duplex(p: &Duplex, force: f64) -> Result<(Loaded, DuplexLayout, f64)> {
    let n = p.sequence.len();
    if n > MAX_HARMONIC_BP {
        return Err(Error::invalid("duplex length", format!("{n} bp"), format!("at most {MAX_HARMONIC_BP} bp (a dense Hessian)")));
    }
    if !(force.is_finite() && force > 0.0) {
        return Err(Error::invalid("force", force, "a positive pull (pN)"));
    }
    // Relax (its matrix lacks the stacking's second derivatives) stalls
    // under a few pN: it starts the solution at ≤ 2 pN, Newton steps with
    // the whole Hessian follow the pull up in stages of ≤ 1.5×.
    let f0 = force.min(2.0);
    let half = Vector3::new(0.0, 0.0, f0 / 2.0);
    let (w, ins, l) = crate::dna_elasticity::loaded_within(p, half, half, 1e-3)?;
    let handles = [ins.rods[l.strands[0]], ins.rods[l.strands[1]]];
    let rods: Vec<Rod> = handles.iter().map(|&h| w.rod(h).cloned()).collect::<Result<_>>()?;
    let off = vec![0, rods[0].coords().len()];
    let m = off[1] + rods[1].coords().len();
    let side = |h: strandkit_core::RodHandle| handles.iter().position(|&x| x == h).ok_or_else(|| Error::input("tension tilt: a constraint on a third rod"));
    let mut terms = Vec::new();
    for (_, c) in w.constraints() {
        let a = side(c.rod)?;
        terms.push(Term { kind: c.kind.clone(), sides: [a, c.other.map(side).transpose()?.unwrap_or(a)], compliance: c.compliance });
    }
    // The two pulls of `loaded` (1 pN in all, along z), as generalised
    // forces N_k F.
    let mut unit = DVector::zeros(m);
    for (r, u) in [(0, l.abscissae[0][n - 1]), (1, l.abscissae[1][0])] {
        let (ctrl, b) = rods[r].basis_at(u)?;
        let d = rods[r].dofs();
        for k in 0..4 {
            unit[off[r] + ctrl[k] * d + 2] += b[0][k] * 0.5;
        }
    }
    let mut sys = Loaded { rods, off, m, terms, load: &unit * f0 };
    let (mut f, mut newton) = (f0, 3);
    let mut residual = sys.polish(3)?;
    while f < force {
        f = (f * 1.5).min(force);
        sys.load = &unit * f;
        residual = sys.polish(4)?;
        newton += 4;
    }
    if !(residual < 1e-8) {
        return Err(Error::NotConverged { iterations: newton, residual, detail: format!("tension tilt: the loaded equilibrium at {force} pN not found (relative residual {residual:.1e})") });
    }
    Ok((sys, l, residual))
}

/// [`tension_tilt`]'s reference: a plain rod of bending stiffness A kT
/// (A in nm, kT in pN·nm) and stretch modulus `stretch` (pN), `length` nm
/// on `control_points`, clamped at s = 0 and pulled by `force` (pN) at
/// its end, harmonic ⟨θ²⟩ of its tangent at the arc lengths `at` (nm).
pub fn rod_tension_tilt(length: f64, control_points: usize, a: f64, stretch: f64, kt: f64, force: f64, at: &[f64]) -> Result<Vec<f64>> {
    if !(force.is_finite() && force > 0.0) {
        return Err(Error::invalid("force", force, "a positive pull (pN)"));
    }
    let mut sys = clamped_and_pulled(reference_rod(length, control_points, a, stretch, kt, 1.0)?, force)?;
    let (cov, ..) = sys.covariance(kt)?;
    tangent_spread(&mut sys, &cov, length, at)
}

/// [`rod_tension_tilt`] as a stepped sampler would read it: the harmonic
/// stationary ⟨θ²⟩ of a linearised stepped sampler ([`Stepper`]) with
/// thermal noise, steps of `h`
/// ns, isotropic drag of viscosity `eta` (pN·ns/nm²), mass `linear_density`
/// per nm (molecular units). What a run of [`reference_rod`] clamped and
/// pulled so converges to, time step's bias included.
#[allow(clippy::too_many_arguments)]
pub fn rod_tension_tilt_stepped(length: f64, control_points: usize, a: f64, stretch: f64, kt: f64, force: f64, at: &[f64], linear_density: f64, eta: f64, h: f64, stepper: Stepper) -> Result<Vec<f64>> {
    positive(&[("force", force), ("time step", h), ("viscosity", eta)])?;
    let mut sys = clamped_and_pulled(reference_rod(length, control_points, a, stretch, kt, linear_density)?, force)?;
    let cov = sys.stepped_covariance(kt, h, eta, stepper)?;
    tangent_spread(&mut sys, &cov, length, at)
}

/// ⟨|δt|²⟩ under `cov` of the unit tangent of the one rod of `sys`
/// (`length` nm long) at the arc lengths `at` (nm).
fn tangent_spread(sys: &mut Loaded, cov: &DMatrix<f64>, length: f64, at: &[f64]) -> Result<Vec<f64>> {
    let (u0, u1) = sys.rods[0].domain();
    let scale = (u1 - u0) / length;
    sys.spread(cov, |rods| at.iter().map(|&s| Ok(rods[0].tangent(u0 + s * scale)?.normalize())).collect())
}

/// `rod` clamped at its start and pulled by `force` along z at its end, at
/// equilibrium.
fn clamped_and_pulled(rod: Rod, force: f64) -> Result<Loaded> {
    let (u0, u1) = rod.domain();
    let terms = strandkit_core::constraint::clamp_kinds(&rod, u0)?.into_iter().map(|kind| Term { kind, sides: [0, 0], compliance: 0.0 }).collect();
    let m = rod.coords().len();
    let mut load = DVector::zeros(m);
    let (ctrl, b) = rod.basis_at(u1)?;
    for k in 0..4 {
        load[ctrl[k] * rod.dofs() + 2] += b[0][k] * force;
    }
    let mut sys = Loaded { rods: vec![rod], off: vec![0], m, terms, load };
    let residual = sys.polish(4)?;
    if !(residual < 1e-8) {
        return Err(Error::NotConverged { iterations: 4, residual, detail: "rod tension tilt: no equilibrium".into() });
    }
    Ok(sys)
}

/// A straight rod along z of `length` nm on `control_points`, without
/// roll, of bending stiffness A kT (A in nm, kT in pN·nm), stretch modulus
/// `stretch` (pN) and mass `linear_density` per nm (molecular units): a
/// circle of radius r with E π r⁴/4 = A kT and E π r² = S.
pub fn reference_rod(length: f64, control_points: usize, a: f64, stretch: f64, kt: f64, linear_density: f64) -> Result<Rod> {
    use strandkit_core::rod::RodBuilder;
    use strandkit_core::section::Section;
    use strandkit_core::Material;
    positive(&[("length", length), ("persistence", a), ("stretch modulus", stretch), ("kT", kt), ("linear density", linear_density)])?;
    let r = 2.0 * (a * kt / stretch).sqrt();
    let area = std::f64::consts::PI * r * r;
    RodBuilder::straight(Vector3::zeros(), Vector3::new(0.0, 0.0, length))
        .control_points(control_points)
        .with_roll(false)
        .section(Section::circle(r)?)
        .material(Material::new("reference", stretch / area, 0.3, linear_density / area)?)
        .build()
}

/// InvalidInput for the first of `values` that is not finite and positive.
fn positive(values: &[(&str, f64)]) -> Result<()> {
    match values.iter().find(|(_, v)| !(v.is_finite() && *v > 0.0)) {
        Some(&(what, v)) => Err(Error::invalid(what, v, "positive")),
        None => Ok(()),
    }
}
