//! Exclusive use of a batch directory by one batch: OS file locks (`flock` on Linux,
//! through [`std::fs::File::lock`]; Linux NFS clients map them to NFS byte-range
//! locks, Lustre needs its `flock` mount option), so a lock dies with its process —
//! a killed batch never leaves a stale lock behind.
//!
//! Files in `DIR` (never copied by `strand merge`):
//!
//! - `.strand-lock`, the **folder lock**: held *exclusively* by a whole batch and by
//!   `strand merge` writing into `DIR`, *shared* by the shards of a batch (they write
//!   disjoint variants, so they may share a directory);
//! - `.strand-holder-<role>` (`all`, `merge`, `shard-I-of-N`), the **holder file**
//!   of each running process, held exclusively while it runs: its content
//!   ([`Holder`]) names the host, the PID and the batch (a hash of its `batch.json`),
//!   so that a refused run can say who holds the directory. One process per role: two
//!   runs of the same shard cannot overlap;
//! - `.strand-lock-plan`, the **plan lock**: held briefly, while a process checks the
//!   running holders and `batch.json` and registers itself. So of two different
//!   batches started into one new directory at once exactly one proceeds, and shards
//!   of one batch with different shard counts (overlapping shares) never run together.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// What a process does in a batch directory.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Role {
    /// `strand batch` without `--shard`: the whole batch.
    Whole,
    /// `strand batch --shard I/N`.
    Shard(usize, usize),
    /// `strand merge` writing into the directory.
    Merge,
}

impl Role {
    fn file_name(self) -> String {
        match self {
            Role::Whole => ".strand-holder-all".into(),
            Role::Shard(i, n) => format!(".strand-holder-shard-{i}-of-{n}"),
            Role::Merge => ".strand-holder-merge".into(),
        }
    }

    fn describe(self) -> String {
        match self {
            Role::Whole => "the whole batch".into(),
            Role::Shard(i, n) => format!("shard {i}/{n}"),
            Role::Merge => "strand merge".into(),
        }
    }
}

/// The content of a holder file: who holds the directory, for messages.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Holder {
    /// Host name of the holding process.
    pub host: String,
    /// Its process id (on `host`).
    pub pid: u32,
    /// What it does (`the whole batch`, `shard 2/4`, `strand merge`).
    pub role: String,
    /// The shard count of a shard, else 0.
    pub shards: usize,
    /// The batch it works on: the hash of its `batch.json` (FNV-1a, hex).
    pub batch: String,
    /// When it started, s since the Unix epoch.
    pub started_unix_s: u64,
}

impl std::fmt::Display for Holder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} on host {}, PID {} (batch {})",
            self.role, self.host, self.pid, self.batch
        )
    }
}

/// Why a batch directory cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum LockError {
    /// Another process holds the directory in a way that excludes this run.
    #[error(
        "{} is in use by {}; wait for it to finish, or use another --out (only the shards I/N of one batch, with the same N, can share a directory)",
        dir.display(),
        list(holders)
    )]
    Busy {
        /// The directory.
        dir: PathBuf,
        /// Its running holders (may be empty if they exited meanwhile).
        holders: Vec<Holder>,
    },
    /// A lock file cannot be created, opened or locked.
    #[error("cannot lock {path}: {source}")]
    Io {
        /// The lock file.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
}

/// The holders for a message.
fn list(holders: &[Holder]) -> String {
    if holders.is_empty() {
        "another process, which has just exited (run again)".into()
    } else {
        holders
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The name of this host (`/proc/sys/kernel/hostname`, `/etc/hostname`, `$HOSTNAME`).
pub(crate) fn host_name() -> String {
    ["/proc/sys/kernel/hostname", "/etc/hostname"]
        .iter()
        .find_map(|p| std::fs::read_to_string(p).ok())
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .unwrap_or_else(|| "unknown-host".into())
}

fn open(path: &Path) -> Result<File, LockError> {
    OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)
        .map_err(|source| LockError::Io {
            path: path.to_path_buf(),
            source,
        })
}

fn lock_io(path: &Path) -> impl Fn(std::io::Error) -> LockError + '_ {
    move |source| LockError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Tries to lock `file`: `Ok(false)` if another process holds it.
fn try_lock(file: &File, shared: bool, path: &Path) -> Result<bool, LockError> {
    let tried = if shared {
        file.try_lock_shared()
    } else {
        file.try_lock()
    };
    match tried {
        Ok(()) => Ok(true),
        Err(TryLockError::WouldBlock) => Ok(false),
        Err(TryLockError::Error(e)) => Err(lock_io(path)(e)),
    }
}

/// The running holders of `dir` other than `except` (a holder file name): those whose
/// holder file is locked. Call with the plan lock held.
fn running_holders(dir: &Path, except: Option<&str>) -> Result<Vec<Holder>, LockError> {
    let entries = std::fs::read_dir(dir).map_err(lock_io(dir))?;
    let mut holders = Vec::new();
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().to_string();
        if !name.starts_with(".strand-holder-") || Some(name.as_str()) == except {
            continue;
        }
        let path = entry.path();
        let mut file = open(&path)?;
        if try_lock(&file, false, &path)? {
            continue; // Nobody holds it: a finished or killed run.
        }
        let mut text = String::new();
        let _ = file.read_to_string(&mut text);
        holders.push(serde_json::from_str(&text).unwrap_or(Holder {
            host: "an unknown host".into(),
            pid: 0,
            role: name.trim_start_matches(".strand-holder-").into(),
            shards: 0,
            batch: "unknown".into(),
            started_unix_s: 0,
        }));
    }
    holders.sort_by(|a, b| (&a.role, &a.host, a.pid).cmp(&(&b.role, &b.host, b.pid)));
    Ok(holders)
}

/// Every holder recorded in `dir`'s holder files, running or not (the last process of
/// each role), for messages.
pub(crate) fn recorded_holders(dir: &Path) -> Vec<Holder> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut holders: Vec<Holder> = entries
        .flatten()
        .filter(|e| {
            e.file_name()
                .to_string_lossy()
                .starts_with(".strand-holder-")
        })
        .filter_map(|e| std::fs::read_to_string(e.path()).ok())
        .filter_map(|text| serde_json::from_str(&text).ok())
        .collect();
    holders.sort_by(|a, b| (&a.role, &a.host, a.pid).cmp(&(&b.role, &b.host, b.pid)));
    holders
}

/// A held batch directory: released when dropped (or when the process ends).
#[derive(Debug)]
pub(crate) struct DirLock {
    _folder: File,
    _holder: File,
    /// The plan lock, held until [`DirLock::release_plan`].
    plan: Option<File>,
}

impl DirLock {
    /// Releases the plan lock (after `batch.json` is checked or written and stale
    /// temporary files are removed), so that the other shards can start.
    pub(crate) fn release_plan(&mut self) {
        self.plan = None;
    }
}

/// Takes `dir` (created if missing) for `role` on the batch hashed `batch`. On success
/// the plan lock is still held: check or write `batch.json` (see [`DirLock`]), then
/// call [`DirLock::release_plan`].
pub(crate) fn acquire(dir: &Path, role: Role, batch: &str) -> Result<DirLock, LockError> {
    std::fs::create_dir_all(dir).map_err(lock_io(dir))?;
    let busy = |holders| LockError::Busy {
        dir: dir.to_path_buf(),
        holders,
    };
    let plan_path = dir.join(".strand-lock-plan");
    let take_plan = || -> Result<File, LockError> {
        let plan = open(&plan_path)?;
        plan.lock().map_err(lock_io(&plan_path))?;
        Ok(plan)
    };
    // The plan lock first: whoever holds the folder lock registered its holder file
    // while holding the plan lock, so once we have it, a refusal can name them.
    let plan = take_plan()?;
    let folder_path = dir.join(".strand-lock");
    let folder = open(&folder_path)?;
    let shared = matches!(role, Role::Shard(..));
    if !try_lock(&folder, shared, &folder_path)? {
        return Err(busy(running_holders(dir, None)?));
    }
    let holder_name = role.file_name();
    let holder_path = dir.join(&holder_name);
    let mut holder = open(&holder_path)?;
    if !try_lock(&holder, false, &holder_path)? {
        return Err(busy(running_holders(dir, None)?));
    }
    let others = running_holders(dir, Some(&holder_name))?;
    let shards = match role {
        Role::Shard(_, n) => n,
        _ => 0,
    };
    if others
        .iter()
        .any(|h| h.batch != batch || (role != Role::Merge && h.shards != shards))
    {
        return Err(busy(others));
    }
    let me = Holder {
        host: host_name(),
        pid: std::process::id(),
        role: role.describe(),
        shards,
        batch: batch.to_string(),
        started_unix_s: std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs()),
    };
    let json = serde_json::to_vec_pretty(&me).unwrap_or_default();
    holder
        .set_len(0)
        .and_then(|()| holder.seek(SeekFrom::Start(0)))
        .and_then(|_| holder.write_all(&json))
        .and_then(|()| holder.flush())
        .map_err(lock_io(&holder_path))?;
    Ok(DirLock {
        _folder: folder,
        _holder: holder,
        plan: Some(plan),
    })
}
