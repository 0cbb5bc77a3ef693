//! Nearest mesh point to a segment (or a point), through the BVH.

use nalgebra::{Point3, Unit, Vector3};
use parry3d_f64::math::Vector as GlamVector;
use parry3d_f64::partitioning::{BvhNode, TraversalAction};

use super::ObstacleMesh;
use super::convert::to_glam;
use super::segment_box::{box_box_distance, segment_box_distance};
use super::work::{count_box, count_exact, count_node};
use crate::closest::{
    Candidate, SegmentTriangle, SegmentTriangleParameters, TIE_TOLERANCE,
    segment_triangle_candidate, segment_triangle_points,
};

/// The nearest point of a mesh to a segment `P(s) = p0 + s (p1 − p0)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Proximity {
    /// Index of the mesh triangle holding the nearest point.
    pub triangle: usize,
    /// Parameter of the nearest point on the segment, in `[0, 1]`.
    pub s: f64,
    /// Barycentric coordinates of the nearest point on the triangle.
    pub barycentric: [f64; 3],
    /// The nearest point on the segment, m.
    pub point_on_segment: Point3<f64>,
    /// The nearest point on the mesh, m.
    pub point_on_mesh: Point3<f64>,
    /// Distance between the two points, m (≥ 0).
    pub distance: f64,
    /// Unit vector from the mesh point to the segment point; `None` when the segment
    /// touches or crosses the mesh surface (distance 0 up to rounding), where no
    /// direction is defined: the caller reports "inside/touching the obstacle at
    /// `point_on_mesh`".
    pub normal: Option<Unit<Vector3<f64>>>,
    /// The interval `[low, high]` of segment parameters whose points are all nearest
    /// (to within rounding): `low == high == s` unless the segment runs parallel to
    /// the mesh over a stretch (an edge lying on a face, or along a ridge).
    pub tie: [f64; 2],
}

impl ObstacleMesh {
    /// The nearest mesh point to segment `[p0, p1]` (m) within `max_distance` (m), or
    /// `None` if the mesh is farther away.
    ///
    /// Candidate triangles come from the BVH (best-first search pruned by the
    /// distance between the segment's and the nodes' bounding boxes); distances are
    /// exact ([`crate::closest_segment_triangle`]). When the nearest points form an
    /// interval spanning several triangles (an edge lying flat over a tessellated
    /// floor), the midpoint of the whole interval is returned.
    pub fn segment_proximity(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        max_distance: f64,
    ) -> Option<Proximity> {
        let (l0, l1) = (self.to_local(p0), self.to_local(p1));
        self.segment_proximity_here(&l0, &l1, max_distance)
            .map(|p| self.to_world(p, p0, p1))
    }

    /// [`ObstacleMesh::segment_proximity`] of a segment in the mesh's own frame.
    fn segment_proximity_here(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        max_distance: f64,
    ) -> Option<Proximity> {
        let [min, max] = self.bounding_box;
        let tolerance = TIE_TOLERANCE * ((p1 - p0).norm() + (max - min).norm());
        let (triangle, best) = self.nearest(p0, p1, max_distance)?;
        let mut result = self.proximity(p0, p1, triangle, best.value, tolerance);
        let half = 0.5 * best.interval;
        result.tie = [(result.s - half).max(0.0), (result.s + half).min(1.0)];
        let on_boundary = best.value.1.contains(&0.0);
        if best.interval > 0.0 || on_boundary {
            let limit = result.distance + tolerance;
            let (low, high) = self.tie_interval(p0, p1, limit);
            if high - low > best.interval * (1.0 + 1e-9) {
                let s = 0.5 * (low + high);
                let point = p0 + (p1 - p0) * s;
                if let Some((triangle, at_mid)) = self.nearest(&point, &point, limit) {
                    let mut mid = self.proximity(&point, &point, triangle, at_mid.value, tolerance);
                    mid.s = s;
                    mid.tie = [low.max(0.0), high.min(1.0)];
                    result = mid;
                }
            }
        }
        Some(result)
    }

    /// The nearest mesh point to `point` (m) within `max_distance` (m).
    pub fn point_proximity(&self, point: &Point3<f64>, max_distance: f64) -> Option<Proximity> {
        self.segment_proximity(point, point, max_distance)
    }

    /// Best-first BVH search for the triangle nearest to the segment.
    fn nearest(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        max_distance: f64,
    ) -> Option<(usize, Candidate<SegmentTriangleParameters>)> {
        let bound = SegmentBound::new(p0, p1);
        let (_, (_, (triangle, candidate))) = self.tree.bvh.find_best(
            max_distance.next_up(),
            |node: &BvhNode, best| {
                count_node();
                bound.distance(node, best)
            },
            |leaf, best| {
                // The nearest triangle of the cluster (the first of equals) nearer than
                // `best`; a triangle whose box is not nearer is not tested.
                let mut found: Option<(f64, (usize, Candidate<SegmentTriangleParameters>))> = None;
                for &t in self.tree.cluster(leaf) {
                    let corners = self.local_triangle(t as usize);
                    let beat = found.as_ref().map_or(best, |f| f.0.min(best));
                    count_box();
                    if bound.triangle_distance(&corners, beat) >= beat {
                        continue;
                    }
                    count_exact();
                    let [a, b, c] = corners;
                    let candidate = segment_triangle_candidate(p0, p1, &a, &b, &c);
                    let distance = candidate.squared.sqrt();
                    if found.as_ref().is_none_or(|f| distance < f.0) {
                        found = Some((distance, (t as usize, candidate)));
                    }
                }
                found
            },
        )?;
        Some((triangle, candidate))
    }

    /// The public result for closest parameters on `triangle`.
    pub(super) fn proximity(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        triangle: usize,
        parameters: SegmentTriangleParameters,
        tolerance: f64,
    ) -> Proximity {
        let [a, b, c] = self.local_triangle(triangle);
        let closest: SegmentTriangle = segment_triangle_points(p0, p1, &a, &b, &c, parameters);
        let normal = (closest.distance > tolerance)
            .then(|| Unit::new_normalize(closest.point_on_segment - closest.point_on_triangle));
        Proximity {
            triangle,
            s: closest.s,
            barycentric: closest.barycentric,
            point_on_segment: closest.point_on_segment,
            point_on_mesh: closest.point_on_triangle,
            distance: closest.distance,
            normal,
            tie: [closest.s, closest.s],
        }
    }

    /// The hull `[low, high]` (in `s`) of the closest-point intervals of every
    /// triangle within `limit` of the segment.
    fn tie_interval(&self, p0: &Point3<f64>, p1: &Point3<f64>, limit: f64) -> (f64, f64) {
        let bound = SegmentBound::new(p0, p1);
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        self.tree.bvh.traverse(|node: &BvhNode| {
            count_node();
            if bound.distance(node, limit) > limit {
                return TraversalAction::Prune;
            }
            if let Some(leaf) = node.leaf_data() {
                for &t in self.tree.cluster(leaf) {
                    let corners = self.local_triangle(t as usize);
                    count_box();
                    if bound.triangle_distance(&corners, limit) > limit {
                        continue;
                    }
                    count_exact();
                    let [a, b, c] = corners;
                    let candidate = segment_triangle_candidate(p0, p1, &a, &b, &c);
                    if candidate.squared <= limit * limit {
                        let half = 0.5 * candidate.interval;
                        low = low.min(candidate.value.0 - half);
                        high = high.max(candidate.value.0 + half);
                    }
                }
            }
            TraversalAction::Continue
        });
        (low, high)
    }
}

/// Lower bounds of the distance between a segment and BVH nodes.
pub(super) struct SegmentBound {
    start: GlamVector,
    direction: GlamVector,
    min: GlamVector,
    max: GlamVector,
}

impl SegmentBound {
    pub(super) fn new(p0: &Point3<f64>, p1: &Point3<f64>) -> Self {
        let (start, end) = (to_glam(p0), to_glam(p1));
        Self {
            start,
            direction: end - start,
            min: start.min(end),
            max: start.max(end),
        }
    }

    /// Distance between the segment and the node's box, or a lower bound of it that
    /// is already above `limit` (the node is pruned either way), m.
    pub(super) fn distance(&self, node: &BvhNode, limit: f64) -> f64 {
        self.box_distance(node.mins(), node.maxs(), limit)
    }

    /// [`SegmentBound::distance`] to the bounding box of triangle `[a, b, c]` (a leaf
    /// holds several triangles: each is pruned by its own box before its exact test).
    pub(super) fn triangle_distance(&self, [a, b, c]: &[Point3<f64>; 3], limit: f64) -> f64 {
        let (a, b, c) = (to_glam(a), to_glam(b), to_glam(c));
        self.box_distance(a.min(b).min(c), a.max(b).max(c), limit)
    }

    /// Distance between the segment and the box `[min, max]`, or a lower bound of it
    /// that is already above `limit`, m.
    fn box_distance(&self, min: GlamVector, max: GlamVector, limit: f64) -> f64 {
        let cheap = box_box_distance(min, max, self.min, self.max);
        if cheap >= limit {
            cheap
        } else {
            segment_box_distance(self.start, self.direction, min, max)
        }
    }
}
