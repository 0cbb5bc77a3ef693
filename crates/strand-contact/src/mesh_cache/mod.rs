//! A content-addressed on-disk cache of built environment meshes (triangles, smooth
//! patches, diagnostics and the BVH), so that a repeated solve, or every worker of a
//! batch, reads a large CAD mesh instead of parsing it and building its BVH again.
//!
//! - **Where**: one file per built mesh in [`MeshCacheSettings::directory`]: by default
//!   `$STRAND_CACHE_DIR`, else `$XDG_CACHE_HOME/strand/meshes`, else
//!   `$HOME/.cache/strand/meshes`; `STRAND_MESH_CACHE=off` turns it off
//!   ([`MeshCacheSettings::from_env`]). The folder may be deleted at any time.
//! - **Key** ([`CacheKey`]): a 128-bit xxh3 hash of the mesh file's bytes, the scale and
//!   pose it is placed with, the Strand version, the cache format version and every
//!   constant the built data depends on (degenerate/sliver thresholds, smooth-patch
//!   angle, BVH cluster size). A changed file, placement or Strand version is a new key.
//! - **Written atomically**: to a uniquely named temporary file in the same folder, then
//!   renamed over the final name, so a reader sees a whole file or none, and concurrent
//!   batch workers building the same mesh both succeed (the last rename wins; the files
//!   are identical).
//! - **Verified on read**: magic, format version, key and a 64-bit xxh3 checksum of the
//!   content, then the sizes, indices and the BVH's shape; a file that fails any check
//!   is ignored, the
//!   mesh is built from its file and the cache file replaced ([`MeshCacheUse::Replaced`]).
//! - **Bounded**: after a write, the least recently used cache files (a hit counts as
//!   a use) are removed until the folder fits in [`MeshCacheSettings::max_bytes`]
//!   (10 GiB by default), and temporaries a crashed writer left are removed after an
//!   hour.
//! - **Small files** (below [`MeshCacheSettings::min_file_bytes`]) are not cached: they
//!   build faster than a cache file is worth.
//!
//! Errors of the cache itself never fail a load: a folder that cannot be written gives
//! [`MeshCacheUse::NotWritten`] with the reason, and the mesh as built.

mod evict;
mod format;
mod key;
mod load_cached;
mod settings;
mod store;
mod usage;

pub use key::CacheKey;
pub use settings::MeshCacheSettings;
pub use usage::MeshCacheUse;
