//! What the mesh cache did for one mesh.

use std::fmt;
use std::path::PathBuf;

/// How an environment mesh was obtained, as far as the on-disk cache is concerned
/// (see [`crate::mesh_cache`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum MeshCacheUse {
    /// The cache was not used: turned off, the file too small to be worth it, or the
    /// mesh not read from a file.
    #[default]
    Off,
    /// Read from the cache file (nothing parsed or built).
    Hit {
        /// The cache file.
        file: PathBuf,
    },
    /// Not in the cache: built from the mesh file and written to the cache.
    Written {
        /// The cache file.
        file: PathBuf,
    },
    /// The cache file was unusable (corrupt, truncated, for another key): ignored,
    /// the mesh built from its file and the cache file replaced.
    Replaced {
        /// The cache file.
        file: PathBuf,
        /// What was wrong with it.
        reason: String,
    },
    /// Built from the mesh file; the cache could not be written (the mesh is fine).
    NotWritten {
        /// Why (e.g. the folder is read-only).
        reason: String,
    },
}

impl MeshCacheUse {
    /// Whether the mesh was read from the cache.
    pub fn is_hit(&self) -> bool {
        matches!(self, Self::Hit { .. })
    }

    /// A one-word summary for results: `off`, `hit`, `written`, `replaced`,
    /// `not written`.
    pub fn label(&self) -> &'static str {
        match self {
            Self::Off => "off",
            Self::Hit { .. } => "hit",
            Self::Written { .. } => "written",
            Self::Replaced { .. } => "replaced",
            Self::NotWritten { .. } => "not written",
        }
    }
}

/// One line for the terminal, e.g. `read from the mesh cache (/home/u/.cache/…)`.
impl fmt::Display for MeshCacheUse {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Off => write!(f, "built (mesh cache not used)"),
            Self::Hit { file } => write!(f, "read from the mesh cache ({})", file.display()),
            Self::Written { file } => {
                write!(
                    f,
                    "built and written to the mesh cache ({})",
                    file.display()
                )
            }
            Self::Replaced { file, reason } => write!(
                f,
                "built; the mesh cache file was unusable ({reason}) and was replaced ({})",
                file.display()
            ),
            Self::NotWritten { reason } => {
                write!(f, "built; the mesh cache could not be written ({reason})")
            }
        }
    }
}
