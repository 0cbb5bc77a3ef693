//! # strand-contact
//!
//! Contact geometry for hoses and cables: the only crate of the workspace that sees
//! parry. Its public API speaks nalgebra (`Point3<f64>`, `Vector3<f64>`, m).
//!
//! - [`closest`]: exact closest points segment–segment and segment–triangle (parry's
//!   GJK witness points are only about 1e-6 accurate, too coarse to linearise
//!   contact constraints at).
//! - [`mesh`]: environment meshes ([`ObstacleMesh`]): OBJ files or triangle lists
//!   turned into triangle arrays with a flat BVH of our own (plain arrays, stored as
//!   they are in the on-disk cache), built once and shared (`Arc`) across
//!   iterations, variants and batches; nearest-point queries of segments, one local
//!   contact per smooth patch ([`ObstacleMesh::local_contacts`]: both flanks of a
//!   groove), the inside of closed meshes ([`ObstacleMesh::encloses`]) and
//!   [`MeshDiagnostics`] (defects, closedness, bounding box).
//! - [`gaps`]: the contact gaps of whole rods (each edge a capsule of the rod's outer
//!   radius) against meshes and against each other (with a broad phase), with the
//!   data the solver needs to linearise them.

pub mod closest;

pub use closest::{
    SegmentSegment, SegmentTriangle, closest_segment_segment, closest_segment_triangle,
};
pub mod mesh;
pub mod mesh_cache;

pub use mesh_cache::{MeshCacheSettings, MeshCacheUse};

pub use mesh::{
    DISTANCE_GRID_STEPS, DistanceBound, KeptTriangles, LocalContact, MeshDiagnostics, MeshError,
    MeshFormat, ObstacleMesh, Proximity, QueryWork, SMOOTH_PATCH_ANGLE_RAD,
    STL_WELD_RELATIVE_TOLERANCE, distance_grid_floor, query_work, write_ascii_stl,
    write_binary_stl,
};
pub mod gaps;
mod huge_pages;

pub use gaps::{
    Gap, GapError, MeshIndex, Obstacle, RodGeometry, all_gaps, mesh_gaps, require_clearance,
    rod_rod_clearances, rod_rod_gaps, rod_rod_gaps_of, rod_rod_local_minima, rod_rod_minima_of,
};
