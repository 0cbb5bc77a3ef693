//! The environment mesh type.

use std::fmt;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3};

use super::MeshDiagnostics;
use super::triangle_tree::TriangleTree;
use crate::mesh_cache::MeshCacheUse;

/// A rigid environment mesh in world coordinates (m): its triangles and a BVH over
/// clusters of neighbouring triangles.
///
/// Immutable once built; share it with `Arc` across iterations, variants and batches.
/// A mesh moved rigidly ([`ObstacleMesh::placed`], a part riding on a motion) shares
/// the triangles and the BVH of the mesh it was placed from: its queries move the
/// query into the mesh's own frame and the answer back, nothing is rebuilt.
#[derive(Clone)]
pub struct ObstacleMesh {
    pub(crate) name: String,
    /// The triangles and their BVH, in the mesh's own frame.
    pub(crate) tree: Arc<TriangleTree>,
    /// Bounding box of the kept triangles in the mesh's own frame, m.
    pub(crate) bounding_box: [Point3<f64>; 2],
    /// The smooth patch of every triangle (named by its smallest triangle index).
    pub(crate) patch: Arc<[u32]>,
    /// The patch of every BVH node, computed on the first full search
    /// ([`ObstacleMesh::node_patches`]).
    pub(crate) node_patches: Arc<super::patch_search::NodePatches>,
    /// The oriented boxes of the BVH's nodes, computed a chunk at a time as searches
    /// reach them ([`ObstacleMesh::node_frame`]).
    pub(crate) node_frames: Arc<super::node_frames::NodeFrames>,
    /// Diagnostics, with the bounding box in world coordinates.
    pub(crate) diagnostics: MeshDiagnostics,
    /// The map from the mesh's own frame to the world (`None`: the identity).
    pub(crate) placement: Option<Isometry3<f64>>,
    /// Whether the mesh came from the on-disk cache (see [`crate::mesh_cache`]).
    pub(crate) cache_use: MeshCacheUse,
}

impl ObstacleMesh {
    /// The mesh's name (the OBJ file stem, or the name given when building it).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The same mesh under another name.
    pub fn with_name(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// Number of triangles kept (degenerate ones are skipped).
    pub fn triangle_count(&self) -> usize {
        self.tree.indices.len()
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.tree.vertices.len()
    }

    /// Number of degenerate (zero-area) triangles skipped when the mesh was built; the
    /// caller may warn about them.
    pub fn skipped_degenerate(&self) -> usize {
        self.diagnostics.degenerate_skipped
    }

    /// Whether the mesh was read from the on-disk cache, built and written to it, or
    /// built without it ([`ObstacleMesh::load_cached`]).
    pub fn cache_use(&self) -> &MeshCacheUse {
        &self.cache_use
    }

    /// Counts, defects, closedness and bounding box of the mesh, for the user.
    pub fn diagnostics(&self) -> &MeshDiagnostics {
        &self.diagnostics
    }

    /// The smooth patch (see [`super::SMOOTH_PATCH_ANGLE_RAD`]) of triangle `index`
    /// (`< triangle_count()`): the smallest triangle index of the patch.
    pub fn patch_of(&self, index: usize) -> usize {
        self.patch[index] as usize
    }

    /// The axis-aligned bounding box `[min, max]` of the kept triangles in world
    /// coordinates, m.
    pub fn bounding_box(&self) -> [Point3<f64>; 2] {
        self.diagnostics.bounding_box_m
    }

    /// The vertices of triangle `index` (`< triangle_count()`) in world coordinates, m.
    pub fn triangle(&self, index: usize) -> [Point3<f64>; 3] {
        let local = self.local_triangle(index);
        match &self.placement {
            None => local,
            Some(pose) => local.map(|p| pose * p),
        }
    }

    /// The vertices of triangle `index` in the mesh's own frame, m (what the queries
    /// work in).
    pub(crate) fn local_triangle(&self, index: usize) -> [Point3<f64>; 3] {
        self.tree.triangle(index)
    }

    /// Memory held by the mesh in bytes: vertices, triangles, BVH, smooth patches and
    /// name (shared with the meshes placed from it).
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.tree.memory_bytes()
            + self.patch.len() * std::mem::size_of::<u32>()
            + self
                .node_patches
                .get()
                .map_or(0, |p| p.len() * std::mem::size_of::<u32>())
            + self.node_frames.memory_bytes()
            + self.name.capacity()
    }
}

impl AsRef<ObstacleMesh> for ObstacleMesh {
    fn as_ref(&self) -> &ObstacleMesh {
        self
    }
}

impl fmt::Debug for ObstacleMesh {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ObstacleMesh")
            .field("name", &self.name)
            .field("triangles", &self.triangle_count())
            .field("vertices", &self.vertex_count())
            .field("skipped_degenerate", &self.diagnostics.degenerate_skipped)
            .field("bounding_box", &self.bounding_box())
            .field("placement", &self.placement)
            .finish()
    }
}
