//! Is every rod statically defined (IV.B)? A quasi-static solve needs every
//! rigid-body mode of every rod (3 translations, 3 rotations, and a uniform
//! roll for rods with roll) to be held, either by the constraints (L m ≠ 0)
//! or by the stiffness (mᵀ K m > 0, e.g. the roll of a curved rod). Checked
//! on the assembled K so that the error names the free motion instead of
//! surfacing as a zero pivot.
use crate::constraint::Row;
use crate::error::{Error, Result};
use crate::world::World;
use nalgebra::{DMatrix, DVector, Vector3};

const NAMES: [&str; 7] = [
    "translation along x",
    "translation along y",
    "translation along z",
    "rotation about x",
    "rotation about y",
    "rotation about z",
    "uniform roll",
];

impl World {
    pub(crate) fn check_statically_defined(&self) -> Result<()> {
        let n = self.ws.layout.n;
        let mut x = vec![0.0; n];
        let mut y = vec![0.0; n];
        for (r, (h, rod)) in self.rods.iter().enumerate() {
            let d = rod.dofs;
            let nc = rod.n_ctrl();
            // Rotations about a held point (if any), so that a rod pinned at
            // one point shows its free motion as a pure rotation.
            let held = self.constraints.iter().find_map(|(_, c)| match c.kind {
                crate::constraint::ConstraintKind::Position { u, .. } if c.rod == h.into() => rod.position(u).ok(),
                _ => None,
            });
            let centroid = held.unwrap_or_else(|| {
                (0..nc).fold(Vector3::zeros(), |c, i| c + Vector3::new(rod.q[i * d], rod.q[i * d + 1], rod.q[i * d + 2]))
                    / nc as f64
            });
            // Rigid modes, orthonormalised (dropping degenerate ones, e.g. the
            // rotation of a straight 3-DOF rod about its own axis).
            let mut modes: Vec<(usize, DVector<f64>)> = Vec::new();
            let mut raw: Vec<(usize, DVector<f64>)> = Vec::new();
            for m in 0..if d == 4 { 7 } else { 6 } {
                let mut v = DVector::<f64>::zeros(nc * d);
                for i in 0..nc {
                    let p = Vector3::new(rod.q[i * d], rod.q[i * d + 1], rod.q[i * d + 2]) - centroid;
                    match m {
                        0..=2 => v[i * d + m] = 1.0,
                        3..=5 => {
                            let w = Vector3::ith(m - 3, 1.0).cross(&p);
                            for a in 0..3 {
                                v[i * d + a] = w[a];
                            }
                        }
                        _ => v[i * d + 3] = 1.0,
                    }
                }
                let norm0 = v.norm();
                raw.push((m, v.clone()));
                for (_, q) in &modes {
                    let c = q.dot(&v);
                    v -= q * c;
                }
                if v.norm() > 1e-8 * norm0.max(1e-300) {
                    let nv = v.norm();
                    modes.push((m, v / nv));
                }
            }
            // L restricted to this rod, rows normalised.
            let mut lrows: Vec<DVector<f64>> = Vec::new();
            let mut buf = vec![Row::default(); 4];
            for (_, c) in self.constraints.iter() {
                if c.rod != h.into() {
                    continue;
                }
                let nr = c.kind.n_rows();
                c.kind.linearize(rod, &mut buf[..nr])?;
                for row in &buf[..nr] {
                    let mut l = DVector::<f64>::zeros(nc * d);
                    for &(i, v) in row.entries() {
                        l[i] += v;
                    }
                    let nl = l.norm();
                    if nl > 0.0 {
                        lrows.push(l / nl);
                    }
                }
            }
            let k = modes.len();
            let q = DMatrix::from_columns(&modes.iter().map(|(_, v)| v.clone()).collect::<Vec<_>>());
            let lq = if lrows.is_empty() {
                DMatrix::zeros(1, k)
            } else {
                DMatrix::from_rows(&lrows.iter().map(|l| l.transpose()).collect::<Vec<_>>()) * &q
            };
            let eig = (lq.transpose() * &lq).symmetric_eigen();
            let kscale = (0..nc * d)
                .map(|i| {
                    let g = self.ws.layout.dof(r, i);
                    self.ws.sys.band.get(g, g).abs()
                })
                .fold(0.0, f64::max);
            for j in 0..k {
                if eig.eigenvalues[j] > 1e-10 {
                    continue;
                }
                // Unconstrained rigid motion: does the stiffness hold it?
                let v = &q * eig.eigenvectors.column(j);
                x.iter_mut().for_each(|t| *t = 0.0);
                for i in 0..nc * d {
                    x[self.ws.layout.dof(r, i)] = v[i];
                }
                self.ws.sys.band.matvec(&x, &mut y);
                let curv: f64 = (0..nc * d).map(|i| v[i] * y[self.ws.layout.dof(r, i)]).sum();
                if !(curv > 1e-8 * kscale) {
                    // Name a single rigid mode that is free by itself if there
                    // is one, else the dominant component of the free motion.
                    let alone = raw.iter().find(|(_, m)| {
                        let nm = m.norm();
                        nm > 0.0 && lrows.iter().all(|l| l.dot(m).abs() <= 1e-8 * nm)
                    });
                    let main = alone.map(|(i, _)| NAMES[*i]).unwrap_or_else(|| {
                        (0..k)
                            .max_by(|&a, &b| eig.eigenvectors[(a, j)].abs().total_cmp(&eig.eigenvectors[(b, j)].abs()))
                            .map_or("rigid motion", |a| NAMES[modes[a].0])
                    });
                    return Err(Error::Singular(format!(
                        "rod {} is not statically defined: its {main} is held by no constraint (add constraints, or use step() for dynamics)",
                        h.0
                    )));
                }
            }
        }
        Ok(())
    }
}
