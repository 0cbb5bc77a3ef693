//! # strand-assets
//!
//! Pure triangle-mesh geometry for Strand's environments and benchmarks: no parry, no
//! solver. A [`TriangleMesh`] is a vertex list (m) and counter-clockwise triangles
//! (outward normals by the right-hand rule). The crate offers
//!
//! - primitives with sizes in metres: [`axis_box`], [`chamfered_box`], [`cylinder`]
//!   (open or capped, axis `+z`, centred), [`tube`] (a ring such as a fan shroud),
//!   [`plane`] (a flat tessellated floor), [`parallelogram`] (flanks of grooves, faces
//!   of corners) and [`wavy_surface`] (exactly `N` triangles,
//!   for benchmark meshes of 1M–4M triangles);
//! - placement and assembly: [`TriangleMesh::transform`], [`TriangleMesh::translated`],
//!   [`TriangleMesh::rotated`], [`merge`];
//! - checks: [`TriangleMesh::signed_volume`], [`TriangleMesh::edge_report`]
//!   (watertight and consistently oriented), [`TriangleMesh::aabb`],
//!   [`TriangleMesh::distance_to_point`] (brute force, exact point–triangle distance);
//! - OBJ files: [`write_obj`] (atomic, optional `o name` objects, a header comment,
//!   unit scaling) and [`read_obj`] (the `v`/`f`/`o` subset this crate writes);
//! - the engine compartment of the cooler-hose case: [`engine_bay`]; the single parts
//!   of the other bundled cases (a box, a V-groove): [`parts`].
//!
//! The `strand-assets` binary writes the engine-bay OBJ files (`engine-bay --out DIR`),
//! the bundled parts (`parts --out DIR`)
//! and large benchmark surfaces (`surface --triangles N --out FILE`); `clearance`
//! measures how far solved hoses stay from a set of OBJ files.
//!
//! ```
//! use nalgebra::{Point3, Vector3};
//! let floor = strand_assets::plane(2.0, 1.0, 200);
//! let post = strand_assets::cylinder(0.05, 0.3, 32, true).translated(&Vector3::new(0.0, 0.0, 0.15));
//! let scene = strand_assets::merge(&[floor, post]);
//! assert_eq!(scene.triangles.len(), 200 + 4 * 32);
//! let b = strand_assets::axis_box(Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 2.0, 3.0));
//! assert!((b.signed_volume() - 6.0).abs() < 1e-12);
//! ```

pub mod engine_bay;
mod error;
mod mesh;
mod obj;
pub mod parts;
mod primitives;

pub use error::AssetError;
pub use mesh::TriangleMesh;
pub use mesh::distance::closest_point_on_triangle;
pub use mesh::edges::EdgeReport;
pub use mesh::merge::merge;
pub use obj::read::{ObjObject, parse_obj, read_obj};
pub use obj::write::{ObjOptions, write_obj};
pub use primitives::axis_box::axis_box;
pub use primitives::chamfered_box::chamfered_box;
pub use primitives::cylinder::cylinder;
pub use primitives::parallelogram::parallelogram;
pub use primitives::plane::plane;
pub use primitives::tube::tube;
pub use primitives::wavy_surface::wavy_surface;
