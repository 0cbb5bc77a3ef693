//! The cache file layout: a 48-byte header, then the content.
//!
//! Header: magic `STRNDMSH`, format version (`u32`), 4 zero bytes, the key (16 bytes),
//! the content length and its checksum (`u64` each). Content: the
//! diagnostics (10 counts as `u64`, closedness, the bounding box as 6 `f64`), then
//! sections (each its length in bytes as `u64`, then the bytes): vertices (`3 f64`
//! each), triangles (`3 u32`), cluster order (`u32`), smooth patch of each triangle
//! (`u32`), the BVH's node boxes (`6 f64` each) and its node links (`u32`), the arrays
//! of [`crate::mesh::TriangleTree`] as they are in memory, so a cache hit reads each
//! straight into its final array. All numbers little-endian. The checksum is the
//! xxh3-64 hash of the xxh3-64 hashes of the diagnostics and of each section (with its
//! length), the sections hashed in parallel.

use std::io::Read;

use nalgebra::Point3;
use rayon::prelude::*;
use xxhash_rust::xxh3::xxh3_64;

use super::key::{CacheKey, FORMAT_VERSION};
use crate::mesh::{FlatBvh, MeshDiagnostics, TriangleTree};

/// The first bytes of every cache file.
const MAGIC: &[u8; 8] = b"STRNDMSH";
/// Bytes before the content.
const HEADER: usize = 48;

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
    let mut digests = Vec::new();
    let mut content = Vec::with_capacity(
        256 + tree.vertices.len() * 24
            + tree.indices.len() * 12
            + tree.order.len() * 4
            + patch.len() * 4
            + tree.bvh.heap_bytes(),
    );
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
    for n in counts {
        content.extend_from_slice(&(n as u64).to_le_bytes());
    }
    let [min, max] = d.bounding_box_m;
    for x in [min.x, min.y, min.z, max.x, max.y, max.z] {
        content.extend_from_slice(&x.to_le_bytes());
    }
    digests.extend_from_slice(&xxh3_64(&content).to_le_bytes());
    let sections: [&[u8]; 6] = [
        bytemuck::cast_slice(&tree.vertices),
        bytemuck::cast_slice(&tree.indices),
        bytemuck::cast_slice(&tree.order),
        bytemuck::cast_slice(patch),
        bytemuck::cast_slice(&tree.bvh.boxes),
        bytemuck::cast_slice(&tree.bvh.links),
    ];
    for section in sections {
        let length = (section.len() as u64).to_le_bytes();
        content.extend_from_slice(&length);
        content.extend_from_slice(section);
        digests.extend_from_slice(&length);
        digests.extend_from_slice(&xxh3_64(section).to_le_bytes());
    }
    let mut file = Vec::with_capacity(HEADER + content.len());
    file.extend_from_slice(MAGIC);
    file.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    file.extend_from_slice(&[0; 4]);
    file.extend_from_slice(&key.0.to_le_bytes());
    file.extend_from_slice(&(content.len() as u64).to_le_bytes());
    file.extend_from_slice(&xxh3_64(&digests).to_le_bytes());
    file.extend_from_slice(&content);
    Ok(file)
}

/// The mesh stored in the cache file `source` (of `file_length` bytes) for `key`, or
/// what is wrong with the file. Reads each section straight into its array and checks
/// the checksum on the way.
pub(crate) fn decode(
    key: &CacheKey,
    source: &mut impl Read,
    file_length: u64,
) -> Result<CachedMesh, String> {
    let mut header = [0u8; HEADER];
    source
        .read_exact(&mut header)
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
    let (length, checksum) = (word(4), word(5));
    if file_length != HEADER as u64 + length {
        return Err(format!(
            "{} bytes, the header says {} (truncated?)",
            file_length,
            HEADER as u64 + length
        ));
    }
    let mut r = Reader {
        source,
        left: length,
        digests: Vec::new(),
    };
    let mut preamble = [0u8; 16 * 8];
    r.fill(&mut preamble)?;
    r.digests
        .extend_from_slice(&xxh3_64(&preamble).to_le_bytes());
    let word = |k: usize| u64::from_le_bytes(preamble[8 * k..8 * k + 8].try_into().expect("8"));
    let counts: [usize; 10] = std::array::from_fn(|k| word(k) as usize);
    let corners: [f64; 6] = std::array::from_fn(|k| f64::from_bits(word(10 + k)));
    let vertices: Vec<[f64; 3]> = r.section()?;
    let indices: Vec<[u32; 3]> = r.section()?;
    let order: Vec<u32> = r.section()?;
    let patch: Vec<u32> = r.section()?;
    let boxes: Vec<[f64; 6]> = r.section()?;
    let links: Vec<u32> = r.section()?;
    if r.left != 0 {
        return Err("longer than its sections (corrupt)".to_string());
    }
    let sections: [&[u8]; 6] = [
        bytemuck::cast_slice(&vertices),
        bytemuck::cast_slice(&indices),
        bytemuck::cast_slice(&order),
        bytemuck::cast_slice(&patch),
        bytemuck::cast_slice(&boxes),
        bytemuck::cast_slice(&links),
    ];
    let hashes: Vec<u64> = sections.par_iter().map(|s| xxh3_64(s)).collect();
    let mut digests = r.digests;
    for (section, hash) in sections.iter().zip(hashes) {
        digests.extend_from_slice(&(section.len() as u64).to_le_bytes());
        digests.extend_from_slice(&hash.to_le_bytes());
    }
    if xxh3_64(&digests) != checksum {
        return Err("checksum mismatch (corrupt)".to_string());
    }
    let bvh = FlatBvh { boxes, links };
    let triangles = indices.len();
    let consistent = counts[0] == triangles
        && counts[3] == vertices.len()
        && order.len() == triangles
        && patch.len() == triangles
        && bvh.is_well_formed(triangles.div_ceil(crate::mesh::CLUSTER_SIZE))
        && indices
            .iter()
            .flatten()
            .all(|&i| (i as usize) < vertices.len())
        && order.iter().all(|&t| (t as usize) < triangles)
        && patch.iter().all(|&p| (p as usize) < triangles);
    if !consistent {
        return Err("inconsistent sizes or indices".to_string());
    }
    let diagnostics = MeshDiagnostics {
        triangles,
        degenerate_skipped: counts[1],
        slivers: counts[2],
        vertices: vertices.len(),
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

/// Little-endian numbers and sections of the content, hashed as they are read.
struct Reader<'a, R: Read> {
    source: &'a mut R,
    /// Content bytes not read yet.
    left: u64,
    /// What the checksum is the hash of (see the [module docs](self)).
    digests: Vec<u8>,
}

impl<R: Read> Reader<'_, R> {
    /// Fills `out` from the content.
    fn fill(&mut self, out: &mut [u8]) -> Result<(), String> {
        if (out.len() as u64) > self.left {
            return Err("truncated".to_string());
        }
        self.source
            .read_exact(out)
            .map_err(|e| format!("cannot read it: {e}"))?;
        self.left -= out.len() as u64;
        Ok(())
    }

    fn u64(&mut self) -> Result<u64, String> {
        let mut word = [0u8; 8];
        self.fill(&mut word)?;
        Ok(u64::from_le_bytes(word))
    }

    /// A section (its length in bytes, then plain numbers), read into its array (its
    /// hash is taken by the caller).
    fn section<T: bytemuck::Pod>(&mut self) -> Result<Vec<T>, String> {
        let bytes = self.u64()?;
        let size = std::mem::size_of::<T>() as u64;
        if bytes > self.left || bytes % size != 0 {
            return Err("inconsistent section length (corrupt)".to_string());
        }
        let mut out = vec![T::zeroed(); (bytes / size) as usize];
        self.fill(bytemuck::cast_slice_mut(&mut out))?;
        Ok(out)
    }
}
