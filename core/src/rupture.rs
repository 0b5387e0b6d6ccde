//! The irreversible stage run after every solve (thesis IV.C step 6,
//! algorithm 3): rupture detection, plastic update and Poisson contraction
//! of every rod, then the rupture itself — the rod is cut where it is most
//! strained beyond its rupture limit, and everything attached to it
//! (constraints, loads, beads, clips, interleaving) moves to the piece that
//! holds its abscissa.
use crate::error::Result;
use crate::handles::RodHandle;
use crate::load::Load;
use crate::rod::{Cut, RuptureSite};
use crate::world::{Event, World};

/// Where an abscissa of the old rod goes: which piece, at which abscissa.
enum Map {
    /// Open rod cut at `u`: left piece keeps the handle, right gets `right`.
    Split { u: f64, right: RodHandle },
    /// Ring opened at `u` (period `n`): new abscissa = (old − u) mod n.
    Opened { u: f64, period: f64 },
}

impl Map {
    fn apply(&self, old: RodHandle, u: &mut f64) -> RodHandle {
        match *self {
            Map::Split { u: cut, right } => {
                if *u > cut {
                    right
                } else {
                    old
                }
            }
            Map::Opened { u: cut, period } => {
                *u = (*u - cut).rem_euclid(period);
                old
            }
        }
    }
}

/// What the inelastic stage did in one call.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Inelastic {
    /// Samples that yielded, and the largest plastic increment (see
    /// [`crate::rod::PlasticUpdate`]).
    pub yielded: usize,
    pub max_increment: f64,
    pub ruptured: bool,
}

impl World {
    /// Algorithm 3 on every rod, then Poisson (II.59); ruptures are
    /// appended to `events`.
    pub(crate) fn inelastic_update(&mut self, events: &mut Vec<Event>) -> Result<Inelastic> {
        let mut out = Inelastic::default();
        let mut sites = Vec::new(); // allocates only when a rod breaks
        for (i, rod) in self.rods.iter_mut() {
            let (p, site) = rod.update_inelastic();
            out.yielded += p.yielded;
            out.max_increment = out.max_increment.max(p.max_increment);
            rod.update_poisson()?;
            if let Some(s) = site {
                sites.push((RodHandle::from(i), s));
            }
        }
        for (h, s) in sites {
            self.rupture(h, s, events)?;
            out.ruptured = true;
        }
        Ok(out)
    }

    /// Cuts rod `h` at the site and moves what was attached to it.
    fn rupture(&mut self, h: RodHandle, site: RuptureSite, events: &mut Vec<Event>) -> Result<()> {
        let cut = self.rod(h)?.cut_at(site.u)?;
        let (map, new_rod) = match cut {
            Cut::Two(pieces) => {
                let [left, right] = *pieces;
                let u = left.domain().1; // the cut, after snapping to a knot
                *self.rod_mut(h)? = left;
                let r: RodHandle = self.rods.insert(right).into();
                (Map::Split { u, right: r }, Some(r))
            }
            Cut::Opened(rod) => {
                let period = self.rod(h)?.n_ctrl() as f64;
                *self.rod_mut(h)? = *rod;
                (Map::Opened { u: site.u, period }, None)
            }
        };
        events.push(Event::RodRuptured {
            rod: h,
            new_rod,
            u: site.u,
            time: self.time,
            mode: site.mode,
            strain: site.strain,
            limit: site.limit,
        });
        self.move_attachments(h, &map, events);
        if let Some(r) = new_rod {
            if let Some(g) = self.interleave.iter_mut().find(|g| g.contains(&h)) {
                g.push(r);
            }
            let extra: Vec<Load> = self
                .loads
                .iter()
                .filter_map(|(_, l)| match l {
                    Load::Distributed { rod, force_per_length } if *rod == h => {
                        Some(Load::Distributed { rod: r, force_per_length: *force_per_length })
                    }
                    _ => None,
                })
                .collect();
            for l in extra {
                self.loads.insert(l);
            }
        }
        Ok(())
    }

    /// Constraints, point loads, beads and clips of rod `h` follow `map`.
    /// A one-rod constraint whose points end on different pieces (a
    /// barycentric one straddling the cut) cannot hold any more: it is
    /// removed and reported as broken with zero force.
    fn move_attachments(&mut self, h: RodHandle, map: &Map, events: &mut Vec<Event>) {
        let mut straddling = Vec::new();
        for (i, c) in self.constraints.iter_mut() {
            let sides = [c.rod, c.other.unwrap_or(c.rod)];
            if !sides.contains(&h) {
                continue;
            }
            let mut to: [Option<RodHandle>; 2] = [None, None];
            let mut split = false;
            for (side, u) in c.kind.abscissae_mut() {
                let s = side as usize;
                if sides[s] != h {
                    continue;
                }
                let r = map.apply(h, u);
                split |= to[s].is_some_and(|prev| prev != r);
                to[s] = Some(r);
            }
            if split {
                straddling.push(i);
                continue;
            }
            if let Some(r) = to[0] {
                c.rod = r;
            }
            if let (Some(r), Some(_)) = (to[1], c.other) {
                c.other = Some(r);
            }
        }
        for i in straddling {
            if let Some(c) = self.constraints.remove(i) {
                events.push(Event::ConstraintBroken { constraint: i.into(), time: self.time, force: 0.0, kind: c.kind });
            }
        }
        for (_, l) in self.loads.iter_mut() {
            if let Load::PointForce { rod, u, .. } | Load::PointTorque { rod, u, .. } = l {
                if *rod == h {
                    *rod = map.apply(h, u);
                }
            }
        }
        for (_, b) in self.beads.iter_mut() {
            if b.rod == h {
                b.rod = map.apply(h, &mut b.u);
                b.u_assembled = b.u;
            }
        }
        let cons = &self.constraints;
        for (_, clip) in self.clips.iter_mut() {
            if let Some((_, con)) = clip.held {
                if let Some(c) = cons.get(con.into()) {
                    clip.held = Some((c.rod, con));
                }
            }
        }
    }
}
