//! Environment meshes: triangle soups (often open, non-manifold CAD meshes) in a parry
//! `TriMesh` with its BVH, and nearest-point queries of segments against them.
//!
//! A mesh is built once (from an OBJ file with [`ObstacleMesh::load_obj`] or from
//! triangles with [`ObstacleMesh::try_from_triangles`]) and is immutable afterwards,
//! so it can be shared (`Arc`) across solver iterations, case variants and batches.
//! Contact is defined by the unsigned distance to the mesh surface, so meshes need
//! not be closed or consistently oriented.

mod convert;
mod error;
mod from_triangles;
mod load_obj;
mod obstacle_mesh;
mod segment_box;
mod segment_proximity;

pub(crate) use convert::to_glam;
pub use error::MeshError;
pub use from_triangles::DEGENERATE_RELATIVE_AREA;
pub use obstacle_mesh::ObstacleMesh;
pub use segment_proximity::Proximity;
