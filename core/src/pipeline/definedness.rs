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

/// A rigid mode of one rod: (rod position, mode id, vector over its
/// coordinates, its coefficients on the rod's raw modes of [`NAMES`]).
type Mode = (usize, usize, DVector<f64>, [f64; 7]);

/// `at_equilibrium`: the iterate is a converged equilibrium; the test is
/// then the Newton matrix's own curvature xᵀKx along the free motion (what
/// makes the undamped solve singular), without the second-order term that
/// a start needs (that term would also need the constraints' curvature
/// where linked rods turn about different axes).
pub(crate) fn check_statically_defined(world: &World, at_equilibrium: bool) -> Result<()> {
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
            let mut coef = [0.0; 7];
            coef[m] = 1.0;
            raw.push((r, m, v.clone(), coef));
            // Degenerate against the mode's natural size (a unit move of
            // every control point; a rotation moves them by up to the rod's
            // length), not against its own norm: a straight 3-DOF rod's spin
            // about itself is round-off (1e-17), not a mode.
            let size = (nc as f64).sqrt() * if (3..=5).contains(&m) { rod.rest_length() } else { 1.0 };
            for (_, _, q, qc) in &modes[first..] {
                let c = q.dot(&v);
                v -= q * c;
                coef.iter_mut().zip(qc).for_each(|(a, b)| *a -= c * b);
            }
            if v.norm() > 1e-8 * size {
                let nv = v.norm();
                coef.iter_mut().for_each(|a| *a /= nv);
                modes.push((r, m, v / nv, coef));
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
                    .map(|(r, _, v, _)| {
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
    let kscale = (0..layout.n).map(|g| world.ws.sys.matrix.diag(g).abs()).fold(0.0, f64::max);
    let n = layout.n;
    let (mut x, mut y) = (vec![0.0; n], vec![0.0; n]);
    // A mode is held when the constraints see it. With modes of unit norm
    // over n control points, a position constraint sees a translation at
    // λ ~ 1/n and a tangent clamp sees a rotation at λ ~ 3/n³ (1e-14 at
    // 40,000 control points), so the scale is relative to the largest λ
    // (round-off on a free mode: ~1e-32 of it). (A start that does not
    // meet its constraints yet can show a free mode at λ ~ e², e the
    // violation; telling that from a weak hold is left to the solve.)
    let lmax = eig.eigenvalues.iter().fold(0.0f64, |m, &l| m.max(l));
    let seen = 1e-14 * lmax;
    for j in 0..k {
        if eig.eigenvalues[j] > seen {
            continue;
        }
        // Unconstrained rigid motion: does the stiffness hold it?
        x.iter_mut().for_each(|t| *t = 0.0);
        // The motion on each rod's raw modes (translations, rotations, roll).
        let mut a = vec![[0.0f64; 7]; rods.len()];
        for (m, (r, _, v, coef)) in modes.iter().enumerate() {
            let c = eig.eigenvectors[(m, j)];
            for i in 0..v.len() {
                x[layout.dof(*r, i)] += c * v[i];
            }
            a[*r].iter_mut().zip(coef).for_each(|(s, k)| *s += c * k);
        }
        world.ws.sys.matrix.matvec(&x, &mut y);
        // Only coordinate rows: the multiplier rows of y are L x ≈ 0.
        // The second derivative of the potential Π along the rigid motion:
        // xᵀKx plus ∂Π/∂q · q'' (q'' = ω × ṗ, the screw motion's;
        // ∂Π/∂q = −B, the static right-hand side). For a symmetry of Π — a
        // spin that no load or constraint resists — it is exactly zero at
        // any configuration, equilibrium or not, where xᵀKx alone shows the
        // stresses of a start shape as a holding stiffness.
        let mut curv = 0.0;
        for (r, (_, rod)) in rods.iter().enumerate() {
            let d = rod.dofs();
            let w = Vector3::new(a[r][3], a[r][4], a[r][5]);
            for i in 0..rod.q.len() {
                let g = layout.dof(r, i);
                curv += x[g] * y[g];
            }
            for i in 0..rod.n_ctrl() {
                // A screw motion ṗ = ω × p + v has p̈ = ω × ṗ: with ṗ the
                // mode itself this holds for a rotation about the rod's
                // own centre combined with translations (a rotation of
                // linked rods about a common axis).
                let xi = Vector3::from_fn(|k, _| x[layout.dof(r, i * d + k)]);
                let q2 = w.cross(&xi);
                for k in 0..3 {
                    if !at_equilibrium {
                        curv -= world.ws.sys.rhs[layout.dof(r, i * d + k)] * q2[k];
                    }
                }
            }
        }
        if std::env::var_os("STRANDKIT_DEBUG").is_some() {
            let xkx: f64 = (0..n).map(|g| x[g] * y[g]).sum();
            eprintln!("definedness: xKx {xkx:.4e} curv {curv:.4e} modes {a:?}");
        }
        // Round-off leaves |mᵀKm| ~ 1e-14 kscale on a free mode (kscale is
        // the axial diagonal EA/Δs); real holding stiffness — the bending
        // of a curved rod, or the geometric stiffness of a rod stressed by
        // its load, e.g. a clamped wire bent by its weight held against a
        // rigid spin about the clamp axis — is far above 1e-12 kscale.
        if std::env::var_os("STRANDKIT_DEBUG").is_some() {
            eprintln!("definedness: mode {j} λ {:.3e} (lmax {lmax:.3e}) curv {curv:.3e} kscale {kscale:.3e}", eig.eigenvalues[j]);
        }
        // A motion that turns rods is judged physically: its curvature per
        // unit displacement² (x has unit norm) against the bending scale
        // EI/L³ of the rods that move, weighted by their share of |x|². A
        // load's geometric stiffness (a clamped wire sagging under its
        // weight spun about the clamp axis: ~1e-2 EI/L³; a rope swinging
        // beside stiff planks; a plank bent by its weight turned about its
        // pins) does not vanish with refinement, while the round-off of a
        // symmetry (a clamped ring spinning about its clamp tangent: ~1e-11
        // EI/L³ at 40 control points) is far below 1e-9. A translation (or
        // roll) is held only by a force field's stiffness, judged against
        // the round-off of the stiffest diagonal (1e-12 kscale).
        let longest = rods.iter().map(|(_, r)| r.rest_length()).fold(0.0, f64::max);
        let (mut turn, mut other) = (0.0f64, 0.0f64);
        for c in &a {
            turn = turn.max((c[3] * c[3] + c[4] * c[4] + c[5] * c[5]).sqrt());
            other = other.max((c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt() / longest).max(c[6].abs());
        }
        let held = if turn > 0.5 * other {
            let (mut bend, mut weight) = (0.0, 0.0);
            for (r, (_, rod)) in rods.iter().enumerate() {
                let share: f64 = (0..rod.q.len()).map(|i| x[layout.dof(r, i)].powi(2)).sum();
                let ei = rod.cache().samples.iter().map(|s| s.consts.ei1.max(s.consts.ei2)).fold(0.0, f64::max);
                bend += share * ei / rod.rest_length().powi(3);
                weight += share;
            }
            let bend = if weight > 0.0 { bend / weight } else { 0.0 };
            if std::env::var_os("STRANDKIT_DEBUG").is_some() {
                eprintln!("definedness: turning motion, curvature {curv:.3e} vs 1e-9 EI/L³ {:.3e} (equilibrium {at_equilibrium})", 1e-9 * bend);
            }
            curv > 1e-9 * bend
        } else {
            curv > 1e-12 * kscale
        };
        if !held {
            // Name a single rigid mode that is free by itself if there is
            // one, else the dominant component of the free motion.
            let alone = raw.iter().enumerate().find(|(m, (_, _, v, _))| {
                let nv = v.norm();
                nv > 0.0 && lraw.iter().all(|row| row[*m].abs() <= 1e-8 * nv)
            });
            // Else the largest raw component of the free motion (rotations
            // weighted by the rod's length: what they move a point by).
            let dominant = || {
                // (A roll moves material points by the section's radius only:
                // name the positional part of a motion first.)
                let weight = |r: usize, m: usize| {
                    a[r][m].abs()
                        * match m {
                            3..=5 => rods[r].1.rest_length(),
                            6 => 1e-3 * rods[r].1.rest_length(),
                            _ => 1.0,
                        }
                };
                (0..rods.len())
                    .flat_map(|r| (0..7).map(move |m| (r, m)))
                    .max_by(|&(r1, m1), &(r2, m2)| weight(r1, m1).total_cmp(&weight(r2, m2)))
                    .map_or((0, "rigid motion"), |(r, m)| (r, NAMES[m]))
            };
            let (r, name) = match alone {
                Some((_, (r, id, _, _))) => (*r, NAMES[*id]),
                None => dominant(),
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
