//! Reading and atomically writing cache files.

use std::fs::File;
use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

/// Temporary files written by this process so far (makes their names unique).
static TEMPORARIES: AtomicU64 = AtomicU64::new(0);

/// The cache file `file`, opened, and its length in bytes: `Ok(None)` when there is
/// none, `Err` with the reason when it exists but cannot be read.
pub(crate) fn open(file: &Path) -> Result<Option<(File, u64)>, String> {
    let opened = File::open(file).and_then(|f| Ok((f.metadata()?.len(), f)));
    match opened {
        Ok((length, f)) => Ok(Some((f, length))),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(format!("cannot read it: {e}")),
    }
}

/// Writes `bytes` to `file` atomically: into a temporary file of a unique name in the
/// same folder (created if missing), then renamed over `file`. A concurrent reader sees
/// the old file, the new one or none, never a part; concurrent writers of the same file
/// both succeed.
pub(crate) fn write_atomically(file: &Path, bytes: &[u8]) -> Result<(), String> {
    let folder = file.parent().unwrap_or(Path::new("."));
    std::fs::create_dir_all(folder)
        .map_err(|e| format!("cannot create the folder {}: {e}", folder.display()))?;
    let name = file
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let temporary = folder.join(format!(
        ".{name}.{}.{}.tmp",
        std::process::id(),
        TEMPORARIES.fetch_add(1, Ordering::Relaxed)
    ));
    let written = File::create(&temporary).and_then(|mut out| out.write_all(bytes));
    let renamed = written.and_then(|()| std::fs::rename(&temporary, file));
    renamed.map_err(|e| {
        let _ = std::fs::remove_file(&temporary);
        format!("cannot write {}: {e}", file.display())
    })
}

#[cfg(test)]
mod tests {
    use std::io::Read;

    use super::*;

    #[test]
    fn a_written_file_reads_back_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("sub/a.strandmesh");
        assert!(open(&file).unwrap().is_none());
        write_atomically(&file, b"first").unwrap();
        write_atomically(&file, b"second").unwrap();
        let (mut reader, length) = open(&file).unwrap().unwrap();
        let mut text = String::new();
        reader.read_to_string(&mut text).unwrap();
        assert_eq!((text.as_str(), length), ("second", 6));
        let names: Vec<_> = std::fs::read_dir(dir.path().join("sub"))
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("a.strandmesh")]);
    }
}
