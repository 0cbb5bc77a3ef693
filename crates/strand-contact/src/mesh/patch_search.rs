//! The nearest triangle of every smooth patch within reach of a segment, through the
//! BVH, without visiting every triangle within reach: what a full search of
//! [`ObstacleMesh::keep_triangles_near`] needs before it collects the kept part.
//!
//! Every node of the BVH knows the one patch all of its triangles belong to, if they
//! do ([`ObstacleMesh::node_patches`], computed on the first full search). A search
//! from the nearest box first keeps the nearest distance `d_P` found on each patch and
//! skips a node of a single patch `P` (or a triangle of `P`) whose box is farther than
//! `d_P + guard`: nothing in it is as near as `d_P` (a node's distance is the larger of
//! its box's and its oriented box's, [`super::node_frames`]). It takes the nodes nearest box
//! first (best first), so that `d_P` is known before farther boxes come up. Nodes holding several patches, and
//! nodes of a patch not met yet, are entered while their box is within reach. On a
//! finely tessellated floor (one patch) the search therefore visits the triangles
//! within `d_P + guard` of the segment and the boxes on the way to them, where a
//! search of everything within reach visits a disc whose triangle count grows with the
//! density.
//!
//! The answer is that of the scan of every triangle within reach
//! ([`ObstacleMesh::scan_near`]): per patch with a triangle within reach, its least
//! exact distance and, among the triangles at that distance, the first in the BVH's
//! depth-first (cluster) order. A skipped triangle's box is farther than `d_P + guard`
//! for the `d_P` of that moment, so its exact distance exceeds the final `d_P`; the
//! guard exceeds the boxes' rounding.

use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::sync::OnceLock;

use nalgebra::Point3;

use super::flat_bvh::LEAF;
use super::kept_triangles::KeptPatch;
use super::segment_proximity::SegmentBound;
use super::work::{count_box, count_exact, count_node};
use super::{CLUSTER_SIZE, ObstacleMesh};
use crate::closest::{segment_triangle_candidate, segment_triangle_lower_bound};

/// A node's patch when its triangles belong to several.
pub(super) const MIXED: u32 = u32::MAX;

/// The per-node patches of a mesh, computed once ([`ObstacleMesh::node_patches`]).
pub(crate) type NodePatches = OnceLock<Vec<u32>>;

/// A node waiting in the best-first search, ordered nearest first.
struct Pending {
    /// Its box distance from the segment, m.
    distance: f64,
    node: u32,
}

impl PartialEq for Pending {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other).is_eq()
    }
}

impl Eq for Pending {}

impl PartialOrd for Pending {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Pending {
    /// Reversed (`BinaryHeap` pops the greatest): the nearer node first, then the
    /// earlier one in preorder.
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .distance
            .total_cmp(&self.distance)
            .then(other.node.cmp(&self.node))
    }
}

/// The nearest triangle found so far on one patch.
struct PatchBest {
    patch: usize,
    nearest: KeptPatch,
    /// The triangle's place in the BVH's depth-first order (ties go to the first).
    rank: usize,
}

impl ObstacleMesh {
    /// The patch of every BVH node (in the tree's preorder): the one patch all of its
    /// triangles belong to, or [`MIXED`]. Computed on first use in `O(nodes)` (children
    /// follow their parent in preorder, so one backward pass), then shared by every
    /// copy and placement of the mesh.
    pub(super) fn node_patches(&self) -> &[u32] {
        self.node_patches.get_or_init(|| {
            let bvh = &self.tree.bvh;
            let mut patches = vec![MIXED; bvh.links.len()];
            for node in (0..bvh.links.len()).rev() {
                let link = bvh.links[node];
                patches[node] = if link & LEAF != 0 {
                    let mut triangles = self.tree.cluster(link & !LEAF).iter();
                    let first = triangles.next().map_or(MIXED, |&t| self.patch[t as usize]);
                    if triangles.all(|&t| self.patch[t as usize] == first) {
                        first
                    } else {
                        MIXED
                    }
                } else {
                    let (left, right) = (patches[node + 1], patches[link as usize]);
                    if left == right { left } else { MIXED }
                };
            }
            patches
        })
    }

    /// The nearest triangle of every patch with a triangle within `radius` (m, exact
    /// distance) of segment `[p0, p1]` (the mesh's own frame), in the order of those
    /// triangles in the BVH's depth-first order; `guard` (m) as the scan's
    /// ([`super::near_scan::near_guard`]). See the module documentation.
    pub(super) fn patch_nearest(
        &self,
        bound: &SegmentBound,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        radius: f64,
        guard: f64,
    ) -> Vec<KeptPatch> {
        let node_patches = self.node_patches();
        let bvh = &self.tree.bvh;
        let mut best: Vec<PatchBest> = Vec::new();
        let skipped = |best: &[PatchBest], patch: u32, distance: f64| {
            patch != MIXED
                && best
                    .iter()
                    .any(|b| b.patch == patch as usize && distance > b.nearest.distance + guard)
        };
        // The distance within which a node or triangle of `patch` is still looked at:
        // `limit`, or its patch's nearest so far plus the guard if less.
        let within = |best: &[PatchBest], patch: u32, limit: f64| {
            if patch == MIXED {
                return limit;
            }
            best.iter()
                .find(|b| b.patch == patch as usize)
                .map_or(limit, |b| limit.min(b.nearest.distance + guard))
        };
        if bvh.boxes.is_empty() {
            return Vec::new();
        }
        let node_limit = radius + bound.rounding;
        // Nearest box first (a best-first search): each patch's nearest distance is
        // known before the boxes beyond it come up, so they are skipped, and only the
        // triangles whose boxes are within it plus the guard are tested exactly.
        let mut pending: BinaryHeap<Pending> = BinaryHeap::with_capacity(128);
        pending.push(Pending {
            distance: bound.node_distance(&bvh.boxes[0], || self.node_frame(0), node_limit),
            node: 0,
        });
        while let Some(Pending { distance, node }) = pending.pop() {
            if distance > node_limit || skipped(&best, node_patches[node as usize], distance) {
                continue;
            }
            count_node();
            let link = bvh.links[node as usize];
            if link & LEAF == 0 {
                for child in [node + 1, link] {
                    // A child of one patch with a nearest so far is skipped beyond it
                    // plus the guard: a bound above that is enough (cheaper to get).
                    let limit = within(&best, node_patches[child as usize], node_limit);
                    let child = child as usize;
                    let distance =
                        bound.node_distance(&bvh.boxes[child], || self.node_frame(child), limit);
                    if distance <= limit {
                        pending.push(Pending {
                            distance,
                            node: child as u32,
                        });
                    }
                }
                continue;
            }
            let cluster = link & !LEAF;
            for (k, &t) in self.tree.cluster(cluster).iter().enumerate() {
                count_box();
                let corners = self.local_triangle(t as usize);
                let patch = self.patch[t as usize];
                let limit = within(&best, patch, radius);
                let box_distance = bound.triangle_distance(&corners, limit);
                if box_distance > limit || skipped(&best, patch, box_distance) {
                    continue;
                }
                let [a, b, c] = corners;
                // A near box on a tilted surface: the plane-and-edges bound may still
                // rule the triangle out (it is at least as far as the bound).
                if best.iter().any(|kept| kept.patch == patch as usize) {
                    count_box();
                    if let Some(lower) = segment_triangle_lower_bound(p0, p1, &a, &b, &c)
                        && skipped(&best, patch, lower)
                    {
                        continue;
                    }
                }
                count_exact();
                let squared = segment_triangle_candidate(p0, p1, &a, &b, &c).squared;
                if squared > radius * radius {
                    continue;
                }
                let here = PatchBest {
                    patch: patch as usize,
                    nearest: KeptPatch {
                        triangle: t,
                        distance: squared.sqrt(),
                    },
                    rank: cluster as usize * CLUSTER_SIZE + k,
                };
                match best.iter_mut().find(|b| b.patch == here.patch) {
                    Some(kept) => {
                        let (d, kept_d) = (here.nearest.distance, kept.nearest.distance);
                        if d < kept_d || (d == kept_d && here.rank < kept.rank) {
                            *kept = here;
                        }
                    }
                    None => best.push(here),
                }
            }
        }
        best.sort_unstable_by_key(|b| b.rank);
        best.into_iter().map(|b| b.nearest).collect()
    }
}
