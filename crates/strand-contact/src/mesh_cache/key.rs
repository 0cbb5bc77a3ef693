//! The content address of a built mesh.

use nalgebra::Isometry3;
use xxhash_rust::xxh3::Xxh3;

use crate::mesh::{DEGENERATE_RELATIVE_AREA, SLIVER_RELATIVE_AREA, SMOOTH_PATCH_ANGLE_RAD};

/// Version of the cache file layout; changed whenever the layout or the meaning of the
/// stored data changes.
pub(crate) const FORMAT_VERSION: u32 = 1;

/// The key of a built mesh: a 128-bit xxh3 hash of everything the built data depends
/// on (see [`crate::mesh_cache`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CacheKey(pub u128);

impl CacheKey {
    /// The key of the mesh file content `bytes` placed by `scale_to_metres` and `pose`
    /// (as in [`crate::ObstacleMesh::load`]).
    pub fn of(bytes: &[u8], scale_to_metres: f64, pose: &Isometry3<f64>) -> Self {
        let mut hasher = Xxh3::new();
        hasher.update(b"strand mesh cache");
        hasher.update(&FORMAT_VERSION.to_le_bytes());
        hasher.update(env!("CARGO_PKG_VERSION").as_bytes());
        let t = pose.translation.vector;
        let q = pose.rotation.coords;
        let numbers = [
            scale_to_metres,
            t.x,
            t.y,
            t.z,
            q.x,
            q.y,
            q.z,
            q.w,
            DEGENERATE_RELATIVE_AREA,
            SLIVER_RELATIVE_AREA,
            SMOOTH_PATCH_ANGLE_RAD,
            crate::mesh::CLUSTER_SIZE as f64,
            crate::mesh::STL_WELD_RELATIVE_TOLERANCE,
        ];
        for x in numbers {
            hasher.update(&x.to_bits().to_le_bytes());
        }
        hasher.update(&(bytes.len() as u64).to_le_bytes());
        hasher.update(bytes);
        Self(hasher.digest128())
    }

    /// The cache file name for this key, `<32 hex digits>.strandmesh`.
    pub fn file_name(&self) -> String {
        format!("{:032x}.strandmesh", self.0)
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use super::*;

    #[test]
    fn the_key_changes_with_the_content_and_the_placement() {
        let pose = Isometry3::identity();
        let base = CacheKey::of(b"v 0 0 0\n", 1e-3, &pose);
        assert_eq!(base, CacheKey::of(b"v 0 0 0\n", 1e-3, &pose));
        assert_ne!(base, CacheKey::of(b"v 0 0 1\n", 1e-3, &pose));
        assert_ne!(base, CacheKey::of(b"v 0 0 0\n", 1.0, &pose));
        let moved = Isometry3::translation(0.0, 0.0, 1e-9);
        assert_ne!(base, CacheKey::of(b"v 0 0 0\n", 1e-3, &moved));
        let turned = Isometry3::new(Vector3::zeros(), Vector3::new(0.0, 0.0, 1e-9));
        assert_ne!(base, CacheKey::of(b"v 0 0 0\n", 1e-3, &turned));
        assert_eq!(base.file_name().len(), 32 + ".strandmesh".len());
    }
}
