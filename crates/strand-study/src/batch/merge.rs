//! `strand merge DIR… [--out DIR]`: combines the directories of a sharded batch.
//!
//! Every `DIR` must hold the same batch (`batch.json`). Each variant is taken from the
//! first `DIR` where it is finished (`result.json`, else `failed.json`) and copied
//! into the output directory (default: the first `DIR`; nothing is copied when the
//! shards shared one directory); a copy whose files fail their integrity check
//! ([`super::integrity`]) is never taken. When every variant is there, `summary.csv` and
//! `summary.svg` are written exactly as an unsharded batch writes them; otherwise
//! the missing variants are listed and nothing is written.

use std::path::{Path, PathBuf};

use strand_report::write_atomic;

use super::integrity::{Stored, clear, inspect};
use super::lock::{self, Role};
use super::manifest::Manifest;
use super::state::FailedVariant;
use super::{failures, write_summary};
use crate::error::{Result, StudyError};

/// What a merge did.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MergeReport {
    /// The directory merged into.
    pub target: PathBuf,
    /// `Manifest::describe` of the batch (case and varied parameters).
    pub batch: String,
    /// Variants copied into `target`.
    pub copied: usize,
    /// Damaged variant copies that were not taken: the variant directory and what
    /// was wrong.
    pub damaged: Vec<String>,
    /// The failed variants, in grid order.
    pub failures: Vec<FailedVariant>,
    /// `summary.csv` and `summary.svg`.
    pub summary: [PathBuf; 2],
}

fn invalid(message: impl Into<String>) -> StudyError {
    StudyError::Input(message.into())
}

fn io_failure(message: impl Into<String>) -> StudyError {
    StudyError::Io(message.into())
}

/// Copies the files of one variant directory into `to` (created), `result.json` and
/// `failed.json` last so that a partial copy is never taken for a finished variant.
fn copy_variant(from: &Path, to: &Path) -> Result<()> {
    let io =
        |path: &Path, e: std::io::Error| io_failure(format!("cannot copy {}: {e}", path.display()));
    std::fs::create_dir_all(to).map_err(|e| io(to, e))?;
    let mut files: Vec<PathBuf> = std::fs::read_dir(from)
        .map_err(|e| io(from, e))?
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|p| {
            p.is_file()
                && !p
                    .file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with('.'))
        })
        .collect();
    files.sort_by_key(|p| {
        let name = p
            .file_name()
            .map(|n| n.to_string_lossy().to_string())
            .unwrap_or_default();
        (name == "result.json" || name == "failed.json", name)
    });
    for file in files {
        let content = std::fs::read(&file).map_err(|e| io(&file, e))?;
        let name = file.file_name().unwrap_or_default();
        write_atomic(&to.join(name), &content)
            .map_err(|e| io_failure(format!("cannot copy {}: {e}", file.display())))?;
    }
    Ok(())
}

/// `strand merge`: merges the batch directories `dirs` (the shards of one batch)
/// into `out_dir` (default: the first of them) and writes the summary. Damaged copies
/// are skipped (and listed in the report); missing variants are an error listing
/// them.
pub fn merge(dirs: &[PathBuf], out_dir: Option<&Path>) -> Result<MergeReport> {
    let Some(first_dir) = dirs.first() else {
        return Err(invalid("strand merge needs at least one batch directory"));
    };
    let mut manifests = Vec::with_capacity(dirs.len());
    for dir in dirs {
        match Manifest::read(dir).map_err(invalid)? {
            Some(m) => manifests.push(m),
            None => {
                return Err(invalid(format!(
                    "{} has no batch.json: it is not a `strand batch` output directory",
                    dir.display()
                )));
            }
        }
    }
    let manifest = manifests[0].clone();
    if let Some((dir, other)) = dirs
        .iter()
        .zip(&manifests)
        .find(|(_, m)| !m.same_batch(&manifest))
    {
        return Err(invalid(format!(
            "{} holds another batch than {}: {} vs {}; merge only the shards of one batch",
            dir.display(),
            first_dir.display(),
            other.describe(),
            manifest.describe()
        )));
    }
    let target = out_dir.unwrap_or(first_dir);
    // No shard may still be writing into the target while it is merged.
    let mut held = lock::acquire(target, Role::Merge, &manifest.identity())?;
    if Manifest::read(target).map_err(invalid)?.is_none() {
        std::fs::create_dir_all(target)
            .map_err(|e| io_failure(format!("cannot create {}: {e}", target.display())))?;
        let json = serde_json::to_vec_pretty(&manifest).map_err(|e| io_failure(e.to_string()))?;
        write_atomic(&target.join("batch.json"), &json)
            .map_err(|e| io_failure(format!("batch plan not written: {e}")))?;
    } else if !Manifest::read(target)
        .map_err(invalid)?
        .is_some_and(|m| m.same_batch(&manifest))
    {
        return Err(invalid(format!(
            "--out {} holds another batch; choose an empty directory",
            target.display()
        )));
    }
    super::cleanup::remove_stale_temporaries(target, None).map_err(io_failure)?;
    held.release_plan();
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    };
    let mut missing = Vec::new();
    let mut copied = 0;
    let mut damaged = Vec::new();
    for entry in &manifest.variants {
        // Each copy checked (integrity): a damaged one is never taken.
        let status = |dir: &Path| inspect(&dir.join("variants").join(&entry.id), &entry.id);
        let statuses: Vec<Stored> = dirs.iter().map(|d| status(d)).collect();
        let source = [Stored::Solved, Stored::Failed].iter().find_map(|want| {
            dirs.iter()
                .zip(&statuses)
                .find(|(_, s)| *s == want)
                .map(|(d, _)| d)
        });
        if source.is_none()
            && let Some((dir, Stored::Damaged(d))) = dirs
                .iter()
                .zip(&statuses)
                .find(|(_, s)| matches!(s, Stored::Damaged(_)))
        {
            damaged.push(format!(
                "{} ({d})",
                dir.join("variants").join(&entry.id).display()
            ));
        }
        match source {
            None if !matches!(status(target), Stored::Solved | Stored::Failed) => {
                missing.push(entry.id.as_str());
            }
            Some(dir) if !same(dir, target) => {
                let to = target.join("variants").join(&entry.id);
                if status(target) != Stored::Solved {
                    clear(&to).map_err(io_failure)?;
                    copy_variant(&dir.join("variants").join(&entry.id), &to)?;
                    copied += 1;
                }
            }
            _ => {}
        }
    }
    if !missing.is_empty() {
        return Err(StudyError::MergeIncomplete {
            missing: missing.iter().map(|m| m.to_string()).collect(),
            total: manifest.variants.len(),
            damaged,
        });
    }
    let (outcomes, summary) = write_summary(target, &manifest, Vec::new())?;
    drop(held);
    Ok(MergeReport {
        target: target.to_path_buf(),
        batch: manifest.describe(),
        copied,
        damaged,
        failures: failures(&outcomes, &vec![true; outcomes.len()]),
        summary,
    })
}
