//! Environment meshes: triangle soups (often open, non-manifold CAD meshes) in plain
//! arrays with a flat BVH over Morton-ordered clusters of triangles, and
//! nearest-point queries of segments against them.
//!
//! A mesh is built once (from an OBJ file with [`ObstacleMesh::load_obj`] or from
//! triangles with [`ObstacleMesh::try_from_triangles`]) and is immutable afterwards,
//! so it can be shared (`Arc`) across solver iterations, case variants and batches.
//! Contact is defined by the unsigned distance to the mesh surface, so meshes need
//! not be closed or consistently oriented. A point near several smooth patches of one
//! mesh (a groove, a corner) has one local contact per patch
//! ([`ObstacleMesh::local_contacts`]). Only a closed, consistently wound mesh has an
//! inside ([`ObstacleMesh::encloses`]); an open mesh (a sheet, a box without a lid)
//! has none.

mod convert;
mod diagnostics;
mod distance_bound;
#[cfg(test)]
mod distance_bound_tests;
mod edge_uses;
mod encloses;
mod error;
mod flat_bvh;
#[cfg(test)]
mod flat_bvh_query_tests;
mod from_triangles;
#[cfg(test)]
mod grid_surface_tests;
mod kept_triangles;
#[cfg(test)]
mod kept_triangles_tests;
mod load_obj;
mod local_contacts;
mod near_scan;
#[cfg(test)]
mod near_scan_tests;
mod node_frames;
#[cfg(test)]
mod node_frames_tests;
mod obstacle_mesh;
mod patch_search;
#[cfg(test)]
mod patch_search_tests;
mod placed;
mod plain_obj;
mod radix_sort;
mod segment_box;
mod segment_proximity;
pub mod stl;
mod topology;
mod triangle_tree;
mod work;

pub use diagnostics::{MeshDiagnostics, SLIVER_RELATIVE_AREA};
pub use distance_bound::{DISTANCE_GRID_STEPS, DistanceBound, distance_grid_floor};
pub use error::{MAX_COORDINATE_M, MeshError};
pub(crate) use flat_bvh::FlatBvh;
pub use from_triangles::DEGENERATE_RELATIVE_AREA;
pub use kept_triangles::KeptTriangles;
pub(crate) use load_obj::{check_placement, name_of};
pub use local_contacts::LocalContact;
pub use obstacle_mesh::ObstacleMesh;
pub use segment_proximity::Proximity;
pub use stl::{MeshFormat, STL_WELD_RELATIVE_TOLERANCE, write_ascii_stl, write_binary_stl};
pub(crate) use stl::{mesh_from_bytes, read};
pub use topology::SMOOTH_PATCH_ANGLE_RAD;
pub(crate) use triangle_tree::{CLUSTER_SIZE, TriangleTree};
pub use work::{QueryWork, query_work};
