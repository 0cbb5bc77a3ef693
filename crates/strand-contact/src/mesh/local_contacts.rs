//! Every local contact of a segment (or a point) with a mesh: one per smooth patch.
//!
//! A vertex lying in a groove touches both flanks; a single nearest point would jump
//! from one flank to the other between iterations. Here every triangle within reach
//! is a candidate; a candidate whose mesh point `q` is not a local minimum of the
//! distance over the surface (a triangle touching `q` is nearer to the segment point)
//! is dropped, and each smooth patch ([`super::SMOOTH_PATCH_ANGLE_RAD`]) keeps its
//! nearest remaining candidate. Coplanar neighbours of a tessellated plane are one
//! patch, so a point on a floor has one contact; a convex ridge seen from above gives
//! the same point from both faces, kept once.

use super::ObstacleMesh;
use super::near_scan::{Near, near_guard};
use super::segment_proximity::SegmentBound;
use crate::closest::{
    Candidate, SegmentTriangleParameters, TIE_TOLERANCE, pick, segment_triangle_candidate,
};
use crate::mesh::Proximity;
use nalgebra::Point3;

/// One local contact: the nearest point of one smooth patch, a local minimum of the
/// distance over the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalContact {
    /// The patch ([`ObstacleMesh::patch_of`]): stable while the contact stays on it,
    /// so it names the constraint across iterations.
    pub patch: usize,
    /// The nearest point of the patch (as [`ObstacleMesh::segment_proximity`] gives
    /// for the whole mesh; `tie` spans the patch's stretch of nearest points).
    pub proximity: Proximity,
    /// The segment parameters `[low, high]` spanned by the patch's nearest points of
    /// its triangles that lie within [`NEAR_TIE_FRACTION`] of the search's guard (about
    /// 1e-9 m) of the patch's nearest distance: the nearly tied stretch. It contains
    /// `proximity.tie`; on a finely faceted convex surface it reaches the next ridges
    /// that a small turn of the segment would bring into contact.
    pub near_tie: [f64; 2],
}

/// Fraction of the guard of the near scan ([`near_guard`], m) within which a triangle's
/// nearest point counts as nearly tied with the patch's nearest ([`LocalContact`]'s
/// `near_tie`). Below 1, every such triangle is tested exactly, never deferred.
pub const NEAR_TIE_FRACTION: f64 = 0.5;

impl ObstacleMesh {
    /// The local contacts of segment `[p0, p1]` (m) within `max_distance` (m), nearest
    /// first; at most one per smooth patch. Empty when the mesh is farther away.
    pub fn local_contacts(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        max_distance: f64,
    ) -> Vec<LocalContact> {
        let (l0, l1) = (self.to_local(p0), self.to_local(p1));
        let out = self
            .local_contacts_here(&l0, &l1, max_distance, Candidates::Everything)
            .expect("a search of the whole mesh always tells");
        self.contacts_to_world(out, p0, p1)
    }

    /// `contacts` of segment `[p0, p1]` (world, m) found in the mesh's own frame, in
    /// world coordinates.
    pub(super) fn contacts_to_world(
        &self,
        mut contacts: Vec<LocalContact>,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
    ) -> Vec<LocalContact> {
        for c in &mut contacts {
            c.proximity = self.to_world(c.proximity, p0, p1);
        }
        contacts
    }

    /// [`ObstacleMesh::local_contacts`] looking only at the triangles `candidates`
    /// (indices `< triangle_count()`, in the BVH's depth-first order) kept by
    /// [`ObstacleMesh::triangles_near`] for a segment from which neither end of
    /// `[p0, p1]` has moved by more than the slack, with `max_distance` at most the
    /// reach asked there: then the same contacts as `local_contacts` (see
    /// `triangles_near`). Where the candidates cannot tell (the midpoint of a stretch of
    /// nearest points lying off every near triangle) it searches the whole mesh.
    pub fn local_contacts_among(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        max_distance: f64,
        candidates: &[u32],
    ) -> Vec<LocalContact> {
        let (l0, l1) = (self.to_local(p0), self.to_local(p1));
        let out =
            self.local_contacts_or_search(&l0, &l1, max_distance, Candidates::List(candidates));
        self.contacts_to_world(out, p0, p1)
    }

    /// [`ObstacleMesh::local_contacts_here`] of `candidates`, or of every triangle
    /// where those cannot tell the midpoint of a stretch.
    pub(super) fn local_contacts_or_search(
        &self,
        l0: &Point3<f64>,
        l1: &Point3<f64>,
        max_distance: f64,
        candidates: Candidates<'_>,
    ) -> Vec<LocalContact> {
        self.local_contacts_here(l0, l1, max_distance, candidates)
            .unwrap_or_else(|| {
                self.local_contacts_here(l0, l1, max_distance, Candidates::Everything)
                    .expect("a search of the whole mesh always tells")
            })
    }

    /// [`ObstacleMesh::local_contacts`] of a segment in the mesh's own frame, looking
    /// at `candidates`; `None` when they cannot tell the midpoint of a stretch (never
    /// for [`Candidates::Everything`]).
    fn local_contacts_here(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        max_distance: f64,
        candidates: Candidates<'_>,
    ) -> Option<Vec<LocalContact>> {
        let [min, max] = self.bounding_box;
        let size = (p1 - p0).norm() + (max - min).norm();
        let tolerance = TIE_TOLERANCE * size;
        let limit = max_distance.next_up();
        let bound = SegmentBound::new(p0, p1, &self.bounding_box);
        let reachable = match candidates {
            Candidates::Everything => self.reachable(&bound, limit, None),
            Candidates::List(list) => self.reachable(&bound, limit, Some(list)),
            Candidates::Within(near) => self.reachable_near(&bound, limit.min(near)),
        };
        let partial = !matches!(candidates, Candidates::Everything);
        let guard = near_guard(tolerance, limit);
        let scan = self.scan_near(p0, p1, limit, reachable, guard);
        let near = &scan.near;
        let mut patches: Vec<usize> = near.iter().map(|n| self.patch_of(n.triangle)).collect();
        patches.sort_unstable();
        patches.dedup();
        let mut out: Vec<LocalContact> = Vec::with_capacity(patches.len());
        for patch in patches {
            let members: Vec<&Near> = near
                .iter()
                .filter(|n| self.patch_of(n.triangle) == patch)
                .collect();
            let candidates: Vec<_> = members.iter().map(|n| n.candidate).collect();
            let best = pick(&candidates, tolerance);
            let Some(&&Near { triangle, .. }) = members
                .iter()
                .find(|n| n.candidate.value == best.value && n.candidate.squared == best.squared)
            else {
                continue;
            };
            if !self.is_local_minimum(p0, p1, triangle, &best, near, tolerance) {
                continue;
            }
            let mut proximity = self.proximity(p0, p1, triangle, best.value, tolerance);
            // The patch's stretch of nearest points (an edge lying on a face).
            let tie_limit = (best.squared.sqrt() + tolerance).powi(2);
            let (low, high) = candidates.iter().filter(|c| c.squared <= tie_limit).fold(
                (f64::INFINITY, f64::NEG_INFINITY),
                |(l, h), c| {
                    let half = 0.5 * c.interval;
                    (l.min(c.value.0 - half), h.max(c.value.0 + half))
                },
            );
            let (low, high) = (low.max(0.0), high.min(1.0));
            proximity.tie = [low, high];
            let near_limit = (best.squared.sqrt() + near_tie_distance(guard)).powi(2);
            let near_tie = candidates
                .iter()
                .filter(|c| c.squared <= near_limit)
                .fold([low, high], |[l, h], c| {
                    let half = 0.5 * c.interval;
                    [l.min(c.value.0 - half), h.max(c.value.0 + half)]
                })
                .map(|s| s.clamp(0.0, 1.0));
            if high - low > best.interval * (1.0 + 1e-9) {
                // Its midpoint, as `segment_proximity` does for the whole mesh.
                let s = 0.5 * (low + high);
                let point = p0 + (p1 - p0) * s;
                // Every member within reach, the deferred ones too, in candidate order.
                let extra = self.deferred_members(&scan, p0, p1, limit, patch);
                let mut all: Vec<&Near> = members.iter().copied().chain(&extra).collect();
                all.sort_by_key(|n| n.position);
                let at: Vec<_> = all
                    .iter()
                    .map(|n| {
                        let [a, b, c] = self.local_triangle(n.triangle);
                        (
                            n.triangle,
                            segment_triangle_candidate(&point, &point, &a, &b, &c),
                        )
                    })
                    .collect();
                let nearest = at.iter().min_by(|x, y| x.1.squared.total_cmp(&y.1.squared));
                // Off every triangle near the segment: kept candidates may miss its own.
                let off =
                    nearest.is_none_or(|(_, c)| c.squared.sqrt() > best.squared.sqrt() + guard);
                if partial && off {
                    return None;
                }
                if let Some((t, c)) = nearest {
                    let mut mid = self.proximity(&point, &point, *t, c.value, tolerance);
                    mid.s = s;
                    mid.tie = [low, high];
                    proximity = mid;
                }
            }
            let duplicate = out.iter().any(|kept| {
                let k = &kept.proximity;
                (k.point_on_mesh - proximity.point_on_mesh).norm() <= SAME_POINT * size
                    && (k.point_on_segment - proximity.point_on_segment).norm() <= SAME_POINT * size
            });
            if !duplicate {
                out.push(LocalContact {
                    patch,
                    proximity,
                    near_tie,
                });
            }
        }
        out.sort_by(|a, b| {
            (a.proximity.distance, a.patch)
                .partial_cmp(&(b.proximity.distance, b.patch))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        Some(out)
    }

    /// Whether the candidate's mesh point `q` is a local minimum of the distance from
    /// the segment point over the surface: no other triangle touching `q` comes nearer
    /// to that point (by more than `tolerance`).
    fn is_local_minimum(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        triangle: usize,
        best: &Candidate<SegmentTriangleParameters>,
        near: &[Near],
        tolerance: f64,
    ) -> bool {
        let (s, [u, v, w]) = best.value;
        let point = p0 + (p1 - p0) * s;
        let [a, b, c] = self.local_triangle(triangle);
        let q = Point3::from(a.coords * u + b.coords * v + c.coords * w);
        let distance = best.squared.sqrt();
        let touch = CONTAINS * (1.0 + distance);
        near.iter().filter(|n| n.triangle != triangle).all(|n| {
            let [a, b, c] = self.local_triangle(n.triangle);
            let low = a.inf(&b).inf(&c);
            let high = a.sup(&b).sup(&c);
            if (0..3).any(|k| q[k] < low[k] - touch || q[k] > high[k] + touch) {
                return true;
            }
            if segment_triangle_candidate(&q, &q, &a, &b, &c).squared > touch * touch {
                return true;
            }
            let other = segment_triangle_candidate(&point, &point, &a, &b, &c);
            other.squared.sqrt() >= distance - tolerance
        })
    }
}

/// The triangles [`ObstacleMesh::local_contacts_here`] looks at.
#[derive(Clone, Copy, Debug)]
pub(super) enum Candidates<'a> {
    /// Every triangle whose box is within reach (through the BVH).
    Everything,
    /// Those of a list (triangle indices in the BVH's depth-first order) whose boxes
    /// are within reach.
    List(&'a [u32]),
    /// Every triangle whose box is within this distance (m) and within reach (through
    /// the BVH): enough when every triangle that can matter is known to be that near
    /// ([`ObstacleMesh::local_contacts_kept`]).
    Within(f64),
}

/// The distance (m) within which a triangle's nearest point is nearly tied with its
/// patch's nearest, for a near scan of guard `guard` (m).
fn near_tie_distance(guard: f64) -> f64 {
    NEAR_TIE_FRACTION * guard
}

/// A triangle within this distance (relative to `1 + distance`, m) of a mesh point
/// touches it.
const CONTAINS: f64 = 1e-10;

/// Two contacts whose points (on the mesh and on the segment) agree to this fraction
/// of the geometry's size are one contact (a ridge seen from both faces).
const SAME_POINT: f64 = 1e-9;
