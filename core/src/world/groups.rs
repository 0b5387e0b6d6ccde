//! Named groups (SPEC §9.0): objects of a world carry labels such as
//! "hbond[17]" or "plank[3]"; a group is every object whose label has that
//! base name ("hbond"), in insertion order, or one label exactly. The world
//! answers group queries — forces, broken flags, positions — without the
//! caller keeping handle lists.
use crate::contact::ContactInfo;
use crate::error::{Error, Result};
use crate::handles::{BeadHandle, ClipHandle, ConstraintHandle, LoadHandle, RodHandle};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A labelled object.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Item {
    Rod(RodHandle),
    Constraint(ConstraintHandle),
    Load(LoadHandle),
    Bead(BeadHandle),
    Clip(ClipHandle),
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Member {
    pub label: String,
    pub item: Item,
}

/// What a constraint's break left behind: when and at which measure.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Broken {
    pub time: f64,
    pub force: f64,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Groups {
    /// Members by base name, in insertion order.
    by_base: BTreeMap<String, Vec<Member>>,
    /// Labelled constraints that broke, sorted by handle.
    broken: Vec<(ConstraintHandle, Broken)>,
}

/// Longest label accepted (characters).
pub const MAX_LABEL: usize = 256;

/// The base name of a label: "hbond[17]" → "hbond".
pub fn base_of(label: &str) -> &str {
    label.split('[').next().unwrap_or(label)
}

/// A label is a non-empty name of letters, digits, `_`, `-`, `.`, `:`, `/`,
/// optionally followed by one bracketed index list such as "[3]" or "[4,7]".
pub fn check_label(label: &str) -> Result<()> {
    let bad = || Error::invalid("label", format!("{label:?}"), "a name of letters, digits, _-.:/ optionally followed by [i] or [i,j] (at most 256 characters)");
    if label.is_empty() || label.chars().count() > MAX_LABEL {
        return Err(bad());
    }
    let (name, rest) = match label.find('[') {
        Some(i) => (&label[..i], &label[i..]),
        None => (label, ""),
    };
    if name.is_empty() || !name.chars().all(|c| c.is_alphanumeric() || "_-.:/".contains(c)) {
        return Err(bad());
    }
    if !rest.is_empty() {
        let inner = rest.strip_prefix('[').and_then(|r| r.strip_suffix(']')).ok_or_else(bad)?;
        if inner.is_empty() || !inner.split(',').all(|p| !p.trim().is_empty() && p.trim().chars().all(|c| c.is_ascii_digit())) {
            return Err(bad());
        }
    }
    Ok(())
}

impl Groups {
    pub(crate) fn add(&mut self, label: &str, item: Item) -> Result<()> {
        check_label(label)?;
        self.by_base.entry(base_of(label).to_string()).or_default().push(Member { label: label.to_string(), item });
        Ok(())
    }
    pub(crate) fn mark_broken(&mut self, h: ConstraintHandle, time: f64, force: f64) {
        let b = Broken { time, force };
        match self.broken.binary_search_by(|x| x.0.cmp(&h)) {
            Ok(i) => self.broken[i].1 = b,
            Err(i) => self.broken.insert(i, (h, b)),
        }
    }
    /// When a labelled constraint broke (None: not broken).
    pub fn broken(&self, h: ConstraintHandle) -> Option<Broken> {
        self.broken.binary_search_by(|x| x.0.cmp(&h)).ok().map(|i| self.broken[i].1)
    }
    /// Members of a group: every label with this base name (`"hbond"`), or
    /// the one label given exactly (`"hbond[17]"`).
    pub fn members(&self, name: &str) -> Result<Vec<Member>> {
        let list = self.by_base.get(base_of(name));
        let found: Vec<Member> = match list {
            Some(l) if name.contains('[') => l.iter().filter(|m| m.label == name).cloned().collect(),
            Some(l) => l.clone(),
            None => Vec::new(),
        };
        if found.is_empty() {
            let known: Vec<&str> = self.by_base.keys().map(|k| k.as_str()).take(20).collect();
            return Err(Error::invalid("group", format!("{name:?}"), format!("one of the world's groups {known:?}")));
        }
        Ok(found)
    }
    /// Base names of all groups.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.by_base.keys().map(|k| k.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn labels() {
        for ok in ["hbond[17]", "plank", "interlock[4,7]", "strand.5p"] {
            check_label(ok).unwrap();
        }
        for bad in ["", "[3]", "a b", "x[", "x[a]", "x[1]y", "x[]"] {
            assert!(check_label(bad).is_err(), "{bad}");
        }
        assert_eq!(base_of("hbond[3]"), "hbond");
    }
}

/// The state of one labelled constraint, as group queries report it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConstraintState {
    pub constraint: ConstraintHandle,
    pub label: String,
    /// Still in the world.
    pub alive: bool,
    /// When and at which measure it broke (None: not broken).
    pub broken: Option<Broken>,
    /// Reaction of the last solve on its first rod (force unit, force ×
    /// length unit); zero once gone.
    pub force: [f64; 3],
    pub torque: [f64; 3],
    /// Tension along its line of action (force unit; None for kinds without
    /// one, or once gone).
    pub tension: Option<f64>,
    /// The point of its first abscissa (length unit; None once gone).
    pub position: Option<[f64; 3]>,
    /// Multipliers of the last solve (empty once gone).
    pub multipliers: Vec<f64>,
}

/// The state of one labelled rod or bead (position: bead centre, or the
/// rod's start; None once gone).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ObjectState {
    pub item: Item,
    pub label: String,
    pub alive: bool,
    pub position: Option<[f64; 3]>,
}

impl super::World {
    /// Members of a group (see [`Groups::members`]).
    pub fn group(&self, name: &str) -> Result<Vec<Member>> {
        self.groups.members(name)
    }

    /// The constraints of a group with their forces, tensions, positions
    /// and broken flags, in label order of insertion.
    pub fn group_constraints(&self, name: &str) -> Result<Vec<ConstraintState>> {
        let mut out = Vec::new();
        for m in self.groups.members(name)? {
            let Item::Constraint(h) = m.item else { continue };
            let mut s = ConstraintState {
                constraint: h,
                label: m.label,
                alive: false,
                broken: self.groups.broken(h),
                force: [0.0; 3],
                torque: [0.0; 3],
                tension: None,
                position: None,
                multipliers: Vec::new(),
            };
            if let Ok(c) = self.constraint(h) {
                let rods = self.rods_of(c)?;
                let r = c.kind.reaction(&rods, &c.multipliers)?;
                s.alive = true;
                s.force = r.force;
                s.torque = r.torque;
                s.tension = c.kind.tension(&rods, &c.multipliers)?;
                let mut first = None;
                c.kind.visit_abscissae(&mut |side, u| {
                    first.get_or_insert((side, u));
                });
                if let Some((side, u)) = first {
                    let rod = if c.other.is_some() && side == 1 { rods[1] } else { rods[0] };
                    s.position = Some(rod.position(u)?.into());
                }
                s.multipliers = c.multipliers.clone();
            }
            out.push(s);
        }
        Ok(out)
    }

    /// The active contacts of the last solve that touch a rod of the group,
    /// each seen from that rod: a pair whose rod a is outside the group and
    /// rod b inside is turned around ([`ContactInfo::turned`]: the forces on
    /// b, its point and abscissa first). A pair with both rods in the group
    /// (self-contact included) is reported once, from its rod a.
    pub fn group_contacts(&self, name: &str) -> Result<Vec<ContactInfo>> {
        self.contacts_of(&self.group_rods(name)?)
    }

    /// [`Self::group_contacts`] for the rods `rods` (sorted by handle).
    fn contacts_of(&self, rods: &[RodHandle]) -> Result<Vec<ContactInfo>> {
        let mut out = Vec::new();
        for c in self.contact_report()? {
            if rods.binary_search(&c.rod_a).is_ok() {
                out.push(c);
            } else if let (Some(b), Some(ub)) = (c.rod_b, c.ub) {
                if rods.binary_search(&b).is_ok() {
                    let point_b = self.rod(b)?.position(ub)?;
                    out.push(c.turned(point_b.into()));
                }
            }
        }
        Ok(out)
    }

    /// The net contact force (normal and friction; force unit) on the
    /// group's rods from everything outside the group: obstacles and other
    /// rods. Pairs between two of its rods act and react inside it and
    /// cancel, so they are left out (not summed to round-off).
    pub fn group_contact_force(&self, name: &str) -> Result<[f64; 3]> {
        let rods = self.group_rods(name)?;
        let inside = |h: Option<RodHandle>| h.is_some_and(|h| rods.binary_search(&h).is_ok());
        let mut f = [0.0; 3];
        for c in self.contacts_of(&rods)? {
            if !inside(c.rod_b) {
                for (k, fk) in f.iter_mut().enumerate() {
                    *fk += c.normal_force * c.normal[k] + c.friction_force[k];
                }
            }
        }
        Ok(f)
    }

    /// The live rods of a group, sorted by handle.
    pub fn group_rods(&self, name: &str) -> Result<Vec<RodHandle>> {
        let mut rods: Vec<RodHandle> = self
            .groups
            .members(name)?
            .into_iter()
            .filter_map(|m| match m.item {
                Item::Rod(h) if self.rod(h).is_ok() => Some(h),
                _ => None,
            })
            .collect();
        rods.sort_unstable();
        rods.dedup();
        Ok(rods)
    }

    /// The rods, beads, loads and clips of a group, alive or gone.
    pub fn group_objects(&self, name: &str) -> Result<Vec<ObjectState>> {
        let mut out = Vec::new();
        for m in self.groups.members(name)? {
            let (alive, position) = match m.item {
                Item::Constraint(_) => continue,
                Item::Rod(h) => match self.rod(h) {
                    Ok(r) => (true, Some(r.position(r.domain().0)?.into())),
                    Err(_) => (false, None),
                },
                Item::Bead(h) => match self.bead_position(h) {
                    Ok(p) => (true, Some(p.into())),
                    Err(_) => (false, None),
                },
                Item::Load(h) => (self.get_load(h).is_ok(), None),
                Item::Clip(h) => match self.clip(h) {
                    Ok(c) => (true, Some(c.center)),
                    Err(_) => (false, None),
                },
            };
            out.push(ObjectState { item: m.item, label: m.label, alive, position });
        }
        Ok(out)
    }
}
