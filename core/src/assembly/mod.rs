//! An [`Assembly`] describes a structure (SPEC §9.0): rods (rest shape,
//! section, material, frame model), beads, constraints (with compliance
//! and break thresholds), loads and named labels, referring to its own rods
//! by index. Builders return one; [`World::insert`] adds it in one batch —
//! everything checked first, the dependency check run once on the sparse
//! structure, nothing added on any error — in time linear in its size, and
//! returns the handles. An Assembly written to JSON and read back is the
//! same Assembly.
use crate::bead::Bead;
use crate::constraint::{BreakPolicy, Breaking, ConstraintKind};
use crate::error::{Error, Result};
use crate::force::Load;
use crate::clip::Clip;
use crate::handles::{BeadHandle, ClipHandle, ConstraintHandle, LoadHandle, RodHandle};
use crate::rod::Rod;
use crate::world::{Constraint, Item, World};
use serde::{Deserialize, Serialize};

/// Documented caps on what an Assembly may hold (checked before anything
/// is allocated for it).
pub const MAX_RODS: usize = 1_000_000;
pub const MAX_CONSTRAINTS: usize = 10_000_000;

#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AssemblyRod {
    pub rod: Rod,
    #[serde(default)]
    pub label: Option<String>,
}

/// A constraint between the assembly's rods `rods[0]` (and `rods[1]` for a
/// relative kind).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AssemblyConstraint {
    pub rod: usize,
    #[serde(default)]
    pub other: Option<usize>,
    pub kind: ConstraintKind,
    #[serde(default)]
    pub compliance: f64,
    #[serde(default)]
    pub breaking: Option<Breaking>,
    #[serde(default)]
    pub label: Option<String>,
    /// Labels of constraints whose breaking removes this one too.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub breaks_with: Vec<String>,
    /// Labels of constraints whose breaking under their own load removes
    /// this one too (not their removal with a third one).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fails_with: Vec<String>,
    /// Compliant, held at the step's end under the trapezoidal rule
    /// instead of averaged ([`crate::world::Constraint::held_at_end`]).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub held_at_end: bool,
}

impl AssemblyConstraint {
    /// Compliance C (length/force; 0 = hard).
    pub fn compliance(&mut self, c: f64) -> &mut Self {
        self.compliance = c;
        self
    }
    /// Breaks above `force` measured by `policy`.
    pub fn breaks(&mut self, force: f64, policy: BreakPolicy) -> &mut Self {
        self.breaking = Some(Breaking::new(force, policy));
        self
    }
    pub fn label(&mut self, label: impl Into<String>) -> &mut Self {
        self.label = Some(label.into());
        self
    }
    /// Held at the step's end under the trapezoidal rule instead of
    /// averaged (a compliant constraint; see `Constraint::held_at_end`).
    pub fn held_at_end(&mut self, held: bool) -> &mut Self {
        self.held_at_end = held;
        self
    }
    /// Removed when the constraint labelled `label` breaks.
    pub fn breaks_with(&mut self, label: impl Into<String>) -> &mut Self {
        self.breaks_with.push(label.into());
        self
    }
    /// Removed when the constraint labelled `label` breaks under its own
    /// load — not when it only goes with another (see [`Self::breaks_with`]).
    pub fn fails_with(&mut self, label: impl Into<String>) -> &mut Self {
        self.fails_with.push(label.into());
        self
    }
}

/// A load on one of the assembly's rods: the load's own rod handle is
/// replaced by the handle of `rods[rod]` at insertion.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AssemblyLoad {
    pub rod: usize,
    pub load: Load,
    #[serde(default)]
    pub label: Option<String>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AssemblyBead {
    pub rod: usize,
    /// Abscissa (spline parameter) on the rod.
    pub u: f64,
    /// Mass (mass unit), viscous friction (force per speed), radius (length).
    pub mass: f64,
    #[serde(default)]
    pub friction: f64,
    #[serde(default)]
    pub radius: f64,
    /// Knotted at `u`: it does not slide.
    #[serde(default)]
    pub fixed: bool,
    #[serde(default)]
    pub label: Option<String>,
}

/// A clip (capture sphere with an exit axis, see [`crate::Clip`]); it
/// captures whichever rod enters it after the first solve, or is inserted
/// already holding one (`holds`, see [`Assembly::hold_in_clip`]).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AssemblyClip {
    /// Centre (length), capture radius (length), exit axis, pull-out resistance (force).
    pub center: [f64; 3],
    pub radius: f64,
    pub axis: [f64; 3],
    pub resistance: f64,
    #[serde(default)]
    pub label: Option<String>,
    /// The assembly constraint (a one-rod `Position`) by which the clip
    /// holds its rod from the start.
    #[serde(default)]
    pub holds: Option<usize>,
}

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Assembly {
    pub rods: Vec<AssemblyRod>,
    #[serde(default)]
    pub constraints: Vec<AssemblyConstraint>,
    #[serde(default)]
    pub loads: Vec<AssemblyLoad>,
    #[serde(default)]
    pub beads: Vec<AssemblyBead>,
    #[serde(default)]
    pub clips: Vec<AssemblyClip>,
}

/// Handles of what `World::insert` added, in the assembly's order, and the
/// half-bandwidth of the world's system afterwards.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Inserted {
    pub rods: Vec<RodHandle>,
    pub constraints: Vec<ConstraintHandle>,
    pub loads: Vec<LoadHandle>,
    pub beads: Vec<BeadHandle>,
    #[serde(default)]
    pub clips: Vec<ClipHandle>,
    pub bandwidth: usize,
}

impl Assembly {
    pub fn new() -> Self {
        Self::default()
    }
    /// Adds a rod; returns its index in the assembly.
    pub fn add_rod(&mut self, rod: Rod, label: Option<&str>) -> usize {
        self.rods.push(AssemblyRod { rod, label: label.map(str::to_string) });
        self.rods.len() - 1
    }
    /// A one-rod constraint on rod `rod` (hard, unbreakable, unlabelled until set).
    pub fn constrain(&mut self, rod: usize, kind: impl Into<ConstraintKind>) -> &mut AssemblyConstraint {
        self.constraints.push(AssemblyConstraint { rod, other: None, kind: kind.into(), compliance: 0.0, breaking: None, label: None, breaks_with: Vec::new(), fails_with: Vec::new(), held_at_end: false });
        let n = self.constraints.len() - 1;
        &mut self.constraints[n]
    }
    /// A relative constraint between rods `a` and `b`.
    pub fn link(&mut self, a: usize, b: usize, kind: impl Into<ConstraintKind>) -> &mut AssemblyConstraint {
        self.constraints.push(AssemblyConstraint { rod: a, other: Some(b), kind: kind.into(), compliance: 0.0, breaking: None, label: None, breaks_with: Vec::new(), fails_with: Vec::new(), held_at_end: false });
        let n = self.constraints.len() - 1;
        &mut self.constraints[n]
    }
    /// Clamps rod `rod` at `u` where it now is (see
    /// [`crate::constraint::clamp_kinds`]), every constraint labelled
    /// `label`; returns their indices.
    pub fn clamp(&mut self, rod: usize, u: f64, label: Option<&str>) -> Result<Vec<usize>> {
        let r = &self.rods.get(rod).ok_or_else(|| Error::invalid("assembly clamp rod", rod, format!("< {} (the assembly's rods)", self.rods.len())))?.rod;
        let kinds = crate::constraint::clamp_kinds(r, u)?;
        Ok(kinds.into_iter().map(|k| {
            let c = self.constrain(rod, k);
            c.label = label.map(str::to_string);
            self.constraints.len() - 1
        }).collect())
    }
    pub fn add_load(&mut self, rod: usize, load: impl Into<Load>, label: Option<&str>) -> usize {
        self.loads.push(AssemblyLoad { rod, load: load.into(), label: label.map(str::to_string) });
        self.loads.len() - 1
    }
    pub fn add_bead(&mut self, rod: usize, u: f64, mass: f64, friction: f64, radius: f64, label: Option<&str>) -> usize {
        self.beads.push(AssemblyBead { rod, u, mass, friction, radius, fixed: false, label: label.map(str::to_string) });
        self.beads.len() - 1
    }
    /// Adds a clip (centre, capture radius, exit axis, resistance); returns its index.
    pub fn add_clip(&mut self, center: [f64; 3], radius: f64, axis: [f64; 3], resistance: f64, label: Option<&str>) -> usize {
        self.clips.push(AssemblyClip { center, radius, axis, resistance, label: label.map(str::to_string), holds: None });
        self.clips.len() - 1
    }
    /// Clip `clip` holds rod `rod` at `u` from the start: a `Position`
    /// constraint pulling r(u) to the clip's centre (labelled as the clip),
    /// released by the clip like a captured rod. Returns its index.
    pub fn hold_in_clip(&mut self, clip: usize, rod: usize, u: f64) -> Result<usize> {
        let c = self.clips.get(clip).ok_or_else(|| Error::invalid("clip", clip, format!("< {} (the assembly's clips)", self.clips.len())))?;
        let (x, label) = (c.center, c.label.clone());
        let kind = crate::constraint::kinds::Position { u, axes: [true, true, true, false], target: [x[0], x[1], x[2], 0.0] };
        let con = self.constrain(rod, kind);
        con.label = label;
        let k = self.constraints.len() - 1;
        self.clips[clip].holds = Some(k);
        Ok(k)
    }
    /// Every label of the assembly (for a quick look at its groups).
    pub fn labels(&self) -> impl Iterator<Item = &str> {
        let r = self.rods.iter().filter_map(|x| x.label.as_deref());
        let c = self.constraints.iter().filter_map(|x| x.label.as_deref());
        let l = self.loads.iter().filter_map(|x| x.label.as_deref());
        let b = self.beads.iter().filter_map(|x| x.label.as_deref());
        let k = self.clips.iter().filter_map(|x| x.label.as_deref());
        r.chain(c).chain(l).chain(b).chain(k)
    }
    pub fn to_json(&self) -> Result<String> {
        serde_json::to_string(self).map_err(|e| Error::io("", format!("assembly: {e}")))
    }
    /// Reads an assembly and rebuilds its rods (checked like a snapshot's).
    pub fn from_json(s: &str) -> Result<Assembly> {
        let mut a: Assembly = serde_json::from_str(s).map_err(|e| Error::io("", format!("assembly: {e}")))?;
        for (i, r) in a.rods.iter_mut().enumerate() {
            r.rod.restore().map_err(|e| e.context(format_args!("assembly rod {i}")))?;
        }
        Ok(a)
    }

    fn rod_index(&self, what: &str, i: usize) -> Result<usize> {
        if i < self.rods.len() {
            Ok(i)
        } else {
            Err(Error::invalid(what, i, format!("an index of the assembly's rods (0..{})", self.rods.len())))
        }
    }
}

impl World {
    /// Adds an assembly in one batch and returns the handles of everything
    /// it added. Every part is checked before anything is added (rod
    /// indices, constraint kinds against their rods, duplicates, linear
    /// dependence — once, on the sparse structure —, loads, beads, labels);
    /// on any error the world is unchanged.
    pub fn insert(&mut self, asm: &Assembly) -> Result<Inserted> {
        crate::error::size("assembly rods", asm.rods.len(), MAX_RODS)?;
        crate::error::size("assembly constraints", asm.constraints.len(), MAX_CONSTRAINTS)?;
        // 1. Everything that does not need the world.
        for (i, r) in asm.rods.iter().enumerate() {
            r.rod.check_state().map_err(|e| e.context(format_args!("assembly rod {i}")))?;
            if let Some(l) = &r.label {
                crate::world::groups::check_label(l)?;
            }
        }
        for (i, c) in asm.constraints.iter().enumerate() {
            let ctx = |e: Error| e.context(format_args!("assembly constraint {i}"));
            let a = asm.rod_index("constraint rod", c.rod).map_err(ctx)?;
            let b = c.other.map(|o| asm.rod_index("constraint other rod", o)).transpose().map_err(ctx)?;
            let rods = [&asm.rods[a].rod, &asm.rods[b.unwrap_or(a)].rod];
            let probe = Constraint { breaking: c.breaking, label: c.label.clone(), breaks_with: c.breaks_with.clone(), fails_with: c.fails_with.clone(), held_at_end: c.held_at_end, ..Constraint::new(RodHandle { index: 0, generation: 0 }, b.map(|_| RodHandle { index: 1, generation: 0 }), c.kind.clone(), c.compliance) };
            probe.check(&rods).map_err(ctx)?;
        }
        for (i, l) in asm.loads.iter().enumerate() {
            let r = asm.rod_index("load rod", l.rod)?;
            l.load.validate(&asm.rods[r].rod).map_err(|e| e.context(format_args!("assembly load {i}")))?;
            if let Some(x) = &l.label {
                crate::world::groups::check_label(x)?;
            }
        }
        for (i, b) in asm.beads.iter().enumerate() {
            let r = asm.rod_index("bead rod", b.rod)?;
            let bead = Bead::new(RodHandle { index: 0, generation: 0 }, b.u, b.mass, b.friction, b.radius)?;
            bead.validate(&asm.rods[r].rod).map_err(|e| e.context(format_args!("assembly bead {i}")))?;
            if let Some(x) = &b.label {
                crate::world::groups::check_label(x)?;
            }
        }
        let mut clips = Vec::with_capacity(asm.clips.len());
        let mut held_by = std::collections::HashSet::new();
        for (i, c) in asm.clips.iter().enumerate() {
            clips.push(Clip::new(c.center, c.radius, c.axis, c.resistance).map_err(|e| e.context(format_args!("assembly clip {i}")))?);
            if let Some(k) = c.holds {
                let ok = asm.constraints.get(k).is_some_and(|x| x.other.is_none() && matches!(x.kind, ConstraintKind::Position(_)));
                if !ok || !held_by.insert(k) {
                    return Err(Error::invalid(format!("assembly clip {i} holds"), k, "a one-rod Position constraint of the assembly, held by one clip only"));
                }
            }
            if let Some(x) = &c.label {
                crate::world::groups::check_label(x)?;
            }
        }
        // 2. Duplicates and linear dependence, once for the batch, against
        // the assembly's own rods (local handles: index = position, generation 0).
        let local = |i: usize| RodHandle { index: i as u32, generation: 0 };
        let local_batch: Vec<Constraint> = asm
            .constraints
            .iter()
            .map(|c| Constraint { breaking: c.breaking, label: c.label.clone(), breaks_with: c.breaks_with.clone(), fails_with: c.fails_with.clone(), held_at_end: c.held_at_end, ..Constraint::new(local(c.rod), c.other.map(local), c.kind.clone(), c.compliance) })
            .collect();
        let rod_of = |h: RodHandle| -> Result<&Rod> {
            asm.rods.get(h.index as usize).map(|r| &r.rod).ok_or_else(|| Error::handle(format!("assembly rod {}", h.index)))
        };
        World::default().check_duplicates(&local_batch)?;
        crate::world::independence::check_with(&rod_of, std::iter::empty(), &local_batch)?;
        // Nothing can fail from here on: the world changes only now.
        let rods: Vec<RodHandle> = asm.rods.iter().map(|r| self.add_rod(r.rod.clone())).collect();
        let batch: Vec<Constraint> = local_batch
            .into_iter()
            .map(|mut c| {
                c.rod = rods[c.rod.index as usize];
                c.other = c.other.map(|o| rods[o.index as usize]);
                c
            })
            .collect();
        let constraints = self.add_checked_constraints(batch)?;
        // 3. Loads, beads, labels: already checked, cannot fail.
        let mut loads = Vec::with_capacity(asm.loads.len());
        for l in &asm.loads {
            let mut load = l.load.clone();
            *load.rod_mut() = rods[l.rod];
            loads.push(LoadHandle::from(self.loads.insert(load)));
        }
        let mut beads = Vec::with_capacity(asm.beads.len());
        for b in &asm.beads {
            // Checked in step 1, so `new` succeeds; the error path is unreachable.
            let bead = Bead { fixed: b.fixed, ..Bead::new(rods[b.rod], b.u, b.mass, b.friction, b.radius)? };
            beads.push(BeadHandle::from(self.beads.insert(bead)));
        }
        for (r, h) in asm.rods.iter().zip(&rods) {
            if let Some(l) = &r.label {
                self.groups.add(l, Item::Rod(*h))?;
            }
        }
        for (l, h) in asm.loads.iter().zip(&loads) {
            if let Some(x) = &l.label {
                self.groups.add(x, Item::Load(*h))?;
            }
        }
        let clips: Vec<ClipHandle> = clips
            .into_iter()
            .zip(&asm.clips)
            .map(|(mut c, a)| {
                c.held = a.holds.map(|k| (rods[asm.constraints[k].rod], constraints[k]));
                ClipHandle::from(self.clips.insert(c))
            })
            .collect();
        for (c, h) in asm.clips.iter().zip(&clips) {
            if let Some(x) = &c.label {
                self.groups.add(x, Item::Clip(*h))?;
            }
        }
        for (b, h) in asm.beads.iter().zip(&beads) {
            if let Some(x) = &b.label {
                self.groups.add(x, Item::Bead(*h))?;
            }
        }
        let bandwidth = crate::pipeline::bandwidth(self)?;
        Ok(Inserted { rods, constraints, loads, beads, clips, bandwidth })
    }
}
