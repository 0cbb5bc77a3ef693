//! Stale temporary files: every file of a batch is written to `.strand-*.tmp` in its
//! directory and renamed into place ([`strand_report::write_atomic`]); a killed run
//! leaves its unrenamed ones behind. A run removes those **of dead writers** only,
//! which the directory lock ([`super::lock`]) makes decidable without knowing who
//! wrote them:
//!
//! - in `DIR` itself (`batch.json`, `summary.csv`, `summary.svg`): written only by a
//!   whole batch, `strand merge` (both exclusive) or under the plan lock, so with the
//!   plan lock held no live process is writing there;
//! - in `DIR/variants/<id>/`: written only by the run that owns the variant; shards
//!   running together have the same shard count, so their shares are disjoint and a
//!   run is the only live writer of the variants it owns.
//!
//! So a run, holding the plan lock, removes the temporary files in `DIR` and in the
//! directories of the variants it owns.

use std::collections::HashSet;
use std::path::Path;

/// Whether `name` is a temporary file of [`strand_report::write_atomic`].
pub(crate) fn is_temporary(name: &str) -> bool {
    name.starts_with(".strand-") && name.ends_with(".tmp")
}

/// Removes the temporary files directly in `dir`; returns how many.
fn clean_dir(dir: &Path) -> Result<usize, String> {
    let entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(0),
        Err(e) => return Err(format!("cannot list {}: {e}", dir.display())),
    };
    let mut removed = 0;
    for entry in entries.flatten() {
        if !is_temporary(&entry.file_name().to_string_lossy()) {
            continue;
        }
        let path = entry.path();
        match std::fs::remove_file(&path) {
            Ok(()) => removed += 1,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => {
                return Err(format!(
                    "cannot remove the stale temporary file {}: {e}",
                    path.display()
                ));
            }
        }
    }
    Ok(removed)
}

/// Removes the stale temporary files in `dir` and in `dir/variants/<id>/` for every
/// id in `owned` (`None`: every variant directory). Call with the plan lock held.
/// Returns how many were removed.
pub(crate) fn remove_stale_temporaries(
    dir: &Path,
    owned: Option<&HashSet<&str>>,
) -> Result<usize, String> {
    let mut removed = clean_dir(dir)?;
    let variants = dir.join("variants");
    let entries = match std::fs::read_dir(&variants) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(removed),
        Err(e) => return Err(format!("cannot list {}: {e}", variants.display())),
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().to_string();
        if owned.is_none_or(|ids| ids.contains(name.as_str())) && entry.path().is_dir() {
            removed += clean_dir(&entry.path())?;
        }
    }
    Ok(removed)
}
