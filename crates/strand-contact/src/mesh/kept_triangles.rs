//! A feature's kept candidate triangles ([`ObstacleMesh::keep_triangles_near`]) with
//! their box distance from the feature where it was searched, so that a later
//! evaluation looks only at the part that can matter given how far the feature moved.
//!
//! On a finely tessellated surface the kept list is a disc of triangles around each
//! contact (those whose boxes lie within the nearest distance plus twice the slack),
//! and most of it matters only if the feature moves by the whole slack. Each patch near
//! at the search keeps one of its triangles `X_P`: its nearest at the search, replaced
//! by its nearest at each later evaluation ([`KeptTriangles::follow`]), so that on a
//! surface the feature slides along, `X_P` stays near the contact. A feature that moved
//! by `δ` from the search looks at the triangles whose stored box distance `b₀` is at
//! most `u + δ + 2 guard`, `u` the largest distance of the segment now to the patches'
//! `X_P` ([`KeptList::part`]). Why the contacts are those of the whole kept list (and
//! so of a full search), whichever triangle of its patch `X_P` is:
//!
//! - every left-out triangle `T` has a box distance now of at least `b₀ − δ > u + 2
//!   guard` (distances move by at most `δ`; one guard covers rounding);
//! - every patch `P` within reach has a nearest distance now `d_P ≤ |X_P now| ≤ u`, and
//!   its nearest triangle now `Z_P` is in the part: it is in the whole list (at the
//!   search it was within `d_P + δ ≤ d_P⁰ + 2δ` of the segment, `d_P⁰` the patch's
//!   nearest distance at the search) and `b₀(Z_P) ≤ d_P + δ ≤ u + δ`; the scan of the
//!   part ([`ObstacleMesh::local_contacts_among`]) tests it or defers it for being
//!   farther than a nearer one, so it finds `d_P`;
//! - so in a scan of the whole list every `T` of a patch with a member in the part is
//!   deferred (its box is farther than `d_P + guard`) and never tested at the end (its
//!   box is farther than `max_P d_P + guard`), and the midpoint of a stretch of `P`
//!   finds `T` farther than `d_P + guard` from it: the answer does not change;
//! - the same holds for a part of the segment (a point of an edge): its box distances
//!   are at least the segment's, and `u` is measured from the part;
//! - a patch whose `X_P` is now out of reach is left out only when all of it is (its
//!   nearest distance at the search minus `δ` is beyond the reach); a patch not near
//!   at the search was farther than reach plus slack. Otherwise the whole list is used.
//!
//! **Kept lists too long to list.** On a finely tessellated surface the disc of the
//! whole list grows with the density (a kept list of a 1M-triangle floor holds hundreds
//! of triangles, most of them never looked at), so a search lists the kept triangles
//! only when there are at most [`MAX_LISTED`]; otherwise it keeps just the patches'
//! triangles `X_P`, and a later evaluation takes every triangle whose box is *now*
//! within `u + 2 guard` of the segment and within reach, through the BVH
//! ([`Candidates::Within`]; its nodes pruned by their oriented boxes too, which leaves
//! out only triangles farther than that). That set is part of a full search's candidates and holds
//! every triangle the answer depends on: each patch within reach has its nearest
//! triangle in it (`d_P ≤ u`), and every triangle left out is farther than `max_P d_P +
//! 2 guard` from the segment now; so its answer is a full search's. Where the whole
//! list would be used, a full search gives its answer. The work of a later evaluation
//! is then that of the triangles within about `u` of the segment and the BVH's nodes
//! above them, not of the disc; with `X_P` followed from the last evaluation, `u`
//! exceeds the contact's distance by what the feature moved since, at second order on
//! a smooth surface (a hose sliding over a 378k-triangle drum: see
//! `kept_triangles_tests`).

use nalgebra::Point3;

use super::ObstacleMesh;
use super::local_contacts::Candidates;
use super::near_scan::Reachable;
use super::work::count_exact;
use crate::closest::segment_triangle_candidate;

/// Lists of at most this many triangles, plus [`SMALL_LIST_PER_PATCH`] per patch, are
/// looked at whole: finding the part costs an exact closest point per patch.
const SMALL_LIST: usize = 16;

/// See [`SMALL_LIST`]: an exact segment–triangle test costs several box tests.
const SMALL_LIST_PER_PATCH: usize = 8;

/// A search lists the kept triangles when there are at most this many; a longer kept
/// disc is not listed (see the module documentation): listing it costs a box test per
/// triangle, and a later evaluation's search of the BVH near the contacts costs about
/// as much as scanning a list of this length.
pub(super) const MAX_LISTED: usize = 64;

/// One smooth patch near the feature at the search.
#[derive(Clone, Copy, Debug)]
pub(super) struct KeptPatch {
    /// A triangle of the patch (index `< triangle_count()`): its nearest at the search,
    /// then its nearest at the latest evaluation ([`KeptTriangles::follow`]).
    pub(super) triangle: u32,
    /// The patch's nearest distance from the segment searched at, m: no triangle of the
    /// patch was nearer at the search.
    pub(super) distance: f64,
}

/// The kept triangles of a search, listed.
#[derive(Clone, Debug)]
struct KeptList {
    /// The kept triangles in the BVH's depth-first order.
    triangles: Vec<u32>,
    /// The box distance (m) of each of `triangles` from the searched segment.
    bounds: Vec<f64>,
}

/// The candidate triangles kept for one rod feature (a vertex sphere or an edge
/// capsule) from a search at segment `from` with `reach` and `slack`
/// ([`ObstacleMesh::keep_triangles_near`]); valid for segments whose ends moved by at
/// most `slack` (m) from `from`, for reaches up to `reach` (m).
#[derive(Clone, Debug)]
pub struct KeptTriangles {
    from: [Point3<f64>; 2],
    reach: f64,
    slack: f64,
    /// The kept triangles, when there are at most [`MAX_LISTED`] of them.
    list: Option<KeptList>,
    /// The nearest triangle of every patch within reach plus slack at the search.
    patches: Vec<KeptPatch>,
}

/// How near the patches kept at a search are to a segment now
/// ([`KeptTriangles::upper`]).
enum NearNow {
    /// A patch may be within reach through another triangle than its nearest at the
    /// search: everything kept is needed.
    Everything,
    /// No patch is within reach.
    Nothing,
    /// Every patch within reach has its nearest triangle at the search within reach,
    /// the farthest of them at this distance (m).
    Within(f64),
}

impl KeptTriangles {
    /// The kept list of a search at `from` (world, m) for `reach` and `slack` (m):
    /// the candidates `kept` (in the BVH's depth-first order) with their box distances,
    /// or `None` when they were too many to list.
    pub(super) fn new(
        from: [Point3<f64>; 2],
        reach: f64,
        slack: f64,
        kept: Option<&[Reachable]>,
        patches: Vec<KeptPatch>,
    ) -> Self {
        Self {
            from,
            reach,
            slack,
            list: kept.map(|kept| KeptList {
                triangles: kept.iter().map(|r| r.triangle as u32).collect(),
                bounds: kept.iter().map(|r| r.bound).collect(),
            }),
            patches,
        }
    }

    /// How far (m) the farther end of segment `[p0, p1]` (world) is from where the
    /// feature was searched.
    pub fn moved_by(&self, p0: &Point3<f64>, p1: &Point3<f64>) -> f64 {
        (p0 - self.from[0]).norm().max((p1 - self.from[1]).norm())
    }

    /// A lower bound (m) of the distance from segment `[p0, p1]` (world) to the mesh,
    /// however far it moved from where it was searched: at the search no triangle was
    /// nearer than the nearest of the patches kept, nor than the reach plus the slack
    /// (a patch farther than that was not kept), and no point of the segment moved by
    /// more than [`KeptTriangles::moved_by`] since (distances are 1-Lipschitz).
    pub fn distance_lower_bound(&self, p0: &Point3<f64>, p1: &Point3<f64>) -> f64 {
        let searched = self
            .patches
            .iter()
            .map(|p| p.distance)
            .fold(self.reach + self.slack, f64::min);
        // The exact distances' rounding (1e-16 of the coordinates) is far below this.
        searched * (1.0 - 1e-12) - 1e-12 - self.moved_by(p0, p1)
    }

    /// Whether the list serves segment `[p0, p1]` (world, m) for `reach` (m): neither
    /// end moved by more than the slack and the reach is not longer than searched.
    pub fn covers(&self, p0: &Point3<f64>, p1: &Point3<f64>, reach: f64) -> bool {
        self.moved_by(p0, p1) <= self.slack && reach <= self.reach
    }

    /// Every kept triangle (indices, in the BVH's depth-first order): what
    /// [`ObstacleMesh::triangles_near`] gives; `None` when the search found more than
    /// it lists (a disc on a finely tessellated surface), see the module documentation.
    pub fn all(&self) -> Option<&[u32]> {
        self.list.as_ref().map(|list| list.triangles.as_slice())
    }

    /// How near the kept patches are to segment `[l0, l1]` (the mesh's own frame),
    /// whose ends moved by at most `moved` (m) from the search, for local contacts
    /// within `limit` (m); `guard` (m) as the scan's.
    fn near_now(
        &self,
        mesh: &ObstacleMesh,
        l0: &Point3<f64>,
        l1: &Point3<f64>,
        moved: f64,
        limit: f64,
        guard: f64,
    ) -> NearNow {
        let mut upper = f64::NEG_INFINITY;
        for patch in &self.patches {
            count_exact();
            let [a, b, c] = mesh.local_triangle(patch.triangle as usize);
            let now = segment_triangle_candidate(l0, l1, &a, &b, &c)
                .squared
                .sqrt();
            if now <= limit {
                upper = upper.max(now);
            } else if patch.distance - moved <= limit + guard {
                return NearNow::Everything;
            }
        }
        if upper == f64::NEG_INFINITY {
            NearNow::Nothing
        } else {
            NearNow::Within(upper)
        }
    }

    /// Takes the triangles of `contacts` (found for this feature by
    /// [`ObstacleMesh::local_contacts_kept`]) as their patches' triangles for the next
    /// evaluation: the distance from a feature to its patches is then measured from
    /// where the feature was last evaluated, not where it was searched, so a feature
    /// that slid along a finely faceted surface looks at the triangles within about
    /// its contact's distance, not within its distance to the triangle it was searched
    /// at (see the module documentation: any triangle of the patch will do). The
    /// contacts and their answers do not depend on it.
    pub fn follow(&mut self, mesh: &ObstacleMesh, contacts: &[super::LocalContact]) {
        for kept in &mut self.patches {
            let patch = mesh.patch_of(kept.triangle as usize);
            if let Some(found) = contacts.iter().find(|c| c.patch == patch) {
                kept.triangle = found.proximity.triangle as u32;
            }
        }
    }

    /// Whether `list` is short enough to look at whole: box-testing it all costs less
    /// than finding the part that can matter (an exact closest point per patch).
    fn looked_at_whole(&self, list: &KeptList) -> bool {
        list.triangles.len() <= SMALL_LIST + SMALL_LIST_PER_PATCH * self.patches.len()
    }
}

impl KeptList {
    /// The triangles (in the BVH's depth-first order) whose box distance at the search
    /// is at most `cutoff` (m): the part that can matter (see the module documentation).
    /// One pass in list order: cheaper than keeping the list sorted by distance (a sort
    /// per search) for the few evaluations that look for a part.
    fn part(&self, cutoff: f64) -> Vec<u32> {
        self.triangles
            .iter()
            .zip(&self.bounds)
            .filter(|&(_, &bound)| bound <= cutoff)
            .map(|(&t, _)| t)
            .collect()
    }
}

impl ObstacleMesh {
    /// [`ObstacleMesh::local_contacts`] of segment `[p0, p1]` (world, m) within
    /// `max_distance` (m) looking only at the triangles of `kept` that can matter
    /// given that no point of the segment is farther than `moved` (m) from the segment
    /// searched at (see the module documentation): the same contacts. The segment is
    /// the feature itself or a part of it (a point of an edge), `moved` the
    /// [`KeptTriangles::moved_by`] of the feature's ends, and `kept` must cover the
    /// feature ([`KeptTriangles::covers`]).
    pub fn local_contacts_kept(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        max_distance: f64,
        kept: &KeptTriangles,
        moved: f64,
    ) -> Vec<super::LocalContact> {
        debug_assert!(moved <= kept.slack && max_distance <= kept.reach);
        let (l0, l1) = (self.to_local(p0), self.to_local(p1));
        let limit = max_distance.next_up();
        let guard = super::near_scan::near_guard(self.tie_tolerance(&l0, &l1), limit);
        // A short list is looked at whole; else the part that can matter given how near
        // the kept patches are now (a listed part, or the BVH near them when unlisted),
        // the whole list or a full search where a patch may be near through another
        // triangle (see the module documentation).
        let part: Vec<u32>;
        let candidates = match &kept.list {
            Some(list) if kept.looked_at_whole(list) => Candidates::List(&list.triangles),
            listed => match (kept.near_now(self, &l0, &l1, moved, limit, guard), listed) {
                (NearNow::Nothing, _) => return Vec::new(),
                (NearNow::Everything, Some(list)) => Candidates::List(&list.triangles),
                (NearNow::Everything, None) => Candidates::Everything,
                (NearNow::Within(upper), Some(list)) => {
                    part = list.part(upper + moved + 2.0 * guard);
                    Candidates::List(&part)
                }
                (NearNow::Within(upper), None) => Candidates::Within(upper + 2.0 * guard),
            },
        };
        let found = self.local_contacts_or_search(&l0, &l1, max_distance, candidates);
        self.contacts_to_world(found, p0, p1)
    }
}
