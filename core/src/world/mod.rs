//! The world: the data of a simulation — rods, constraints, loads, beads and
//! clips addressed by handles (Rapier-style sets), named groups, the
//! contact set, the integration parameters and the clock. It does no
//! stepping: [`crate::pipeline`] steps it (`World::step`, `World::relax`
//! are one-line conveniences defined there). Snapshots (serde, versioned)
//! reload bit-for-bit.
mod constraints;
mod energy;
pub(crate) mod independence;
pub mod events;
pub mod groups;
pub mod params;

pub use constraints::Constraint;
pub use energy::Energy;
pub use events::Event;
pub use groups::{Broken, ConstraintState, Groups, Item, Member, ObjectState};
pub use params::{IntegrationParameters, Scheme, Units};

use crate::bead::Bead;
use crate::clip::Clip;
use crate::contact::{ContactSet, Detector};
use crate::error::{Error, Result};
use crate::force::Load;
use crate::handles::{Arena, BeadHandle, ClipHandle, ConstraintHandle, Index, LoadHandle, RodHandle};
use crate::rod::Rod;
use crate::system::Workspace;
use serde::{Deserialize, Serialize};

/// Snapshot format name and version: `World::from_json` refuses anything else.
pub const SNAPSHOT_FORMAT: &str = "strandkit-world";
pub const SNAPSHOT_VERSION: u32 = 2;

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct World {
    pub(crate) rods: Arena<Rod>,
    pub(crate) constraints: Arena<Constraint>,
    pub(crate) loads: Arena<Load>,
    pub(crate) beads: Arena<Bead>,
    pub(crate) clips: Arena<Clip>,
    pub params: IntegrationParameters,
    pub(crate) time: f64,
    pub(crate) steps: u64,
    /// Energy growth of the current run of energy-creating steps (the
    /// divergence guard's memory; see `pipeline::solve::commit`).
    #[serde(default)]
    pub(crate) growth: Growth,
    /// Groups of rods whose control points are interleaved by parameter
    /// (a user override of the computed ordering).
    pub(crate) interleave: Vec<Vec<RodHandle>>,
    pub(crate) groups: Groups,
    pub(crate) contacts: ContactSet,
    /// Scratch of the pipeline (linear system, layout cache); not data.
    #[serde(skip)]
    pub(crate) ws: Workspace,
    /// Contact detectors run before each solve.
    #[serde(default)]
    pub(crate) detectors: Vec<Detector>,
    /// The thermal noise's random stream (its seed and position).
    #[serde(default)]
    pub(crate) noise: crate::force::thermal::Stream,
}

/// Consecutive dynamic steps that ended with more energy than they started
/// with plus the work done on them, and their combined growth factor.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct Growth {
    pub(crate) steps: u32,
    pub(crate) factor: f64,
}

/// The versioned envelope of a snapshot.
#[derive(Serialize)]
struct SnapshotOut<'a> {
    format: &'static str,
    version: u32,
    world: &'a World,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SnapshotIn {
    format: String,
    version: u32,
    world: World,
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

    /// Adds a rod; checks that its state is finite.
    pub fn add_rod(&mut self, rod: Rod) -> RodHandle {
        self.rods.insert(rod).into()
    }
    /// Removes a rod with its constraints, loads and beads (a clip holding
    /// it lets go).
    pub fn remove_rod(&mut self, h: RodHandle) -> Result<Rod> {
        let rod = self.rods.remove(h.into()).ok_or_else(|| bad_rod(h))?;
        let cs: Vec<_> = self.constraints.iter().filter(|(_, c)| c.rod == h || c.other == Some(h)).map(|(i, _)| i).collect();
        self.interleave.iter_mut().for_each(|g| g.retain(|r| *r != h));
        self.interleave.retain(|g| g.len() > 1);
        cs.into_iter().for_each(|i| drop(self.constraints.remove(i)));
        let ls: Vec<_> = self.loads.iter().filter(|(_, l)| l.rod() == h).map(|(i, _)| i).collect();
        ls.into_iter().for_each(|i| drop(self.loads.remove(i)));
        let bs: Vec<_> = self.beads.iter().filter(|(_, b)| b.rod == h).map(|(i, _)| i).collect();
        bs.into_iter().for_each(|i| drop(self.beads.remove(i)));
        self.contacts.pairs.retain(|p| !p.rods.contains(&h));
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
    pub fn n_rods(&self) -> usize {
        self.rods.len()
    }
    /// Live constraints in handle order.
    pub fn constraints(&self) -> impl Iterator<Item = (ConstraintHandle, &Constraint)> {
        self.constraints.iter().map(|(i, c)| (i.into(), c))
    }
    pub fn n_constraints(&self) -> usize {
        self.constraints.len()
    }
    /// Live loads in handle order.
    pub fn loads(&self) -> impl Iterator<Item = (LoadHandle, &Load)> {
        self.loads.iter().map(|(i, l)| (i.into(), l))
    }
    /// Live beads in handle order.
    pub fn beads(&self) -> impl Iterator<Item = (BeadHandle, &Bead)> {
        self.beads.iter().map(|(i, b)| (i.into(), b))
    }
    /// Clips in handle order.
    pub fn clips(&self) -> impl Iterator<Item = (ClipHandle, &Clip)> {
        self.clips.iter().map(|(i, c)| (i.into(), c))
    }
    /// The named groups of the world.
    pub fn groups(&self) -> &Groups {
        &self.groups
    }
    /// The contact pairs of the last solve.
    pub fn contacts(&self) -> &ContactSet {
        &self.contacts
    }
    /// The contact set, to add pairs by hand while no detector runs.
    pub fn contacts_mut(&mut self) -> &mut ContactSet {
        &mut self.contacts
    }
    /// Registers a contact detector ([`crate::contact::rods::RodContacts`],
    /// [`crate::contact::obstacle::Obstacle`]), run before every solve.
    pub fn add_contact_detector(&mut self, d: impl Into<Detector>) -> Result<()> {
        let d = d.into();
        d.validate()?;
        if let Detector::Rods(r) = &d {
            // The rods it names are in this world (a removed rod, or an
            // index the world never gave, is refused).
            r.rods_named().try_for_each(|h| self.rod(h).map(drop))?;
        }
        self.detectors.push(d);
        Ok(())
    }
    /// The active contacts of the last solve: rods, points, normals, forces.
    pub fn contact_report(&self) -> Result<Vec<crate::contact::ContactInfo>> {
        self.contacts.report(|h| self.rod(h))
    }
    /// The registered contact detectors, in the order they run.
    pub fn contact_detectors(&self) -> &[Detector] {
        &self.detectors
    }
    /// Removes every contact detector and the pairs they found.
    pub fn clear_contact_detectors(&mut self) {
        self.detectors.clear();
        self.contacts.pairs.clear();
    }

    /// Interleaves the control points of these rods in the band by their
    /// relative position along each rod (thesis IV.A). The ordering is
    /// otherwise computed (reverse Cuthill–McKee over linked rods), so this
    /// is only an override.
    pub fn interleave(&mut self, rods: &[RodHandle]) -> Result<()> {
        if rods.len() < 2 {
            return Err(Error::invalid("interleave rods", rods.len(), "at least two rods"));
        }
        for (k, r) in rods.iter().enumerate() {
            self.rod(*r)?;
            if rods[..k].contains(r) {
                return Err(Error::invalid("interleave rods", format!("rod {} twice", r.index), "distinct rods"));
            }
            if self.interleave.iter().any(|g| g.contains(r)) {
                return Err(Error::invalid("interleave rods", format!("rod {}", r.index), "a rod not already in an interleaved group"));
            }
        }
        self.interleave.push(rods.to_vec());
        Ok(())
    }

    /// Gives an object a label ("plank[3]"), making it a member of the group
    /// of its base name ("plank").
    pub fn set_label(&mut self, item: Item, label: &str) -> Result<()> {
        match item {
            Item::Rod(h) => drop(self.rod(h)?),
            Item::Constraint(h) => {
                self.constraint(h)?;
                if let Some(c) = self.constraints.get_mut(h.into()) {
                    groups::check_label(label)?;
                    c.label = Some(label.to_string());
                }
            }
            Item::Load(h) => drop(self.get_load(h)?),
            Item::Bead(h) => drop(self.bead(h)?),
            Item::Clip(h) => drop(self.clip(h)?),
        }
        self.groups.add(label, item)
    }

    pub fn add_load(&mut self, load: Load) -> Result<LoadHandle> {
        load.validate(self.rod(load.rod())?)?;
        Ok(self.loads.insert(load).into())
    }
    pub fn get_load(&self, h: LoadHandle) -> Result<&Load> {
        self.loads.get(h.into()).ok_or_else(|| bad_load(h))
    }
    pub fn set_load(&mut self, h: LoadHandle, load: Load) -> Result<()> {
        self.get_load(h)?;
        load.validate(self.rod(load.rod())?)?;
        *self.loads.get_mut(h.into()).ok_or_else(|| bad_load(h))? = load;
        Ok(())
    }
    pub fn remove_load(&mut self, h: LoadHandle) -> Result<Load> {
        self.loads.remove(h.into()).ok_or_else(|| bad_load(h))
    }

    /// Threads a bead on a rod at abscissa u: mass (> 0), viscous friction
    /// (force per unit sliding speed, ≥ 0), radius (length, ≥ 0: beads on
    /// one rod keep their centres r_a + r_b apart along it).
    pub fn add_bead(&mut self, rod: RodHandle, u: f64, mass: f64, friction: f64, radius: f64) -> Result<BeadHandle> {
        let b = Bead::new(rod, u, mass, friction, radius)?;
        b.validate(self.rod(rod)?)?;
        Ok(self.beads.insert(b).into())
    }
    pub fn bead(&self, h: BeadHandle) -> Result<&Bead> {
        self.beads.get(h.into()).ok_or_else(|| Error::handle(format!("bead {}", h.index)))
    }
    /// Takes a bead off its rod.
    pub fn remove_bead(&mut self, h: BeadHandle) -> Result<Bead> {
        self.beads.remove(h.into()).ok_or_else(|| Error::handle(format!("bead {}", h.index)))
    }
    /// Sets the external force on a bead (besides gravity; force unit).
    pub fn set_bead_force(&mut self, h: BeadHandle, force: [f64; 3]) -> Result<()> {
        crate::constraint::finite3(&force, "bead force")?;
        self.beads.get_mut(h.into()).ok_or_else(|| Error::handle(format!("bead {}", h.index)))?.force = force;
        Ok(())
    }
    /// Knots a bead at its abscissa (`true`) or lets it slide again.
    pub fn set_bead_fixed(&mut self, h: BeadHandle, fixed: bool) -> Result<()> {
        let b = self.beads.get_mut(h.into()).ok_or_else(|| Error::handle(format!("bead {}", h.index)))?;
        b.fixed = fixed;
        if fixed {
            b.velocity = 0.0;
            b.carried = None;
        }
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
        let c = Clip::new(center, radius, axis, resistance)?;
        Ok(self.clips.insert(c).into())
    }
    pub fn clip(&self, h: ClipHandle) -> Result<&Clip> {
        self.clips.get(h.into()).ok_or_else(|| Error::handle(format!("clip {}", h.index)))
    }

    /// Serialises the whole world (JSON, floats round-trip exactly) in the
    /// versioned snapshot envelope.
    pub fn to_json(&self) -> Result<String> {
        serde_json::to_string(&SnapshotOut { format: SNAPSHOT_FORMAT, version: SNAPSHOT_VERSION, world: self })
            .map_err(|e| Error::io("", format!("snapshot: {e}")))
    }
    /// A world from `to_json` text: the envelope's format and version are
    /// checked, then every rod is rebuilt and every object validated
    /// against the rods it refers to.
    pub fn from_json(s: &str) -> Result<World> {
        #[derive(Deserialize)]
        struct Envelope {
            format: Option<String>,
            version: Option<u32>,
        }
        let env: Envelope = serde_json::from_str(s).map_err(|e| Error::io("", format!("snapshot: not a strandkit snapshot ({e})")))?;
        match (env.format.as_deref(), env.version) {
            (Some(SNAPSHOT_FORMAT), Some(SNAPSHOT_VERSION)) => {}
            (Some(SNAPSHOT_FORMAT), v) => {
                return Err(Error::io("", format!("snapshot: version {v:?} is not supported (this build reads version {SNAPSHOT_VERSION})")))
            }
            _ => return Err(Error::io("", format!("snapshot: not a strandkit world snapshot (format {:?})", env.format))),
        }
        let snap: SnapshotIn = serde_json::from_str(s).map_err(|e| Error::io("", format!("snapshot: {e}")))?;
        debug_assert_eq!((snap.format.as_str(), snap.version), (SNAPSHOT_FORMAT, SNAPSHOT_VERSION));
        let mut w = snap.world;
        w.repair_after_load()?;
        Ok(w)
    }

    /// Rebuilds what is not serialised and validates everything that was.
    fn repair_after_load(&mut self) -> Result<()> {
        self.rods.repair()?;
        self.constraints.repair()?;
        self.loads.repair()?;
        self.beads.repair()?;
        self.clips.repair()?;
        self.params.validate()?;
        crate::error::finite("snapshot time", self.time)?;
        if !(self.growth.factor >= 0.0 && self.growth.factor.is_finite()) {
            return Err(Error::invalid("snapshot growth factor", self.growth.factor, "finite and ≥ 0"));
        }
        for (i, r) in self.rods.iter_mut() {
            r.restore().map_err(|e| e.context(format_args!("snapshot rod {}", i.0)))?;
        }
        for (i, c) in self.constraints.iter() {
            let rods = self.rods_of(c).map_err(|e| e.context(format_args!("snapshot constraint {}", i.0)))?;
            c.check(&rods).map_err(|e| e.context(format_args!("snapshot constraint {}", i.0)))?;
        }
        for (i, l) in self.loads.iter() {
            l.validate(self.rod(l.rod())?).map_err(|e| e.context(format_args!("snapshot load {}", i.0)))?;
        }
        for (i, b) in self.beads.iter() {
            b.validate(self.rod(b.rod)?).map_err(|e| e.context(format_args!("snapshot bead {}", i.0)))?;
        }
        for (i, c) in self.clips.iter() {
            c.validate().map_err(|e| e.context(format_args!("snapshot clip {}", i.0)))?;
            if let Some((r, con)) = c.held {
                self.rod(r)?;
                self.constraint(con)?;
            }
        }
        for g in &self.interleave {
            for r in g {
                self.rod(*r)?;
            }
        }
        for p in &self.contacts.pairs {
            let rods = [self.rod(p.rods[0])?, self.rod(p.rods[1])?];
            p.kind.validate(&rods)?;
            if let Some(f) = &p.friction {
                crate::contact::friction::check_mu(f.mu)?;
            }
        }
        for d in &self.detectors {
            d.validate().map_err(|e| e.context("snapshot contact detector"))?;
        }
        Ok(())
    }

    /// Writes a snapshot atomically (temporary file + rename).
    pub fn save(&self, path: &std::path::Path) -> Result<()> {
        crate::io::write_atomic(path, self.to_json()?.as_bytes())
    }
    /// Reads a snapshot written by [`World::save`] (at most 4 GiB).
    pub fn load(path: &std::path::Path) -> Result<World> {
        let meta = std::fs::metadata(path).map_err(|e| Error::io(path.display().to_string(), e))?;
        crate::error::size("snapshot file size (bytes)", meta.len() as usize, MAX_SNAPSHOT_BYTES)?;
        let s = std::fs::read_to_string(path).map_err(|e| Error::io(path.display().to_string(), e))?;
        World::from_json(&s).map_err(|e| match e {
            Error::Io { message, .. } => Error::Io { path: path.display().to_string(), message },
            other => other,
        })
    }
}

/// Largest snapshot file `World::load` reads (bytes).
pub const MAX_SNAPSHOT_BYTES: usize = 1 << 32;

/// The position of rod `h` in iteration order, from [`World::rod_positions`].
pub(crate) fn position_of(pos: &[Option<(u32, usize)>], h: RodHandle) -> Result<usize> {
    let i: Index = h.into();
    match pos.get(i.0 as usize) {
        Some(Some((g, k))) if *g == i.1 => Ok(*k),
        _ => Err(bad_rod(h)),
    }
}

pub(crate) fn bad_rod(h: RodHandle) -> Error {
    Error::handle(format!("rod {}", h.index))
}
pub(crate) fn bad_con(h: ConstraintHandle) -> Error {
    Error::handle(format!("constraint {}", h.index))
}
fn bad_load(h: LoadHandle) -> Error {
    Error::handle(format!("load {}", h.index))
}
