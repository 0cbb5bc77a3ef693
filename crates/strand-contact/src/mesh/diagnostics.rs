//! What a user should know about an environment mesh: size, defects, closedness.

use std::fmt;

use nalgebra::Point3;

/// Diagnostics of one environment mesh, computed once when it is built.
///
/// Topology (edges, closedness, smooth patches) is computed with vertices at exactly
/// the same position **welded** into one; the contact mesh itself keeps the duplicates
/// (the distance to the surface does not depend on them).
#[derive(Clone, Debug, PartialEq)]
pub struct MeshDiagnostics {
    /// Triangles kept for contact (degenerate ones excluded).
    pub triangles: usize,
    /// Degenerate (zero-area, see [`super::DEGENERATE_RELATIVE_AREA`]) triangles that
    /// were skipped.
    pub degenerate_skipped: usize,
    /// Kept triangles that are slivers: twice their area below [`SLIVER_RELATIVE_AREA`]
    /// times their longest edge squared (very thin, but usable).
    pub slivers: usize,
    /// Vertices as given (duplicates included).
    pub vertices: usize,
    /// Vertices at exactly the same position as an earlier vertex (welded for the
    /// topology checks, kept in the contact mesh).
    pub duplicate_vertices: usize,
    /// Edges of the welded mesh used by exactly one triangle (the rim of an open
    /// surface).
    pub boundary_edges: usize,
    /// Edges of the welded mesh used by three or more triangles.
    pub non_manifold_edges: usize,
    /// Edges used by two triangles that run along it in the same direction
    /// (inconsistent winding).
    pub misoriented_edges: usize,
    /// Whether the mesh is closed and consistently wound (watertight): every welded
    /// edge is shared by exactly two triangles traversing it in opposite directions.
    /// Only a closed mesh has an inside (see [`super::ObstacleMesh::encloses`]).
    pub closed: bool,
    /// Number of smooth patches: groups of edge-connected triangles whose normals turn
    /// by less than [`super::SMOOTH_PATCH_ANGLE_RAD`] across each shared edge. Each patch
    /// a rod touches gives its own contact constraint.
    pub patches: usize,
    /// Axis-aligned bounding box `[min, max]` of the kept triangles, m.
    pub bounding_box_m: [Point3<f64>; 2],
}

/// A kept triangle is a sliver when twice its area is below this fraction of its
/// longest edge squared (an equilateral triangle has 0.87).
pub const SLIVER_RELATIVE_AREA: f64 = 1e-6;

impl MeshDiagnostics {
    /// Warnings for the user: degenerate triangles, slivers, duplicates, open or
    /// non-manifold edges, inconsistent winding. Empty for a clean mesh.
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let mut note = |count: usize, what: &str| {
            if count > 0 {
                out.push(format!("{count} {what}"));
            }
        };
        note(
            self.degenerate_skipped,
            "degenerate (zero-area) triangle(s) skipped",
        );
        note(self.slivers, "sliver triangle(s) (nearly zero area) kept");
        note(
            self.duplicate_vertices,
            "duplicate vertex/vertices (welded for the edge checks)",
        );
        note(self.non_manifold_edges, "non-manifold edge(s)");
        note(
            self.misoriented_edges,
            "edge(s) with inconsistent triangle winding",
        );
        out
    }

    /// The size of the bounding box along x, y, z, m.
    pub fn size_m(&self) -> [f64; 3] {
        let [min, max] = self.bounding_box_m;
        [max.x - min.x, max.y - min.y, max.z - min.z]
    }
}

/// One line: counts, closedness and the bounding box in mm.
impl fmt::Display for MeshDiagnostics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [min, max] = self.bounding_box_m;
        let [sx, sy, sz] = self.size_m().map(|x| x * 1e3);
        write!(
            f,
            "{} triangles ({} degenerate skipped, {} slivers), {} vertices ({} duplicates, welded \
             for the edge checks), {} open boundary edges, {} non-manifold edges, {}; \
             box ({:.1}, {:.1}, {:.1})..({:.1}, {:.1}, {:.1}) mm, size {sx:.1} x {sy:.1} x {sz:.1} mm",
            self.triangles,
            self.degenerate_skipped,
            self.slivers,
            self.vertices,
            self.duplicate_vertices,
            self.boundary_edges,
            self.non_manifold_edges,
            if self.closed {
                "closed (has an inside)".to_string()
            } else if self.misoriented_edges > 0 {
                format!("not closed ({} misoriented edges)", self.misoriented_edges)
            } else {
                "open (no inside)".to_string()
            },
            min.x * 1e3,
            min.y * 1e3,
            min.z * 1e3,
            max.x * 1e3,
            max.y * 1e3,
            max.z * 1e3,
        )
    }
}
