//! Is the world statically defined (IV.B)? A quasi-static solve needs every
//! rigid-body mode of every rod (3 translations, 3 rotations, and a uniform
//! roll for rods with roll), and every combination of them across linked
//! rods, to be held either by the constraints (L m ≠ 0) or by the stiffness
//! (mᵀ K m > 0, e.g. the roll of a curved rod). Checked on the assembled K
//! so that the error names the free motion instead of surfacing as a zero
//! pivot.
use crate::constraint::{Anchoring, ConstraintKind, Row};
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

/// A rigid mode of one rod: (rod position, mode id, vector over its coordinates).
type Mode = (usize, usize, DVector<f64>);

pub(crate) fn check_statically_defined(world: &World) -> Result<()> {
    let layout = &world.ws.layout;
    let rods: Vec<_> = world.rods.iter().collect();
    let index: std::collections::HashMap<crate::handles::RodHandle, usize> =
        rods.iter().enumerate().map(|(r, (i, _))| ((*i).into(), r)).collect();
    let pos_of = |h: crate::handles::RodHandle| index.get(&h).copied();
    // The first full position constraint of each rod (its pivot for rotations).
    let mut pivot: Vec<Option<f64>> = vec![None; rods.len()];
    for (_, c) in world.constraints.iter() {
        if let (ConstraintKind::Position(p), Some(r)) = (&c.kind, pos_of(c.rod)) {
            pivot[r].get_or_insert(p.u);
        }
    }
    // Rigid modes per rod, orthonormalised within the rod (dropping
    // degenerate ones, e.g. a straight 3-DOF rod's spin about itself);
    // `raw` keeps them unorthogonalised, for naming.
    let mut modes: Vec<Mode> = Vec::new();
    let mut raw: Vec<Mode> = Vec::new();
    for (r, (_, rod)) in rods.iter().enumerate() {
        let d = rod.dofs();
        let nc = rod.n_ctrl();
        let point = |i: usize| Vector3::new(rod.coords()[i * d], rod.coords()[i * d + 1], rod.coords()[i * d + 2]);
        // Rotations about a held point (if any), so that a rod pinned at
        // one point shows its free motion as a pure rotation.
        let held = pivot[r].and_then(|u| rod.position(u).ok());
        let centre = held.unwrap_or_else(|| (0..nc).fold(Vector3::zeros(), |c, i| c + point(i)) / nc as f64);
        let first = modes.len();
        for m in 0..if d == 4 { 7 } else { 6 } {
            let mut v = DVector::<f64>::zeros(nc * d);
            for i in 0..nc {
                match m {
                    0..=2 => v[i * d + m] = 1.0,
                    3..=5 => {
                        let w = Vector3::ith(m - 3, 1.0).cross(&(point(i) - centre));
                        for a in 0..3 {
                            v[i * d + a] = w[a];
                        }
                    }
                    _ => v[i * d + 3] = 1.0,
                }
            }
            raw.push((r, m, v.clone()));
            // Degenerate against the mode's natural size (a unit move of
            // every control point; a rotation moves them by up to the rod's
            // length), not against its own norm: a straight 3-DOF rod's spin
            // about itself is round-off (1e-17), not a mode.
            let size = (nc as f64).sqrt() * if (3..=5).contains(&m) { rod.rest_length() } else { 1.0 };
            for (_, _, q) in &modes[first..] {
                let c = q.dot(&v);
                v -= q * c;
            }
            if v.norm() > 1e-8 * size {
                let nv = v.norm();
                modes.push((r, m, v / nv));
            }
        }
    }
    // Normalised constraint rows applied to the modes: (L Q) and (L m_raw).
    let k = modes.len();
    let mut lq: Vec<Vec<f64>> = Vec::new();
    let mut lraw: Vec<Vec<f64>> = Vec::new();
    let mut buf = [Row::default(); crate::constraint::MAX_ROWS];
    for (_, c) in world.constraints.iter() {
        let nr = c.kind.n_rows();
        c.kind.linearize(&world.rods_of(c)?, &mut buf[..nr])?;
        let which = [pos_of(c.rod), pos_of(c.other.unwrap_or(c.rod))];
        for row in &buf[..nr] {
            let norm = row.entries().iter().map(|e| e.2 * e.2).sum::<f64>().sqrt();
            if norm == 0.0 {
                continue;
            }
            let apply = |set: &[Mode]| -> Vec<f64> {
                set.iter()
                    .map(|(r, _, v)| {
                        row.entries()
                            .iter()
                            .filter(|e| e.0 < 2 && which[e.0 as usize] == Some(*r))
                            .map(|&(_, i, x)| x * v[i])
                            .sum::<f64>()
                            / norm
                    })
                    .collect()
            };
            lq.push(apply(&modes));
            lraw.push(apply(&raw));
        }
    }
    let lq = if lq.is_empty() {
        DMatrix::zeros(1, k)
    } else {
        DMatrix::from_row_iterator(lq.len(), k, lq.iter().flatten().copied())
    };
    let eig = (lq.transpose() * &lq).symmetric_eigen();
    let kscale = (0..layout.n).map(|g| world.ws.sys.band.get(g, g).abs()).fold(0.0, f64::max);
    let n = layout.n;
    let (mut x, mut y) = (vec![0.0; n], vec![0.0; n]);
    // A mode is held when the constraints see it. The scale is relative:
    // with modes of unit norm over n control points, a tangent clamp sees a
    // rotation at λ ~ 3/n³ of what a position constraint sees of a
    // translation (λ ~ 1/n), while round-off on a free mode is ~1e-32.
    let lmax = eig.eigenvalues.iter().fold(0.0f64, |m, &l| m.max(l));
    for j in 0..k {
        if eig.eigenvalues[j] > 1e-14 * lmax {
            continue;
        }
        // Unconstrained rigid motion: does the stiffness hold it?
        x.iter_mut().for_each(|t| *t = 0.0);
        for (m, (r, _, v)) in modes.iter().enumerate() {
            let c = eig.eigenvectors[(m, j)];
            for i in 0..v.len() {
                x[layout.dof(*r, i)] += c * v[i];
            }
        }
        world.ws.sys.band.matvec(&x, &mut y);
        // Only coordinate rows: the multiplier rows of y are L x ≈ 0.
        let mut curv = 0.0;
        for (r, (_, rod)) in rods.iter().enumerate() {
            for i in 0..rod.q.len() {
                let g = layout.dof(r, i);
                curv += x[g] * y[g];
            }
        }
        // Round-off leaves |mᵀKm| ~ 1e-14 kscale on a free mode (kscale is
        // the axial diagonal EA/Δs); real holding stiffness — the bending
        // of a curved rod, or the geometric stiffness of a rod stressed by
        // its load, e.g. a clamped wire bent by its weight held against a
        // rigid spin about the clamp axis — is far above 1e-12 kscale.
        if !(curv > 1e-12 * kscale) {
            // Name a single rigid mode that is free by itself if there is
            // one, else the dominant component of the free motion.
            let alone = raw.iter().enumerate().find(|(m, (_, _, v))| {
                let nv = v.norm();
                nv > 0.0 && lraw.iter().all(|row| row[*m].abs() <= 1e-8 * nv)
            });
            let (r, name) = match alone {
                Some((_, (r, id, _))) => (*r, NAMES[*id]),
                None => (0..k)
                    .max_by(|&a, &b| eig.eigenvectors[(a, j)].abs().total_cmp(&eig.eigenvectors[(b, j)].abs()))
                    .map_or((0, "rigid motion"), |a| (modes[a].0, NAMES[modes[a].1])),
            };
            return Err(Error::singular(format!(
                "rod {} is not statically defined: its {name} is held by no constraint (add constraints, or use step() for dynamics)",
                rods[r].0 .0
            )));
        }
    }
    Ok(())
}

/// The thesis' rule for switching to quasi-statics (IV.B): every rod is
/// held at ≥ 2 points, or at one point with an orientation. A point is
/// a position constraint on x, y and z (or a full relative position /
/// coplanar clamp to a rod that is itself held); an orientation is a
/// tangent constraint, an oriented slider, or a relative orientation to
/// a held rod. Stricter than [`Self::check_statically_defined`], which
/// also accepts motions held by the stiffness of a stressed rod (a
/// pendulum hanging under its weight has a static equilibrium, but its
/// swing is dynamics the quasi-static switch must keep).
pub(crate) fn check_anchored(world: &World) -> Result<()> {
    use crate::handles::RodHandle;
    let rods: Vec<RodHandle> = world.rods().map(|(h, _)| h).collect();
    let mut held: Vec<bool> = vec![false; rods.len()];
    let index: std::collections::HashMap<RodHandle, usize> = rods.iter().enumerate().map(|(i, h)| (*h, i)).collect();
    let idx = |h: RodHandle| index.get(&h).copied();
    // The constraints touching each rod, found once.
    let mut touching: Vec<Vec<&crate::world::Constraint>> = vec![Vec::new(); rods.len()];
    for (_, c) in world.constraints() {
        for h in [Some(c.rod), c.other.filter(|o| *o != c.rod)].into_iter().flatten() {
            if let Some(i) = idx(h) {
                touching[i].push(c);
            }
        }
    }
    // Links count once their other rod is held: iterate to a fixed point.
    loop {
        let mut changed = false;
        for (i, &h) in rods.iter().enumerate() {
            if held[i] {
                continue;
            }
            let (mut points, mut orient) = (Vec::<f64>::new(), 0usize);
            for &c in &touching[i] {
                let other_held = |o: Option<RodHandle>, me: RodHandle| {
                    let o = o.unwrap_or(me);
                    o != me && idx(o).is_some_and(|j| held[j])
                };
                let peer = if c.rod == h { c.other } else if c.other == Some(h) { Some(c.rod) } else { continue };
                // The abscissa on this rod: the first of its side.
                let my_side = if c.rod == h { 0 } else { 1 };
                let mut u = f64::NAN;
                c.kind.visit_abscissae(&mut |side, x| {
                    if side == my_side && u.is_nan() {
                        u = x;
                    }
                });
                match c.kind.anchoring() {
                    Anchoring::Point => points.push(u),
                    Anchoring::Orientation => orient += 1,
                    Anchoring::PointViaPeer if other_held(peer, h) => points.push(u),
                    Anchoring::OrientationViaPeer if other_held(peer, h) => orient += 1,
                    Anchoring::None | Anchoring::PointViaPeer | Anchoring::OrientationViaPeer => {}
                }
            }
            points.sort_by(f64::total_cmp);
            points.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * (1.0 + a.abs()));
            if points.len() >= 2 || (points.len() == 1 && orient >= 1) {
                held[i] = true;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    match held.iter().position(|x| !x) {
        None => Ok(()),
        Some(i) => Err(Error::singular(format!(
            "rod {} is held neither at two points nor at one point with an orientation (IV.B): it stays dynamic",
            rods[i].index
        ))),
    }
}
