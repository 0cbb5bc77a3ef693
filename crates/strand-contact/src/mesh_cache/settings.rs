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
}

impl MeshCacheSettings {
    /// The default threshold below which mesh files are not cached, bytes.
    pub const DEFAULT_MIN_FILE_BYTES: u64 = 1 << 20;

    /// The cache turned off.
    pub fn off() -> Self {
        Self {
            directory: None,
            min_file_bytes: Self::DEFAULT_MIN_FILE_BYTES,
        }
    }

    /// The cache in `directory`, for files of at least `min_file_bytes` bytes.
    pub fn in_directory(directory: impl Into<PathBuf>, min_file_bytes: u64) -> Self {
        Self {
            directory: Some(directory.into()),
            min_file_bytes,
        }
    }

    /// The settings from the environment: off when `STRAND_MESH_CACHE` is `off`, `0`,
    /// `false` or `no`; else the folder `$STRAND_CACHE_DIR`, or
    /// `$XDG_CACHE_HOME/strand/meshes`, or `$HOME/.cache/strand/meshes` (off when none
    /// of them is set).
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
        Self {
            directory,
            min_file_bytes: Self::DEFAULT_MIN_FILE_BYTES,
        }
    }
}
