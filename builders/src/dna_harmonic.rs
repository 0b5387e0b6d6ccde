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
use crate::dna::{duplex, Duplex, DuplexLayout, BOLTZMANN};
use nalgebra::{DMatrix, DVector, Vector3};
use strandkit_core::constraint::Row;
use strandkit_core::{Error, Result, Rod};

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
    let mut rods: Vec<Rod> = asm.rods.iter().map(|r| r.rod.clone()).collect();
    let off = [0, rods[0].coords().len()];
    let m = off[1] + rods[1].coords().len();
    let eps = 1e-6;

    let mut h_strand = DMatrix::<f64>::zeros(m, m);
    for (r, rod) in rods.iter_mut().enumerate() {
        let q0 = rod.coords().to_vec();
        for i in 0..q0.len() {
            let mut q = q0.clone();
            q[i] += eps;
            rod.set_coords(&q)?;
            let fp = rod.internal_forces();
            q[i] -= 2.0 * eps;
            rod.set_coords(&q)?;
            let fm = rod.internal_forces();
            for j in 0..q0.len() {
                h_strand[(off[r] + j, off[r] + i)] = -(fp[j] - fm[j]) / (2.0 * eps);
            }
        }
        rod.set_coords(&q0)?;
    }
    h_strand = (&h_strand + h_strand.transpose()) * 0.5;

    let refs: Vec<&Rod> = rods.iter().collect();
    let (mut h_stack, mut h_rung) = (DMatrix::<f64>::zeros(m, m), DMatrix::<f64>::zeros(m, m));
    let (mut stacks, mut rigid) = (Vec::new(), Vec::new());
    for c in &asm.constraints {
        let mut rows = vec![Row::default(); c.kind.n_rows()];
        let pair: Vec<&Rod> = std::iter::once(refs[c.rod]).chain(c.other.map(|o| refs[o])).collect();
        c.kind.linearize(&pair, &mut rows)?;
        let dense = dense_rows(&rows, [off[c.rod], c.other.map(|o| off[o]).unwrap_or(0)], m);
        if c.compliance == 0.0 {
            rigid.extend(dense.into_iter().map(|(v, _)| v));
            continue;
        }
        let target = if c.kind.name() == "BasePairStep" { &mut h_stack } else { &mut h_rung };
        for (v, _) in &dense {
            *target += v * v.transpose() / c.compliance;
        }
        if c.kind.name() == "BasePairStep" {
            stacks.push(dense);
        }
    }
    let h = &h_strand + &h_stack + &h_rung;

    // Null space of the rigid rows, then the covariance without the six
    // rigid motions (the six smallest eigenvalues, ≈ 0).
    let basis = if rigid.is_empty() {
        DMatrix::identity(m, m)
    } else {
        let g = DMatrix::from_fn(rigid.len(), m, |i, j| rigid[i][j]);
        let e = (g.transpose() * &g).symmetric_eigen();
        let top = e.eigenvalues.amax();
        let cols: Vec<usize> = (0..m).filter(|&i| e.eigenvalues[i].abs() < 1e-10 * top).collect();
        DMatrix::from_fn(m, cols.len(), |i, j| e.eigenvectors[(i, cols[j])])
    };
    let hr = basis.transpose() * &h * &basis;
    let e = ((&hr + hr.transpose()) * 0.5).symmetric_eigen();
    let mut order: Vec<usize> = (0..e.eigenvalues.len()).collect();
    order.sort_by(|&a, &b| e.eigenvalues[a].total_cmp(&e.eigenvalues[b]));
    if order.len() <= 6 || !(e.eigenvalues[order[6]] > 1e-9 * e.eigenvalues.amax()) {
        return Err(Error::singular("harmonic statistics: a soft mode beyond the six rigid motions"));
    }
    let mut cov_r = DMatrix::<f64>::zeros(basis.ncols(), basis.ncols());
    for &i in order.iter().skip(6) {
        let v = e.eigenvectors.column(i);
        cov_r += v * v.transpose() * (kt / e.eigenvalues[i]);
    }
    let cov = &basis * cov_r * basis.transpose();
    let held = [&h_strand, &h_stack, &h_rung].map(|hh| (hh * &cov).trace() / kt);

    let interior: Vec<&Vec<(DVector<f64>, f64)>> = stacks.iter().skip(SKIP).take(stacks.len().saturating_sub(2 * SKIP)).collect();
    let mut row_equipartition = [0.0; 6];
    for (r, out) in row_equipartition.iter_mut().enumerate() {
        *out = interior.iter().map(|rows| (rows[r].0.transpose() * &cov * &rows[r].0)[(0, 0)] / kt).sum::<f64>() / interior.len().max(1) as f64;
    }

    // Axis directions of pairs 1 … n−2 and their Jacobians.
    let axes = |rods: &[Rod]| pair_axes([&rods[0], &rods[1]], &l);
    let z0 = axes(&rods)?;
    let mut d = vec![DMatrix::<f64>::zeros(3, m); z0.len()];
    for col in 0..m {
        let (r, i) = if col < off[1] { (0, col) } else { (1, col - off[1]) };
        let q0 = rods[r].coords().to_vec();
        let mut q = q0.clone();
        q[i] += eps;
        rods[r].set_coords(&q)?;
        let zp = axes(&rods)?;
        q[i] -= 2.0 * eps;
        rods[r].set_coords(&q)?;
        let zm = axes(&rods)?;
        rods[r].set_coords(&q0)?;
        for k in 0..z0.len() {
            let dz = (zp[k] - zm[k]) / (2.0 * eps);
            for a in 0..3 {
                d[k][(a, col)] = dz[a];
            }
        }
    }
    let mut axis_decorrelation = Vec::with_capacity(ks.len());
    for &k in ks {
        let first = interior_pairs(n, k)?;
        let mean = first.clone().map(|i| 0.5 * ((&d[i] - &d[i + k]) * &cov * (&d[i] - &d[i + k]).transpose()).trace()).sum::<f64>() / first.len() as f64;
        axis_decorrelation.push((k, mean));
    }
    Ok(Harmonic { row_equipartition, held, freedoms: basis.ncols() - 6, axis_decorrelation })
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
    Ok((1..n.saturating_sub(1))
        .map(|k| {
            let x = (pts[k].1 - pts[k].0).normalize();
            let c = (pts[k + 1].0 + pts[k + 1].1 - pts[k - 1].0 - pts[k - 1].1) * 0.5;
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
