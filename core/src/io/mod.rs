//! File output helpers: every file is written to a temporary sibling and
//! renamed into place, so an interrupted run never leaves a corrupt file.
use crate::error::{Error, Result};
use std::io::Write;
use std::path::Path;

pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |e: std::io::Error| Error::io(path.display().to_string(), format!("{e}"));
    let name = path.file_name().ok_or_else(|| Error::io(path.display().to_string(), format!("not a file path")))?;
    let tmp = path.with_file_name(format!(".{}.tmp{}", name.to_string_lossy(), std::process::id()));
    let mut f = std::fs::File::create(&tmp).map_err(io)?;
    f.write_all(bytes).map_err(io)?;
    f.sync_all().map_err(io)?;
    drop(f);
    std::fs::rename(&tmp, path).map_err(io)
}

pub mod gltf;
pub mod mesh;
pub mod trajectory;
