//! A feature's kept candidate triangles ([`ObstacleMesh::keep_triangles_near`]) sorted
//! by their box distance from the feature where it was searched, so that a later
//! evaluation looks only at the part that can matter given how far the feature moved.
//!
//! On a finely tessellated surface the kept list is a disc of triangles around each
//! contact (those whose boxes lie within the nearest distance plus twice the slack),
//! and most of it matters only if the feature moves by the whole slack. A feature that
//! moved by `δ` looks at the triangles whose stored box distance `b₀` is at most `u +
//! δ + 2 guard`, `u` the largest distance of the segment now to the nearest triangle
//! each patch had at the search ([`KeptTriangles::within`]). Why the contacts are those
//! of the whole kept list (and so of a full search):
//!
//! - every left-out triangle `T` has a box distance now of at least `b₀ − δ > u + 2
//!   guard` (distances move by at most `δ`; one guard covers rounding);
//! - the scan of the part ([`ObstacleMesh::local_contacts_among`]) finds for every
//!   patch `P` within reach a nearest distance `d_P ≤ u`: its nearest triangle at the
//!   search `X_P` is in the part (`b₀(X_P) ≤ d_P⁰ ≤ |X_P now| + δ ≤ u + δ`) and is either
//!   tested or deferred for being farther than a nearer one;
//! - so in a scan of the whole list every `T` of a patch with a member in the part is
//!   deferred (its box is farther than `d_P + guard`) and never tested at the end (its
//!   box is farther than `max_P d_P + guard`), and the midpoint of a stretch of `P`
//!   finds `T` farther than `d_P + guard` from it: the answer does not change;
//! - the same holds for a part of the segment (a point of an edge): its box distances
//!   are at least the segment's, and `u` is measured from the part;
//! - a patch whose `X_P` is now out of reach is left out only when all of it is (its
//!   distance at the search minus `δ` is beyond the reach); a patch not near at the
//!   search was farther than reach plus slack. Otherwise the whole list is used.

use nalgebra::Point3;

use super::ObstacleMesh;
use super::near_scan::Reachable;
use super::work::count_exact;
use crate::closest::segment_triangle_candidate;

/// Lists of at most this many triangles, plus [`SMALL_LIST_PER_PATCH`] per patch, are
/// looked at whole: finding the part costs an exact closest point per patch.
const SMALL_LIST: usize = 16;

/// See [`SMALL_LIST`]: an exact segment–triangle test costs several box tests.
const SMALL_LIST_PER_PATCH: usize = 8;

/// The nearest triangle of one smooth patch at the search.
#[derive(Clone, Copy, Debug)]
pub(super) struct KeptPatch {
    /// The triangle (index `< triangle_count()`).
    pub(super) triangle: u32,
    /// Its distance from the segment searched at, m.
    pub(super) distance: f64,
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
    /// The kept triangles in the BVH's depth-first order.
    triangles: Vec<u32>,
    /// `(box distance from the searched segment in m, index into triangles)`, nearest
    /// first.
    by_bound: Vec<(f64, u32)>,
    /// The nearest triangle of every patch within reach plus slack at the search.
    patches: Vec<KeptPatch>,
}

impl KeptTriangles {
    /// The kept list of a search at `from` (world, m) for `reach` and `slack` (m):
    /// `kept`, the candidates `reachable` (in the BVH's depth-first order, `position`
    /// their index there) kept, sorted by box distance and then position.
    pub(super) fn new(
        from: [Point3<f64>; 2],
        reach: f64,
        slack: f64,
        reachable: &[Reachable],
        kept: &[Reachable],
        patches: Vec<KeptPatch>,
    ) -> Self {
        // The index in `triangles` of every kept position (`u32::MAX`: not kept).
        let mut index = vec![u32::MAX; reachable.len()];
        for r in kept {
            index[r.position] = 0;
        }
        let mut triangles = Vec::with_capacity(kept.len());
        for r in reachable {
            if index[r.position] != u32::MAX {
                index[r.position] = triangles.len() as u32;
                triangles.push(r.triangle as u32);
            }
        }
        // Positions increase with the index: still sorted by (distance, index).
        let by_bound = kept.iter().map(|r| (r.bound, index[r.position])).collect();
        Self {
            from,
            reach,
            slack,
            triangles,
            by_bound,
            patches,
        }
    }

    /// How far (m) the farther end of segment `[p0, p1]` (world) is from where the
    /// feature was searched.
    pub fn moved_by(&self, p0: &Point3<f64>, p1: &Point3<f64>) -> f64 {
        (p0 - self.from[0]).norm().max((p1 - self.from[1]).norm())
    }

    /// Whether the list serves segment `[p0, p1]` (world, m) for `reach` (m): neither
    /// end moved by more than the slack and the reach is not longer than searched.
    pub fn covers(&self, p0: &Point3<f64>, p1: &Point3<f64>, reach: f64) -> bool {
        self.moved_by(p0, p1) <= self.slack && reach <= self.reach
    }

    /// Every kept triangle (indices, in the BVH's depth-first order): what
    /// [`ObstacleMesh::triangles_near`] gives.
    pub fn all(&self) -> &[u32] {
        &self.triangles
    }

    /// The kept triangles (in the BVH's depth-first order) that can matter for the local
    /// contacts within `limit` (m) of segment `[l0, l1]` (the mesh's own frame), whose
    /// ends moved by at most `moved` (m) from the search; `guard` (m) as the scan's
    /// ([`super::near_scan::near_guard`]). `None`: the whole list is needed (a patch
    /// near at the search whose nearest triangle is now out of reach might still be
    /// within it through another, or the list is short). See the module documentation.
    pub(super) fn within(
        &self,
        mesh: &ObstacleMesh,
        l0: &Point3<f64>,
        l1: &Point3<f64>,
        moved: f64,
        limit: f64,
        guard: f64,
    ) -> Option<Vec<u32>> {
        if self.triangles.len() <= SMALL_LIST + SMALL_LIST_PER_PATCH * self.patches.len() {
            // Box-testing them all costs less than finding the part.
            return None;
        }
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
                return None;
            }
        }
        if upper == f64::NEG_INFINITY {
            return Some(Vec::new());
        }
        let cutoff = upper + moved + 2.0 * guard;
        let count = self.by_bound.partition_point(|(bound, _)| *bound <= cutoff);
        Some(in_list_order(
            self.by_bound[..count].iter().map(|(_, i)| *i),
            &self.triangles,
        ))
    }
}

/// The triangles `list[i]` of the positions `picked` (distinct, below `list.len()`), in
/// the order of `list`: the positions are marked in a bit set and read back in order,
/// which costs one pass over `list.len() / 64` words instead of a sort of the picked.
fn in_list_order(picked: impl Iterator<Item = u32>, list: &[u32]) -> Vec<u32> {
    let mut marked = vec![0_u64; list.len().div_ceil(64)];
    let mut count = 0;
    for i in picked {
        marked[i as usize / 64] |= 1 << (i % 64);
        count += 1;
    }
    let mut out = Vec::with_capacity(count);
    for (w, &word) in marked.iter().enumerate() {
        let mut bits = word;
        while bits != 0 {
            let bit = bits.trailing_zeros() as usize;
            out.push(list[w * 64 + bit]);
            bits &= bits - 1;
        }
    }
    out
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
        match kept.within(self, &l0, &l1, moved, limit, guard) {
            Some(part) => self.local_contacts_among(p0, p1, max_distance, &part),
            None => self.local_contacts_among(p0, p1, max_distance, kept.all()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::in_list_order;

    /// The bit set gives the picked positions' entries in list order, as sorting the
    /// positions does: every subset size, list lengths around multiples of 64.
    #[test]
    fn picked_positions_come_back_in_list_order() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move |n: usize| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % n as u64) as usize
        };
        for length in [1, 2, 63, 64, 65, 127, 128, 129, 1000] {
            let list: Vec<u32> = (0..length as u32).map(|i| i * 7 + 3).collect();
            for _ in 0..20 {
                // A random permutation's prefix of random size: distinct positions.
                let mut positions: Vec<u32> = (0..length as u32).collect();
                for i in (1..length).rev() {
                    positions.swap(i, next(i + 1));
                }
                positions.truncate(next(length + 1));
                let mut sorted = positions.clone();
                sorted.sort_unstable();
                let expected: Vec<u32> = sorted.iter().map(|&i| list[i as usize]).collect();
                assert_eq!(in_list_order(positions.into_iter(), &list), expected);
            }
        }
    }
}
