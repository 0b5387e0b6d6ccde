//! Time stepping (SPEC §3): linearised implicit Euler and the quasi-static
//! Newton solve, both on the KKT system of [`crate::system`].
mod beads;
mod definedness;
mod dynamic;
pub mod quasi_dynamic;
mod statics;

use crate::error::{Error, Result};
use crate::handles::Index;
use crate::load::Load;
use crate::system::kkt::{Coefficients, ConstraintRef};
use crate::system::layout::ConstraintSlot;
use crate::system::{KktSystem, Layout};
use crate::world::World;
use serde::{Deserialize, Serialize};

/// All integration settings in one place (Rapier-style).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct IntegrationParameters {
    /// Time step h (time unit).
    pub dt: f64,
    /// Gravity (length/time²); the body force is μ g per unit length.
    pub gravity: [f64; 3],
    /// Assemble segments in parallel (rayon).
    pub parallel: bool,
    /// Quasi-static convergence: Newton increment ≤ tol × rod length (and
    /// tol radians on roll), constraint violation ≤ tol × rod length.
    pub relax_tolerance: f64,
    pub relax_max_iterations: usize,
    /// relax() with plastic flow: equilibrium and plastic update alternate
    /// until the largest offset increment (strain, or curvature/twist ×
    /// rest length) is below this (dimensionless). The alternation converges
    /// linearly (≈ 0.9 per round in a bent clamped wire), so this is looser
    /// than `relax_tolerance`.
    #[serde(default = "default_plastic_tolerance")]
    pub plastic_tolerance: f64,
    /// Band LU, sparse, or chosen by the half-bandwidth (default).
    #[serde(default)]
    pub linear_solver: crate::system::LinearSolver,
}

impl Default for IntegrationParameters {
    fn default() -> Self {
        IntegrationParameters {
            dt: 1e-3,
            gravity: [0.0, 0.0, 0.0],
            parallel: true,
            relax_tolerance: 1e-10,
            relax_max_iterations: 500,
            plastic_tolerance: default_plastic_tolerance(),
            linear_solver: crate::system::LinearSolver::Auto,
        }
    }
}

fn default_plastic_tolerance() -> f64 {
    1e-6
}

impl IntegrationParameters {
    pub fn validate(&self) -> Result<()> {
        crate::error::positive("plastic_tolerance", self.plastic_tolerance)?;
        crate::error::positive("dt", self.dt)?;
        for g in self.gravity {
            crate::error::finite("gravity", g)?;
        }
        crate::error::positive("relax_tolerance", self.relax_tolerance)?;
        if self.relax_max_iterations == 0 {
            return Err(Error::input("relax_max_iterations must be > 0"));
        }
        Ok(())
    }
}

/// What a solve did.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StepReport {
    /// Time after the step.
    pub time: f64,
    pub n_unknowns: usize,
    pub n_multipliers: usize,
    /// Half-bandwidth of the KKT band.
    pub bandwidth: usize,
    /// Relative residual of the last linear solve.
    pub residual: f64,
    /// The sparse factorisation solved it (else a band factorisation).
    #[serde(default)]
    pub sparse: bool,
    /// The band LDLᵀ solved it (else the pivoting band LU or the sparse path).
    #[serde(default)]
    pub ldlt: bool,
    /// Entries stored by the factorisation (fill included): n (2 kl + ku + 1)
    /// for the band LU, the factor's nonzeros for the sparse path.
    #[serde(default)]
    pub factor_entries: usize,
    /// Elastic energy before the step.
    pub elastic_energy: f64,
    /// Samples whose plastic offset moved after this step (SPEC §6).
    #[serde(default)]
    pub plastic_samples: usize,
    /// What happened in this step (broken constraints, departed sliders,
    /// clips, ruptures), in the order it happened.
    pub events: Vec<crate::world::Event>,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RelaxReport {
    /// Linear solves performed (accepted and rejected).
    pub iterations: usize,
    pub rejected: usize,
    /// Final Newton increment (max norm, length unit) and constraint violation.
    pub increment: f64,
    pub violation: f64,
    /// Total potential energy U − Fᵀq at the end.
    pub potential: f64,
    pub bandwidth: usize,
    pub n_unknowns: usize,
    /// Samples whose plastic offset moved during the solve (counted at
    /// every intermediate equilibrium) (SPEC §6).
    #[serde(default)]
    pub plastic_samples: usize,
    /// Largest plastic offset increment of the last round (see
    /// `IntegrationParameters::plastic_tolerance`); above the tolerance when
    /// the flow stagnated (a plastic distribution left indeterminate).
    #[serde(default)]
    pub plastic_increment: f64,
    /// What happened at the equilibrium found (broken constraints, clips,
    /// a rupture — which ends the solve).
    pub events: Vec<crate::world::Event>,
}

/// Buffers reused across steps (not serialised).
#[derive(Debug, Default)]
pub struct Workspace {
    pub(crate) sys: KktSystem,
    pub(crate) layout: Layout,
    /// What `layout` was built for: rods (id, control points, dofs,
    /// segment fingerprint), constraint slots, interleaved groups.
    pub(crate) layout_rods: Vec<(Index, usize, usize, usize)>,
    pub(crate) layout_slots: Vec<ConstraintSlot>,
    pub(crate) layout_groups: Vec<Vec<crate::handles::RodHandle>>,
    pub(crate) slots: Vec<ConstraintSlot>,
    /// Allocations kept for the per-step vectors of references (always
    /// empty between steps, see [`recycle`]).
    pub(crate) rod_refs: Vec<&'static crate::rod::Rod>,
    pub(crate) con_refs: Vec<ConstraintRef<'static>>,
    pub(crate) masses: Vec<(usize, f64, f64)>,
    pub(crate) ext: Vec<Vec<f64>>,
    pub(crate) rod_ids: Vec<Index>,
    pub(crate) con_ids: Vec<Index>,
    /// Sliders that left their rod in the last solve.
    pub(crate) left: Vec<Index>,
}

impl World {
    /// Builds the layout, the external forces, and assembles the system.
    /// Returns the elastic energy.
    pub(crate) fn assemble(&mut self, k: Coefficients) -> Result<f64> {
        self.assemble_with(k, false)
    }

    /// `bead_unknowns`: beads' abscissae are unknowns (statics), placed like
    /// sliders next to the control points they touch.
    pub(crate) fn assemble_with(&mut self, k: Coefficients, bead_unknowns: bool) -> Result<f64> {
        self.params.validate()?;
        // Contacts follow the closest points of their rods.
        let rods_arena = &self.rods;
        for (_, c) in self.constraints.iter_mut() {
            if let (Some(a), Some(b)) = (rods_arena.get(c.rod.into()), rods_arena.get(c.other.unwrap_or(c.rod).into())) {
                c.kind.project(&[a, b])?;
            }
        }
        let ws = &mut self.ws;
        ws.rod_ids.clear();
        ws.rod_ids.extend(self.rods.iter().map(|(i, _)| i));
        ws.con_ids.clear();
        ws.con_ids.extend(self.constraints.iter().map(|(i, _)| i));
        let mut rods: Vec<&crate::rod::Rod> = recycle(std::mem::take(&mut ws.rod_refs));
        rods.extend(self.rods.iter().map(|(_, r)| r));
        let pos = |h: crate::handles::RodHandle| -> Result<usize> {
            let i: Index = h.into();
            ws.rod_ids.iter().position(|x| *x == i).ok_or_else(|| Error::handle(format!("rod {h:?} was removed")))
        };
        ws.slots.clear();
        let mut crefs: Vec<ConstraintRef<'_>> = recycle(std::mem::take(&mut ws.con_refs));
        for (_, c) in self.constraints.iter() {
            let (a, b) = (pos(c.rod)?, pos(c.other.unwrap_or(c.rod))?);
            let t = c.kind.touched(&[rods[a], rods[b]])?;
            ws.slots.push(ConstraintSlot {
                rods: [a, b],
                n_rows: c.kind.n_rows(),
                n_extra: c.kind.n_extra(),
                touched: t.items,
                len: t.len,
            });
            crefs.push(ConstraintRef { rods: [a, b], kind: &c.kind, compliance: c.compliance, lambda: &c.multipliers });
        }
        let mut static_beads = Vec::new();
        if bead_unknowns {
            for (_, b) in self.beads.iter() {
                let r = pos(b.rod)?;
                let ctrl = rods[r].basis_at(b.u)?.0;
                let mut touched = [(0u8, 0usize); crate::constraint::MAX_TOUCHED];
                for (t, c) in touched.iter_mut().zip(ctrl) {
                    *t = (0, c);
                }
                ws.slots.push(ConstraintSlot { rods: [r, r], n_rows: 0, n_extra: 1, touched, len: 4 });
                static_beads.push(crate::system::kkt::BeadRef { rod: r, u: b.u, load: b.rod_force, mass: b.mass });
            }
        }
        // The layout (algorithms 9–10) changes only with the topology: rods
        // (identity, size), constraint slots (touched control points move
        // when a slider changes segment) and interleaving. Rebuilt then only,
        // so a step allocates nothing.
        let shape_now = rods.iter().zip(&ws.rod_ids).map(|(r, i)| (*i, r.n_ctrl(), r.dofs, segment_fingerprint(r)));
        let same = ws.layout_rods.len() == rods.len()
            && ws.layout_rods.iter().copied().eq(shape_now)
            && ws.layout_slots == ws.slots
            && ws.layout_groups == self.interleave;
        if !same {
            let segs: Vec<_> = rods.iter().map(|r| (r.n_ctrl(), r.dofs, r.cache.seg_ctrl.as_slice())).collect();
            let groups: Vec<Vec<usize>> = self
                .interleave
                .iter()
                .map(|g| g.iter().map(|h| pos(*h)).collect::<Result<Vec<_>>>())
                .collect::<Result<_>>()?;
            let n_ctrl: Vec<usize> = rods.iter().map(|r| r.n_ctrl()).collect();
            let order = crate::system::layout::control_point_order(&n_ctrl, &groups);
            ws.layout = Layout::build(&segs, &order, &ws.slots);
            ws.layout_rods = rods.iter().zip(&ws.rod_ids).map(|(r, i)| (*i, r.n_ctrl(), r.dofs, segment_fingerprint(r))).collect();
            ws.layout_slots.clone_from(&ws.slots);
            ws.layout_groups.clone_from(&self.interleave);
        }
        // External generalised forces: gravity and loads (III.1–III.10).
        ws.ext.resize_with(rods.len(), Vec::new);
        let g = self.params.gravity;
        for (r, rod) in rods.iter().enumerate() {
            let f = &mut ws.ext[r];
            f.clear();
            f.resize(rod.q.len(), 0.0);
            let d = rod.dofs;
            for (s, ctrl) in rod.cache.seg_ctrl.iter().enumerate() {
                for k in 0..4 {
                    for a in 0..3 {
                        f[ctrl[k] * d + a] += rod.cache.seg_mass_weight[s][k] * g[a];
                    }
                }
            }
        }
        let mut masses = std::mem::take(&mut ws.masses);
        masses.clear();
        for (_, b) in self.beads.iter() {
            let r = pos(b.rod)?;
            let (ctrl, bs) = rods[r].basis_at(b.u)?;
            let d = rods[r].dofs;
            for k in 0..4 {
                for a in 0..3 {
                    ws.ext[r][ctrl[k] * d + a] += bs[0][k] * b.rod_force[a];
                }
            }
            masses.push((r, b.u, b.mass));
        }
        for (_, l) in self.loads.iter() {
            let r = pos(l.rod())?;
            let rod = rods[r];
            let f = &mut ws.ext[r];
            let d = rod.dofs;
            match l {
                Load::PointForce { u, force, .. } => {
                    let (ctrl, b) = rod.basis_at(*u)?;
                    for k in 0..4 {
                        for a in 0..3 {
                            f[ctrl[k] * d + a] += b[0][k] * force[a];
                        }
                    }
                }
                Load::PointTorque { u, torque, .. } => {
                    let (ctrl, b) = rod.basis_at(*u)?;
                    for k in 0..4 {
                        f[ctrl[k] * d + 3] += b[0][k] * torque;
                    }
                }
                Load::Distributed { force_per_length, .. } => {
                    for (s, ctrl) in rod.cache.seg_ctrl.iter().enumerate() {
                        for k in 0..4 {
                            for a in 0..3 {
                                f[ctrl[k] * d + a] += rod.cache.seg_len_weight[s][k] * force_per_length[a];
                            }
                        }
                    }
                }
            }
        }
        let energy = ws.sys.assemble(&ws.layout, &rods, &ws.ext, &crefs, &masses, k, self.params.parallel);
        let energy = energy.and_then(|e| ws.sys.assemble_beads(&ws.layout, &rods, crefs.len(), &static_beads, k).map(|_| e));
        ws.masses = masses;
        ws.con_refs = recycle(crefs);
        ws.rod_refs = recycle(rods);
        let energy = energy?;
        for (_, b) in self.beads.iter_mut() {
            b.u_assembled = b.u;
        }
        Ok(energy)
    }

    /// Solves the assembled system; errors name the offending unknown.
    pub(crate) fn solve_system(&mut self) -> Result<f64> {
        let ws = &mut self.ws;
        let (layout, rod_ids, con_ids) = (&ws.layout, &ws.rod_ids, &ws.con_ids);
        let describe = |g: usize| describe_unknown(layout, rod_ids, con_ids, g);
        ws.sys.solve(layout, self.params.linear_solver, describe)
    }

    /// Applies the solution: q += ΔX (returns max |ΔX| over positions and
    /// over roll), stores multipliers Λ = −y.
    pub(crate) fn apply_solution(&mut self, scale: f64, set_velocity: Option<f64>) -> (f64, f64) {
        let ws = &self.ws;
        let (mut dx_max, mut dth_max) = (0.0f64, 0.0f64);
        for (r, (_, rod)) in self.rods.iter_mut().enumerate() {
            let d = rod.dofs;
            for i in 0..rod.n_ctrl() {
                for a in 0..d {
                    let dx = scale * ws.sys.sol[ws.layout.cp_index[r][i] + a];
                    rod.q[i * d + a] += dx;
                    if let Some(inv_h) = set_velocity {
                        rod.v[i * d + a] = dx * inv_h;
                    }
                    if a < 3 {
                        dx_max = dx_max.max(dx.abs());
                    } else {
                        dth_max = dth_max.max(dx.abs());
                    }
                }
            }
        }
        let rods = &self.rods;
        let mut left = Vec::new();
        for (c, (h, con)) in self.constraints.iter_mut().enumerate() {
            let r0 = ws.layout.row_index[c];
            for (i, m) in con.multipliers.iter_mut().enumerate() {
                *m = -ws.sys.sol[r0 + i];
            }
            let ne = con.kind.n_extra();
            if ne > 0 {
                let du: Vec<f64> = (0..ne).map(|k| scale * ws.sys.sol[ws.layout.extra_index[c] + k]).collect();
                let (Some(a), Some(b)) = (rods.get(con.rod.into()), rods.get(con.other.unwrap_or(con.rod).into())) else {
                    continue;
                };
                if !con.kind.advance(&[a, b], &du) {
                    left.push(h);
                }
            }
        }
        self.ws.left.extend(left);
        (dx_max, dth_max)
    }

    /// Removes the sliders that left their rod during the last solve.
    pub(crate) fn drop_departed_sliders(&mut self) -> Vec<crate::world::Event> {
        let left = std::mem::take(&mut self.ws.left);
        let mut events = Vec::new();
        for h in left {
            if let Some(c) = self.constraints.remove(h) {
                events.push(crate::world::Event::SliderLeft { constraint: h.into(), time: self.time, kind: c.kind });
            }
        }
        events
    }

    /// Largest constraint residual |E − CΛ| of the assembled system (a
    /// compliant row is at rest when its violation equals C Λ).
    pub(crate) fn violation(&self) -> f64 {
        let mut v = 0.0f64;
        for (c, (_, con)) in self.constraints.iter().enumerate() {
            for i in 0..con.kind.n_rows() {
                let e = self.ws.sys.rhs[self.ws.layout.row_index[c] + i];
                v = v.max((e - con.compliance * con.multipliers[i]).abs());
            }
        }
        v
    }

    /// Largest constraint violation |target − g(q)| at the current coordinates.
    pub(crate) fn constraint_violation(&self) -> Result<f64> {
        let mut rows = [crate::constraint::Row::default(); crate::constraint::MAX_ROWS];
        let mut v = 0.0f64;
        for (_, c) in self.constraints.iter() {
            let nr = c.kind.n_rows();
            let pair = self.rods_of(c)?;
            let mut kind = c.kind.clone();
            kind.project(&pair)?; // contacts: at the current closest points
            kind.linearize(&pair, &mut rows[..nr])?;
            v = rows[..nr]
                .iter()
                .zip(&c.multipliers)
                .fold(v, |m, (r, l)| m.max((r.rhs - c.compliance * l).abs()));
        }
        Ok(v)
    }

    /// Potential energy U − Σ F_ext·q with the external forces of the last assembly.
    pub(crate) fn potential(&self) -> f64 {
        let mut p = 0.0;
        for (r, (_, rod)) in self.rods.iter().enumerate() {
            p += rod.elastic_energy();
            p -= self.ws.ext[r].iter().zip(&rod.q).map(|(f, q)| f * q).sum::<f64>();
        }
        p
    }
}

/// Which control points each segment uses, folded into one number (a rod
/// replaced by one of the same size but other knot multiplicities changes it).
fn segment_fingerprint(r: &crate::rod::Rod) -> usize {
    r.cache.seg_ctrl.iter().enumerate().fold(r.n_segments(), |h, (s, c)| {
        h.wrapping_mul(31).wrapping_add(c[0] ^ (c[3] << 20) ^ s)
    })
}

/// Empties a vector and reuses its allocation for another element type of
/// the same size and alignment — here references of another lifetime — so
/// per-step vectors of borrows keep their buffer between steps (the
/// in-place `collect` of `vec::IntoIter` keeps the allocation).
fn recycle<T, U>(mut v: Vec<T>) -> Vec<U> {
    v.clear();
    v.into_iter().map(|_| unreachable!("the vector was cleared")).collect()
}

/// The workspace is scratch space: a cloned world starts with empty buffers
/// (and rebuilds its layout on its first solve).
impl Clone for Workspace {
    fn clone(&self) -> Self {
        Workspace::default()
    }
}

fn describe_unknown(layout: &Layout, rod_ids: &[Index], con_ids: &[Index], g: usize) -> crate::error::Unknown {
    use crate::error::Unknown;
    for (r, cps) in layout.cp_index.iter().enumerate() {
        for (i, &start) in cps.iter().enumerate() {
            if g >= start && g < start + layout.dofs[r] {
                return Unknown::Coordinate { rod: rod_ids[r].into(), ctrl: i, axis: g - start };
            }
        }
    }
    for (c, &start) in layout.extra_index.iter().enumerate() {
        if g >= start && g < layout.row_index[c] {
            return match con_ids.get(c) {
                Some(&h) => Unknown::Abscissa { constraint: h.into() },
                None => Unknown::BeadAbscissa { bead: c - con_ids.len() },
            };
        }
    }
    for (c, &start) in layout.row_index.iter().enumerate() {
        if g >= start && g < start + layout.row_count[c] {
            if let Some(&h) = con_ids.get(c) {
                return Unknown::Multiplier { constraint: h.into(), row: g - start };
            }
        }
    }
    Unknown::Index { index: g }
}
