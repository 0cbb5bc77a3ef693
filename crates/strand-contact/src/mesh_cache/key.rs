//! The content address of a built mesh.

use nalgebra::Isometry3;
use std::fs::File;
use std::io::Read;
use std::path::Path;

use xxhash_rust::xxh3::{Xxh3, xxh3_64, xxh3_128_with_seed};

use crate::mesh::{DEGENERATE_RELATIVE_AREA, SLIVER_RELATIVE_AREA, SMOOTH_PATCH_ANGLE_RAD};

/// Version of the cache file layout; changed whenever the layout or the meaning of the
/// stored data changes.
pub(crate) const FORMAT_VERSION: u32 = 1;

/// The key of a built mesh: a 128-bit xxh3 hash of the file bytes, seeded by the 64-bit
/// xxh3 hash of everything else the built data depends on (see [`crate::mesh_cache`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CacheKey(pub u128);

impl CacheKey {
    /// The key of the mesh file content `bytes` placed by `scale_to_metres` and `pose`
    /// (as in [`crate::ObstacleMesh::load`]).
    pub fn of(bytes: &[u8], scale_to_metres: f64, pose: &Isometry3<f64>) -> Self {
        let seed = seed(bytes.len() as u64, scale_to_metres, pose);
        Self(xxh3_128_with_seed(bytes, seed))
    }

    /// The key of the mesh file `path` (its content hashed as it is read through a
    /// small buffer: nothing is kept), the same as [`CacheKey::of`] its bytes.
    pub fn of_file(
        path: &Path,
        scale_to_metres: f64,
        pose: &Isometry3<f64>,
    ) -> std::io::Result<Self> {
        let mut file = File::open(path)?;
        let length = file.metadata()?.len();
        let mut hasher = Xxh3::with_seed(seed(length, scale_to_metres, pose));
        let mut buffer = vec![0u8; 1 << 20];
        let mut read = 0u64;
        loop {
            let n = file.read(&mut buffer)?;
            if n == 0 {
                break;
            }
            hasher.update(&buffer[..n]);
            read += n as u64;
        }
        if read != length {
            return Err(std::io::Error::other("the file changed while it was read"));
        }
        Ok(Self(hasher.digest128()))
    }

    /// The cache file name for this key, `<32 hex digits>.strandmesh`.
    pub fn file_name(&self) -> String {
        format!("{:032x}.strandmesh", self.0)
    }
}

/// The 64-bit xxh3 hash of everything but the file bytes that the built mesh depends
/// on: the format and Strand versions, the file length, the placement and the
/// constants of the mesh build.
fn seed(length: u64, scale_to_metres: f64, pose: &Isometry3<f64>) -> u64 {
    let mut parameters = b"strand mesh cache".to_vec();
    parameters.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    parameters.extend_from_slice(env!("CARGO_PKG_VERSION").as_bytes());
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
        parameters.extend_from_slice(&x.to_bits().to_le_bytes());
    }
    parameters.extend_from_slice(&length.to_le_bytes());
    xxh3_64(&parameters)
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

    #[test]
    fn the_key_of_a_file_read_in_pieces_is_the_key_of_its_bytes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.obj");
        // Over two read buffers, not a multiple of either the buffer or xxh3's stripes.
        let bytes: Vec<u8> = (0..2_500_037u32).map(|i| (i * 7919 % 251) as u8).collect();
        std::fs::write(&path, &bytes).unwrap();
        let pose = Isometry3::translation(0.1, 0.2, 0.3);
        let key = CacheKey::of_file(&path, 1e-3, &pose).unwrap();
        assert_eq!(key, CacheKey::of(&bytes, 1e-3, &pose));
        assert_ne!(key, CacheKey::of(&bytes[1..], 1e-3, &pose));
    }
}
