//! A wiring harness (SPEC §9.5, thesis III.C.2, fig. III.13): cables of
//! different radii ("branches") joined at junctions — taped breakouts
//! where branch ends share a point and a direction (relative position and
//! relative orientation of the tangents, III.55 and III.58) — with
//! connectors clamping ends to the structure.
//!
//! Branches are straight at rest, laid along their polylines; they have
//! no torsion (3 coordinates per control point), so a branch is held
//! against turning about its junction tangent by its other end: give every
//! leaf a connector for `relax` (free leaves are for `step`). At a
//! junction the branches' tangents must agree in direction (a breakout:
//! they leave together and bend apart), and every branch must be joined
//! to the others. Axes: y up (use gravity (0, −9.81, 0)).
use crate::cable::check_cable;
use crate::curves::Polyline;
use crate::rope::Rope;
use nalgebra::Vector3;
use strandkit_core::constraint::kinds::{RelativeOrientation, RelativePosition};
use strandkit_core::error::{positive, size};
use strandkit_core::{Assembly, Error, Result, Rod};

/// Most branches a harness may have.
pub const MAX_BRANCHES: usize = 10_000;

/// Which end of a branch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BranchEnd {
    Start,
    End,
}

impl BranchEnd {
    fn name(self) -> &'static str {
        match self {
            BranchEnd::Start => "start",
            BranchEnd::End => "end",
        }
    }
}

/// Parameters of [`harness`] (SI units). `Default` is a harness like the
/// thesis' fig. III.13 (40 control points there): a 0.5 m trunk (radius
/// 6 mm) with two 3.5 mm branches coming in at its start and three of
/// 2.5–4 mm leaving its end, every leaf in a connector.
#[derive(Clone, Debug, PartialEq)]
pub struct Harness {
    /// Each branch's route (m), from its start to its end.
    pub branches: Vec<Vec<[f64; 3]>>,
    /// Each branch's radius (m).
    pub radii: Vec<f64>,
    /// Each junction: the branch ends that meet there (same point, same
    /// tangent direction).
    pub junctions: Vec<Vec<(usize, BranchEnd)>>,
    /// Branch ends clamped where they are (position and tangent).
    pub connectors: Vec<(usize, BranchEnd)>,
    /// Radius (m) of the bends the routes' corners are rounded to.
    pub bend_radius: f64,
    /// Young's modulus (Pa) and density (kg/m³) of every branch.
    pub young_modulus: f64,
    pub density: f64,
    /// Control points per metre of branch (at least 4 per branch).
    pub control_points_per_metre: f64,
}

impl Default for Harness {
    fn default() -> Self {
        use BranchEnd::*;
        Harness {
            branches: vec![
                vec![[0.0, 0.0, 0.0], [0.5, 0.0, 0.0]],
                vec![[-0.4, 0.15, 0.0], [-0.1, 0.0, 0.0], [0.0, 0.0, 0.0]],
                vec![[-0.4, -0.15, 0.0], [-0.1, 0.0, 0.0], [0.0, 0.0, 0.0]],
                vec![[0.5, 0.0, 0.0], [0.6, 0.0, 0.0], [0.9, 0.2, 0.0]],
                vec![[0.5, 0.0, 0.0], [0.6, 0.0, 0.0], [0.9, 0.0, 0.0]],
                vec![[0.5, 0.0, 0.0], [0.6, 0.0, 0.0], [0.9, -0.2, 0.0]],
            ],
            radii: vec![0.006, 0.0035, 0.0035, 0.004, 0.003, 0.0025],
            junctions: vec![vec![(0, Start), (1, End), (2, End)], vec![(0, End), (3, Start), (4, Start), (5, Start)]],
            connectors: vec![(1, Start), (2, Start), (3, End), (4, End), (5, End)],
            bend_radius: 0.1,
            young_modulus: 1e8,
            density: 2000.0,
            control_points_per_metre: 12.0,
        }
    }
}

/// Where things are in the assembly.
#[derive(Clone, Debug, PartialEq)]
pub struct HarnessLayout {
    /// Rod index of each branch.
    pub branches: Vec<usize>,
    /// Each junction's links: (main end, other end, RelativePosition
    /// constraint index, RelativeOrientation constraint index); the main
    /// end is the first one listed.
    pub junctions: Vec<Vec<JunctionLink>>,
    /// Constraint indices of each connector's clamp.
    pub connectors: Vec<Vec<usize>>,
    /// Rest length of each branch (m).
    pub lengths: Vec<f64>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JunctionLink {
    pub main: (usize, BranchEnd),
    pub other: (usize, BranchEnd),
    pub position: usize,
    pub orientation: usize,
}

impl Harness {
    /// Checks everything but the junction tangents (they need the rods);
    /// returns the routes.
    fn routes(&self) -> Result<Vec<Polyline>> {
        let n = self.branches.len();
        size("branches", n, MAX_BRANCHES)?;
        if n == 0 {
            return Err(Error::invalid("branches", "none", "at least one branch"));
        }
        if self.radii.len() != n {
            return Err(Error::invalid("radii", format!("{} radii", self.radii.len()), format!("one per branch ({n})")));
        }
        positive("young_modulus", self.young_modulus)?;
        positive("density", self.density)?;
        positive("control_points_per_metre", self.control_points_per_metre)?;
        positive("bend_radius", self.bend_radius)?;
        let mut routes = Vec::with_capacity(n);
        for (k, b) in self.branches.iter().enumerate() {
            size(&format!("branches[{k}] points"), b.len(), crate::cable::MAX_PATH_POINTS)?;
            check_cable(self.radii[k], &format!("radii[{k}]"), self.young_modulus, self.density)?;
            routes.push(Polyline::new(b.iter().map(|&p| Vector3::from(p)).collect(), &format!("branches[{k}]"))?);
        }
        let at = |(b, e): (usize, BranchEnd)| if e == BranchEnd::Start { routes[b].nodes[0] } else { routes[b].nodes[routes[b].nodes.len() - 1] };
        // Each end in one junction or connector at most.
        let mut used: std::collections::HashMap<(usize, BranchEnd), String> = Default::default();
        let mut claim = |end: (usize, BranchEnd), by: String| -> Result<()> {
            if end.0 >= n {
                return Err(Error::invalid(by, format!("branch {}", end.0), format!("a branch index < {n}")));
            }
            if let Some(prev) = used.insert(end, by.clone()) {
                return Err(Error::invalid(by, format!("branch {}'s {}", end.0, end.1.name()), format!("an end not already in {prev}")));
            }
            Ok(())
        };
        for (j, ends) in self.junctions.iter().enumerate() {
            if ends.len() < 2 {
                return Err(Error::invalid(format!("junctions[{j}]"), format!("{} ends", ends.len()), "at least 2 branch ends"));
            }
            for &e in ends {
                claim(e, format!("junctions[{j}]"))?;
            }
            let p0 = at(ends[0]);
            let tol = 1e-3 * ends.iter().map(|e| self.radii[e.0]).fold(f64::INFINITY, f64::min);
            for &e in &ends[1..] {
                let d = (at(e) - p0).norm();
                if d > tol {
                    return Err(Error::invalid(
                        format!("junctions[{j}]"),
                        format!("branch {}'s {} {d:.3e} m from branch {}'s {}", e.0, e.1.name(), ends[0].0, ends[0].1.name()),
                        format!("ends at one point (within {tol:.1e} m)"),
                    ));
                }
            }
        }
        for (c, &e) in self.connectors.iter().enumerate() {
            claim(e, format!("connectors[{c}]"))?;
        }
        // Every branch joined to branch 0 (union–find over the junctions).
        let mut parent: Vec<usize> = (0..n).collect();
        fn find(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                p[x] = p[p[x]];
                x = p[x];
            }
            x
        }
        for ends in &self.junctions {
            for e in &ends[1..] {
                let (a, b) = (find(&mut parent, ends[0].0), find(&mut parent, e.0));
                parent[a] = b;
            }
        }
        let root = find(&mut parent, 0);
        if let Some(k) = (0..n).find(|&k| find(&mut parent, k) != root) {
            return Err(Error::invalid("junctions", format!("branch {k} not joined to branch 0"), "a junction graph joining every branch (a harness is one piece)"));
        }
        Ok(routes)
    }
}

/// Builds the harness (see the module doc). Labels: "branch[k]",
/// "junction[j]" (its constraints), "connector[c]".
pub fn harness(p: &Harness) -> Result<(Assembly, HarnessLayout)> {
    let routes = p.routes()?;
    let mut rods: Vec<Rod> = Vec::with_capacity(routes.len());
    for (k, route) in routes.iter().enumerate() {
        let length = route.length();
        let n = ((length * p.control_points_per_metre).ceil() + 1.0).max(4.0);
        if n > crate::rope::MAX_ROPE_CONTROL_POINTS as f64 {
            return Err(Error::invalid("control_points_per_metre", p.control_points_per_metre, format!("at most {} control points per branch (branch {k} is {length:.3} m)", crate::rope::MAX_ROPE_CONTROL_POINTS)));
        }
        let rope = Rope::solid(p.radii[k], p.young_modulus, p.density);
        rods.push(crate::cable::lay(&rope, &format!("branch[{k}]"), &route.rounded(p.bend_radius), n as usize)?);
    }
    let u_of = |rods: &[Rod], (b, e): (usize, BranchEnd)| {
        let (u0, u1) = rods[b].domain();
        if e == BranchEnd::Start { u0 } else { u1 }
    };
    // Tangents at a junction agree (a breakout), within 2°.
    for (j, ends) in p.junctions.iter().enumerate() {
        let t0 = rods[ends[0].0].tangent(u_of(&rods, ends[0]))?;
        for &e in &ends[1..] {
            let t = rods[e.0].tangent(u_of(&rods, e))?;
            let angle = t0.dot(&t).clamp(-1.0, 1.0).acos().to_degrees();
            if angle > 2.0 {
                let hint = if angle > 90.0 { format!("; give branch {}'s route the other way round", e.0) } else { String::new() };
                return Err(Error::invalid(
                    format!("junctions[{j}]"),
                    format!("branch {}'s tangent {angle:.1}° from branch {}'s", e.0, ends[0].0),
                    format!("tangents in the same direction at a junction (within 2°: the branches leave it together){hint}"),
                ));
            }
        }
    }
    let lengths = rods.iter().map(|r| r.rest_length()).collect();
    let us: Vec<Vec<f64>> = p.junctions.iter().map(|ends| ends.iter().map(|&e| u_of(&rods, e)).collect()).collect();
    let cu: Vec<f64> = p.connectors.iter().map(|&e| u_of(&rods, e)).collect();
    let mut asm = Assembly::new();
    let branches: Vec<usize> = rods.into_iter().enumerate().map(|(k, r)| asm.add_rod(r, Some(&format!("branch[{k}]")))).collect();
    let mut junctions = Vec::with_capacity(p.junctions.len());
    for (j, ends) in p.junctions.iter().enumerate() {
        let label = format!("junction[{j}]");
        let (main, ua) = (ends[0], us[j][0]);
        let mut links = Vec::new();
        for (&other, &ub) in ends[1..].iter().zip(&us[j][1..]) {
            let (a, b) = (branches[main.0], branches[other.0]);
            asm.link(a, b, RelativePosition { ua, ub, axes: [true, true, true, false], offset: [0.0; 4] }).label(label.clone());
            let position = asm.constraints.len() - 1;
            asm.link(a, b, RelativeOrientation { ua, ub, roll: false }).label(label.clone());
            links.push(JunctionLink { main, other, position, orientation: asm.constraints.len() - 1 });
        }
        junctions.push(links);
    }
    let mut connectors = Vec::with_capacity(p.connectors.len());
    for (c, (&(b, _), &u)) in p.connectors.iter().zip(&cu).enumerate() {
        connectors.push(asm.clamp(branches[b], u, Some(&format!("connector[{c}]")))?);
    }
    Ok((asm, HarnessLayout { branches, junctions, connectors, lengths }))
}
