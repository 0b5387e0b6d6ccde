//! Triangle meshes as obstacles: the triangles in a bounding-volume tree
//! (median splits, leaves of a few triangles) and the closed-form closest
//! point on a triangle (Ericson, Real-Time Collision Detection §5.1.5).
//! The side a point is on is that of the nearest triangle's face normal
//! (counter-clockwise vertices seen from outside), so a mesh has an
//! outside even when it is not closed (a terrain, a wall).
use crate::error::{Error, Result};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Most triangles a mesh may have (checked before allocating).
pub const MAX_TRIANGLES: usize = 50_000_000;
const LEAF: usize = 4;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct MeshData {
    vertices: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
}

/// A triangle mesh (lengths in the world's unit).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(try_from = "MeshData", into = "MeshData")]
pub struct TriMesh {
    vertices: Vec<Vector3<f64>>,
    triangles: Vec<[u32; 3]>,
    nodes: Vec<Node>,
    /// Triangle indices in tree order.
    order: Vec<u32>,
}

impl PartialEq for TriMesh {
    fn eq(&self, o: &TriMesh) -> bool {
        self.vertices == o.vertices && self.triangles == o.triangles
    }
}

#[derive(Clone, Debug)]
struct Node {
    lo: Vector3<f64>,
    hi: Vector3<f64>,
    /// Leaf: range in `order`; inner: children at `first` and `first + 1`… (see `build`).
    first: u32,
    count: u32,
    /// Inner nodes: index of the right child (the left is the next node).
    right: u32,
}

impl TryFrom<MeshData> for TriMesh {
    type Error = Error;
    fn try_from(d: MeshData) -> Result<TriMesh> {
        TriMesh::new(d.vertices, d.triangles)
    }
}

impl From<TriMesh> for MeshData {
    fn from(m: TriMesh) -> MeshData {
        MeshData { vertices: m.vertices.iter().map(|v| (*v).into()).collect(), triangles: m.triangles }
    }
}

impl TriMesh {
    /// A mesh from its vertices (length) and triangles (vertex indices):
    /// at least one triangle, every index in range, every vertex finite,
    /// no triangle of zero area.
    pub fn new(vertices: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Result<TriMesh> {
        if triangles.is_empty() {
            return Err(Error::input("mesh: no triangles"));
        }
        crate::error::size("mesh triangle count", triangles.len(), MAX_TRIANGLES)?;
        for (i, v) in vertices.iter().enumerate() {
            crate::constraint::finite3(v, &format!("mesh vertex {i}"))?;
        }
        let vertices: Vec<Vector3<f64>> = vertices.into_iter().map(Vector3::from).collect();
        for (i, t) in triangles.iter().enumerate() {
            if t.iter().any(|&k| k as usize >= vertices.len()) {
                return Err(Error::invalid(&format!("mesh triangle {i}"), format!("{t:?}"), format!("vertex indices below {}", vertices.len())));
            }
            let [a, b, c] = t.map(|k| vertices[k as usize]);
            if !((b - a).cross(&(c - a)).norm() > 0.0) {
                return Err(Error::invalid(&format!("mesh triangle {i}"), format!("{t:?}"), "three vertices not on one line"));
            }
        }
        let mut m = TriMesh { vertices, triangles, nodes: Vec::new(), order: Vec::new() };
        m.order = (0..m.triangles.len() as u32).collect();
        let mut order = std::mem::take(&mut m.order);
        m.build(&mut order, 0);
        m.order = order;
        Ok(m)
    }
    pub fn n_triangles(&self) -> usize {
        self.triangles.len()
    }
    pub fn vertices(&self) -> impl Iterator<Item = [f64; 3]> + '_ {
        self.vertices.iter().map(|v| (*v).into())
    }
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }
    pub(crate) fn validate(&self) -> Result<()> {
        if self.triangles.is_empty() || self.nodes.is_empty() {
            return Err(Error::input("mesh: no triangles"));
        }
        Ok(())
    }
    fn corners(&self, t: u32) -> [Vector3<f64>; 3] {
        self.triangles[t as usize].map(|k| self.vertices[k as usize])
    }
    /// Builds the subtree over `order[..]` (starting at `offset` in the
    /// whole order); returns its node index.
    fn build(&mut self, order: &mut [u32], offset: usize) -> usize {
        let (mut lo, mut hi) = (Vector3::repeat(f64::INFINITY), Vector3::repeat(f64::NEG_INFINITY));
        for &t in order.iter() {
            for c in self.corners(t) {
                lo = lo.inf(&c);
                hi = hi.sup(&c);
            }
        }
        let me = self.nodes.len();
        self.nodes.push(Node { lo, hi, first: offset as u32, count: order.len() as u32, right: 0 });
        if order.len() > LEAF {
            // Split at the median centroid along the longest side.
            let axis = (hi - lo).imax();
            let key = |m: &TriMesh, t: u32| m.corners(t).iter().map(|c| c[axis]).sum::<f64>();
            let mid = order.len() / 2;
            order.select_nth_unstable_by(mid, |&x, &y| key(self, x).total_cmp(&key(self, y)));
            let (left, right) = order.split_at_mut(mid);
            self.build(left, offset);
            let r = self.build(right, offset + mid);
            self.nodes[me].count = 0;
            self.nodes[me].right = r as u32;
        }
        me
    }
    /// Signed distance from `p` and the outward unit normal, over the
    /// triangles within `reach`; `None` when there is none.
    pub fn nearest(&self, p: &Vector3<f64>, reach: f64) -> Option<(f64, Vector3<f64>)> {
        // The nearest distance, its point, and the sum of the unit normals
        // of every face at that distance: at an edge or a vertex several
        // faces tie, and the side is decided by their mean normal (one
        // face's normal alone can call an outside point inside at a sharp
        // edge).
        let mut best: Option<(f64, Vector3<f64>, Vector3<f64>)> = None;
        let tie = |d: f64| 1e-12 * (1.0 + d + p.norm());
        // Depth-first on a fixed stack, no allocation per probe: the tree
        // splits at the median, so it is at most 33 levels deep for u32
        // triangle indices and the stack holds at most one more entry.
        let (mut stack, mut top) = ([0usize; 64], 1);
        while top > 0 {
            top -= 1;
            let i = stack[top];
            let nd = &self.nodes[i];
            let limit = best.map_or(reach, |b| (b.0 + tie(b.0)).min(reach));
            let out = (nd.lo - p).sup(&(p - nd.hi)).sup(&Vector3::zeros());
            if out.norm() > limit {
                continue;
            }
            if nd.count > 0 {
                for &t in &self.order[nd.first as usize..(nd.first + nd.count) as usize] {
                    let [a, b, c] = self.corners(t);
                    let q = closest_on_triangle(p, &a, &b, &c);
                    let d = (p - q).norm();
                    if d > limit {
                        continue;
                    }
                    let face = (b - a).cross(&(c - a)).normalize();
                    best = match best {
                        Some((bd, bq, n)) if (d - bd).abs() <= tie(bd) => Some((bd, bq, n + face)),
                        Some((bd, _, _)) if d > bd => best,
                        _ => Some((d, q, face)),
                    };
                }
            } else {
                stack[top] = i + 1;
                stack[top + 1] = nd.right as usize;
                top += 2;
            }
        }
        let (d, q, faces) = best?;
        let side = (p - q).dot(&faces);
        if d > 1e-12 * (1.0 + p.norm()) {
            let mut dir = (p - q) / d;
            // Over a face (or a flat edge) p − q is the face normal but for
            // rounding in the closest point: take the normal itself.
            if let Some(n) = faces.try_normalize(0.0) {
                if dir.cross(&n).norm() < 1e-6 {
                    dir = n * dir.dot(&n).signum();
                }
            }
            Some(if side >= 0.0 { (d, dir) } else { (-d, -dir) })
        } else {
            Some((0.0, faces.try_normalize(0.0).unwrap_or(Vector3::z())))
        }
    }
}

/// The point of triangle abc nearest to p (Ericson §5.1.5: Voronoi regions
/// of the vertices, then the edges, then the face).
pub fn closest_on_triangle(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>, c: &Vector3<f64>) -> Vector3<f64> {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed form against a dense sampling of the triangle.
    #[test]
    fn closest_point_matches_sampling() {
        let mut s = 0x2545F4914F6CDD1Du64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..200 {
            let v: Vec<Vector3<f64>> = (0..4).map(|_| Vector3::new(rnd(), rnd(), rnd())).collect();
            let (p, a, b, c) = (v[0] * 2.0, v[1], v[2], v[3]);
            let q = closest_on_triangle(&p, &a, &b, &c);
            let n = 400;
            let mut best = f64::INFINITY;
            for i in 0..=n {
                for j in 0..=(n - i) {
                    let x = a + (b - a) * (i as f64 / n as f64) + (c - a) * (j as f64 / n as f64);
                    best = best.min((p - x).norm());
                }
            }
            let d = (p - q).norm();
            // The samples lie within an edge / n of every point of the triangle.
            let edge = (b - a).norm().max((c - a).norm()).max((c - b).norm());
            assert!(d <= best + 1e-12 && best - d < edge / n as f64, "{d} vs sampled {best}");
        }
    }

    /// A sharp ridge (faces meeting at 33°): points outside near its edge
    /// are outside, whichever face the search meets first.
    #[test]
    fn sign_at_a_sharp_edge_follows_both_faces() {
        // Two faces sharing the edge along y at the origin, opening
        // downwards: the ridge of a roof, outside above.
        let h = 1.0f64;
        let (xa, xb) = (-0.3f64, 0.3f64);
        let v = vec![[0.0, -1.0, 0.0], [0.0, 1.0, 0.0], [xa, -1.0, -h], [xa, 1.0, -h], [xb, -1.0, -h], [xb, 1.0, -h]];
        // Counter-clockwise seen from outside (normals up and out).
        let t = vec![[0, 3, 2], [0, 1, 3], [0, 5, 1], [0, 4, 5]];
        let m = TriMesh::new(v, t).unwrap();
        for k in 0..64 {
            let phi = std::f64::consts::PI * (k as f64 + 0.5) / 64.0;
            let p = Vector3::new(0.064 * phi.cos(), 0.1, 0.064 * phi.sin());
            let (d, n) = m.nearest(&p, 1.0).unwrap();
            assert!(d > 0.0 && n.z > -1e-12, "{p:?}: distance {d}, normal {n:?}");
        }
        assert!(m.nearest(&Vector3::new(0.0, 0.0, -0.5), 2.0).unwrap().0 < 0.0);
    }

    /// The tree answers as a scan over every triangle does.
    #[test]
    fn tree_matches_brute_force() {
        // A bumpy 20 × 20 grid surface.
        let n = 20;
        let mut v = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
                v.push([x, y, 0.1 * (7.0 * x).sin() * (5.0 * y).cos()]);
            }
        }
        let mut t = Vec::new();
        let id = |i: usize, j: usize| (i * (n + 1) + j) as u32;
        for i in 0..n {
            for j in 0..n {
                t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let m = TriMesh::new(v, t).unwrap();
        for k in 0..300 {
            let p = Vector3::new((k as f64 * 0.37).fract() * 1.2 - 0.1, (k as f64 * 0.61).fract() * 1.2 - 0.1, (k as f64 * 0.13).fract() * 0.6 - 0.3);
            let brute = (0..m.n_triangles() as u32)
                .map(|t| {
                    let [a, b, c] = m.corners(t);
                    (p - closest_on_triangle(&p, &a, &b, &c)).norm()
                })
                .fold(f64::INFINITY, f64::min);
            let (d, _) = m.nearest(&p, 10.0).unwrap();
            assert!((d.abs() - brute).abs() < 1e-12, "{d} vs {brute}");
            assert!(m.nearest(&p, 0.5 * brute).is_none() || brute == 0.0);
        }
    }
}
