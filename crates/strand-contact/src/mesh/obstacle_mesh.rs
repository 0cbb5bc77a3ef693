//! The environment mesh type.

use std::fmt;

use nalgebra::Point3;
use parry3d_f64::shape::TriMesh;

use super::MeshDiagnostics;
use super::convert::from_glam;

/// A rigid environment mesh in world coordinates (m): a parry `TriMesh` with its BVH.
///
/// Immutable once built; share it with `Arc` across iterations, variants and batches.
#[derive(Clone)]
pub struct ObstacleMesh {
    pub(crate) name: String,
    pub(crate) trimesh: TriMesh,
    pub(crate) bounding_box: [Point3<f64>; 2],
    /// The smooth patch of every triangle (named by its smallest triangle index).
    pub(crate) patch: Vec<u32>,
    pub(crate) diagnostics: MeshDiagnostics,
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

    /// The axis-aligned bounding box `[min, max]` of the kept triangles, m.
    pub fn bounding_box(&self) -> [Point3<f64>; 2] {
        self.bounding_box
    }

    /// The vertices of triangle `index` (`< triangle_count()`), m.
    pub fn triangle(&self, index: usize) -> [Point3<f64>; 3] {
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
            .field("bounding_box", &self.bounding_box)
            .finish()
    }
}
