//! Atomic writing of the result files: every file is first written completely to a
//! temporary file in the target directory, and only when *all* files are staged are
//! they renamed into place. On any error the temporary files are removed, so no
//! half-written file remains. (Atomic against the process failing, not durable against
//! a power loss: files are not `fsync`ed.)

use std::io::Write;
use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

use crate::cad::ExportUnit;
use crate::csv::rod_csv;
use crate::result::ResultDoc;

/// Why results could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// Creating the directory, writing or renaming a file failed.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file or directory concerned.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A rod name that is not a safe file name.
    #[error("rod name '{0}' cannot be used as a file name (use letters, digits, '_', '-', '.')")]
    UnsafeName(String),
    /// Serialising the JSON failed.
    #[error("cannot serialise the results: {0}")]
    Json(#[from] serde_json::Error),
}

/// Whether `name` is safe as a file stem: non-empty, letters, digits, `_`, `-`, `.`,
/// not starting with `.`.
pub fn is_safe_name(name: &str) -> bool {
    !name.is_empty()
        && !name.starts_with('.')
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
}

/// Files prepared in temporary files, to be renamed into place together.
struct Staged {
    files: Vec<(NamedTempFile, PathBuf)>,
}

impl Staged {
    fn add(&mut self, dir: &Path, name: &str, content: &[u8]) -> Result<(), ReportError> {
        let path = dir.join(name);
        let io = |source| ReportError::Io {
            path: path.clone(),
            source,
        };
        let mut builder = tempfile::Builder::new();
        builder.prefix(".strand-").suffix(".tmp");
        // Like an ordinary new file (0o666 minus the umask), not tempfile's private 0o600.
        #[cfg(unix)]
        builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
        let mut file = builder.tempfile_in(dir).map_err(io)?;
        // No `fsync` per file: it was most of the time of writing a variant (7 files,
        // 5-10 ms each on a loaded disk) and is not what makes the set atomic (the
        // rename is); after a power loss a batch's resume checks `result.json` against
        // the checksum in `state.json` and solves a damaged variant again.
        file.write_all(content).map_err(io)?;
        self.files.push((file, path));
        Ok(())
    }

    fn commit(self) -> Result<Vec<PathBuf>, ReportError> {
        let mut written = Vec::with_capacity(self.files.len());
        for (file, path) in self.files {
            file.persist(&path).map_err(|e| ReportError::Io {
                path: path.clone(),
                source: e.error,
            })?;
            written.push(path);
        }
        Ok(written)
    }
}

/// Writes `content` to `path` atomically (temporary file in the same directory, then
/// rename). The directory must exist.
pub fn write_atomic(path: &Path, content: &[u8]) -> Result<(), ReportError> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path.file_name().ok_or_else(|| ReportError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file path"),
    })?;
    let mut staged = Staged { files: Vec::new() };
    staged.add(dir, &name.to_string_lossy(), content)?;
    staged.commit().map(|_| ())
}

/// Writes `DIR/result.json`, `DIR/<rod>.csv` for every rod, `DIR/rods.vtp` (the
/// centrelines with their sectional quantities for ParaView, [`crate::rods_vtp`]),
/// `DIR/tubes.obj` (tube surface meshes, [`crate::tubes_obj`]) and `DIR/tubes.stl` (the
/// same surfaces as binary STL, [`crate::tubes_stl`]), geometry in m, creating `DIR`
/// if missing. Returns the written paths (`result.json` last: it is renamed into place
/// only after every other file, so its presence marks a complete set).
pub fn write_results(dir: &Path, doc: &ResultDoc) -> Result<Vec<PathBuf>, ReportError> {
    write_results_in(dir, doc, &ExportUnit::metre())
}

/// As [`write_results`], with the geometry of `rods.vtp`, `tubes.obj` and `tubes.stl`
/// in `unit` (the case's length unit: CAD out). `result.json` and the CSV files stay
/// in SI units.
pub fn write_results_in(
    dir: &Path,
    doc: &ResultDoc,
    unit: &ExportUnit,
) -> Result<Vec<PathBuf>, ReportError> {
    if let Some(bad) = doc.rods.iter().find(|r| !is_safe_name(&r.name)) {
        return Err(ReportError::UnsafeName(bad.name.clone()));
    }
    let json = serde_json::to_vec_pretty(doc)?;
    write_result_files(dir, doc, &json, unit)
}

/// As [`write_results_in`], with the bytes of `result.json` given: `result_json` must
/// be `serde_json::to_vec_pretty(doc)` (a batch needs them first, for the checksum in
/// `state.json`, and so serialises `doc` once). The tube surfaces are built once for
/// `tubes.obj` and `tubes.stl` ([`crate::rod_tube_meshes`]).
pub fn write_result_files(
    dir: &Path,
    doc: &ResultDoc,
    result_json: &[u8],
    unit: &ExportUnit,
) -> Result<Vec<PathBuf>, ReportError> {
    if let Some(bad) = doc.rods.iter().find(|r| !is_safe_name(&r.name)) {
        return Err(ReportError::UnsafeName(bad.name.clone()));
    }
    std::fs::create_dir_all(dir).map_err(|source| ReportError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut staged = Staged { files: Vec::new() };
    for rod in &doc.rods {
        staged.add(dir, &format!("{}.csv", rod.name), rod_csv(rod).as_bytes())?;
    }
    staged.add(
        dir,
        "rods.vtp",
        crate::vtk::rods_vtp_in(doc, unit).as_bytes(),
    )?;
    let meshes = crate::tube::rod_tube_meshes(doc);
    staged.add(
        dir,
        "tubes.obj",
        crate::tube::tubes_obj_of(doc, &meshes, unit).as_bytes(),
    )?;
    staged.add(
        dir,
        "tubes.stl",
        &crate::cad::tubes_stl_of(doc, &meshes, unit),
    )?;
    staged.add(dir, "result.json", result_json)?;
    staged.commit()
}
