//! The irreversible stage run after every solve (thesis IV.C step 6,
//! algorithm 3): rupture detection, plastic update and Poisson contraction
//! of every rod, then the rupture itself — the rod is cut where it is most
//! strained beyond its rupture limit, and everything attached to it
//! (constraints, loads, beads, clips, interleaving) moves to the piece that
//! holds its abscissa.
use crate::error::Result;
use crate::handles::RodHandle;
use crate::force::OnRupture;
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

/// Algorithm 3 on every rod, then Poisson (II.59); ruptures are
/// appended to `events`.
pub(crate) fn inelastic_update(world: &mut World, events: &mut Vec<Event>) -> Result<Inelastic> {
    let mut out = Inelastic::default();
    let mut sites = Vec::new(); // allocates only when a rod breaks
    for (i, rod) in world.rods.iter_mut() {
        let (p, site) = rod.update_inelastic();
        out.yielded += p.yielded;
        out.max_increment = out.max_increment.max(p.max_increment);
        rod.update_poisson()?;
        if let Some(s) = site {
            sites.push((RodHandle::from(i), s));
        }
    }
    for (h, s) in sites {
        rupture(world, h, s, events)?;
        out.ruptured = true;
    }
    Ok(out)
}

/// Cuts rod `h` at the site and moves what was attached to it.
fn rupture(world: &mut World, h: RodHandle, site: RuptureSite, events: &mut Vec<Event>) -> Result<()> {
    let cut = world.rod(h)?.cut_at(site.u)?;
    let (map, new_rod) = match cut {
        Cut::Two(pieces) => {
            let [left, right] = *pieces;
            let u = left.domain().1; // the cut, after snapping to a knot
            *world.rod_mut(h)? = left;
            let r: RodHandle = world.rods.insert(right).into();
            (Map::Split { u, right: r }, Some(r))
        }
        Cut::Opened(rod) => {
            let period = world.rod(h)?.n_ctrl() as f64;
            *world.rod_mut(h)? = *rod;
            (Map::Opened { u: site.u, period }, None)
        }
    };
    events.push(Event::RodRuptured {
        rod: h,
        new_rod,
        u: site.u,
        time: world.time,
        mode: site.mode,
        strain: site.strain,
        limit: site.limit,
    });
    move_attachments(world, h, &map, events);
    if let Some(r) = new_rod {
        if let Some(g) = world.interleave.iter_mut().find(|g| g.contains(&h)) {
            g.push(r);
        }
        // Distributed loads act on both pieces.
        let extra: Vec<_> = world
            .loads
            .iter()
            .filter(|(_, l)| l.rod() == h && l.on_rupture() == OnRupture::Copy)
            .map(|(_, l)| {
                let mut l = l.clone();
                *l.rod_mut() = r;
                l
            })
            .collect();
        for l in extra {
            world.loads.insert(l);
        }
    }
    for piece in [Some(h), new_rod].into_iter().flatten() {
        drop_if_fragment(world, piece, events)?;
    }
    Ok(())
}

/// Removes `h` if it is shorter than its own thickness and no constraint
/// holds it (a free chip: see [`Event::FragmentRemoved`]; a short piece
/// left in a grip stays).
fn drop_if_fragment(world: &mut World, h: RodHandle, events: &mut Vec<Event>) -> Result<()> {
    if world.constraints.iter().any(|(_, c)| c.rod == h || c.other == Some(h)) {
        return Ok(());
    }
    let rod = world.rod(h)?;
    let area = rod.sections().iter().filter_map(|s| s.props().ok()).map(|p| p.area).fold(0.0f64, f64::max);
    let thickness = 2.0 * (area / std::f64::consts::PI).sqrt();
    let rest_length = rod.rest_length();
    if rest_length < thickness {
        world.remove_rod(h)?;
        events.push(Event::FragmentRemoved { rod: h, rest_length, time: world.time });
    }
    Ok(())
}

/// Constraints, point loads, beads and clips of rod `h` follow `map`.
/// A one-rod constraint whose points end on different pieces (a
/// barycentric one straddling the cut) cannot hold any more: it is
/// removed and reported as broken with zero force.
fn move_attachments(world: &mut World, h: RodHandle, map: &Map, events: &mut Vec<Event>) {
    let mut straddling = Vec::new();
    for (i, c) in world.constraints.iter_mut() {
        let sides = [c.rod, c.other.unwrap_or(c.rod)];
        if !sides.contains(&h) {
            continue;
        }
        // A one-rod constraint's abscissae all lie on the same rod
        // (even those tagged side 1, e.g. a barycentric driven point).
        let one_rod = c.other.is_none();
        let mut to: [Option<RodHandle>; 2] = [None, None];
        let mut split = false;
        c.kind.visit_abscissae_mut(&mut |side, u| {
            let s = if one_rod { 0 } else { side.min(1) as usize };
            if sides[s] != h {
                return;
            }
            let r = map.apply(h, u);
            split |= to[s].is_some_and(|prev| prev != r);
            to[s] = Some(r);
        });
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
    let mut gone = Vec::new();
    for i in straddling {
        gone.extend(super::post_solve::drop_unheld(world, i, events));
    }
    super::post_solve::remove_dependents(world, gone, events);
    for (_, l) in world.loads.iter_mut() {
        if l.rod() != h || l.on_rupture() != OnRupture::Follow {
            continue;
        }
        let mut u = l.abscissa_mut().map_or(f64::NAN, |u| *u);
        let r = map.apply(h, &mut u);
        if let Some(x) = l.abscissa_mut() {
            *x = u;
        }
        *l.rod_mut() = r;
    }
    // Contact pairs of the old rod are stale; detection makes new ones.
    world.contacts.pairs.retain(|p| !p.rods.contains(&h));
    for (_, b) in world.beads.iter_mut() {
        if b.rod == h {
            b.rod = map.apply(h, &mut b.u);
            b.u_assembled = b.u;
        }
    }
    let cons = &world.constraints;
    for (_, clip) in world.clips.iter_mut() {
        if let Some((_, con)) = clip.held {
            if let Some(c) = cons.get(con.into()) {
                clip.held = Some((c.rod, con));
            }
        }
    }
}
