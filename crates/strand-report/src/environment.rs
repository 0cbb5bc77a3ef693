//! Diagnostics of the environment meshes for `result.json` (`environment[*].diagnostics`).

use std::sync::Arc;

use serde::{Deserialize, Serialize};
use strand_contact::ObstacleMesh;

use crate::{EnvironmentOutline, ResultDoc};

/// What the user should know about one environment mesh (see
/// `strand_contact::MeshDiagnostics`): counts, defects, closedness and bounding box.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshDiagnosticsResult {
    /// Triangles kept for contact.
    pub triangles: usize,
    /// Degenerate (zero-area) triangles skipped.
    pub degenerate_skipped: usize,
    /// Kept triangles that are nearly degenerate (slivers).
    pub slivers: usize,
    /// Vertices in the file (duplicates included).
    pub vertices: usize,
    /// Vertices at exactly the same position as another one.
    pub duplicate_vertices: usize,
    /// Whether duplicates were welded: always `true` for the edge checks (boundary,
    /// non-manifold, closed); the contact mesh keeps them (harmless for distances).
    pub duplicate_vertices_welded: bool,
    /// Edges used by one triangle only (open rim).
    pub boundary_edges: usize,
    /// Edges used by three or more triangles.
    pub non_manifold_edges: usize,
    /// Edges whose two triangles disagree about the winding.
    pub misoriented_edges: usize,
    /// Closed and consistently wound: only then does the mesh have an inside.
    pub closed: bool,
    /// Smooth patches (each touched patch is one contact constraint per rod feature).
    pub patches: usize,
    /// Smallest corner of the bounding box, m.
    pub bounding_box_min_m: [f64; 3],
    /// Largest corner of the bounding box, m.
    pub bounding_box_max_m: [f64; 3],
    /// Size of the bounding box along x, y, z, m.
    pub size_m: [f64; 3],
    /// The on-disk mesh cache: `off`, `hit` (read from the cache), `written` (built and
    /// cached), `replaced` (an unusable cache file rebuilt) or `not written`.
    #[serde(default)]
    pub cache: String,
    /// What the mesh cache did, in words (with the cache file).
    #[serde(default)]
    pub cache_detail: String,
}

impl MeshDiagnosticsResult {
    /// The diagnostics of `mesh`.
    pub fn of(mesh: &ObstacleMesh) -> Self {
        let d = mesh.diagnostics();
        let [min, max] = d.bounding_box_m;
        Self {
            triangles: d.triangles,
            degenerate_skipped: d.degenerate_skipped,
            slivers: d.slivers,
            vertices: d.vertices,
            duplicate_vertices: d.duplicate_vertices,
            duplicate_vertices_welded: true,
            boundary_edges: d.boundary_edges,
            non_manifold_edges: d.non_manifold_edges,
            misoriented_edges: d.misoriented_edges,
            closed: d.closed,
            patches: d.patches,
            bounding_box_min_m: [min.x, min.y, min.z],
            bounding_box_max_m: [max.x, max.y, max.z],
            size_m: d.size_m(),
            cache: mesh.cache_use().label().to_string(),
            cache_detail: mesh.cache_use().to_string(),
        }
    }
}

/// Puts the diagnostics of every mesh into `doc.environment`, one entry per mesh by
/// name (an existing entry, e.g. with outline segments, keeps its segments).
pub fn collect_environment(doc: &mut ResultDoc, meshes: &[Arc<ObstacleMesh>]) {
    for mesh in meshes {
        let diagnostics = Some(MeshDiagnosticsResult::of(mesh));
        match doc.environment.iter_mut().find(|e| e.name == mesh.name()) {
            Some(entry) => entry.diagnostics = diagnostics,
            None => doc.environment.push(EnvironmentOutline {
                name: mesh.name().to_string(),
                segments_m: Vec::new(),
                truncated: false,
                surface_m: Vec::new(),
                surface_cell_m: None,
                diagnostics,
            }),
        }
    }
}
