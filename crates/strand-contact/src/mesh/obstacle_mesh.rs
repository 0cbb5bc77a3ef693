//! The environment mesh type.

use std::fmt;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3};
use parry3d_f64::shape::TriMesh;

use super::MeshDiagnostics;
use super::convert::from_glam;

/// A rigid environment mesh in world coordinates (m): a parry `TriMesh` with its BVH.
///
/// Immutable once built; share it with `Arc` across iterations, variants and batches.
/// A mesh moved rigidly ([`ObstacleMesh::placed`], a part riding on a motion) shares
/// the triangles and the BVH of the mesh it was placed from: its queries move the
/// query into the mesh's own frame and the answer back, nothing is rebuilt.
#[derive(Clone)]
pub struct ObstacleMesh {
    pub(crate) name: String,
    /// The triangles and their BVH, in the mesh's own frame.
    pub(crate) trimesh: Arc<TriMesh>,
    /// Bounding box of the kept triangles in the mesh's own frame, m.
    pub(crate) bounding_box: [Point3<f64>; 2],
    /// The smooth patch of every triangle (named by its smallest triangle index).
    pub(crate) patch: Arc<[u32]>,
    /// Diagnostics, with the bounding box in world coordinates.
    pub(crate) diagnostics: MeshDiagnostics,
    /// The map from the mesh's own frame to the world (`None`: the identity).
    pub(crate) placement: Option<Isometry3<f64>>,
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
        self.trimesh.num_triangles()
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.trimesh.vertices().len()
    }

    /// Number of degenerate (zero-area) triangles skipped when the mesh was built; the
    /// caller may warn about them.
    pub fn skipped_degenerate(&self) -> usize {
        self.diagnostics.degenerate_skipped
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
        let vertices = self.trimesh.vertices();
        self.trimesh.indices()[index].map(|i| from_glam(vertices[i as usize]))
    }

    /// Approximate memory use of the mesh and its BVH in bytes.
    pub fn memory_bytes(&self) -> usize {
        self.trimesh.total_memory_size() + self.name.capacity()
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
