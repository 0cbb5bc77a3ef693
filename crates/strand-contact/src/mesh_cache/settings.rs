//! Where the mesh cache lives and whether it is used.

use std::path::PathBuf;

/// Settings of the on-disk mesh cache (see [`crate::mesh_cache`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MeshCacheSettings {
    /// The cache folder; `None` turns the cache off. Default: see [`Self::from_env`].
    pub directory: Option<PathBuf>,
    /// Mesh files smaller than this are built, not cached, bytes (default
    /// [`Self::DEFAULT_MIN_FILE_BYTES`], 1 MiB: about 25k triangles of OBJ).
    pub min_file_bytes: u64,
    /// The most the folder's cache files may take, bytes: after a cache file is
    /// written, the least recently used ones (a hit counts as a use) are removed until
    /// the rest fit (default [`Self::DEFAULT_MAX_BYTES`], 10 GiB; `STRAND_MESH_CACHE_MAX_MB`).
    pub max_bytes: u64,
}

impl MeshCacheSettings {
    /// The default threshold below which mesh files are not cached, bytes.
    pub const DEFAULT_MIN_FILE_BYTES: u64 = 1 << 20;

    /// The default size limit of the cache folder, bytes (10 GiB: about forty
    /// 4M-triangle meshes).
    pub const DEFAULT_MAX_BYTES: u64 = 10 << 30;

    /// The cache turned off.
    pub fn off() -> Self {
        Self {
            directory: None,
            min_file_bytes: Self::DEFAULT_MIN_FILE_BYTES,
            max_bytes: Self::DEFAULT_MAX_BYTES,
        }
    }

    /// The cache in `directory`, for files of at least `min_file_bytes` bytes, within
    /// the default size limit.
    pub fn in_directory(directory: impl Into<PathBuf>, min_file_bytes: u64) -> Self {
        Self {
            directory: Some(directory.into()),
            min_file_bytes,
            max_bytes: Self::DEFAULT_MAX_BYTES,
        }
    }

    /// The same settings with the cache folder limited to `max_bytes` bytes.
    pub fn with_max_bytes(self, max_bytes: u64) -> Self {
        Self { max_bytes, ..self }
    }

    /// The settings from the environment: off when `STRAND_MESH_CACHE` is `off`, `0`,
    /// `false` or `no`; else the folder `$STRAND_CACHE_DIR`, or
    /// `$XDG_CACHE_HOME/strand/meshes`, or `$HOME/.cache/strand/meshes` (off when none
    /// of them is set). The size limit is `$STRAND_MESH_CACHE_MAX_MB` megabytes (10⁶
    /// bytes) when that is a whole number, else the default.
    pub fn from_env() -> Self {
        let var = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty());
        let disabled = var("STRAND_MESH_CACHE").is_some_and(|v| {
            let v = v.to_string_lossy().to_ascii_lowercase();
            matches!(v.trim(), "off" | "0" | "false" | "no")
        });
        let directory = if disabled {
            None
        } else {
            var("STRAND_CACHE_DIR")
                .map(PathBuf::from)
                .or_else(|| var("XDG_CACHE_HOME").map(|d| PathBuf::from(d).join("strand/meshes")))
                .or_else(|| var("HOME").map(|d| PathBuf::from(d).join(".cache/strand/meshes")))
        };
        let max_bytes = var("STRAND_MESH_CACHE_MAX_MB")
            .and_then(|v| v.to_string_lossy().trim().parse::<u64>().ok())
            .map_or(Self::DEFAULT_MAX_BYTES, |mb| mb.saturating_mul(1_000_000));
        Self {
            directory,
            min_file_bytes: Self::DEFAULT_MIN_FILE_BYTES,
            max_bytes,
        }
    }
}
