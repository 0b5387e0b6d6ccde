//! Binary glTF 2.0 (`.glb`) export of tube meshes, for Blender, three.js
//! and every other glTF viewer. One node and one mesh per rod (part), named
//! `rod{p}`, each with float32 POSITION and NORMAL and uint32 indices; a
//! plain coloured material per rod. Units: the world's length unit (glTF
//! viewers assume metres).
use super::mesh::TubeMesh;
use crate::error::{Error, Result};
use serde_json::json;
use std::path::Path;

const MAGIC: u32 = 0x4654_6C67; // "glTF"
const CHUNK_JSON: u32 = 0x4E4F_534A; // "JSON"
const CHUNK_BIN: u32 = 0x004E_4942; // "BIN\0"
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// Vertex and triangle ranges of each part (parts are contiguous, as
/// `TubeMesh::append` builds them).
fn parts(m: &TubeMesh) -> Vec<(u32, std::ops::Range<usize>, std::ops::Range<usize>)> {
    let mut out: Vec<(u32, std::ops::Range<usize>, std::ops::Range<usize>)> = Vec::new();
    let part_of = |v: usize| m.part.get(v).copied().unwrap_or(0);
    let (mut v0, mut t0) = (0, 0);
    while v0 < m.vertices.len() {
        let p = part_of(v0);
        let v1 = (v0..m.vertices.len()).find(|&v| part_of(v) != p).unwrap_or(m.vertices.len());
        let t1 = (t0..m.triangles.len()).find(|&t| (m.triangles[t][0] as usize) >= v1).unwrap_or(m.triangles.len());
        out.push((p, v0..v1, t0..t1));
        (v0, t0) = (v1, t1);
    }
    out
}

/// A distinct colour per rod (golden-angle hue steps).
fn colour(i: usize) -> [f64; 4] {
    let h = (i as f64 * 0.618_033_988_75).fract() * 6.0;
    let x = 1.0 - (h % 2.0 - 1.0).abs();
    let (r, g, b) = match h as u32 {
        0 => (1.0, x, 0.0),
        1 => (x, 1.0, 0.0),
        2 => (0.0, 1.0, x),
        3 => (0.0, x, 1.0),
        4 => (x, 0.0, 1.0),
        _ => (1.0, 0.0, x),
    };
    [0.15 + 0.7 * r, 0.15 + 0.7 * g, 0.15 + 0.7 * b, 1.0]
}

impl TubeMesh {
    /// The mesh as a binary glTF 2.0 file.
    pub fn to_glb(&self) -> Result<Vec<u8>> {
        if self.triangles.iter().flatten().any(|&i| i as usize >= self.vertices.len()) {
            return Err(Error::input("glTF export: a triangle refers to a missing vertex"));
        }
        let nv = self.vertices.len();
        let mut bin: Vec<u8> = Vec::with_capacity(24 * nv + 12 * self.triangles.len());
        for v in self.vertices.iter().chain(&self.normals) {
            for x in v {
                bin.extend_from_slice(&(*x as f32).to_le_bytes());
            }
        }
        let idx_start = bin.len();
        let (mut accessors, mut meshes, mut nodes, mut materials) = (vec![], vec![], vec![], vec![]);
        for (k, (p, vr, tr)) in parts(self).into_iter().enumerate() {
            let off = bin.len() - idx_start;
            for t in &self.triangles[tr.clone()] {
                for &i in t {
                    bin.extend_from_slice(&(i - vr.start as u32).to_le_bytes()); // indices are per primitive
                }
            }
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for v in &self.vertices[vr.clone()] {
                for a in 0..3 {
                    let x = f64::from(v[a] as f32);
                    lo[a] = lo[a].min(x);
                    hi[a] = hi[a].max(x);
                }
            }
            let a0 = accessors.len();
            accessors.push(json!({"bufferView": 0, "byteOffset": 12 * vr.start, "componentType": FLOAT,
                "count": vr.len(), "type": "VEC3", "min": lo, "max": hi}));
            accessors.push(json!({"bufferView": 1, "byteOffset": 12 * vr.start, "componentType": FLOAT,
                "count": vr.len(), "type": "VEC3"}));
            accessors.push(json!({"bufferView": 2, "byteOffset": off, "componentType": UNSIGNED_INT,
                "count": 3 * tr.len(), "type": "SCALAR"}));
            materials.push(json!({"name": format!("rod{p}"), "doubleSided": false,
                "pbrMetallicRoughness": {"baseColorFactor": colour(p as usize), "metallicFactor": 0.0, "roughnessFactor": 0.6}}));
            meshes.push(json!({"name": format!("rod{p}"), "primitives": [{
                "attributes": {"POSITION": a0, "NORMAL": a0 + 1}, "indices": a0 + 2, "material": k, "mode": 4}]}));
            nodes.push(json!({"name": format!("rod{p}"), "mesh": k}));
        }
        let idx_len = bin.len() - idx_start;
        let doc = json!({
            "asset": {"version": "2.0", "generator": concat!("strandkit ", env!("CARGO_PKG_VERSION"))},
            "scene": 0,
            "scenes": [{"nodes": (0..nodes.len()).collect::<Vec<_>>()}],
            "nodes": nodes, "meshes": meshes, "materials": materials, "accessors": accessors,
            "bufferViews": [
                {"buffer": 0, "byteOffset": 0, "byteLength": 12 * nv, "target": ARRAY_BUFFER},
                {"buffer": 0, "byteOffset": 12 * nv, "byteLength": 12 * nv, "target": ARRAY_BUFFER},
                {"buffer": 0, "byteOffset": idx_start, "byteLength": idx_len, "target": ELEMENT_ARRAY_BUFFER}],
            "buffers": [{"byteLength": bin.len()}],
        });
        let mut text = serde_json::to_vec(&doc).map_err(|e| Error::io("", format!("glTF JSON: {e}")))?;
        // Chunks are 4-byte aligned: JSON padded with spaces, BIN with zeros.
        text.resize(text.len().next_multiple_of(4), b' ');
        bin.resize(bin.len().next_multiple_of(4), 0);
        let total = 12 + 8 + text.len() + 8 + bin.len();
        let total32 = u32::try_from(total).map_err(|_| Error::input(format!("glTF export: {total} bytes exceed 4 GiB")))?;
        let mut out = Vec::with_capacity(total);
        for w in [MAGIC, 2, total32, text.len() as u32, CHUNK_JSON] {
            out.extend_from_slice(&w.to_le_bytes());
        }
        out.extend_from_slice(&text);
        for w in [bin.len() as u32, CHUNK_BIN] {
            out.extend_from_slice(&w.to_le_bytes());
        }
        out.extend_from_slice(&bin);
        Ok(out)
    }

    /// Writes binary glTF atomically (temporary file + rename).
    pub fn write_glb(&self, path: &Path) -> Result<()> {
        super::write_atomic(path, &self.to_glb()?)
    }
}

#[cfg(test)]
mod tests {
    use super::super::mesh::{tube, TubeOptions};
    use super::*;
    use crate::material::Material;
    use crate::rod::RodBuilder;
    use crate::section::Section;
    use nalgebra::Vector3;

    fn u32_at(b: &[u8], i: usize) -> u32 {
        u32::from_le_bytes(b[i..i + 4].try_into().unwrap())
    }

    /// Reads our GLB back by the spec: header, chunks, accessors; the
    /// positions and indices reproduce the mesh.
    #[test]
    fn glb_reads_back() {
        let mut mesh = TubeMesh::default();
        for (p, y) in [(0u32, 0.0), (1, 0.5)] {
            let r = RodBuilder::straight(Vector3::new(0.0, y, 0.0), Vector3::new(1.0, y, 0.2))
                .control_points(6)
                .section(Section::circle(0.05).unwrap())
                .material(Material::preset("nylon").unwrap())
                .build()
                .unwrap();
            mesh.append(&tube(&r, &TubeOptions::default()).unwrap(), p);
        }
        let b = mesh.to_glb().unwrap();
        assert_eq!((u32_at(&b, 0), u32_at(&b, 4), u32_at(&b, 8) as usize), (MAGIC, 2, b.len()));
        let jl = u32_at(&b, 12) as usize;
        assert_eq!((u32_at(&b, 16), jl % 4), (CHUNK_JSON, 0));
        let doc: serde_json::Value = serde_json::from_slice(&b[20..20 + jl]).unwrap();
        let bin = &b[20 + jl + 8..];
        assert_eq!(u32_at(&b, 20 + jl + 4), CHUNK_BIN);
        assert_eq!(doc["meshes"].as_array().unwrap().len(), 2);
        let views = &doc["bufferViews"];
        let mut seen_vertices = 0;
        for (k, m) in doc["meshes"].as_array().unwrap().iter().enumerate() {
            let prim = &m["primitives"][0];
            let pos = &doc["accessors"][prim["attributes"]["POSITION"].as_u64().unwrap() as usize];
            let idx = &doc["accessors"][prim["indices"].as_u64().unwrap() as usize];
            let n = pos["count"].as_u64().unwrap() as usize;
            let p0 = views[0]["byteOffset"].as_u64().unwrap() as usize + pos["byteOffset"].as_u64().unwrap() as usize;
            for v in 0..n {
                for a in 0..3 {
                    let x = f32::from_le_bytes(bin[p0 + 12 * v + 4 * a..p0 + 12 * v + 4 * a + 4].try_into().unwrap());
                    assert_eq!(x, mesh.vertices[seen_vertices + v][a] as f32);
                    assert!(f64::from(x) >= pos["min"][a].as_f64().unwrap() && f64::from(x) <= pos["max"][a].as_f64().unwrap());
                }
            }
            let i0 = views[2]["byteOffset"].as_u64().unwrap() as usize + idx["byteOffset"].as_u64().unwrap() as usize;
            let ni = idx["count"].as_u64().unwrap() as usize;
            assert!((0..ni).all(|j| (u32_at(bin, i0 + 4 * j) as usize) < n), "rod {k}: index out of its primitive");
            seen_vertices += n;
        }
        assert_eq!(seen_vertices, mesh.vertices.len());
    }
}
