//! The cache file layout: a 48-byte header, then the content.
//!
//! Header: magic `STRNDMSH`, format version (`u32`), 4 zero bytes, the key (16 bytes),
//! the content length and its checksum (`u64` each). Content: the diagnostics (10
//! counts as `u64`, closedness, the bounding box as 6 `f64`), the lengths in bytes of
//! the six sections (`u64` each), then the sections back to back: vertices (`3 f64`
//! each), triangles (`3 u32`), cluster order (`u32`), smooth patch of each triangle
//! (`u32`), the BVH's node boxes (`6 f64`) and its node links (`u32`): the arrays of
//! [`crate::mesh::TriangleTree`] as they are in memory. All numbers little-endian.
//!
//! A cache hit reads every piece of [`CHUNK_BYTES`] of the sections straight into its
//! final array (nothing is decoded), the pieces on all cores, each hashed as soon as it
//! is read. The checksum is the xxh3-64 hash of the xxh3-64 hash of the diagnostics and
//! section lengths, then of the xxh3-64 hashes of the pieces in file order.

use std::fs::File;

use nalgebra::Point3;
use rayon::prelude::*;
use xxhash_rust::xxh3::xxh3_64;

use super::key::{CacheKey, FORMAT_VERSION};
use crate::mesh::{FlatBvh, MeshDiagnostics, TriangleTree};

/// The first bytes of every cache file.
const MAGIC: &[u8; 8] = b"STRNDMSH";
/// Bytes before the content.
const HEADER: usize = 48;
/// Sections of the content.
const SECTIONS: usize = 6;
/// Bytes of the content before the sections: diagnostics and section lengths.
const PREAMBLE: usize = 16 * 8 + SECTIONS * 8;
/// Bytes of a section read and hashed as one piece (1 MiB; the last may be shorter).
const CHUNK_BYTES: usize = 1 << 20;

/// The parts of a built mesh that a cache file holds.
pub(crate) struct CachedMesh {
    /// Triangles and BVH.
    pub tree: TriangleTree,
    /// Smooth patch of every triangle.
    pub patch: Vec<u32>,
    /// Diagnostics (bounding box in the mesh's frame).
    pub diagnostics: MeshDiagnostics,
}

/// The cache file bytes of `mesh` under `key`.
pub(crate) fn encode(
    key: &CacheKey,
    tree: &TriangleTree,
    patch: &[u32],
    d: &MeshDiagnostics,
) -> Result<Vec<u8>, String> {
    let sections: [&[u8]; SECTIONS] = [
        bytemuck::cast_slice(&tree.vertices),
        bytemuck::cast_slice(&tree.indices),
        bytemuck::cast_slice(&tree.order),
        bytemuck::cast_slice(patch),
        bytemuck::cast_slice(&tree.bvh.boxes),
        bytemuck::cast_slice(&tree.bvh.links),
    ];
    let counts = [
        d.triangles,
        d.degenerate_skipped,
        d.slivers,
        d.vertices,
        d.duplicate_vertices,
        d.boundary_edges,
        d.non_manifold_edges,
        d.misoriented_edges,
        d.patches,
        usize::from(d.closed),
    ];
    let [min, max] = d.bounding_box_m;
    let corners = [min.x, min.y, min.z, max.x, max.y, max.z];
    let mut preamble = Vec::with_capacity(PREAMBLE);
    counts
        .iter()
        .for_each(|&n| preamble.extend_from_slice(&(n as u64).to_le_bytes()));
    corners
        .iter()
        .for_each(|x| preamble.extend_from_slice(&x.to_le_bytes()));
    sections
        .iter()
        .for_each(|s| preamble.extend_from_slice(&(s.len() as u64).to_le_bytes()));
    let pieces: Vec<&[u8]> = sections
        .iter()
        .flat_map(|s| s.chunks(CHUNK_BYTES))
        .collect();
    let hashes: Vec<u64> = pieces.par_iter().map(|piece| xxh3_64(piece)).collect();
    let content = PREAMBLE + sections.iter().map(|s| s.len()).sum::<usize>();
    let mut file = Vec::with_capacity(HEADER + content);
    file.extend_from_slice(MAGIC);
    file.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    file.extend_from_slice(&[0; 4]);
    file.extend_from_slice(&key.0.to_le_bytes());
    file.extend_from_slice(&(content as u64).to_le_bytes());
    file.extend_from_slice(&checksum(&preamble, &hashes).to_le_bytes());
    file.extend_from_slice(&preamble);
    sections.iter().for_each(|s| file.extend_from_slice(s));
    Ok(file)
}

/// The checksum of the content from the preamble and the hashes of the pieces.
fn checksum(preamble: &[u8], hashes: &[u64]) -> u64 {
    let mut digests = xxh3_64(preamble).to_le_bytes().to_vec();
    hashes
        .iter()
        .for_each(|h| digests.extend_from_slice(&h.to_le_bytes()));
    xxh3_64(&digests)
}

/// The mesh stored in the cache file `source` (of `file_length` bytes) for `key`, or
/// what is wrong with the file. Reads the pieces of each section straight into its
/// array on all cores and checks the checksum.
pub(crate) fn decode(
    key: &CacheKey,
    source: &File,
    file_length: u64,
) -> Result<CachedMesh, String> {
    let mut header = [0u8; HEADER];
    read_at(source, &mut header, 0)
        .map_err(|_| "not a Strand mesh cache file (too short)".to_string())?;
    if &header[..8] != MAGIC {
        return Err("not a Strand mesh cache file".to_string());
    }
    let word = |k: usize| u64::from_le_bytes(header[8 * k..8 * k + 8].try_into().expect("8"));
    let version = word(1) as u32;
    if version != FORMAT_VERSION {
        return Err(format!(
            "format version {version}, expected {FORMAT_VERSION}"
        ));
    }
    if (u128::from(word(2)) | u128::from(word(3)) << 64) != key.0 {
        return Err("stored for another mesh".to_string());
    }
    let (length, expected) = (word(4), word(5));
    if file_length != HEADER as u64 + length {
        return Err(format!(
            "{} bytes, the header says {} (truncated?)",
            file_length,
            HEADER as u64 + length
        ));
    }
    if length < PREAMBLE as u64 {
        return Err("shorter than its preamble (corrupt)".to_string());
    }
    let mut preamble = [0u8; PREAMBLE];
    read_at(source, &mut preamble, HEADER as u64).map_err(|e| format!("cannot read it: {e}"))?;
    let word = |k: usize| u64::from_le_bytes(preamble[8 * k..8 * k + 8].try_into().expect("8"));
    let counts: [usize; 10] = std::array::from_fn(|k| word(k) as usize);
    let corners: [f64; 6] = std::array::from_fn(|k| f64::from_bits(word(10 + k)));
    let bytes: [u64; SECTIONS] = std::array::from_fn(|k| word(16 + k));
    if bytes.iter().try_fold(0u64, |sum, &b| sum.checked_add(b)) != Some(length - PREAMBLE as u64) {
        return Err("inconsistent section lengths (corrupt)".to_string());
    }
    let mut vertices: Vec<[f64; 3]> = zeroed(bytes[0])?;
    let mut indices: Vec<[u32; 3]> = zeroed(bytes[1])?;
    let mut order: Vec<u32> = zeroed(bytes[2])?;
    let mut patch: Vec<u32> = zeroed(bytes[3])?;
    let mut boxes: Vec<[f64; 6]> = zeroed(bytes[4])?;
    let mut links: Vec<u32> = zeroed(bytes[5])?;
    let sections: [&mut [u8]; SECTIONS] = [
        bytemuck::cast_slice_mut(&mut vertices),
        bytemuck::cast_slice_mut(&mut indices),
        bytemuck::cast_slice_mut(&mut order),
        bytemuck::cast_slice_mut(&mut patch),
        bytemuck::cast_slice_mut(&mut boxes),
        bytemuck::cast_slice_mut(&mut links),
    ];
    let mut offset = (HEADER + PREAMBLE) as u64;
    let mut pieces: Vec<(u64, &mut [u8])> = Vec::new();
    for section in sections {
        for piece in section.chunks_mut(CHUNK_BYTES) {
            let at = offset;
            offset += piece.len() as u64;
            pieces.push((at, piece));
        }
    }
    let hashes: Result<Vec<u64>, String> = pieces
        .into_par_iter()
        .map(|(at, piece)| {
            read_at(source, piece, at).map_err(|e| format!("cannot read it: {e}"))?;
            Ok(xxh3_64(piece))
        })
        .collect();
    if checksum(&preamble, &hashes?) != expected {
        return Err("checksum mismatch (corrupt)".to_string());
    }
    let bvh = FlatBvh { boxes, links };
    let triangles = indices.len();
    let (n, clusters) = (
        vertices.len(),
        triangles.div_ceil(crate::mesh::CLUSTER_SIZE),
    );
    let consistent = counts[0] == triangles
        && counts[3] == n
        && order.len() == triangles
        && patch.len() == triangles
        && all_below(bytemuck::cast_slice(&indices), n)
        && all_below(&order, triangles)
        && all_below(&patch, triangles)
        && bvh.is_well_formed(clusters);
    if !consistent {
        return Err("inconsistent sizes or indices".to_string());
    }
    let diagnostics = MeshDiagnostics {
        triangles,
        degenerate_skipped: counts[1],
        slivers: counts[2],
        vertices: n,
        duplicate_vertices: counts[4],
        boundary_edges: counts[5],
        non_manifold_edges: counts[6],
        misoriented_edges: counts[7],
        patches: counts[8],
        closed: counts[9] != 0,
        bounding_box_m: [
            Point3::new(corners[0], corners[1], corners[2]),
            Point3::new(corners[3], corners[4], corners[5]),
        ],
    };
    Ok(CachedMesh {
        tree: TriangleTree {
            vertices,
            indices,
            order,
            bvh,
        },
        patch,
        diagnostics,
    })
}

/// Whether every number of `values` is below `bound`: in pieces of 64 Ki numbers on
/// all cores (a parallel test per number would cost more than the test).
fn all_below(values: &[u32], bound: usize) -> bool {
    values
        .par_chunks(1 << 16)
        .all(|piece| piece.iter().all(|&v| (v as usize) < bound))
}

/// An array of `bytes` bytes of zeros (huge pages advised: it is written next), or why
/// a section of that length is corrupt.
fn zeroed<T: bytemuck::Pod>(bytes: u64) -> Result<Vec<T>, String> {
    let size = std::mem::size_of::<T>() as u64;
    if !bytes.is_multiple_of(size) {
        return Err("inconsistent section length (corrupt)".to_string());
    }
    let mut array = vec![T::zeroed(); (bytes / size) as usize];
    crate::huge_pages::advise(&mut array);
    Ok(array)
}

/// Fills `out` from `file` at byte `offset` (without moving a shared cursor, so that
/// several threads read one file).
fn read_at(file: &File, out: &mut [u8], offset: u64) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        std::os::unix::fs::FileExt::read_exact_at(file, out, offset)
    }
    #[cfg(not(unix))]
    {
        use std::io::{Read, Seek, SeekFrom};
        let mut handle = file.try_clone()?;
        handle.seek(SeekFrom::Start(offset))?;
        handle.read_exact(out)
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Point3;

    use super::*;
    use crate::ObstacleMesh;

    /// A grid of `2 n²` triangles whose sections span several pieces.
    fn grid(n: usize) -> ObstacleMesh {
        let vertices: Vec<Point3<f64>> = (0..=n)
            .flat_map(|j| {
                (0..=n).map(move |i| Point3::new(i as f64, j as f64, ((i * j) % 7) as f64 * 0.1))
            })
            .collect();
        let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let triangles: Vec<[u32; 3]> = (0..n)
            .flat_map(|j| {
                (0..n).flat_map(move |i| {
                    [
                        [at(i, j), at(i + 1, j), at(i + 1, j + 1)],
                        [at(i, j), at(i + 1, j + 1), at(i, j + 1)],
                    ]
                })
            })
            .collect();
        ObstacleMesh::try_from_triangles("grid", vertices, &triangles).unwrap()
    }

    #[test]
    fn sections_of_several_pieces_read_back_exactly_and_any_damaged_piece_is_caught() {
        let mesh = grid(300);
        let key = CacheKey(0x1234_5678_9abc_def0_1122_3344_5566_7788);
        let bytes = encode(&key, &mesh.tree, &mesh.patch, &mesh.diagnostics).unwrap();
        // The node boxes alone span several pieces.
        assert!(mesh.tree.bvh.boxes.len() * 48 > 3 * CHUNK_BYTES);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("grid.strandmesh");
        std::fs::write(&path, &bytes).unwrap();
        let file = File::open(&path).unwrap();
        let back = decode(&key, &file, bytes.len() as u64).unwrap();
        assert_eq!(back.tree.vertices, mesh.tree.vertices);
        assert_eq!(back.tree.indices, mesh.tree.indices);
        assert_eq!(back.tree.order, mesh.tree.order);
        assert_eq!(back.tree.bvh, mesh.tree.bvh);
        assert_eq!(back.patch, mesh.patch.to_vec());
        assert_eq!(back.diagnostics, mesh.diagnostics);
        // One flipped bit in the first, a middle and the last piece.
        for at in [HEADER + PREAMBLE + 5, bytes.len() / 2 + 3, bytes.len() - 1] {
            let mut damaged = bytes.clone();
            damaged[at] ^= 0x04;
            std::fs::write(&path, &damaged).unwrap();
            let file = File::open(&path).unwrap();
            let reason = decode(&key, &file, bytes.len() as u64).err().unwrap();
            assert!(reason.contains("checksum"), "{at}: {reason}");
        }
        // Another key, version or section length.
        let other = CacheKey(key.0 ^ 1);
        std::fs::write(&path, &bytes).unwrap();
        let file = File::open(&path).unwrap();
        assert!(
            decode(&other, &file, bytes.len() as u64)
                .err()
                .unwrap()
                .contains("another mesh")
        );
        let mut damaged = bytes.clone();
        damaged[HEADER + 16 * 8] ^= 0x08;
        std::fs::write(&path, &damaged).unwrap();
        let file = File::open(&path).unwrap();
        assert!(
            decode(&key, &file, bytes.len() as u64)
                .err()
                .unwrap()
                .contains("section length")
        );
    }
}
