//! Reading triangle meshes for obstacles: Wavefront OBJ (`v` and `f`
//! lines; polygons fanned into triangles; `v/vt/vn` and negative indices
//! accepted) and STL (binary, or ASCII `solid … facet … vertex`). The file
//! (at most 1 GiB) is read whole; vertex, corner and triangle counts are
//! checked as they grow, a binary STL's count before its triangles are
//! allocated; a file that is missing, empty or not a mesh is an error
//! naming the file.
use crate::contact::mesh::{TriMesh, MAX_TRIANGLES};
use crate::error::{Error, Result};
use std::path::Path;

/// Largest mesh file read (bytes).
pub const MAX_MESH_BYTES: u64 = 1 << 30;
/// Most vertices a mesh file may list (checked as they are read).
pub const MAX_VERTICES: usize = 3 * MAX_TRIANGLES;
/// Most corners one OBJ face may have.
const MAX_FACE_CORNERS: usize = 1 << 16;

impl TriMesh {
    /// A mesh from an `.obj` or `.stl` file (lengths as in the file).
    pub fn from_file(path: &Path) -> Result<TriMesh> {
        let name = path.display().to_string();
        let fail = |m: String| Error::io(name.clone(), m);
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        if !matches!(ext.as_deref(), Some("obj" | "stl")) {
            return Err(Error::invalid("mesh file extension", &name, ".obj or .stl"));
        }
        let meta = std::fs::metadata(path).map_err(|e| Error::io(name.clone(), e))?;
        if meta.len() > MAX_MESH_BYTES {
            return Err(fail(format!("{} bytes is larger than the {} a mesh may have", meta.len(), MAX_MESH_BYTES)));
        }
        let bytes = std::fs::read(path).map_err(|e| Error::io(name.clone(), e))?;
        if bytes.is_empty() {
            return Err(fail("empty file, not a mesh".into()));
        }
        let (v, t) = if ext.as_deref() == Some("obj") { parse_obj(&bytes).map_err(fail)? } else { parse_stl(&bytes).map_err(fail)? };
        TriMesh::new(v, t).map_err(|e| e.context(format_args!("mesh {name}")))
    }
}

type Parsed = (Vec<[f64; 3]>, Vec<[u32; 3]>);

fn parse_obj(bytes: &[u8]) -> std::result::Result<Parsed, String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "not a text OBJ file".to_string())?;
    let (mut v, mut t) = (Vec::new(), Vec::new());
    for (line_no, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        let bad = |what: &str| format!("line {}: {what}: {line:?}", line_no + 1);
        match it.next() {
            Some("v") => {
                if v.len() >= MAX_VERTICES {
                    return Err(format!("more than {MAX_VERTICES} vertices"));
                }
                let mut p = [0.0; 3];
                for x in p.iter_mut() {
                    *x = it.next().and_then(|s| s.parse().ok()).ok_or_else(|| bad("a vertex needs three numbers"))?;
                }
                v.push(p);
            }
            Some("f") => {
                let mut idx = Vec::new();
                for w in it {
                    if idx.len() >= MAX_FACE_CORNERS {
                        return Err(bad("a face has too many corners"));
                    }
                    let first = w.split('/').next().unwrap_or("");
                    let k: i64 = first.parse().map_err(|_| bad("a face index is not an integer"))?;
                    // 1-based; negative counts back from the last vertex.
                    let k = if k > 0 { k - 1 } else { v.len() as i64 + k };
                    if k < 0 || k >= v.len() as i64 {
                        return Err(bad("a face index is out of range"));
                    }
                    idx.push(k as u32);
                }
                if idx.len() < 3 {
                    return Err(bad("a face needs three vertices"));
                }
                if t.len() + idx.len() - 2 > MAX_TRIANGLES {
                    return Err(format!("more than {MAX_TRIANGLES} triangles"));
                }
                for k in 1..idx.len() - 1 {
                    t.push([idx[0], idx[k], idx[k + 1]]);
                }
            }
            _ => {}
        }
    }
    if t.is_empty() {
        return Err("no faces: not an OBJ mesh".into());
    }
    Ok((v, t))
}

fn parse_stl(bytes: &[u8]) -> std::result::Result<Parsed, String> {
    // Binary: an 80-byte header, a u32 count, 50 bytes per triangle. ASCII
    // files start with "solid" but so do some binary headers: the size decides.
    if bytes.len() >= 84 {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if bytes.len() == 84 + 50 * n {
            if n == 0 {
                return Err("binary STL with no triangles".into());
            }
            if n > MAX_TRIANGLES {
                return Err(format!("{n} triangles, more than {MAX_TRIANGLES}"));
            }
            let (mut v, mut t) = (Vec::with_capacity(3 * n), Vec::with_capacity(n));
            for k in 0..n {
                let rec = &bytes[84 + 50 * k..84 + 50 * (k + 1)];
                let f = |i: usize| f32::from_le_bytes([rec[i], rec[i + 1], rec[i + 2], rec[i + 3]]) as f64;
                for c in 0..3 {
                    let o = 12 + 12 * c;
                    v.push([f(o), f(o + 4), f(o + 8)]);
                }
                t.push([3 * k as u32, 3 * k as u32 + 1, 3 * k as u32 + 2]);
            }
            return Ok(weld(v, t));
        }
    }
    let text = std::str::from_utf8(bytes).map_err(|_| "neither a binary STL (size does not match its count) nor an ASCII one".to_string())?;
    if !text.trim_start().starts_with("solid") {
        return Err("not an STL file (no \"solid\" and the size is not a binary STL's)".into());
    }
    let mut v = Vec::new();
    for (line_no, line) in text.lines().enumerate() {
        let mut it = line.split_whitespace();
        if it.next() == Some("vertex") {
            if v.len() >= MAX_VERTICES {
                return Err(format!("more than {MAX_VERTICES} vertices"));
            }
            let mut p = [0.0; 3];
            for x in p.iter_mut() {
                *x = it.next().and_then(|s| s.parse().ok()).ok_or_else(|| format!("line {}: a vertex needs three numbers", line_no + 1))?;
            }
            v.push(p);
        }
    }
    if v.is_empty() || v.len() % 3 != 0 {
        return Err(format!("{} vertices: not a whole number of facets", v.len()));
    }
    let t = (0..v.len() as u32 / 3).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect();
    Ok(weld(v, t))
}

/// STL repeats each vertex per facet: merges exact repeats.
fn weld(v: Vec<[f64; 3]>, t: Vec<[u32; 3]>) -> Parsed {
    let mut index = std::collections::HashMap::new();
    let mut out = Vec::new();
    let map: Vec<u32> = v
        .iter()
        .map(|p| {
            let key = p.map(f64::to_bits);
            *index.entry(key).or_insert_with(|| {
                out.push(*p);
                out.len() as u32 - 1
            })
        })
        .collect();
    (out, t.into_iter().map(|f| f.map(|k| map[k as usize])).collect())
}
