//! Rod–rod gaps: capsule–capsule distances between edges of all rods.

use super::broad_phase::{Aabb, overlapping_pairs};
use super::mesh_gaps::check_margin;
use super::{Gap, GapError, Obstacle, RodGeometry, validate};
use crate::closest::{TIE_TOLERANCE, closest_segment_segment};
use nalgebra::Unit;

/// One [`Gap`] per pair of rod edges whose gap `distance − radius_a − radius_b` is at
/// most `margin` (m), over all rods including each rod with itself.
///
/// Each pair appears once: `rod`/`edge` is the lower `(rod, edge)` of the two, `with`
/// the other (`Obstacle::Rod` with its parameter `t`). Edges sharing a vertex
/// (consecutive edges of one rod) are always skipped; `exclude(rod_a, edge_a, rod_b,
/// edge_b)` skips further pairs (e.g. edges close along the same rod, or rod ends
/// held together by a junction), called with `(rod_a, edge_a) < (rod_b, edge_b)`.
///
/// Candidates come from a sweep-and-prune broad phase over the edges' capsule boxes
/// grown by half the margin.
pub fn rod_rod_gaps(
    rods: &[RodGeometry],
    margin: f64,
    mut exclude: impl FnMut(usize, usize, usize, usize) -> bool,
) -> Result<Vec<Gap>, GapError> {
    validate(rods)?;
    check_margin(margin)?;
    let mut edges = Vec::new();
    let mut boxes = Vec::new();
    for (rod, geometry) in rods.iter().enumerate() {
        for (edge, ends) in geometry.vertices.windows(2).enumerate() {
            edges.push((rod, edge));
            let grow = geometry.radius + 0.5 * margin;
            boxes.push(Aabb::of_segment(&ends[0], &ends[1], grow));
        }
    }
    let mut gaps = Vec::new();
    for (first, second) in overlapping_pairs(&boxes) {
        // Edges are listed in (rod, edge) order, so `first` is the lower one.
        let ((rod_a, edge_a), (rod_b, edge_b)) = (edges[first], edges[second]);
        if rod_a == rod_b && edge_b <= edge_a + 1 {
            continue;
        }
        if exclude(rod_a, edge_a, rod_b, edge_b) {
            continue;
        }
        let (a, b) = (&rods[rod_a], &rods[rod_b]);
        let (a0, a1) = (&a.vertices[edge_a], &a.vertices[edge_a + 1]);
        let (b0, b1) = (&b.vertices[edge_b], &b.vertices[edge_b + 1]);
        let closest = closest_segment_segment(a0, a1, b0, b1);
        let gap = closest.distance - a.radius - b.radius;
        if gap > margin {
            continue;
        }
        let size = (a1 - a0).norm().max((b1 - b0).norm());
        let direction = closest.point_on_first - closest.point_on_second;
        if closest.distance <= TIE_TOLERANCE * size {
            return Err(GapError::CentrelineTouches {
                rod: rod_a,
                edge: edge_a,
                what: format!("crosses rod {rod_b} edge {edge_b}"),
                point: closest.point_on_second,
            });
        }
        gaps.push(Gap {
            rod: rod_a,
            edge: edge_a,
            s: closest.s,
            with: Obstacle::Rod {
                rod: rod_b,
                edge: edge_b,
                t: closest.t,
            },
            point: closest.point_on_first,
            witness: closest.point_on_second,
            normal: Unit::new_normalize(direction),
            gap,
        });
    }
    Ok(gaps)
}
