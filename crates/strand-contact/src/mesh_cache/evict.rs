//! Keeping the cache folder within its size limit.
//!
//! After a cache file is written, the least recently used cache files are removed
//! until the folder's cache files fit in [`MeshCacheSettings::max_bytes`]. "Used" is the
//! file's modification time: writing sets it, and a cache hit refreshes it. Temporary
//! files that a crashed writer left behind are removed once they are an hour old (a
//! live writer renames its temporary within seconds). Nothing else in the folder is
//! touched.
//!
//! Removing a file that another process is reading is safe: an open file stays
//! readable until it is closed, and a process that finds the file gone builds the mesh
//! from its file, as for any miss.
//!
//! [`MeshCacheSettings::max_bytes`]: super::MeshCacheSettings::max_bytes

use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime};

/// Age after which a temporary file is taken to be left behind by a crashed writer.
const ABANDONED_TEMPORARY_AGE: Duration = Duration::from_secs(3600);

/// What one eviction pass removed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Eviction {
    /// Cache files removed (least recently used first).
    pub files: usize,
    /// Their size, bytes.
    pub bytes: u64,
    /// Abandoned temporary files removed.
    pub temporaries: usize,
}

/// One cache file of the folder.
struct Entry {
    path: PathBuf,
    bytes: u64,
    used: SystemTime,
}

/// Removes the least recently used cache files (`*.strandmesh`) of `directory` until
/// they total at most `max_bytes`, never `keep` (the file just written or read), and
/// the temporary files older than an hour. Files that vanish meanwhile (another
/// process evicting) are skipped; a folder that cannot be listed removes nothing.
pub(crate) fn evict_least_recently_used(directory: &Path, keep: &Path, max_bytes: u64) -> Eviction {
    let mut eviction = Eviction::default();
    let Ok(listing) = std::fs::read_dir(directory) else {
        return eviction;
    };
    let now = SystemTime::now();
    let mut entries = Vec::new();
    for item in listing.flatten() {
        let path = item.path();
        let Ok(metadata) = item.metadata() else {
            continue;
        };
        if !metadata.is_file() {
            continue;
        }
        let name = item.file_name().to_string_lossy().into_owned();
        let used = metadata.modified().unwrap_or(now);
        if name.starts_with('.') && name.ends_with(".tmp") {
            let age = now.duration_since(used).unwrap_or_default();
            if age > ABANDONED_TEMPORARY_AGE && std::fs::remove_file(&path).is_ok() {
                eviction.temporaries += 1;
            }
        } else if name.ends_with(".strandmesh") {
            entries.push(Entry {
                path,
                bytes: metadata.len(),
                used,
            });
        }
    }
    let mut total: u64 = entries.iter().map(|e| e.bytes).sum();
    entries.sort_by_key(|e| e.used);
    for entry in entries {
        if total <= max_bytes {
            break;
        }
        if entry.path == keep {
            continue;
        }
        if std::fs::remove_file(&entry.path).is_ok() {
            total -= entry.bytes;
            eviction.files += 1;
            eviction.bytes += entry.bytes;
        }
    }
    eviction
}

/// Marks `file` as used now (its modification time), so that eviction keeps the
/// files a repeated solve or a batch reads. Best effort: a file that cannot be touched
/// (another owner) only ages.
pub(crate) fn mark_used(file: &std::fs::File) {
    let _ = file.set_modified(SystemTime::now());
}

#[cfg(test)]
mod tests {
    use std::fs::File;

    use super::*;

    fn file(dir: &Path, name: &str, bytes: usize, age_s: u64) -> PathBuf {
        let path = dir.join(name);
        std::fs::write(&path, vec![7u8; bytes]).unwrap();
        let when = SystemTime::now() - Duration::from_secs(age_s);
        File::options()
            .write(true)
            .open(&path)
            .unwrap()
            .set_modified(when)
            .unwrap();
        path
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn the_oldest_cache_files_go_until_the_rest_fits_and_the_kept_one_stays() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        file(d, "a.strandmesh", 100, 400);
        let kept = file(d, "b.strandmesh", 100, 300);
        file(d, "c.strandmesh", 100, 200);
        file(d, "d.strandmesh", 100, 100);
        file(d, "notes.txt", 1000, 10_000);
        // 400 bytes of cache files, 250 allowed: a goes (oldest), b is kept although
        // older than c, so c goes too.
        let eviction = evict_least_recently_used(d, &kept, 250);
        assert_eq!((eviction.files, eviction.bytes), (2, 200));
        assert_eq!(names(d), ["b.strandmesh", "d.strandmesh", "notes.txt"]);
        // Within the limit nothing more goes.
        assert_eq!(
            evict_least_recently_used(d, &kept, 250),
            Eviction::default()
        );
    }

    #[test]
    fn abandoned_temporaries_go_and_live_ones_stay() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        file(d, ".x.strandmesh.12.0.tmp", 10, 2 * 3600);
        file(d, ".y.strandmesh.13.0.tmp", 10, 5);
        let keep = d.join("none.strandmesh");
        let eviction = evict_least_recently_used(d, &keep, u64::MAX);
        assert_eq!((eviction.files, eviction.temporaries), (0, 1));
        assert_eq!(names(d), [".y.strandmesh.13.0.tmp"]);
    }

    #[test]
    fn a_use_makes_a_file_the_newest() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let old = file(d, "old.strandmesh", 100, 500);
        file(d, "new.strandmesh", 100, 10);
        mark_used(&File::open(&old).unwrap());
        let keep = d.join("none.strandmesh");
        evict_least_recently_used(d, &keep, 150);
        assert_eq!(names(d), ["old.strandmesh"]);
    }

    #[test]
    fn a_missing_folder_removes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let gone = dir.path().join("gone");
        assert_eq!(
            evict_least_recently_used(&gone, &gone, 0),
            Eviction::default()
        );
    }
}
