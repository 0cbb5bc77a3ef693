//! Which edges of a rod can hold its least gap to a mesh: a report's clearance needs
//! only the least gap of every rod and mesh, not every local contact within its
//! 100 mm reach, so the listing ([`Contact::mesh_gaps`]) runs only on the edges (and
//! their vertices) that a cheap lower bound of their distance does not rule out.
//!
//! Each edge's distance `d` to the mesh has a lower bound `⌊d⌋` with
//! `15/16 d < ⌊d⌋ ≤ d` ([`ObstacleMesh::segment_distance_bound`]), so the least
//! distance `D` of all edges is below `16/15` of every bound; an edge whose bound is
//! above that by more than [`LEAST_GAP_GUARD`] is ruled out, and of the rest (those
//! within about 7 % of `D`) the exact distances
//! ([`ObstacleMesh::segment_distance`]) keep the edges within the guard of `D`. An
//! edge farther than that cannot hold a gap within the guard of `D`: every gap the listing gives on an edge or at its vertices is at least the
//! edge's distance (less rounding), and the listing's least gap is within rounding
//! and its interior-point band of `D`. The listing of the edges left gives the same
//! least gap, at the same place, as the listing of every edge: the same features in
//! the same order with the same numbers, less the ones that cannot be least.

use strand_contact::{ObstacleMesh, RodGeometry};

use super::Contact;

/// How far above the least distance (m) an edge's distance may be and still be
/// listed: far above the rounding of distances (about 1e-16 m per metre of the
/// coordinates), the band by which an interior point must be nearer than its edge's
/// vertices to be listed (1e-12 m per metre of edge) and the low-order parts of the
/// positions added to the gaps.
pub(crate) const LEAST_GAP_GUARD: f64 = 1e-9;

/// `16/15`, rounded up, and a relative margin for the product's rounding.
const BOUND_TO_DISTANCE: f64 = (16.0 / 15.0) * (1.0 + 1e-12);

impl Contact {
    /// Per edge of `geometry`, whether it may hold the rod's least gap to `mesh`
    /// within `reach` (m, centreline to surface), and the reach that holds every gap
    /// of those edges within [`LEAST_GAP_GUARD`] of the least ([`Contact::edges_within`]);
    /// `None` where no edge is within reach.
    pub(super) fn least_gap_edges(
        mesh: &ObstacleMesh,
        geometry: &RodGeometry,
        reach: f64,
    ) -> Option<(Vec<bool>, f64)> {
        Self::edges_within(mesh, geometry, reach, 0.0)
    }

    /// Per edge of `geometry`, whether it may hold a gap to `mesh` within `band` (m)
    /// of the rod's least (and [`LEAST_GAP_GUARD`]), within `reach` (m, centreline to
    /// surface); `None` where no edge is within reach. Also returns the reach (m,
    /// centreline to surface, at most `reach`) within which those gaps lie: the
    /// least distance, the band and twice the guard (a listing within it finds them
    /// with the same numbers and leaves out the farther local contacts, whose
    /// candidate triangles would cost a search of the whole reach).
    pub(super) fn edges_within(
        mesh: &ObstacleMesh,
        geometry: &RodGeometry,
        reach: f64,
        band: f64,
    ) -> Option<(Vec<bool>, f64)> {
        let guard = LEAST_GAP_GUARD + band;
        let vertices = geometry.vertices;
        let edges = vertices.len().saturating_sub(1);
        // Each edge's lower bound, with the least upper bound of the least distance.
        let mut bounds = vec![f64::INFINITY; edges];
        let mut least = f64::INFINITY;
        for (edge, bound) in bounds.iter_mut().enumerate() {
            let (a, b) = (&vertices[edge], &vertices[edge + 1]);
            let limit = reach.min(least + guard);
            if !Self::in_reach(mesh, a, b, limit) {
                continue;
            }
            if let Some(found) = mesh.segment_distance_bound(a, b, limit) {
                *bound = found;
                least = least.min(found * BOUND_TO_DISTANCE);
            }
        }
        // The edges the bounds leave, by their exact distances.
        let mut distances = vec![f64::INFINITY; edges];
        let mut nearest = f64::INFINITY;
        for (edge, distance) in distances.iter_mut().enumerate() {
            if bounds[edge] > least + guard {
                continue;
            }
            let (a, b) = (&vertices[edge], &vertices[edge + 1]);
            let limit = reach.min(least + guard);
            if let Some(found) = mesh.segment_distance(a, b, limit) {
                *distance = found;
                nearest = nearest.min(found);
            }
        }
        nearest.is_finite().then(|| {
            let marks = distances
                .iter()
                .map(|&distance| distance <= nearest + guard)
                .collect();
            (marks, reach.min(nearest + guard + LEAST_GAP_GUARD))
        })
    }
}
