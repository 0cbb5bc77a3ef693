//! What a variant directory holds, checked: a resumed batch trusts a finished variant
//! only when its files pass their checksums (see [`super::state`]).
//!
//! - **Solved**: `result.json` and `state.json` both present, `state.json` valid JSON
//!   whose own checksum matches and whose recorded checksum of `result.json` matches
//!   that file byte for byte (a `state.json` without checksums, written by an older
//!   version, needs a `result.json` that parses).
//! - **Failed**: no `result.json`, a `failed.json` that parses and names the variant.
//! - **Missing**: neither (never run, or interrupted before `result.json` was
//!   renamed into place).
//! - **Damaged**: anything else. The batch removes the damaged files of the variants it
//!   owns, solves them again (their dependants then start from the recomputed state,
//!   exactly as in an uninterrupted run) and names them in its output.

use std::path::Path;

use strand_report::ResultDoc;

use super::state::{FailedVariant, StoredState};

/// A damaged file of a variant: which one and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Damage {
    /// The file's name in the variant directory (`state.json`, `result.json`,
    /// `failed.json`).
    pub file: &'static str,
    /// What is wrong with it, as a phrase.
    pub reason: String,
}

impl std::fmt::Display for Damage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.file, self.reason)
    }
}

/// The checked content of one variant directory.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Stored {
    /// Nothing finished.
    Missing,
    /// A solved variant whose files pass their checks.
    Solved,
    /// A recorded failure.
    Failed,
    /// A file that fails its check.
    Damaged(Damage),
}

fn damaged(file: &'static str, reason: impl Into<String>) -> Stored {
    Stored::Damaged(Damage {
        file,
        reason: reason.into(),
    })
}

/// Reads `dir/name`: `Ok(None)` if it does not exist.
fn read(dir: &Path, name: &str) -> Result<Option<Vec<u8>>, String> {
    match std::fs::read(dir.join(name)) {
        Ok(bytes) => Ok(Some(bytes)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(format!("cannot be read ({e})")),
    }
}

/// Checks the files of variant `id` in `dir` (`DIR/variants/<id>`).
pub(crate) fn inspect(dir: &Path, id: &str) -> Stored {
    let result = match read(dir, "result.json") {
        Ok(r) => r,
        Err(e) => return damaged("result.json", e),
    };
    if let Some(result) = result {
        let state = match read(dir, "state.json") {
            Ok(Some(state)) => state,
            Ok(None) => return damaged("state.json", "missing next to result.json"),
            Err(e) => return damaged("state.json", e),
        };
        let stored: StoredState = match serde_json::from_slice(&state) {
            Ok(s) => s,
            Err(e) => return damaged("state.json", format!("not a stored state ({e})")),
        };
        if let Err(e) = stored.verify(Some(&result)) {
            let file = match e {
                super::state::ChecksumError::State => "state.json",
                super::state::ChecksumError::Result => "result.json",
            };
            return damaged(file, e.to_string());
        }
        if !stored.has_checksums() {
            // An older batch: the structure is all there is to check.
            if let Err(e) = serde_json::from_slice::<ResultDoc>(&result) {
                return damaged("result.json", format!("not a result ({e})"));
            }
        }
        return Stored::Solved;
    }
    match read(dir, "failed.json") {
        Err(e) => damaged("failed.json", e),
        Ok(None) => Stored::Missing,
        Ok(Some(bytes)) => match serde_json::from_slice::<FailedVariant>(&bytes) {
            Err(e) => damaged("failed.json", format!("not a failure record ({e})")),
            Ok(f) if f.id != id => damaged(
                "failed.json",
                format!("records variant '{}', not this one", f.id),
            ),
            Ok(_) => Stored::Failed,
        },
    }
}

/// Removes the files a damaged variant may have (`result.json` first, so that an
/// interruption never leaves a finished-looking variant), so that it is solved again.
pub(crate) fn clear(dir: &Path) -> Result<(), String> {
    for name in ["result.json", "failed.json", "state.json"] {
        let path = dir.join(name);
        match std::fs::remove_file(&path) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(format!("cannot remove damaged {}: {e}", path.display())),
        }
    }
    Ok(())
}
