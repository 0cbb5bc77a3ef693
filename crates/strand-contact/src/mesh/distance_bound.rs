//! A lower bound of a segment's distance to a mesh that depends on that distance alone,
//! through the BVH: what the step's conservative advancement needs, found without
//! descending to the exact nearest triangle.
//!
//! The bound is `⌊d⌋`, the exact distance `d` rounded down to a fixed grid of
//! [`DISTANCE_GRID_STEPS`] geometric steps per binary octave ([`distance_grid_floor`]),
//! so `15/16 d < ⌊d⌋ ≤ d`. The search keeps the least exact distance `b` found so far
//! (starting from a hinted triangle's, if any) and prunes every node and triangle whose
//! box is at least `⌊b⌋` away (less a rounding margin): once nothing is left, every
//! triangle not tested is at least `⌊b⌋` away and `b` is one triangle's distance, so
//! `⌊b⌋ ≤ d ≤ b` and, the floor being monotone, `⌊d⌋ = ⌊b⌋`. The search
//! stops as soon as the boxes left are no nearer than the grid point below the best
//! triangle, instead of descending until they are no nearer than the triangle itself
//! (an edge lying along a finely tessellated floor has a whole strip of boxes just
//! nearer than its nearest triangle), and its answer is a function of `d`: it does not
//! depend on which triangle the search met first, on the shape of the tree or on the
//! rounding margin of the boxes (which grows with the coordinates), so identical
//! geometry gets bit-identical bounds whatever else the mesh or the scene holds.

use nalgebra::Point3;

use super::ObstacleMesh;
use super::segment_proximity::SegmentBound;
use super::work::{count_box, count_exact, count_node};
use crate::closest::segment_triangle_candidate;

/// Steps of the grid of [`distance_grid_floor`] per binary octave of distances: the
/// grid points `2ᵉ · 2^(k/12)`, `k = 0..11`, 5.95 % apart, so a distance `d` (m) is
/// rounded down by less than `d / 16`. (Four steps, bounds within `d / 6`, cost the
/// contact solve over a 1M-triangle floor 16 % fewer instructions with the same
/// iterates, but a thin cable in a 90° groove (the everyday harness's seed 3, case 17)
/// then took 780 iterations without converging where twelve steps converge in 91:
/// shorter step limits change the path, so the grid stays fine.)
pub const DISTANCE_GRID_STEPS: usize = 12;

/// The grid points of one octave, `2^(k/12)` for `k = 0..11` (any fixed values from 1
/// with ratios below 16/15 would do; these are 5.95 % apart).
const OCTAVE: [f64; DISTANCE_GRID_STEPS] = [
    1.0,
    1.0594630943592953,
    1.122462048309373,
    1.189207115002721,
    1.2599210498948732,
    1.3348398541700344,
    std::f64::consts::SQRT_2,
    1.4983070768766815,
    1.5874010519681994,
    1.681792830507429,
    1.7817974362806785,
    1.8877486253633868,
];

/// `d` (m, ≥ 0) rounded down to the grid `2ᵉ · 2^(k/12)` (`e` any exponent, `k =
/// 0..11`): for `d` from 2.3·10⁻³⁰⁸ m (the least normal float) on, `15/16 d < 2^(−1/12)
/// d < result ≤ d`; below, 0. Exact (the octave's grid point times a power of two) and
/// monotone: `a ≤ b` gives `⌊a⌋ ≤ ⌊b⌋`, and a grid point is its own floor.
pub fn distance_grid_floor(d: f64) -> f64 {
    debug_assert!(d >= 0.0, "distance {d}");
    const EXPONENT: u64 = 0x7ff << 52;
    let bits = d.to_bits();
    let exponent = bits & EXPONENT;
    if exponent == 0 || exponent == EXPONENT {
        // Zero and subnormal distances round to 0; infinity (and NaN) stay.
        return if exponent == 0 { 0.0 } else { d };
    }
    // d = 2ᵉ m with m in [1, 2), both exact.
    let scale = f64::from_bits(exponent);
    let mantissa = f64::from_bits((bits & !EXPONENT) | (1023 << 52));
    let k = OCTAVE.partition_point(|&g| g <= mantissa) - 1;
    OCTAVE[k] * scale
}

impl ObstacleMesh {
    /// A lower bound (m) of the distance `d` from segment `[p0, p1]` (m) to the mesh,
    /// when `d ≤ max_distance` (m); `None` when the mesh is farther.
    ///
    /// The bound is `d` rounded down to the grid of [`distance_grid_floor`], `d` the
    /// least of the exact segment–triangle distances (those of
    /// [`ObstacleMesh::segment_proximity`], which on an edge lying over a stretch of
    /// tied nearest points may report the same distance to within rounding): never
    /// above `d`, above `15/16 d`, and a function of `d` alone, so the same segment over
    /// the same triangles gets the same bound bit for bit whatever else the mesh holds
    /// and however its tree is shaped. It costs less than the exact search: the BVH
    /// descent stops at boxes as far as the grid point below the nearest triangle found,
    /// and no closest points or tie intervals are computed.
    pub fn segment_distance_bound(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        max_distance: f64,
    ) -> Option<f64> {
        self.segment_distance_bound_from(p0, p1, max_distance, None)
            .map(|found| found.bound)
    }

    /// [`ObstacleMesh::segment_distance_bound`] starting from triangle `hint` (its
    /// index, ignored when out of range or farther than `max_distance`), with the
    /// nearest triangle the search tested, to hint the next query of a segment that
    /// moved a little. The bound is the same whatever the hint (see the module
    /// documentation: it is `⌊d⌋` for any starting triangle); a hint near the nearest
    /// triangle only prunes the descent from the start, so the search need not find
    /// the nearest triangle before it can stop.
    pub fn segment_distance_bound_from(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        max_distance: f64,
        hint: Option<usize>,
    ) -> Option<DistanceBound> {
        let (l0, l1) = (self.to_local(p0), self.to_local(p1));
        self.distance_bound_here(&l0, &l1, max_distance, hint)
    }

    /// [`ObstacleMesh::segment_distance_bound_from`] of a segment in the mesh's own
    /// frame.
    pub(super) fn distance_bound_here(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        max_distance: f64,
        hint: Option<usize>,
    ) -> Option<DistanceBound> {
        let bound = SegmentBound::new(p0, p1, &self.bounding_box);
        let mut best = Bounded::within(max_distance);
        if let Some(t) = hint.filter(|&t| t < self.triangle_count()) {
            count_exact();
            let [a, b, c] = self.local_triangle(t);
            best.offer(
                t,
                segment_triangle_candidate(p0, p1, &a, &b, &c)
                    .squared
                    .sqrt(),
            );
        }
        self.tree.bvh.nearer_first(
            &mut best,
            |best, _, node_box| {
                count_node();
                bound.distance(node_box, best.limit() + bound.rounding)
            },
            |best, node_bound, _| best.may_hold(node_bound - bound.rounding),
            |best, leaf| {
                for &t in self.tree.cluster(leaf) {
                    let corners = self.local_triangle(t as usize);
                    count_box();
                    let limit = best.limit() + bound.rounding;
                    let lower = bound.triangle_distance(&corners, limit) - bound.rounding;
                    if !best.may_hold(lower) {
                        continue;
                    }
                    count_exact();
                    let [a, b, c] = corners;
                    best.offer(
                        t as usize,
                        segment_triangle_candidate(p0, p1, &a, &b, &c)
                            .squared
                            .sqrt(),
                    );
                }
            },
        );
        best.found.then(|| DistanceBound {
            bound: distance_grid_floor(best.distance),
            nearest_tested: best.triangle,
        })
    }

    /// [`ObstacleMesh::segment_distance_bound`] (in the mesh's frame) from every
    /// triangle's exact distance (the reference of the BVH search in the tests).
    #[cfg(test)]
    pub(super) fn distance_bound_by_scan(
        &self,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
        max_distance: f64,
    ) -> Option<f64> {
        (0..self.triangle_count())
            .map(|t| {
                let [a, b, c] = self.local_triangle(t);
                segment_triangle_candidate(p0, p1, &a, &b, &c)
                    .squared
                    .sqrt()
            })
            .filter(|&d| d <= max_distance)
            .reduce(f64::min)
            .map(distance_grid_floor)
    }
}

/// What [`ObstacleMesh::segment_distance_bound_from`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistanceBound {
    /// The lower bound of the distance, m: the exact distance rounded down to the grid
    /// of [`distance_grid_floor`].
    pub bound: f64,
    /// The nearest of the triangles the search computed exact distances of (the
    /// nearest one, or one at most `1/15` of the distance farther; which one depends on
    /// the tree), a hint for the next query.
    pub nearest_tested: usize,
}

/// The state of a [`ObstacleMesh::segment_distance_bound`] search.
struct Bounded {
    /// The least exact distance found (at first `max_distance`), m.
    distance: f64,
    /// Whether a triangle within `max_distance` was found.
    found: bool,
    /// That triangle.
    triangle: usize,
    /// [`distance_grid_floor`] of `distance` once found, m: everything at least this
    /// far is pruned.
    floor: f64,
}

impl Bounded {
    /// Nothing found yet, searching within `max_distance` (m).
    fn within(max_distance: f64) -> Self {
        Self {
            distance: max_distance,
            found: false,
            triangle: 0,
            floor: max_distance,
        }
    }

    /// The distance (m) beyond which nothing is looked at (for the boxes' cheap tests).
    #[inline]
    fn limit(&self) -> f64 {
        self.floor
    }

    /// Whether a triangle or node at least `lower` (m) away may change the answer:
    /// within `max_distance` while nothing is found, then nearer than the grid point
    /// below the best (nothing is nearer than 0).
    #[inline]
    fn may_hold(&self, lower: f64) -> bool {
        if self.found {
            self.floor > 0.0 && lower < self.floor
        } else {
            lower <= self.floor
        }
    }

    /// Keeps triangle `triangle` at exact distance `distance` (m) if it is nearer.
    #[inline]
    fn offer(&mut self, triangle: usize, distance: f64) {
        let nearer = if self.found {
            distance < self.distance
        } else {
            distance <= self.distance
        };
        if nearer {
            *self = Self {
                distance,
                found: true,
                triangle,
                floor: distance_grid_floor(distance),
            };
        }
    }
}
