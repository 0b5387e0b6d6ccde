//! The world: rods, constraints and loads addressed by handles (Rapier-style
//! sets), one [`IntegrationParameters`], and `step` / `relax` returning
//! reports. Snapshots (serde) reload bit-for-bit.
use crate::constraint::{ConstraintKind, Reaction};
use crate::error::{Error, Result};
use crate::bead::Bead;
use crate::clip::Clip;
use crate::handles::{Arena, BeadHandle, ClipHandle, ConstraintHandle, LoadHandle, RodHandle};
use crate::integrator::{IntegrationParameters, Workspace};
use crate::load::Load;
use crate::rod::Rod;
use serde::{Deserialize, Serialize};

/// A constraint on one rod with its compliance (0 = hard; > 0: a spring of
/// stiffness 1/C) and the multipliers of the last solve (force/torque units).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Constraint {
    pub rod: RodHandle,
    /// Second rod of a relative constraint (None: the constraint is on `rod` only).
    #[serde(default)]
    pub other: Option<RodHandle>,
    pub kind: ConstraintKind,
    pub compliance: f64,
    pub multipliers: Vec<f64>,
    /// Force-threshold rupture (III.C.3, algorithm 5); None = unbreakable.
    pub breaking: Option<Breaking>,
}

/// A constraint breaks after a solve whose reaction exceeds `force` (force
/// unit): the magnitude of its reaction force, or with `tension_only` (1-row
/// distance links) the tension −Λ only, so compression never breaks it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Breaking {
    pub force: f64,
    pub tension_only: bool,
}

/// Something that happened during a solve.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Event {
    /// A constraint exceeded its break force and was removed.
    ConstraintBroken { constraint: ConstraintHandle, time: f64, force: f64, kind: ConstraintKind },
    /// A sliding constraint's abscissa left its rod; the constraint was removed.
    SliderLeft { constraint: ConstraintHandle, time: f64, kind: ConstraintKind },
    /// A bead slid off the end of its rod and was removed.
    BeadLeft { bead: BeadHandle, time: f64 },
    /// A clip captured a rod (position constraint `constraint` at abscissa u).
    ClipCaptured { clip: ClipHandle, rod: RodHandle, constraint: ConstraintHandle, u: f64, time: f64 },
    /// A clip released its rod: the pull-out force exceeded its resistance.
    ClipReleased { clip: ClipHandle, rod: RodHandle, force: f64, time: f64 },
    /// Material rupture (SPEC §6): `rod` was cut at abscissa `u` where its
    /// relative strain in `mode` passed `limit`. An open rod keeps the piece
    /// on [start, u] under its handle and the piece on [u, end] becomes
    /// `new_rod`; a ring is opened into one rod (new_rod None) whose abscissa
    /// s is the ring's u + s.
    RodRuptured {
        rod: RodHandle,
        new_rod: Option<RodHandle>,
        u: f64,
        time: f64,
        mode: crate::rod::StrainMode,
        strain: f64,
        limit: f64,
    },
}

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct World {
    pub(crate) rods: Arena<Rod>,
    pub(crate) constraints: Arena<Constraint>,
    pub(crate) loads: Arena<Load>,
    #[serde(default)]
    pub(crate) beads: Arena<Bead>,
    #[serde(default)]
    pub(crate) clips: Arena<Clip>,
    pub params: IntegrationParameters,
    pub(crate) time: f64,
    pub(crate) steps: u64,
    /// Groups of rods whose control points are interleaved in the band.
    #[serde(default)]
    pub(crate) interleave: Vec<Vec<RodHandle>>,
    #[serde(skip)]
    pub(crate) ws: Workspace,
}

impl World {
    pub fn new(params: IntegrationParameters) -> Self {
        World { params, ..Default::default() }
    }

    /// Simulated time (time unit).
    pub fn time(&self) -> f64 {
        self.time
    }
    pub fn n_steps(&self) -> u64 {
        self.steps
    }

    pub fn add_rod(&mut self, rod: Rod) -> RodHandle {
        self.rods.insert(rod).into()
    }
    /// Removes a rod with its constraints and loads.
    pub fn remove_rod(&mut self, h: RodHandle) -> Result<Rod> {
        let rod = self.rods.remove(h.into()).ok_or_else(|| bad_rod(h))?;
        let cs: Vec<_> =
            self.constraints.iter().filter(|(_, c)| c.rod == h || c.other == Some(h)).map(|(i, _)| i).collect();
        self.interleave.iter_mut().for_each(|g| g.retain(|r| *r != h));
        cs.into_iter().for_each(|i| drop(self.constraints.remove(i)));
        let ls: Vec<_> = self.loads.iter().filter(|(_, l)| l.rod() == h).map(|(i, _)| i).collect();
        ls.into_iter().for_each(|i| drop(self.loads.remove(i)));
        let bs: Vec<_> = self.beads.iter().filter(|(_, b)| b.rod == h).map(|(i, _)| i).collect();
        bs.into_iter().for_each(|i| drop(self.beads.remove(i)));
        Ok(rod)
    }
    pub fn rod(&self, h: RodHandle) -> Result<&Rod> {
        self.rods.get(h.into()).ok_or_else(|| bad_rod(h))
    }
    pub fn rod_mut(&mut self, h: RodHandle) -> Result<&mut Rod> {
        self.rods.get_mut(h.into()).ok_or_else(|| bad_rod(h))
    }
    pub fn rods(&self) -> impl Iterator<Item = (RodHandle, &Rod)> {
        self.rods.iter().map(|(i, r)| (i.into(), r))
    }
    /// Live constraints in handle order.
    pub fn constraints(&self) -> impl Iterator<Item = (ConstraintHandle, &Constraint)> {
        self.constraints.iter().map(|(i, c)| (i.into(), c))
    }
    /// Live beads in handle order.
    pub fn beads(&self) -> impl Iterator<Item = (BeadHandle, &Bead)> {
        self.beads.iter().map(|(i, b)| (i.into(), b))
    }
    /// Clips in handle order.
    pub fn clips(&self) -> impl Iterator<Item = (ClipHandle, &Clip)> {
        self.clips.iter().map(|(i, c)| (i.into(), c))
    }

    /// Adds a hard (compliance 0) or compliant one-rod constraint. Errors:
    /// removed rod, abscissa outside the rod, non-finite target, duplicate,
    /// linearly dependent on the rod's other constraints.
    pub fn add_constraint(&mut self, rod: RodHandle, kind: ConstraintKind, compliance: f64) -> Result<ConstraintHandle> {
        if kind.n_rods() != 1 {
            return Err(Error::input(format!("{kind:?} links two points: use add_link")));
        }
        self.insert_constraint(rod, None, kind, compliance)
    }

    /// Adds a relative constraint between rod `a` (abscissa ua) and rod `b`
    /// (ub); `a` and `b` may be the same rod.
    pub fn add_link(&mut self, a: RodHandle, b: RodHandle, kind: ConstraintKind, compliance: f64) -> Result<ConstraintHandle> {
        if kind.n_rods() != 2 {
            return Err(Error::input(format!("{kind:?} is a one-rod constraint: use add_constraint")));
        }
        self.insert_constraint(a, Some(b), kind, compliance)
    }

    /// Coplanar relative clamp between rod a at ua and rod b at ub (III.61):
    /// α0, α1 are solved from the current geometry, r_a − r_b = α0 r_a' +
    /// α1 r_b'. Errors when the tangents are parallel or the link is not in
    /// their plane (the thesis' restriction).
    pub fn add_coplanar_clamp(&mut self, a: RodHandle, ua: f64, b: RodHandle, ub: f64, compliance: f64) -> Result<ConstraintHandle> {
        let v3 = |d: [f64; 4]| nalgebra::Vector3::new(d[0], d[1], d[2]);
        let (ra, rb) = (self.rod(a)?, self.rod(b)?);
        let d = v3(ra.eval(ua, 0)?) - v3(rb.eval(ub, 0)?);
        let (ta, tb) = (v3(ra.eval(ua, 1)?), v3(rb.eval(ub, 1)?));
        let m = nalgebra::Matrix3x2::from_columns(&[ta, tb]);
        let mtm = m.transpose() * m;
        let inv = mtm.try_inverse().filter(|_| ta.cross(&tb).norm() > 1e-9 * ta.norm() * tb.norm()).ok_or_else(|| {
            Error::input("coplanar clamp: the two tangents are parallel (use RelativePosition + RelativeOrientation)")
        })?;
        let alpha = inv * (m.transpose() * d);
        if (m * alpha - d).norm() > 1e-9 * d.norm().max(1e-300) {
            return Err(Error::input("coplanar clamp: the link is not in the plane of the two tangents"));
        }
        self.add_link(a, b, ConstraintKind::CoplanarClamp { ua, ub, alpha: [alpha[0], alpha[1]] }, compliance)
    }

    /// Interleaves the control points of these rods in the band (thesis
    /// IV.A: linked rods, e.g. the two strands of a helix, alternate), so a
    /// dense set of links between them keeps a narrow band.
    pub fn interleave(&mut self, rods: &[RodHandle]) -> Result<()> {
        for r in rods {
            self.rod(*r)?;
            if self.interleave.iter().any(|g| g.contains(r)) {
                return Err(Error::input(format!("rod {r:?} is already in an interleaved group")));
            }
        }
        self.interleave.push(rods.to_vec());
        Ok(())
    }

    /// The rods a constraint acts on (the first twice for one-rod kinds).
    pub(crate) fn rods_of(&self, c: &Constraint) -> Result<[&Rod; 2]> {
        let a = self.rod(c.rod)?;
        Ok([a, c.other.map_or(Ok(a), |b| self.rod(b))?])
    }

    fn insert_constraint(
        &mut self,
        rod: RodHandle,
        other: Option<RodHandle>,
        kind: ConstraintKind,
        compliance: f64,
    ) -> Result<ConstraintHandle> {
        let probe = Constraint { rod, other, kind, compliance, multipliers: Vec::new(), breaking: None };
        probe.kind.validate(&self.rods_of(&probe)?)?;
        crate::error::non_negative("compliance", compliance)?;
        let kind = probe.kind;
        for (h, c) in self.constraints.iter() {
            if c.rod == rod && c.other == other && duplicates(&c.kind, &kind) {
                return Err(Error::input(format!(
                    "duplicate constraint: {kind:?} repeats constraint {} on the same rod at the same abscissa",
                    h.0
                )));
            }
        }
        let n = kind.n_rows();
        let c = Constraint { rod, other, kind, compliance, multipliers: vec![0.0; n], breaking: None };
        self.check_independent(&c)?;
        Ok(self.constraints.insert(c).into())
    }

    /// Rejects a constraint whose rows are linearly dependent (at the current
    /// configuration) on the rows already imposed on the same rods: redundant
    /// rows leave the multipliers undefined and contradictory ones have no
    /// solution (SPEC §5). Modified Gram–Schmidt on the rows, dense over the
    /// coordinates of the rods involved.
    fn check_independent(&self, new: &Constraint) -> Result<()> {
        let involved = |c: &Constraint| [Some(c.rod), c.other].into_iter().flatten().collect::<Vec<_>>();
        let mine = involved(new);
        let related: Vec<_> =
            self.constraints.iter().filter(|(_, c)| involved(c).iter().any(|r| mine.contains(r))).collect();
        // Coordinate offsets of every rod touched.
        let mut rods: Vec<RodHandle> = mine.clone();
        for (_, c) in &related {
            for r in involved(c) {
                if !rods.contains(&r) {
                    rods.push(r);
                }
            }
        }
        let mut offset = Vec::with_capacity(rods.len());
        let mut n = 0;
        for r in &rods {
            offset.push(n);
            n += self.rod(*r)?.coords().len();
        }
        let at = |h: RodHandle| offset[rods.iter().position(|r| *r == h).unwrap_or(0)]; // every rod is in `rods`
        let mut buf = [crate::constraint::Row::default(); crate::constraint::MAX_ROWS];
        let mut dense = |c: &Constraint| -> Result<Vec<Vec<f64>>> {
            let nr = c.kind.n_rows();
            c.kind.linearize(&self.rods_of(c)?, &mut buf[..nr])?;
            let base = [at(c.rod), at(c.other.unwrap_or(c.rod))];
            Ok(buf[..nr]
                .iter()
                .map(|row| {
                    let mut v = vec![0.0; n];
                    // (entries on a slider's own abscissa unknown, w = 2, are private to it)
                    row.entries().iter().filter(|e| e.0 < 2).for_each(|&(w, i, x)| v[base[w as usize] + i] += x);
                    v
                })
                .collect())
        };
        let mut basis: Vec<Vec<f64>> = Vec::new();
        let mut owners = Vec::new();
        let add = |mut v: Vec<f64>, basis: &mut Vec<Vec<f64>>| -> bool {
            let n0 = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            for b in basis.iter() {
                let c: f64 = b.iter().zip(&v).map(|(a, b)| a * b).sum();
                v.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
            }
            let n1 = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            if n1 <= 1e-9 * n0 {
                return false;
            }
            basis.push(v.into_iter().map(|x| x / n1).collect());
            true
        };
        for (h, c) in &related {
            for row in dense(c)? {
                if add(row, &mut basis) {
                    owners.push(h.0);
                }
            }
        }
        for row in dense(new)? {
            if !add(row, &mut basis) {
                owners.sort_unstable();
                owners.dedup();
                return Err(Error::input(format!(
                    "linearly dependent constraint: {:?} repeats what constraints {owners:?} on the same rods already impose (redundant rows leave the forces undefined; contradictory ones have no solution)",
                    new.kind
                )));
            }
        }
        Ok(())
    }
    pub fn remove_constraint(&mut self, h: ConstraintHandle) -> Result<Constraint> {
        self.constraints.remove(h.into()).ok_or_else(|| bad_con(h))
    }
    pub fn constraint(&self, h: ConstraintHandle) -> Result<&Constraint> {
        self.constraints.get(h.into()).ok_or_else(|| bad_con(h))
    }
    /// Replaces a constraint's kind (moving targets: how a user drags,
    /// rotates or pulls). The new kind must have the same rows.
    pub fn set_constraint(&mut self, h: ConstraintHandle, kind: ConstraintKind) -> Result<()> {
        let probe = Constraint { kind, ..self.constraint(h)?.clone() };
        probe.kind.validate(&self.rods_of(&probe)?)?;
        let kind = probe.kind;
        let c = self.constraints.get_mut(h.into()).ok_or_else(|| bad_con(h))?;
        if kind.n_rows() != c.kind.n_rows() || std::mem::discriminant(&kind) != std::mem::discriminant(&c.kind) {
            return Err(Error::input("set_constraint: the new constraint must be of the same kind and rows"));
        }
        c.kind = kind;
        Ok(())
    }
    /// Makes a constraint breakable (None: unbreakable again).
    pub fn set_breaking(&mut self, h: ConstraintHandle, breaking: Option<Breaking>) -> Result<()> {
        let c = self.constraints.get_mut(h.into()).ok_or_else(|| bad_con(h))?;
        if let Some(b) = breaking {
            crate::error::positive("break force", b.force)?;
            if b.tension_only
                && !matches!(c.kind, ConstraintKind::Distance { .. } | ConstraintKind::RelativeDistance { .. } | ConstraintKind::Contact { .. })
            {
                return Err(Error::input("tension-only breaking applies to distance links; use tension_only = false"));
            }
        }
        c.breaking = breaking;
        Ok(())
    }

    /// Removes the constraints whose last reaction exceeds their break
    /// force (algorithm 5) and reports them.
    pub(crate) fn break_constraints(&mut self) -> Result<Vec<Event>> {
        let mut broken = Vec::new();
        for (h, c) in self.constraints.iter() {
            let Some(b) = c.breaking else { continue };
            let f = if b.tension_only {
                -c.multipliers[0]
            } else {
                let r = c.kind.reaction(&self.rods_of(c)?, &c.multipliers)?;
                nalgebra::Vector3::from(r.force).norm()
            };
            if f > b.force {
                broken.push((h, f));
            }
        }
        let mut events = Vec::with_capacity(broken.len());
        for (h, force) in broken {
            if let Some(c) = self.constraints.remove(h) {
                events.push(Event::ConstraintBroken { constraint: h.into(), time: self.time, force, kind: c.kind });
            }
        }
        Ok(events)
    }

    /// Force and torque the constraint exerted on its rod in the last solve.
    pub fn reaction(&self, h: ConstraintHandle) -> Result<Reaction> {
        let c = self.constraint(h)?;
        c.kind.reaction(&self.rods_of(c)?, &c.multipliers)
    }

    pub fn add_load(&mut self, load: Load) -> Result<LoadHandle> {
        self.check_load(&load)?;
        Ok(self.loads.insert(load).into())
    }
    pub fn set_load(&mut self, h: LoadHandle, load: Load) -> Result<()> {
        self.check_load(&load)?;
        *self.loads.get_mut(h.into()).ok_or_else(|| bad_load(h))? = load;
        Ok(())
    }
    pub fn remove_load(&mut self, h: LoadHandle) -> Result<Load> {
        self.loads.remove(h.into()).ok_or_else(|| bad_load(h))
    }

    fn check_load(&self, load: &Load) -> Result<()> {
        let rod = self.rod(load.rod())?;
        let fin = |v: &[f64]| -> Result<()> {
            for x in v {
                crate::error::finite("load value", *x)?;
            }
            Ok(())
        };
        match load {
            Load::PointForce { u, force, .. } => {
                rod.knots().locate(*u)?;
                fin(force)
            }
            Load::PointTorque { u, torque, .. } => {
                rod.knots().locate(*u)?;
                if rod.dofs() == 3 {
                    return Err(Error::input("point torque on a rod without roll coordinate"));
                }
                fin(&[*torque])
            }
            Load::Distributed { force_per_length, .. } => fin(force_per_length),
        }
    }

    /// Threads a bead on a rod at abscissa u: mass (> 0), viscous friction
    /// (force per unit sliding speed, ≥ 0), radius (length, ≥ 0: beads on
    /// one rod keep their centres r_a + r_b apart along it).
    pub fn add_bead(&mut self, rod: RodHandle, u: f64, mass: f64, friction: f64, radius: f64) -> Result<BeadHandle> {
        self.rod(rod)?.knots().locate(crate::error::finite("bead abscissa u", u)?)?;
        crate::error::positive("bead mass", mass)?;
        crate::error::non_negative("bead friction", friction)?;
        crate::error::non_negative("bead radius", radius)?;
        let b = Bead { rod, u, velocity: 0.0, mass, friction, radius, force: [0.0; 3], step_ds: 0.0, rod_force: [0.0; 3], u_assembled: u };
        Ok(self.beads.insert(b).into())
    }
    pub fn bead(&self, h: BeadHandle) -> Result<&Bead> {
        self.beads.get(h.into()).ok_or_else(|| Error::handle(format!("bead {h:?} does not exist (removed?)")))
    }
    /// Takes a bead off its rod.
    pub fn remove_bead(&mut self, h: BeadHandle) -> Result<Bead> {
        self.beads.remove(h.into()).ok_or_else(|| Error::handle(format!("bead {h:?} does not exist (removed?)")))
    }
    /// Sets the external force on a bead (besides gravity; force unit).
    pub fn set_bead_force(&mut self, h: BeadHandle, force: [f64; 3]) -> Result<()> {
        crate::constraint::finite3(&force, "bead force")?;
        self.beads.get_mut(h.into()).ok_or_else(|| Error::handle(format!("bead {h:?} does not exist")))?.force = force;
        Ok(())
    }
    /// Position of a bead (length unit).
    pub fn bead_position(&self, h: BeadHandle) -> Result<nalgebra::Vector3<f64>> {
        let b = self.bead(h)?;
        self.rod(b.rod)?.position(b.u)
    }

    /// Adds a clip: capture sphere (centre, radius > 0), exit axis (non-zero)
    /// and pull-out resistance (> 0, force unit). Captures happen after
    /// solves (`step`, `relax`), reported as events.
    pub fn add_clip(&mut self, center: [f64; 3], radius: f64, axis: [f64; 3], resistance: f64) -> Result<ClipHandle> {
        crate::constraint::finite3(&center, "clip centre")?;
        crate::error::positive("clip radius", radius)?;
        let a = crate::constraint::unit(&axis, "clip exit axis")?;
        crate::error::positive("clip resistance", resistance)?;
        let c = Clip { center, radius, axis: a.into(), resistance, held: None, disarmed: false };
        Ok(self.clips.insert(c).into())
    }
    pub fn clip(&self, h: ClipHandle) -> Result<&Clip> {
        self.clips.get(h.into()).ok_or_else(|| Error::handle(format!("clip {h:?} does not exist")))
    }

    /// Algorithms 4–5: release held rods pulled out harder than the clip's
    /// resistance, capture rods that entered an armed clip.
    pub(crate) fn update_clips(&mut self) -> Result<Vec<Event>> {
        let mut events = Vec::new();
        let ids: Vec<_> = self.clips.iter().map(|(i, _)| i).collect();
        for i in ids {
            let Some(clip) = self.clips.get(i).cloned() else { continue };
            let axis = nalgebra::Vector3::from(clip.axis);
            if let Some((rod, con)) = clip.held {
                // Force of the clip on the rod along −axis = pull-out force.
                let pull = match self.reaction(con) {
                    Ok(r) => -nalgebra::Vector3::from(r.force).dot(&axis),
                    Err(_) => 0.0, // the constraint was removed (rod removed, broken)
                };
                if self.constraint(con).is_err() || pull > clip.resistance {
                    let _ = self.remove_constraint(con);
                    if let Some(c) = self.clips.get_mut(i) {
                        c.held = None;
                        c.disarmed = true;
                    }
                    events.push(Event::ClipReleased { clip: i.into(), rod, force: pull, time: self.time });
                }
                continue;
            }
            // Closest sample of every rod to the centre.
            let centre = nalgebra::Vector3::from(clip.center);
            let mut best: Option<(RodHandle, f64, f64)> = None;
            for (h, rod) in self.rods() {
                for (u, p) in rod.sample_params().into_iter().zip(rod.sample_points()) {
                    let d = (p - centre).norm();
                    if d <= clip.radius && best.is_none_or(|b| d < b.2) {
                        best = Some((h, u, d));
                    }
                }
            }
            match best {
                None => {
                    if let Some(c) = self.clips.get_mut(i) {
                        c.disarmed = false;
                    }
                }
                Some((rod, u, _)) if !clip.disarmed => {
                    let u = closest_abscissa(self.rod(rod)?, centre, u)?;
                    let kind = ConstraintKind::Position { u, axes: [true, true, true, false], target: [clip.center[0], clip.center[1], clip.center[2], 0.0] };
                    if let Ok(con) = self.add_constraint(rod, kind, 0.0) {
                        if let Some(c) = self.clips.get_mut(i) {
                            c.held = Some((rod, con));
                        }
                        events.push(Event::ClipCaptured { clip: i.into(), rod, constraint: con, u, time: self.time });
                    }
                }
                _ => {}
            }
        }
        Ok(events)
    }

    /// Serialises the whole world (JSON, floats round-trip exactly).
    pub fn to_json(&self) -> Result<String> {
        serde_json::to_string(self).map_err(|e| Error::io("", e.to_string()))
    }
    pub fn from_json(s: &str) -> Result<World> {
        let mut w: World = serde_json::from_str(s).map_err(|e| Error::io("", format!("snapshot: {e}")))?;
        for (_, r) in w.rods.iter_mut() {
            r.prepare()?;
        }
        Ok(w)
    }
    /// Writes a snapshot atomically (temporary file + rename).
    pub fn save(&self, path: &std::path::Path) -> Result<()> {
        crate::io::write_atomic(path, self.to_json()?.as_bytes())
    }
    pub fn load(path: &std::path::Path) -> Result<World> {
        let s = std::fs::read_to_string(path).map_err(|e| Error::io(path.display().to_string(), format!("{e}")))?;
        World::from_json(&s)
    }
}

/// Abscissa of the point of `rod` closest to `p`, by Newton from `u`.
fn closest_abscissa(rod: &Rod, p: nalgebra::Vector3<f64>, mut u: f64) -> Result<f64> {
    let (lo, hi) = rod.domain();
    for _ in 0..20 {
        let (r, d1, d2) = (rod.eval(u, 0)?, rod.eval(u, 1)?, rod.eval(u, 2)?);
        let v = nalgebra::Vector3::new(r[0], r[1], r[2]) - p;
        let (t, c) = (nalgebra::Vector3::new(d1[0], d1[1], d1[2]), nalgebra::Vector3::new(d2[0], d2[1], d2[2]));
        let h = t.dot(&t) + v.dot(&c);
        if !(h > 0.0) {
            break;
        }
        let du = v.dot(&t) / h;
        u = (u - du).clamp(lo, hi);
        if du.abs() < 1e-14 * (1.0 + u.abs()) {
            break;
        }
    }
    Ok(u)
}

fn duplicates(a: &ConstraintKind, b: &ConstraintKind) -> bool {
    use ConstraintKind::*;
    if (a.u() - b.u()).abs() > 1e-12 * (1.0 + a.u().abs()) {
        return false;
    }
    let same_b = |x: f64, y: f64| (x - y).abs() <= 1e-12 * (1.0 + x.abs());
    if let (Some((_, ub1)), Some((_, ub2))) = (crate::constraint::relative::abscissae(a), crate::constraint::relative::abscissae(b)) {
        if !same_b(ub1, ub2) {
            return false;
        }
    }
    match (a, b) {
        (Position { axes: x, .. }, Position { axes: y, .. }) => x.iter().zip(y).any(|(p, q)| *p && *q),
        (Tangent { .. }, Tangent { .. })
        | (MaterialRoll { .. }, MaterialRoll { .. })
        | (Curvature { .. }, Curvature { .. })
        | (Axis { .. }, Axis { .. })
        | (RelativeOrientation { .. }, RelativeOrientation { .. })
        | (RelativeDistance { .. }, RelativeDistance { .. })
        | (Contact { .. }, Contact { .. })
        | (OrientedSlidingPoint { .. }, OrientedSlidingPoint { .. })
        | (SlidingPoint { .. }, SlidingPoint { .. })
        | (CoplanarClamp { .. }, CoplanarClamp { .. }) => true,
        (RelativePosition { axes: x, .. }, RelativePosition { axes: y, .. }) => x.iter().zip(y).any(|(p, q)| *p && *q),
        _ => false,
    }
}

fn bad_rod(h: RodHandle) -> Error {
    Error::handle(format!("rod {h:?} does not exist (removed?)"))
}
fn bad_con(h: ConstraintHandle) -> Error {
    Error::handle(format!("constraint {h:?} does not exist (removed?)"))
}
fn bad_load(h: LoadHandle) -> Error {
    Error::handle(format!("load {h:?} does not exist (removed?)"))
}
