//! Tube meshes (generalised cylinders, SPEC §1.3 / II.6) and their OBJ and
//! legacy-VTK export. A ring of `points_per_ring` vertices is placed around
//! the centreline at each of evenly spaced parameters, oriented by the
//! rotation-minimising frames of [`crate::frames`]; consecutive rings are
//! joined by quads split into two triangles. The radius is the bounding
//! radius of the section blended along the rod (II.26), so non-circular
//! sections show as their enclosing tube.
use crate::error::{Error, Result};
use crate::frames;
use crate::rod::Rod;
use crate::section::Section;
use crate::spline::KnotKind;
use crate::world::World;
use std::fmt::Write as _;
use std::path::Path;

/// Resolution and look of a tube mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TubeOptions {
    /// Rings per spline segment (≥ 1).
    pub rings_per_segment: usize,
    /// Vertices per ring (≥ 3).
    pub points_per_ring: usize,
    /// Multiplies the section radius (e.g. to thicken thin yarns on screen).
    pub radius_scale: f64,
    /// Close open rods with flat end discs.
    pub caps: bool,
}

impl Default for TubeOptions {
    fn default() -> Self {
        TubeOptions { rings_per_segment: 6, points_per_ring: 12, radius_scale: 1.0, caps: true }
    }
}

impl TubeOptions {
    pub fn validate(&self) -> Result<()> {
        if self.rings_per_segment < 1 {
            return Err(Error::input("rings_per_segment must be >= 1"));
        }
        if self.points_per_ring < 3 {
            return Err(Error::input(format!("points_per_ring must be >= 3, got {}", self.points_per_ring)));
        }
        crate::error::positive("radius_scale", self.radius_scale)?;
        Ok(())
    }
}

/// Triangle mesh with per-vertex normals; `part` labels each vertex with the
/// index of the rod it came from (rods in world order).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TubeMesh {
    pub vertices: Vec<[f64; 3]>,
    pub normals: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    pub part: Vec<u32>,
}

/// Display radius at u: the bounding radius of the blended section.
fn radius_at(rod: &Rod, u: f64) -> Result<f64> {
    let (ctrl, b) = rod.basis_at(u)?;
    let s = rod.sections();
    let blended = Section::blend([&s[ctrl[0]], &s[ctrl[1]], &s[ctrl[2]], &s[ctrl[3]]], b[0])?;
    Ok(blended.bounding_radius())
}

/// Vertices of the tube around `rod` (rings, and caps on an open rod);
/// an error, before anything is allocated, beyond
/// [`super::MAX_OUTPUT_POINTS`] (or on overflow).
pub fn tube_vertices(rod: &Rod, opts: &TubeOptions) -> Result<usize> {
    opts.validate()?;
    let m = opts.points_per_ring;
    // A closed rod's last ring is its first, and it has no caps.
    let closed = rod.knots().kind() == KnotKind::Periodic;
    let n = rod
        .n_segments()
        .checked_mul(opts.rings_per_segment)
        .and_then(|r| r.checked_add(usize::from(!closed)))
        .and_then(|r| r.checked_mul(m))
        .and_then(|v| if opts.caps && !closed { m.checked_add(1)?.checked_mul(2)?.checked_add(v) } else { Some(v) });
    match n {
        Some(n) if n <= super::MAX_OUTPUT_POINTS => Ok(n),
        _ => Err(Error::invalid(
            "tube mesh size",
            format!("{} segments × {} rings × {} points per ring", rod.n_segments(), opts.rings_per_segment, m),
            format!("at most {} vertices (lower rings_per_segment or points_per_ring)", super::MAX_OUTPUT_POINTS),
        )),
    }
}

/// The tube around one rod (at most [`super::MAX_OUTPUT_POINTS`] vertices).
pub fn tube(rod: &Rod, opts: &TubeOptions) -> Result<TubeMesh> {
    tube_vertices(rod, opts)?;
    let closed = rod.knots().kind() == KnotKind::Periodic;
    let n_rings = rod.n_segments() * opts.rings_per_segment + 1;
    let us = frames::uniform_params(rod, n_rings)?;
    let f = frames::rotation_minimising(rod, &us, None)?;
    // A closed rod's last ring is its first: join back to ring 0 instead.
    let rings = if closed { n_rings - 1 } else { n_rings };
    let m = opts.points_per_ring;
    let mut mesh = TubeMesh::default();
    for fr in f.iter().take(rings) {
        let r = opts.radius_scale * radius_at(rod, fr.u)?;
        for k in 0..m {
            let phi = 2.0 * std::f64::consts::PI * k as f64 / m as f64;
            let n = fr.d1 * phi.cos() + fr.d2 * phi.sin();
            mesh.vertices.push((fr.point + n * r).into());
            mesh.normals.push(n.into());
        }
    }
    let idx = |ring: usize, k: usize| ((ring % rings) * m + k % m) as u32;
    let joins = if closed { rings } else { rings - 1 };
    for i in 0..joins {
        for k in 0..m {
            let (a, b, c, d) = (idx(i, k), idx(i, k + 1), idx(i + 1, k + 1), idx(i + 1, k));
            // Counter-clockwise seen from outside: normals point outwards.
            mesh.triangles.push([a, b, c]);
            mesh.triangles.push([a, c, d]);
        }
    }
    if opts.caps && !closed {
        for (ring, fr, outward) in [(0, &f[0], -1.0), (rings - 1, &f[rings - 1], 1.0)] {
            // Caps get their own vertices so that their normals are the axis.
            let centre = mesh.vertices.len() as u32;
            let n: [f64; 3] = (fr.tangent * outward).into();
            mesh.vertices.push(fr.point.into());
            mesh.normals.push(n);
            for k in 0..m {
                mesh.vertices.push(mesh.vertices[idx(ring, k) as usize]);
                mesh.normals.push(n);
            }
            for k in 0..m {
                let (a, b) = (centre + 1 + k as u32, centre + 1 + ((k + 1) % m) as u32);
                mesh.triangles.push(if outward > 0.0 { [centre, a, b] } else { [centre, b, a] });
            }
        }
    }
    mesh.part = vec![0; mesh.vertices.len()];
    Ok(mesh)
}

impl TubeMesh {
    /// Appends another mesh, labelling its vertices with `part`.
    pub fn append(&mut self, other: &TubeMesh, part: u32) {
        let base = self.vertices.len() as u32;
        self.vertices.extend_from_slice(&other.vertices);
        self.normals.extend_from_slice(&other.normals);
        self.triangles.extend(other.triangles.iter().map(|t| [t[0] + base, t[1] + base, t[2] + base]));
        self.part.extend(std::iter::repeat_n(part, other.vertices.len()));
    }

    /// Wavefront OBJ text: one group per part, `f v//vn` faces (1-based).
    pub fn to_obj(&self) -> String {
        let mut s = String::with_capacity(64 * self.vertices.len() + 32 * self.triangles.len());
        s.push_str("# strandkit tube mesh\n");
        for v in &self.vertices {
            let _ = writeln!(s, "v {:.9e} {:.9e} {:.9e}", v[0], v[1], v[2]);
        }
        for n in &self.normals {
            let _ = writeln!(s, "vn {:.6} {:.6} {:.6}", n[0], n[1], n[2]);
        }
        let mut current = None;
        for t in &self.triangles {
            let p = self.part.get(t[0] as usize).copied().unwrap_or(0);
            if current != Some(p) {
                let _ = writeln!(s, "g rod{p}");
                current = Some(p);
            }
            let (a, b, c) = (t[0] + 1, t[1] + 1, t[2] + 1);
            let _ = writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}");
        }
        s
    }

    /// Legacy VTK (ASCII POLYDATA) text with point normals and a `rod`
    /// scalar per point, which ParaView and VisIt read.
    pub fn to_vtk(&self) -> String {
        let (nv, nt) = (self.vertices.len(), self.triangles.len());
        let mut s = String::with_capacity(64 * nv + 32 * nt);
        s.push_str("# vtk DataFile Version 3.0\nstrandkit tube mesh\nASCII\nDATASET POLYDATA\n");
        let _ = writeln!(s, "POINTS {nv} double");
        for v in &self.vertices {
            let _ = writeln!(s, "{:.9e} {:.9e} {:.9e}", v[0], v[1], v[2]);
        }
        let _ = writeln!(s, "POLYGONS {nt} {}", 4 * nt);
        for t in &self.triangles {
            let _ = writeln!(s, "3 {} {} {}", t[0], t[1], t[2]);
        }
        let _ = writeln!(s, "POINT_DATA {nv}\nNORMALS normals double");
        for n in &self.normals {
            let _ = writeln!(s, "{:.6} {:.6} {:.6}", n[0], n[1], n[2]);
        }
        s.push_str("SCALARS rod int 1\nLOOKUP_TABLE default\n");
        for p in &self.part {
            let _ = writeln!(s, "{p}");
        }
        s
    }

    /// Writes OBJ atomically (temporary file + rename).
    pub fn write_obj(&self, path: &Path) -> Result<()> {
        super::write_atomic(path, self.to_obj().as_bytes())
    }
    /// Writes legacy VTK atomically (temporary file + rename).
    pub fn write_vtk(&self, path: &Path) -> Result<()> {
        super::write_atomic(path, self.to_vtk().as_bytes())
    }
}

/// Tubes of every rod of a world, in world order (part = position in that
/// order); at most [`super::MAX_OUTPUT_POINTS`] vertices in all.
pub fn world_tubes(world: &World, opts: &TubeOptions) -> Result<TubeMesh> {
    let mut total = 0usize;
    for (_, rod) in world.rods() {
        total = total.saturating_add(tube_vertices(rod, opts)?);
    }
    if total > super::MAX_OUTPUT_POINTS {
        return Err(Error::invalid(
            "tube mesh size",
            format!("{total} vertices over {} rods", world.n_rods()),
            format!("at most {} vertices (lower rings_per_segment or points_per_ring)", super::MAX_OUTPUT_POINTS),
        ));
    }
    let mut mesh = TubeMesh::default();
    for (i, (_, rod)) in world.rods().enumerate() {
        mesh.append(&tube(rod, opts)?, i as u32);
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::Material;
    use crate::rod::RodBuilder;
    use nalgebra::Vector3;

    fn rod(section: Section, n: usize) -> Rod {
        RodBuilder::straight(Vector3::zeros(), Vector3::new(2.0, 0.0, 0.0))
            .control_points(n)
            .section(section)
            .material(Material::preset("nylon").unwrap())
            .build()
            .unwrap()
    }

    #[test]
    fn counts_radius_and_orientation() {
        let r = rod(Section::circle(0.1).unwrap(), 6);
        let o = TubeOptions { rings_per_segment: 4, points_per_ring: 8, radius_scale: 1.0, caps: true };
        let m = tube(&r, &o).unwrap();
        let rings = r.n_segments() * 4 + 1;
        assert_eq!(m.vertices.len(), rings * 8 + 2 * (8 + 1));
        assert_eq!(m.triangles.len(), (rings - 1) * 8 * 2 + 2 * 8);
        // Every side vertex is at the radius from the axis (x axis).
        for v in &m.vertices[..rings * 8] {
            assert!(((v[1] * v[1] + v[2] * v[2]).sqrt() - 0.1).abs() < 1e-12);
        }
        // Outward winding: each side triangle's normal points away from the axis.
        for t in &m.triangles[..(rings - 1) * 16] {
            let p: Vec<Vector3<f64>> = t.iter().map(|&i| Vector3::from(m.vertices[i as usize])).collect();
            let n = (p[1] - p[0]).cross(&(p[2] - p[0]));
            let c = (p[0] + p[1] + p[2]) / 3.0;
            assert!(n.dot(&Vector3::new(0.0, c.y, c.z)) > 0.0);
        }
        // Caps: closed surface, so the signed volume is that of the cylinder (polygon area).
        let vol: f64 = m
            .triangles
            .iter()
            .map(|t| {
                let p: Vec<Vector3<f64>> = t.iter().map(|&i| Vector3::from(m.vertices[i as usize])).collect();
                p[0].dot(&p[1].cross(&p[2])) / 6.0
            })
            .sum();
        let polygon = 0.5 * 8.0 * 0.01 * (2.0 * std::f64::consts::PI / 8.0).sin();
        assert!((vol - polygon * 2.0).abs() < 1e-9, "{vol}");
    }

    #[test]
    fn bounding_radius_of_non_circular_sections() {
        let r = rod(Section::rectangle(0.3, 0.4).unwrap(), 5);
        let m = tube(&r, &TubeOptions { caps: false, ..Default::default() }).unwrap();
        for v in &m.vertices {
            assert!(((v[1] * v[1] + v[2] * v[2]).sqrt() - 0.25).abs() < 1e-12);
        }
    }

    #[test]
    fn obj_and_vtk_text_and_files() {
        let r = rod(Section::circle(0.1).unwrap(), 4);
        let mut m = tube(&r, &TubeOptions::default()).unwrap();
        let one = m.clone();
        m.append(&one, 1);
        let obj = m.to_obj();
        assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), m.vertices.len());
        assert_eq!(obj.lines().filter(|l| l.starts_with("f ")).count(), m.triangles.len());
        assert!(obj.contains("g rod0") && obj.contains("g rod1"));
        let vtk = m.to_vtk();
        assert!(vtk.contains(&format!("POINTS {} double", m.vertices.len())));
        assert!(vtk.contains(&format!("POLYGONS {} {}", m.triangles.len(), 4 * m.triangles.len())));
        let dir = std::env::temp_dir().join(format!("strandkit-mesh-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        m.write_obj(&dir.join("a.obj")).unwrap();
        m.write_vtk(&dir.join("a.vtk")).unwrap();
        assert_eq!(std::fs::read_to_string(dir.join("a.vtk")).unwrap(), vtk);
        // No temporary file is left behind.
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2);
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn bad_options_are_errors() {
        let r = rod(Section::circle(0.1).unwrap(), 4);
        for o in [
            TubeOptions { points_per_ring: 2, ..Default::default() },
            TubeOptions { rings_per_segment: 0, ..Default::default() },
            TubeOptions { radius_scale: f64::NAN, ..Default::default() },
            // Sizes that used to abort the process on allocation, or overflow.
            TubeOptions { rings_per_segment: 1_000_000_000, points_per_ring: 1_000_000_000, ..Default::default() },
            TubeOptions { rings_per_segment: 1 << 63, ..Default::default() },
            TubeOptions { rings_per_segment: usize::MAX, points_per_ring: usize::MAX, ..Default::default() },
        ] {
            assert!(matches!(tube(&r, &o), Err(Error::InvalidInput { .. })), "{o:?}");
        }
    }

    #[test]
    fn size_cap_counts_exactly() {
        let r = rod(Section::circle(0.1).unwrap(), 4); // 1 segment
        let o = |rings, caps| TubeOptions { rings_per_segment: rings, points_per_ring: 10, caps, ..Default::default() };
        // (rings + 1) × 10 vertices (+ 22 for the caps) against 10^7.
        assert_eq!(tube_vertices(&r, &o(999_999, false)).unwrap(), crate::io::MAX_OUTPUT_POINTS);
        assert!(tube_vertices(&r, &o(1_000_000, false)).is_err());
        assert!(tube_vertices(&r, &o(999_999, true)).is_err());
        assert_eq!(tube(&r, &o(5, true)).unwrap().vertices.len(), tube_vertices(&r, &o(5, true)).unwrap());
        let ring = RodBuilder::curve(6.0, |t| Vector3::new(t.cos(), t.sin(), 0.0))
            .control_points(8)
            .knots(KnotKind::Periodic)
            .section(Section::circle(0.1).unwrap())
            .material(Material::preset("nylon").unwrap())
            .build()
            .unwrap();
        assert_eq!(tube(&ring, &o(3, true)).unwrap().vertices.len(), tube_vertices(&ring, &o(3, true)).unwrap());
        let half = TubeOptions { rings_per_segment: 1, points_per_ring: usize::MAX / 2, caps: true, ..Default::default() };
        assert!(tube_vertices(&r, &half).is_err());
        // A world: the sum over its rods.
        let mut w = World::new(crate::world::IntegrationParameters::default());
        w.add_rod(r.clone());
        w.add_rod(r);
        assert!(matches!(world_tubes(&w, &o(600_000, false)), Err(Error::InvalidInput { .. })));
        assert_eq!(world_tubes(&w, &o(4, false)).unwrap().vertices.len(), 100);
    }
}
