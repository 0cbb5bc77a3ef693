//! Rod–rod gaps: capsule–capsule distances between edges of all rods.

use super::broad_phase::Aabb;
use super::edge_tree::EdgeTree;
use super::mesh_gaps::check_margin;
use super::{Gap, GapError, Obstacle, RodGeometry, validate};
use crate::closest::{TIE_TOLERANCE, closest_segment_segment};
use nalgebra::Unit;

#[cfg(test)]
thread_local! {
    /// Edge pairs whose exact gap was computed on this thread (a work counter).
    pub(crate) static PAIRS_EVALUATED: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// One [`Gap`] per pair of rod edges whose gap `distance − radius_a − radius_b` is at
/// most `margin` (m), over all rods including each rod with itself.
///
/// Each pair appears once: `rod`/`edge` is the lower `(rod, edge)` of the two, `with`
/// the other (`Obstacle::Rod` with its parameter `t`); gaps come sorted by
/// `(rod, edge, with)`. Edges sharing a vertex (consecutive edges of one rod) are
/// always skipped; `exclude(rod_a, edge_a, rod_b, edge_b)` skips further pairs (e.g.
/// edges close along the same rod, or rod ends held together by a junction), called
/// with `(rod_a, edge_a) < (rod_b, edge_b)`.
///
/// **Contract on `exclude` along one rod:** the excluded partners further along the
/// same rod form one run next to the edge: if `exclude(r, a, r, c)` with `c > a + 1`,
/// then `exclude(r, a, r, b)` for every `a + 1 < b < c` (true of any rule "closer than
/// some arc length", which is what near neighbours are). The end of that run is found
/// by a galloping search (`O(log)` calls per edge) and the edges inside it are never
/// enumerated; every pair past it is still asked about.
///
/// Candidates come from a bounding-box tree over the edges' capsule boxes grown by
/// half the margin (`O(edges · log edges)` plus the pairs whose boxes overlap).
pub fn rod_rod_gaps(
    rods: &[RodGeometry],
    margin: f64,
    exclude: impl FnMut(usize, usize, usize, usize) -> bool,
) -> Result<Vec<Gap>, GapError> {
    rod_rod_gaps_of(rods, margin, exclude, None)
}

/// [`rod_rod_gaps`] of only the pairs whose lower edge (in rod, then edge order: the
/// gap's own edge) `owners` marks (per rod, per edge), where given: the same gaps,
/// with the same numbers, as those of [`rod_rod_gaps`] with such an edge, in the
/// same order. A centreline touching in a pair not searched is not reported.
pub fn rod_rod_gaps_of(
    rods: &[RodGeometry],
    margin: f64,
    mut exclude: impl FnMut(usize, usize, usize, usize) -> bool,
    owners: Option<&[Vec<bool>]>,
) -> Result<Vec<Gap>, GapError> {
    validate(rods)?;
    check_margin(margin)?;
    let (edges, boxes) = edges_and_boxes(rods, margin);
    let tree = EdgeTree::new(&boxes);
    let mut gaps = Vec::new();
    let mut candidates = Vec::new();
    for (first, &(rod_a, edge_a)) in edges.iter().enumerate() {
        if owners.is_some_and(|owners| !owners[rod_a][edge_a]) {
            continue;
        }
        // The first partner along the own rod that is not excluded; past the rod's end
        // (`segments`), the next rod's first edge.
        let segments = rods[rod_a].vertices.len() - 1;
        let along = first_partner(edge_a, segments, |b| exclude(rod_a, edge_a, rod_a, b));
        candidates.clear();
        tree.overlapping_from(&boxes[first], first + (along - edge_a), |second| {
            candidates.push(second);
        });
        for &second in &candidates {
            // Edges are listed in (rod, edge) order, so `first` is the lower one.
            let (rod_b, edge_b) = edges[second];
            if rod_a == rod_b && edge_b <= edge_a + 1 {
                continue;
            }
            if exclude(rod_a, edge_a, rod_b, edge_b) {
                continue;
            }
            if let Some(gap) = edge_pair_gap(rods, (rod_a, edge_a), (rod_b, edge_b), margin)? {
                gaps.push(gap);
            }
        }
    }
    Ok(gaps)
}

/// Every edge of `rods` as `(rod, edge)` in that order, with its capsule's box grown by
/// half of `margin` (two boxes overlap where the capsules may be within `margin`).
pub(super) fn edges_and_boxes(
    rods: &[RodGeometry],
    margin: f64,
) -> (Vec<(usize, usize)>, Vec<Aabb>) {
    let mut edges = Vec::new();
    let mut boxes = Vec::new();
    for (rod, geometry) in rods.iter().enumerate() {
        for (edge, ends) in geometry.vertices.windows(2).enumerate() {
            edges.push((rod, edge));
            let grow = geometry.radius + 0.5 * margin;
            boxes.push(Aabb::of_segment(&ends[0], &ends[1], grow));
        }
    }
    (edges, boxes)
}

/// The gap between edge `edge_a` of rod `rod_a` and edge `edge_b` of rod `rod_b`
/// (`(rod_a, edge_a)` the lower) if it is at most `within` (m); `Err` if their
/// centrelines touch (a gap below any `within ≥ 0`).
pub(super) fn edge_pair_gap(
    rods: &[RodGeometry],
    (rod_a, edge_a): (usize, usize),
    (rod_b, edge_b): (usize, usize),
    within: f64,
) -> Result<Option<Gap>, GapError> {
    #[cfg(test)]
    PAIRS_EVALUATED.with(|c| c.set(c.get() + 1));
    let (a, b) = (&rods[rod_a], &rods[rod_b]);
    let (a0, a1) = (&a.vertices[edge_a], &a.vertices[edge_a + 1]);
    let (b0, b1) = (&b.vertices[edge_b], &b.vertices[edge_b + 1]);
    // Their centres' distance less their half lengths bounds the segments' distance
    // from below: most candidates of a box query are rejected here for a few flops.
    let lower = (nalgebra::center(a0, a1) - nalgebra::center(b0, b1)).norm()
        - 0.5 * ((a1 - a0).norm() + (b1 - b0).norm());
    if lower - a.radius - b.radius > within {
        return Ok(None);
    }
    let closest = closest_segment_segment(a0, a1, b0, b1);
    let gap = closest.distance - a.radius - b.radius;
    if gap > within {
        return Ok(None);
    }
    let size = (a1 - a0).norm().max((b1 - b0).norm());
    if closest.distance <= TIE_TOLERANCE * size {
        return Err(GapError::CentrelineTouches {
            rod: rod_a,
            edge: edge_a,
            what: format!("crosses rod {rod_b} edge {edge_b}"),
            point: closest.point_on_second,
        });
    }
    Ok(Some(Gap {
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
        normal: Unit::new_normalize(closest.point_on_first - closest.point_on_second),
        gap,
    }))
}

/// The first edge `b ≥ edge + 2` of a rod of `segments` edges with `excluded(b)`
/// false, or `segments` if there is none, assuming the excluded ones form a run from
/// `edge + 2` (see [`rod_rod_gaps`]): a galloping search, `O(log run)` calls.
pub(super) fn first_partner(
    edge: usize,
    segments: usize,
    mut excluded: impl FnMut(usize) -> bool,
) -> usize {
    let start = edge + 2;
    if start >= segments || !excluded(start) {
        return start.min(segments);
    }
    // `low` is excluded; find `high` that is not (or the end), doubling the step.
    let (mut low, mut step) = (start, 1);
    let mut high = loop {
        let probe = low + step;
        if probe >= segments {
            break segments;
        }
        if !excluded(probe) {
            break probe;
        }
        low = probe;
        step *= 2;
    };
    // Bisect: `low` excluded, `high` not (or the end).
    while high - low > 1 {
        let middle = low + (high - low) / 2;
        if excluded(middle) {
            low = middle;
        } else {
            high = middle;
        }
    }
    high
}
