//! File output helpers: every file is written to a temporary sibling and
//! renamed into place, so an interrupted run never leaves a corrupt file,
//! and a failed write (full disk, the target a directory, …) removes its
//! temporary and leaves the target as it was.
use crate::error::{Error, Result};
use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

/// At most this many points (mesh vertices, sampled parameters) per
/// generated output: a larger request is an input error rather than an
/// allocation that aborts the process.
pub const MAX_OUTPUT_POINTS: usize = 10_000_000;

pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |e: std::io::Error| Error::io(path.display().to_string(), format!("{e}"));
    let name = path.file_name().ok_or_else(|| Error::io(path.display().to_string(), "not a file path"))?;
    // Unique per call, so that two writers of one path never share a temporary.
    static CALLS: AtomicU64 = AtomicU64::new(0);
    let n = CALLS.fetch_add(1, Ordering::Relaxed);
    let tmp = path.with_file_name(format!(".{}.tmp{}-{n}", name.to_string_lossy(), std::process::id()));
    let written = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    written.map_err(|e| {
        // Best effort: the temporary may not exist (create failed).
        let _ = std::fs::remove_file(&tmp);
        io(e)
    })
}

pub mod gltf;
pub mod mesh;
pub mod mesh_read;
pub mod trajectory;

#[cfg(test)]
mod tests {
    use super::*;

    fn names(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
        v.sort();
        v
    }

    #[test]
    fn failed_writes_leave_no_temporary_and_the_target_as_it_was() {
        let d = std::env::temp_dir().join(format!("strandkit-atomic-{}", std::process::id()));
        std::fs::create_dir_all(d.join("target")).unwrap();
        // The target is a directory: the rename fails after the data was written.
        let e = write_atomic(&d.join("target"), &[7u8; 4096]).unwrap_err();
        assert!(matches!(&e, Error::Io { path, .. } if path.ends_with("target")), "{e}");
        assert_eq!(names(&d), ["target"]);
        assert_eq!(names(&d.join("target")), Vec::<String>::new());
        // A missing parent: nothing is created.
        assert!(matches!(write_atomic(&d.join("missing/x.txt"), b"x"), Err(Error::Io { .. })));
        assert_eq!(names(&d), ["target"]);
        // A good write replaces the file whole and leaves only it.
        write_atomic(&d.join("a.txt"), b"old").unwrap();
        write_atomic(&d.join("a.txt"), b"new").unwrap();
        assert_eq!(std::fs::read(d.join("a.txt")).unwrap(), b"new");
        assert_eq!(names(&d), ["a.txt", "target"]);
        // Not a file path at all.
        assert!(matches!(write_atomic(Path::new("/"), b"x"), Err(Error::Io { .. })));
        std::fs::remove_dir_all(&d).ok();
    }
}
