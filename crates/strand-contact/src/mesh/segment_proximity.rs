//! Nearest mesh point to a segment (or a point), through the BVH.

use nalgebra::{Point3, Unit, Vector3};
use parry3d_f64::math::Vector as GlamVector;

use super::convert::to_glam;
use super::flat_bvh::NodeBox;
use super::node_frames::NodeFrame;
use super::segment_box::{box_box_distance, segment_box_distance};
use super::work::{count_box, count_exact, count_node};
use super::{CLUSTER_SIZE, ObstacleMesh};
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

    /// The distance (m) from segment `[p0, p1]` (m) to the mesh, when it is within
    /// `max_distance` (m): the least exact segment–triangle distance as the search of
    /// [`ObstacleMesh::segment_proximity`] compares them, without closest points or a
    /// tie interval.
    pub fn segment_distance(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        max_distance: f64,
    ) -> Option<f64> {
        let (l0, l1) = (self.to_local(p0), self.to_local(p1));
        self.nearest(&l0, &l1, max_distance)
            .map(|(_, candidate)| candidate.squared.sqrt())
    }

    /// The nearest mesh point to `point` (m) within `max_distance` (m).
    pub fn point_proximity(&self, point: &Point3<f64>, max_distance: f64) -> Option<Proximity> {
        self.segment_proximity(point, point, max_distance)
    }

    /// Depth-first BVH search, nearer node first, for the triangle nearest to the
    /// segment within `max_distance` (m): the least exact distance, and of equal ones
    /// the triangle first in the cluster order (`TriangleTree::order`), the answer of
    /// [`ObstacleMesh::nearest_by_scan`] over every triangle.
    pub(super) fn nearest(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        max_distance: f64,
    ) -> Option<(usize, Candidate<SegmentTriangleParameters>)> {
        let bound = SegmentBound::new(p0, p1, &self.bounding_box);
        let mut best = Nearest::within(max_distance);
        self.tree.bvh.nearer_first(
            &mut best,
            |best, _, node_box| {
                count_node();
                bound.distance(node_box, best.distance + bound.rounding)
            },
            |best, node_bound, first| {
                best.may_be_beaten(node_bound - bound.rounding, first as usize * CLUSTER_SIZE)
            },
            |best, leaf| {
                let start = leaf as usize * CLUSTER_SIZE;
                for (rank, &t) in (start..).zip(self.tree.cluster(leaf)) {
                    let corners = self.local_triangle(t as usize);
                    count_box();
                    // A triangle whose box is not nearer is not tested.
                    let limit = best.distance + bound.rounding;
                    let lower = bound.triangle_distance(&corners, limit) - bound.rounding;
                    if !best.may_be_beaten(lower, rank) {
                        continue;
                    }
                    count_exact();
                    let [a, b, c] = corners;
                    best.offer(rank, t, segment_triangle_candidate(p0, p1, &a, &b, &c));
                }
            },
        );
        best.found
    }

    /// [`ObstacleMesh::nearest`] by testing every triangle in the cluster order (the
    /// reference of the BVH search in the tests).
    #[cfg(test)]
    pub(super) fn nearest_by_scan(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        max_distance: f64,
    ) -> Option<(usize, Candidate<SegmentTriangleParameters>)> {
        let mut best = Nearest::within(max_distance);
        for (rank, &t) in self.tree.order.iter().enumerate() {
            let [a, b, c] = self.local_triangle(t as usize);
            best.offer(rank, t, segment_triangle_candidate(p0, p1, &a, &b, &c));
        }
        best.found
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
    pub(super) fn tie_interval(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        limit: f64,
    ) -> (f64, f64) {
        let bound = SegmentBound::new(p0, p1, &self.bounding_box);
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        self.tree.bvh.depth_first(
            |_, node| {
                count_node();
                bound.may_be_within(node, limit)
            },
            |leaf| {
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
            },
        );
        (low, high)
    }
}

/// The best triangle of a nearest-point search so far.
struct Nearest {
    /// Its distance (at first the search radius, just above `max_distance`), m.
    distance: f64,
    /// Its place in the cluster order (0 at first: a triangle at the radius is out).
    rank: usize,
    /// The triangle and its closest points.
    found: Option<(usize, Candidate<SegmentTriangleParameters>)>,
}

impl Nearest {
    /// Nothing found yet, searching within `max_distance` (m).
    fn within(max_distance: f64) -> Self {
        Self {
            distance: max_distance.next_up(),
            rank: 0,
            found: None,
        }
    }

    /// Whether something at `distance` (m) and place `rank` in the cluster order
    /// beats the best: nearer, or as near and earlier.
    #[inline]
    fn beaten_by(&self, distance: f64, rank: usize) -> bool {
        distance < self.distance || (distance == self.distance && rank < self.rank)
    }

    /// Whether something at least `lower` (m) away and at place `rank` or later in the
    /// cluster order may beat the best.
    #[inline]
    fn may_be_beaten(&self, lower: f64, rank: usize) -> bool {
        self.beaten_by(lower, rank)
    }

    /// Keeps triangle `t` (place `rank`) with closest points `candidate` if it beats
    /// the best.
    #[inline]
    fn offer(&mut self, rank: usize, t: u32, candidate: Candidate<SegmentTriangleParameters>) {
        let distance = candidate.squared.sqrt();
        if self.beaten_by(distance, rank) {
            *self = Self {
                distance,
                rank,
                found: Some((t as usize, candidate)),
            };
        }
    }
}

/// Lower bounds of the distance between a segment and BVH nodes.
pub(super) struct SegmentBound {
    /// The segment's ends, m.
    ends: [Point3<f64>; 2],
    start: GlamVector,
    direction: GlamVector,
    min: GlamVector,
    max: GlamVector,
    /// A bound of the rounding errors (m) of the box distances and the exact distances
    /// of the segment to the mesh: a search prunes a node only when its box is farther
    /// than what it looks for by more than this, so that it finds what a scan of every
    /// triangle's box and exact distance finds (which rounding could otherwise change
    /// by an ulp, and a tie with it). [`ROUNDING`] times the largest coordinate
    /// magnitude of the segment and the mesh's bounding box.
    pub(super) rounding: f64,
}

/// Relative size of [`SegmentBound::rounding`] (about 4500 ulps).
const ROUNDING: f64 = 1e-12;

impl SegmentBound {
    /// The bounds for segment `[p0, p1]` and a mesh of bounding box `mesh_box`, m.
    pub(super) fn new(p0: &Point3<f64>, p1: &Point3<f64>, mesh_box: &[Point3<f64>; 2]) -> Self {
        let (start, end) = (to_glam(p0), to_glam(p1));
        let magnitude = [p0, p1, &mesh_box[0], &mesh_box[1]]
            .iter()
            .map(|p| p.coords.amax())
            .fold(0.0, f64::max);
        Self {
            ends: [*p0, *p1],
            start,
            direction: end - start,
            min: start.min(end),
            max: start.max(end),
            rounding: ROUNDING * magnitude,
        }
    }

    /// Whether a node's box may hold a triangle whose box is within `limit` (m) of the
    /// segment (rounding included).
    pub(super) fn may_be_within(&self, node: &NodeBox, limit: f64) -> bool {
        let limit = limit + self.rounding;
        self.distance(node, limit) <= limit
    }

    /// [`SegmentBound::may_be_within`], the node also pruned when its oriented box
    /// ([`NodeFrame`]) is farther than `limit` (m): then no triangle in it is within
    /// `limit`, though its axis-aligned box may be.
    pub(super) fn may_be_within_frames<'f>(
        &self,
        node: &NodeBox,
        frame: impl FnOnce() -> &'f NodeFrame,
        limit: f64,
    ) -> bool {
        let limit = limit + self.rounding;
        self.node_distance(node, frame, limit) <= limit
    }

    /// A lower bound (m) of the distance between the segment and anything in a node:
    /// the larger of its box's distance ([`SegmentBound::distance`]) and its oriented
    /// box's ([`NodeFrame::distance_within`]), or a lower bound of either already above
    /// `limit` (m). The cheap bounds of both boxes come first, then the oriented box's
    /// exact distance (on a slope the tighter one), the axis-aligned box's last. The
    /// oriented box is asked for (`frame`, computed with its chunk on first use) only
    /// for a node whose axis-aligned box is not ruled out by its cheap bound.
    pub(super) fn node_distance<'f>(
        &self,
        node: &NodeBox,
        frame: impl FnOnce() -> &'f NodeFrame,
        limit: f64,
    ) -> f64 {
        let min = GlamVector::new(node[0], node[1], node[2]);
        let max = GlamVector::new(node[3], node[4], node[5]);
        let cheap = box_box_distance(min, max, self.min, self.max);
        if cheap > limit {
            return cheap;
        }
        let framed = frame().distance_within(&self.ends[0], &self.ends[1], limit);
        if framed > limit || self.direction == GlamVector::ZERO {
            return framed.max(cheap);
        }
        segment_box_distance(self.start, self.direction, min, max).max(framed)
    }

    /// Distance between the segment and the node's box, or a lower bound of it that
    /// is already above `limit` (the node is pruned either way), m.
    pub(super) fn distance(&self, node: &NodeBox, limit: f64) -> f64 {
        let min = GlamVector::new(node[0], node[1], node[2]);
        let max = GlamVector::new(node[3], node[4], node[5]);
        self.box_distance(min, max, limit)
    }

    /// [`SegmentBound::distance`] to the bounding box of triangle `[a, b, c]` (a leaf
    /// holds several triangles: each is pruned by its own box before its exact test).
    pub(super) fn triangle_distance(&self, [a, b, c]: &[Point3<f64>; 3], limit: f64) -> f64 {
        let (a, b, c) = (to_glam(a), to_glam(b), to_glam(c));
        self.box_distance(a.min(b).min(c), a.max(b).max(c), limit)
    }

    /// Distance between the segment and the box `[min, max]`, or a lower bound of it
    /// that is already above `limit`, m. For a point (a vertex's query) the box-to-box
    /// distance is the exact one.
    fn box_distance(&self, min: GlamVector, max: GlamVector, limit: f64) -> f64 {
        let cheap = box_box_distance(min, max, self.min, self.max);
        if cheap > limit || self.direction == GlamVector::ZERO {
            cheap
        } else {
            segment_box_distance(self.start, self.direction, min, max)
        }
    }
}
