//! The content address of a built mesh.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

use nalgebra::Isometry3;
use rayon::prelude::*;
use xxhash_rust::xxh3::{xxh3_64, xxh3_128, xxh3_128_with_seed};

use crate::mesh::{DEGENERATE_RELATIVE_AREA, SLIVER_RELATIVE_AREA, SMOOTH_PATCH_ANGLE_RAD};

/// Version of the cache file layout; changed whenever the layout or the meaning of the
/// stored data changes.
pub(crate) const FORMAT_VERSION: u32 = 3;

/// The key of a built mesh: a 128-bit xxh3 hash, seeded by the 64-bit xxh3 hash of
/// everything else the built data depends on (see [`crate::mesh_cache`]), of the
/// 128-bit xxh3 hashes of the file's pieces of 1 MiB (so that the pieces of a large
/// file are read and hashed on all cores).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CacheKey(pub u128);

/// Bytes of a mesh file hashed as one piece of its [`CacheKey`] (1 MiB: enough pieces
/// to keep every core busy to the end of a large file).
pub(crate) const PIECE_BYTES: usize = 1 << 20;

impl CacheKey {
    /// The key of the mesh file content `bytes` placed by `scale_to_metres` and `pose`
    /// (as in [`crate::ObstacleMesh::load`]).
    pub fn of(bytes: &[u8], scale_to_metres: f64, pose: &Isometry3<f64>) -> Self {
        let pieces: Vec<u128> = bytes.par_chunks(PIECE_BYTES).map(xxh3_128).collect();
        Self::of_pieces(&pieces, bytes.len() as u64, scale_to_metres, pose)
    }

    /// The key of the mesh file `path`, the same as [`CacheKey::of`] its bytes: its
    /// pieces read and hashed in parallel, each thread through its own file handle and
    /// a buffer of one piece (the file is never held whole).
    pub fn of_file(
        path: &Path,
        scale_to_metres: f64,
        pose: &Isometry3<f64>,
    ) -> std::io::Result<Self> {
        let length = std::fs::metadata(path)?.len();
        let count = length.div_ceil(PIECE_BYTES as u64);
        let pieces: std::io::Result<Vec<u128>> = (0..count)
            .into_par_iter()
            .map_init(
                || {
                    (
                        File::open(path),
                        vec![0u8; PIECE_BYTES.min(length as usize)],
                    )
                },
                |(file, buffer), k| {
                    let start = k * PIECE_BYTES as u64;
                    let size = (length - start).min(PIECE_BYTES as u64) as usize;
                    let file = file
                        .as_mut()
                        .map_err(|e| std::io::Error::new(e.kind(), e.to_string()))?;
                    file.seek(SeekFrom::Start(start))?;
                    let piece = &mut buffer[..size];
                    file.read_exact(piece)?;
                    Ok(xxh3_128(piece))
                },
            )
            .collect();
        let pieces = pieces?;
        if std::fs::metadata(path)?.len() != length {
            return Err(std::io::Error::other("the file changed while it was read"));
        }
        Ok(Self::of_pieces(&pieces, length, scale_to_metres, pose))
    }

    /// The key from the hashes of a file's pieces.
    fn of_pieces(
        pieces: &[u128],
        length: u64,
        scale_to_metres: f64,
        pose: &Isometry3<f64>,
    ) -> Self {
        let seed = seed(length, scale_to_metres, pose);
        let bytes: Vec<u8> = pieces.iter().flat_map(|h| h.to_le_bytes()).collect();
        Self(xxh3_128_with_seed(&bytes, seed))
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
        // Over two pieces, not a multiple of either the piece or xxh3's stripes.
        let bytes: Vec<u8> = (0..(2 * PIECE_BYTES as u32 + 500_037))
            .map(|i| (i * 7919 % 251) as u8)
            .collect();
        std::fs::write(&path, &bytes).unwrap();
        let pose = Isometry3::translation(0.1, 0.2, 0.3);
        let key = CacheKey::of_file(&path, 1e-3, &pose).unwrap();
        assert_eq!(key, CacheKey::of(&bytes, 1e-3, &pose));
        assert_ne!(key, CacheKey::of(&bytes[1..], 1e-3, &pose));
        // A change in any piece changes the key.
        for at in [0, PIECE_BYTES, bytes.len() - 1] {
            let mut changed = bytes.clone();
            changed[at] ^= 1;
            assert_ne!(key, CacheKey::of(&changed, 1e-3, &pose));
        }
    }
}
