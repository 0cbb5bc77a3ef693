//! The triangles within reach of a segment, for [`ObstacleMesh::local_contacts`], with
//! exact closest points computed only where they can change the answer.
//!
//! The candidates are the triangles whose bounding box is within reach (from the BVH,
//! or from a list kept by the caller, [`ObstacleMesh::triangles_near`]). On a finely
//! tessellated surface most of them lie on a smooth patch whose nearest point is
//! already known to be much nearer; an exact segment–triangle test costs several times
//! a box test, so the candidate of least box distance of every patch is tested first
//! and any other one of patch `P` is only *deferred* (not tested) when its box
//! distance `b > d_P + guard`, `d_P` the nearest distance found on `P` so far (in any
//! order of the candidates). Why the answer is unchanged:
//!
//! - the exact distance of a deferred triangle is at least `b > d_P + guard`, and `d_P`
//!   only decreases, so it is neither the patch's nearest nor a tie of it (ties lie
//!   within `tolerance < guard`), nor in the stretch of nearest points;
//! - a patch is only deferred from once it has a member within reach, so the set of
//!   patches is that of the full scan;
//! - the local-minimum test of a patch's nearest point `q` (distance `d_P` from the
//!   segment point) looks at triangles touching `q` (within `touch < guard` of it),
//!   which are within `d_P + guard` of the segment: every deferred triangle whose box
//!   is within `max_P d_P + guard` is tested at the end ([`NearScan::finish`]);
//! - the midpoint of a stretch may lie off the nearest triangles' intervals: there the
//!   deferred members of the patch are tested too ([`ObstacleMesh::deferred_members`]).
//!
//! The near triangles keep the candidates' order (the BVH's depth-first order for both
//! sources, which is the cluster order `TriangleTree::order`), so ties are broken as by
//! a scan of every candidate.

use nalgebra::Point3;

use super::ObstacleMesh;
use super::kept_triangles::KeptTriangles;
use super::segment_proximity::SegmentBound;
use super::work::{count_box, count_exact, count_node};
use crate::closest::{
    Candidate, SegmentTriangleParameters, TIE_TOLERANCE, segment_triangle_candidate,
    segment_triangle_lower_bound,
};

/// The margin (m) by which a candidate's box must be farther than its patch's nearest
/// triangle to be deferred: above the tie tolerance `tolerance` (m, `TIE_TOLERANCE`
/// times the size), the distance below which two contacts are one (`SAME_POINT`, 1e-9
/// times the size), the touching distance of the local-minimum test (`CONTAINS`) and
/// the rounding of the box distances at distances up to `limit` (m).
pub(super) fn near_guard(tolerance: f64, limit: f64) -> f64 {
    2e3 * tolerance + 1e-9 * (1.0 + limit)
}

/// What a BVH descent prunes its nodes by.
#[derive(Clone, Copy)]
enum NodeBounds {
    /// Their axis-aligned boxes: every triangle whose box is within reach is found.
    Boxes,
    /// Their axis-aligned and oriented boxes: every triangle within reach is found.
    Frames,
}

/// One triangle within reach, with its exact closest points.
pub(super) struct Near {
    /// Its place among the candidates (their order breaks ties).
    pub(super) position: usize,
    pub(super) triangle: usize,
    pub(super) candidate: Candidate<SegmentTriangleParameters>,
}

/// A candidate triangle whose box is within reach.
#[derive(Clone, Copy)]
pub(super) struct Reachable {
    /// Its place among the candidates.
    pub(super) position: usize,
    pub(super) triangle: usize,
    /// Distance from the segment to the triangle's box (a lower bound of its own), m.
    pub(super) bound: f64,
}

/// The result of [`ObstacleMesh::scan_near`].
pub(super) struct NearScan {
    /// The triangles tested and within reach, in candidate order.
    pub(super) near: Vec<Near>,
    /// The triangles not tested (their boxes farther than their patch's nearest).
    deferred: Vec<Reachable>,
}

impl ObstacleMesh {
    /// The candidate triangles (indices, in the BVH's depth-first order) for
    /// [`ObstacleMesh::local_contacts_among`] of any segment whose ends are within
    /// `slack` (m) of `p0` and `p1`, for reaches up to `reach` (m): a list to keep while
    /// the segment moves by less than `slack`.
    ///
    /// Why nothing that matters is left out. Let `R = reach + slack` and `d_P` the
    /// nearest distance of smooth patch `P` to `[p0, p1]` among its triangles within
    /// `R`; the list holds every triangle within `max_P d_P + 2 slack + guard` (those
    /// whose boxes are, except under nodes whose oriented boxes are farther:
    /// see `reachable_near`). For a segment `[q0, q1]` with `|qᵢ − pᵢ| ≤ δ ≤ slack` every point moved
    /// by at most `δ` (`(1 − s)|q0 − p0| + s |q1 − p1|`), so distances change by at most
    /// `δ`. A patch within `reach` of the new segment was within `R` of the old one,
    /// and its new nearest distance is at most `d_P + δ` (its old nearest triangle
    /// moved by `δ`). The answer of [`ObstacleMesh::local_contacts`] depends (see the
    /// module documentation) only on the triangles within `d_P' + guard` of the new
    /// segment for some patch `P'`, i.e. within `max_P d_P + δ + guard`, which were
    /// within `max_P d_P + 2δ + guard` of the old one: all in the list. (The midpoint
    /// of a stretch of nearest points may be off every near triangle;
    /// `local_contacts_among` then searches the whole mesh.)
    pub fn triangles_near(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        reach: f64,
        slack: f64,
    ) -> Vec<u32> {
        self.keep_triangles_listing(p0, p1, reach, slack, usize::MAX)
            .all()
            .expect("listed without a limit")
            .to_vec()
    }

    /// The list of [`ObstacleMesh::triangles_near`], kept with the box distance of every
    /// triangle and the nearest triangle of every patch, so that a later evaluation
    /// looks only at the part that can matter ([`ObstacleMesh::local_contacts_kept`]).
    /// A list of more than [`super::kept_triangles::MAX_LISTED`] triangles (a disc on a
    /// finely tessellated surface) is not listed: the nearest triangles of the patches
    /// are kept, and a later evaluation searches the BVH near them.
    pub fn keep_triangles_near(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        reach: f64,
        slack: f64,
    ) -> KeptTriangles {
        self.keep_triangles_listing(p0, p1, reach, slack, super::kept_triangles::MAX_LISTED)
    }

    /// [`ObstacleMesh::keep_triangles_near`], listing at most `max_listed` triangles.
    pub(super) fn keep_triangles_listing(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        reach: f64,
        slack: f64,
        max_listed: usize,
    ) -> KeptTriangles {
        let (l0, l1) = (self.to_local(p0), self.to_local(p1));
        let tolerance = self.tie_tolerance(&l0, &l1);
        let radius = (reach + slack).next_up();
        let guard = near_guard(tolerance, radius);
        let bound = SegmentBound::new(&l0, &l1, &self.bounding_box);
        // The nearest triangle of every patch within reach plus slack, then the part
        // kept: every triangle whose box (and oriented node boxes) is within the
        // farthest of them plus twice the slack and guard (and within reach plus
        // slack), in depth-first order.
        let patches = self.patch_nearest(&bound, &l0, &l1, radius, guard);
        let farthest = patches
            .iter()
            .map(|k| k.distance)
            .reduce(f64::max)
            .unwrap_or(f64::NEG_INFINITY);
        let keep = farthest + 2.0 * slack + 2.0 * guard;
        let in_order = if keep >= 0.0 {
            self.reachable_at_most(
                &bound,
                keep.min(radius),
                None,
                max_listed,
                NodeBounds::Frames,
            )
        } else {
            Some(Vec::new())
        };
        KeptTriangles::new([*p0, *p1], reach, slack, in_order.as_deref(), patches)
    }

    /// The tie tolerance (m) of the queries of segment `[l0, l1]` (the mesh's own
    /// frame): `TIE_TOLERANCE` times the segment's length plus the mesh's diagonal.
    pub(super) fn tie_tolerance(&self, l0: &Point3<f64>, l1: &Point3<f64>) -> f64 {
        let [min, max] = self.bounding_box;
        TIE_TOLERANCE * ((l1 - l0).norm() + (max - min).norm())
    }

    /// The triangles (in the mesh's own frame) whose boxes are within `limit` (m) of the
    /// segment: from the BVH when `list` is `None`, else from `list` (triangle indices).
    pub(super) fn reachable(
        &self,
        bound: &SegmentBound,
        limit: f64,
        list: Option<&[u32]>,
    ) -> Vec<Reachable> {
        self.reachable_at_most(bound, limit, list, usize::MAX, NodeBounds::Boxes)
            .expect("no limit to pass")
    }

    /// [`ObstacleMesh::reachable`] from the BVH, leaving out the nodes whose oriented
    /// boxes ([`super::node_frames`]) are beyond `limit` as well: every triangle within
    /// `limit` of the segment, and of the others only some whose boxes are (what a
    /// search that needs every triangle within a distance, not every box, looks at).
    pub(super) fn reachable_near(&self, bound: &SegmentBound, limit: f64) -> Vec<Reachable> {
        self.reachable_at_most(bound, limit, None, usize::MAX, NodeBounds::Frames)
            .expect("no limit to pass")
    }

    /// [`ObstacleMesh::reachable`] (or [`ObstacleMesh::reachable_near`], with
    /// `NodeBounds::Frames`), or `None` as soon as more than `max_listed` triangles are
    /// found (the rest is not looked at).
    fn reachable_at_most(
        &self,
        bound: &SegmentBound,
        limit: f64,
        list: Option<&[u32]>,
        max_listed: usize,
        nodes: NodeBounds,
    ) -> Option<Vec<Reachable>> {
        let mut out = Vec::new();
        let over = std::cell::Cell::new(false);
        let mut test = |t: u32| {
            if over.get() {
                return;
            }
            count_box();
            let corners = self.local_triangle(t as usize);
            let distance = bound.triangle_distance(&corners, limit);
            if distance > limit {
                return;
            }
            if out.len() == max_listed {
                over.set(true);
                return;
            }
            out.push(Reachable {
                position: out.len(),
                triangle: t as usize,
                bound: distance,
            });
        };
        match list {
            Some(list) => list.iter().for_each(|&t| test(t)),
            None => self.tree.bvh.depth_first(
                |node, node_box| {
                    count_node();
                    !over.get()
                        && match nodes {
                            NodeBounds::Boxes => bound.may_be_within(node_box, limit),
                            NodeBounds::Frames => bound.may_be_within_frames(
                                node_box,
                                || self.node_frame(node),
                                limit,
                            ),
                        }
                },
                |leaf| self.tree.cluster(leaf).iter().for_each(|&t| test(t)),
            ),
        }
        (!over.get()).then_some(out)
    }

    /// The exact closest points of the `reachable` triangles that can matter for the
    /// local contacts of segment `[p0, p1]` within `limit` (m); see the module
    /// documentation. `guard` (m) exceeds the tie tolerance and the touching distance.
    ///
    /// Without sorting the candidates: the one of least box distance of every patch is
    /// tested first (on a tessellated surface nearly the patch's nearest), then the
    /// rest in candidate order, each deferred against its patch's nearest distance so
    /// far. The order does not matter for the answer (a deferred triangle's distance
    /// exceeds the patch's final nearest distance plus the guard whenever it was
    /// deferred), only for how many are tested; sorting all candidates by box distance
    /// cost more than the tests it saved (an eighth of a contact solve on a 1M-triangle
    /// floor, growing as `k log k` with the candidates).
    pub(super) fn scan_near(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        limit: f64,
        reachable: Vec<Reachable>,
        guard: f64,
    ) -> NearScan {
        // (patch, index of its candidate of least box distance; ties: the first).
        let mut first: Vec<(usize, usize)> = Vec::new();
        for (i, r) in reachable.iter().enumerate() {
            let patch = self.patch_of(r.triangle);
            match first.iter_mut().find(|(p, _)| *p == patch) {
                Some(f) if r.bound < reachable[f.1].bound => f.1 = i,
                Some(_) => {}
                None => first.push((patch, i)),
            }
        }
        // Nearest distance found on each patch so far (few patches: a list).
        let mut nearest: Vec<(usize, f64)> = Vec::new();
        let mut near = Vec::new();
        for &(patch, i) in &first {
            if let Some(found) = self.exact(p0, p1, reachable[i], limit) {
                nearest.push((patch, found.candidate.squared.sqrt()));
                near.push(found);
            }
        }
        let mut tested_first: Vec<usize> = first.iter().map(|&(_, i)| i).collect();
        tested_first.sort_unstable();
        let mut tested_first = tested_first.into_iter().peekable();
        let mut deferred = Vec::new();
        for (i, r) in reachable.into_iter().enumerate() {
            if tested_first.next_if_eq(&i).is_some() {
                continue;
            }
            let patch = self.patch_of(r.triangle);
            let seen = nearest.iter().position(|(p, _)| *p == patch);
            if let Some(k) = seen {
                let beyond = nearest[k].1 + guard;
                if r.bound > beyond {
                    deferred.push(r);
                    continue;
                }
                // The box is near: the plane-and-edges bound may still rule it out.
                if let Some(lower) = self.lower_bound(p0, p1, r.triangle)
                    && lower > beyond
                {
                    deferred.push(Reachable { bound: lower, ..r });
                    continue;
                }
            }
            if let Some(found) = self.exact(p0, p1, r, limit) {
                let distance = found.candidate.squared.sqrt();
                match seen {
                    Some(k) => nearest[k].1 = nearest[k].1.min(distance),
                    None => nearest.push((patch, distance)),
                }
                near.push(found);
            }
        }
        let farthest = nearest.iter().map(|(_, d)| *d).fold(0.0, f64::max) + guard;
        let mut scan = NearScan { near, deferred };
        scan.finish(self, p0, p1, limit, farthest);
        scan
    }

    /// A lower bound (m) of the distance of `triangle` from segment `[p0, p1]`, tighter
    /// than its box on a tilted surface ([`segment_triangle_lower_bound`]); `None` for
    /// a sliver. Counted as a box test.
    fn lower_bound(&self, p0: &Point3<f64>, p1: &Point3<f64>, triangle: usize) -> Option<f64> {
        count_box();
        let [a, b, c] = self.local_triangle(triangle);
        segment_triangle_lower_bound(p0, p1, &a, &b, &c)
    }

    /// The exact closest points of candidate `r`, if within `limit` (m).
    fn exact(&self, p0: &Point3<f64>, p1: &Point3<f64>, r: Reachable, limit: f64) -> Option<Near> {
        count_exact();
        let [a, b, c] = self.local_triangle(r.triangle);
        let candidate = segment_triangle_candidate(p0, p1, &a, &b, &c);
        (candidate.squared <= limit * limit).then_some(Near {
            position: r.position,
            triangle: r.triangle,
            candidate,
        })
    }

    /// The deferred members of `patch` within `limit` (m) of the segment, tested (for
    /// the midpoint of a stretch, which may lie off the nearest triangles).
    pub(super) fn deferred_members(
        &self,
        scan: &NearScan,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        limit: f64,
        patch: usize,
    ) -> Vec<Near> {
        scan.deferred
            .iter()
            .filter(|r| self.patch_of(r.triangle) == patch)
            .filter_map(|&r| self.exact(p0, p1, r, limit))
            .collect()
    }
}

impl NearScan {
    /// Tests the deferred triangles whose boxes are within `farthest` (m: the farthest
    /// patch's nearest distance plus the guard), which may touch a patch's nearest
    /// point, and puts the near triangles back in candidate order.
    fn finish(
        &mut self,
        mesh: &ObstacleMesh,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        limit: f64,
        farthest: f64,
    ) {
        let (test, keep): (Vec<Reachable>, Vec<Reachable>) = std::mem::take(&mut self.deferred)
            .into_iter()
            .partition(|r| r.bound <= farthest);
        self.deferred = keep;
        self.near.extend(
            test.into_iter()
                .filter_map(|r| mesh.exact(p0, p1, r, limit)),
        );
        self.near.sort_by_key(|n| n.position);
    }
}
