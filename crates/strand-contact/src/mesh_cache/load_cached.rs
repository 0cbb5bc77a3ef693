//! Loading a mesh file through the cache.

use std::path::Path;
use std::sync::Arc;

use nalgebra::Isometry3;

use super::format::{CachedMesh, decode, encode};
use super::{CacheKey, MeshCacheSettings, MeshCacheUse, evict, store};
use crate::mesh::{MeshError, ObstacleMesh, check_placement, mesh_from_bytes, name_of, read};

impl ObstacleMesh {
    /// Loads a mesh file like [`ObstacleMesh::load`] (OBJ or STL, placed by
    /// `x_world = pose · (scale_to_metres · x_file)`, m, rad), through the on-disk
    /// cache of `settings` (see [`crate::mesh_cache`]): a file already built with the
    /// same content and placement is read from the cache, else it is built and
    /// written there. [`ObstacleMesh::cache_use`] says which. The mesh, its contacts
    /// and its diagnostics are the same either way; the errors are those of
    /// [`ObstacleMesh::load`] (the cache never adds one).
    pub fn load_cached(
        path: impl AsRef<Path>,
        scale_to_metres: f64,
        pose: &Isometry3<f64>,
        settings: &MeshCacheSettings,
    ) -> Result<Self, MeshError> {
        let path = path.as_ref();
        check_placement(&path.display().to_string(), scale_to_metres, pose)?;
        let unreadable = |source| MeshError::Read {
            path: path.to_path_buf(),
            source,
        };
        let length = std::fs::metadata(path).map_err(unreadable)?.len();
        let directory = settings
            .directory
            .as_ref()
            .filter(|_| cfg!(target_endian = "little"))
            .filter(|_| length >= settings.min_file_bytes);
        let Some(directory) = directory else {
            return mesh_from_bytes(path, &read(path)?, scale_to_metres, pose);
        };
        // A hit needs only the key: the file is hashed as it is read, not kept.
        let key = CacheKey::of_file(path, scale_to_metres, pose).map_err(unreadable)?;
        let file = directory.join(key.file_name());
        let fault = match store::open(&file) {
            Ok(None) => None,
            Ok(Some((stored, length))) => match decode(&key, &stored, length) {
                Ok(cached) => {
                    evict::mark_used(&stored);
                    let mut mesh = from_cached(name_of(path), cached);
                    mesh.cache_use = MeshCacheUse::Hit { file };
                    return Ok(mesh);
                }
                Err(reason) => Some(reason),
            },
            Err(reason) => Some(reason),
        };
        let bytes = read(path)?;
        let mut mesh = mesh_from_bytes(path, &bytes, scale_to_metres, pose)?;
        // The key of what was built (the file may have changed since it was hashed).
        let key = CacheKey::of(&bytes, scale_to_metres, pose);
        drop(bytes);
        let file = directory.join(key.file_name());
        let written = encode(&key, &mesh.tree, &mesh.patch, &mesh.diagnostics)
            .and_then(|encoded| store::write_atomically(&file, &encoded));
        if written.is_ok() {
            evict::evict_least_recently_used(directory, &file, settings.max_bytes);
        }
        mesh.cache_use = match (written, fault) {
            (Ok(()), None) => MeshCacheUse::Written { file },
            (Ok(()), Some(reason)) => MeshCacheUse::Replaced { file, reason },
            (Err(reason), _) => MeshCacheUse::NotWritten { reason },
        };
        Ok(mesh)
    }
}

/// The mesh named `name` from what a cache file stored.
fn from_cached(name: String, cached: CachedMesh) -> ObstacleMesh {
    ObstacleMesh {
        name,
        bounding_box: cached.diagnostics.bounding_box_m,
        tree: Arc::new(cached.tree),
        patch: cached.patch.into(),
        node_patches: Default::default(),
        node_frames: Default::default(),
        diagnostics: cached.diagnostics,
        placement: None,
        cache_use: MeshCacheUse::Off,
    }
}
