//! A cheap lower bound of the distance between a segment and a triangle: the bound a
//! scan uses to skip the exact closest points ([`super::segment_triangle_candidate`],
//! several hundred operations) of a triangle that cannot be the nearest.
//!
//! A triangle's bounding box is a loose bound on a finely tessellated, tilted surface:
//! the boxes of the tens of triangles around a contact point reach up to the query's
//! nearest distance, so every one of them would be tested exactly. This bound splits
//! the distance into the part along the triangle's normal and the part in its plane:
//! for a point `x` with height `h(x)` over the plane and signed distances `oᵢ(x)`
//! outside the lines of the three edges (positive outside), every point `y` of the
//! triangle satisfies `|x − y|² = h² + |x̄ − y|² ≥ h² + max(0, maxᵢ oᵢ)²` (`x̄` the
//! projection; the triangle lies inside each edge's half-plane). Along the segment
//! `x(s) = p0 + s (p1 − p0)`, `h` and `oᵢ` are linear in `s`, so
//!
//! `min_s dist(x(s), T)² ≥ min_s h(s)² + min_s max(0, maxᵢ oᵢ(s))²`,
//!
//! each minimum in closed form: `|h|` is least at an end unless the segment crosses
//! the plane, and the largest of three linear functions is least at an end or where
//! two of them cross. It is exact for a point over the triangle or beside an edge and
//! for a segment parallel to the plane, and below the distance otherwise.

use nalgebra::{Point3, Vector3};

/// Triangles whose sine of the smallest angle at `a` is below this are not bounded
/// (their normal's direction is known only to about `3 ε / sin`, see
/// [`segment_triangle_lower_bound`]).
const SLIVER_SINE: f64 = 1e-4;

/// A lower bound (m) of the distance between segment `[p0, p1]` and triangle `(a, b,
/// c)` (positions in m), or `None` for a triangle too thin for its normal to be
/// trusted (then use its bounding box).
///
/// Rounding: with the sine at `a` at least [`SLIVER_SINE`] the computed unit normal
/// and edge directions are within about `1e-11` rad of the true ones, so the bound
/// exceeds the exact distance by at most `1e-11` times the segment's distance from
/// `a` (plus a few ulps): `1e-12` m at 0.1 m. The result is reduced by `1e-10` times
/// that distance and the triangle's size, which covers it.
pub(crate) fn segment_triangle_lower_bound(
    p0: &Point3<f64>,
    p1: &Point3<f64>,
    a: &Point3<f64>,
    b: &Point3<f64>,
    c: &Point3<f64>,
) -> Option<f64> {
    let (ab, ac) = (b - a, c - a);
    let normal = ab.cross(&ac);
    let area2 = normal.norm_squared();
    let sides2 = ab.norm_squared() * ac.norm_squared();
    // Written as a positive test so that NaN (a degenerate triangle) gives no bound.
    let thick = area2 > SLIVER_SINE * SLIVER_SINE * sides2;
    if !thick || !area2.is_finite() {
        return None;
    }
    let unit = normal / area2.sqrt();
    let (r0, r1) = (p0 - a, p1 - a);
    // The part along the normal: least |h| over the segment.
    let (h0, h1) = (unit.dot(&r0), unit.dot(&r1));
    let height = if (h0 <= 0.0) != (h1 <= 0.0) {
        0.0
    } else {
        h0.abs().min(h1.abs())
    };
    // The part in the plane: outside distances of the three edge lines at both ends.
    let edges: [(Vector3<f64>, Vector3<f64>); 3] = [(ab, r0), (c - b, p0 - b), (a - c, p0 - c)];
    let d = p1 - p0;
    let mut outside = [(0.0, 0.0); 3];
    for (k, (edge, from)) in edges.iter().enumerate() {
        let out = edge.cross(&unit);
        let length = out.norm();
        let positive = length > 0.0;
        if !positive {
            return None;
        }
        let start = out.dot(from) / length;
        outside[k] = (start, start + out.dot(&d) / length);
    }
    let largest = |s: f64| {
        outside
            .iter()
            .map(|(o0, o1)| o0 + s * (o1 - o0))
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let mut least = largest(0.0).min(largest(1.0));
    for i in 0..3 {
        for j in i + 1..3 {
            let (oi, oj) = (outside[i], outside[j]);
            let slope = (oi.1 - oi.0) - (oj.1 - oj.0);
            if slope != 0.0 {
                let s = (oj.0 - oi.0) / slope;
                if s > 0.0 && s < 1.0 {
                    least = least.min(largest(s));
                }
            }
        }
    }
    let in_plane = least.max(0.0);
    let bound = (height * height + in_plane * in_plane).sqrt();
    let size = r0.norm().max(r1.norm()) + ab.norm().max(ac.norm());
    Some((bound - 1e-10 * size).max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::closest::segment_triangle_candidate;

    fn random(state: &mut u64) -> f64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        (*state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    fn point(state: &mut u64, scale: f64) -> Point3<f64> {
        Point3::new(random(state), random(state), random(state)) * scale
    }

    /// Below the exact distance on random segments, points and triangles of every
    /// shape, and equal to it where the nearest point lies inside the triangle or on
    /// an edge's interior with the segment a point.
    #[test]
    fn never_above_the_exact_distance() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let (mut bounded, mut tight) = (0, 0);
        for case in 0..20_000 {
            let (a, b, c) = (
                point(&mut state, 1.0),
                point(&mut state, 1.0),
                point(&mut state, 1.0),
            );
            let p0 = point(&mut state, 2.0);
            let p1 = if case % 3 == 0 {
                p0
            } else {
                p0 + point(&mut state, 0.5).coords
            };
            let exact = segment_triangle_candidate(&p0, &p1, &a, &b, &c)
                .squared
                .sqrt();
            let Some(bound) = segment_triangle_lower_bound(&p0, &p1, &a, &b, &c) else {
                continue;
            };
            bounded += 1;
            assert!(bound <= exact, "case {case}: {bound} > {exact}");
            if exact - bound <= 1e-9 * (1.0 + exact) {
                tight += 1;
            }
        }
        assert!(bounded > 19_000, "{bounded}");
        // Most random pairs are nearest at a vertex of one or the other, where the
        // bound is below: it must still be exact for a good share.
        assert!(tight > 2_000, "{tight}");
    }

    /// Exact for a point over the face, for a point beside an edge and for a segment
    /// lying parallel over the plane beside the triangle.
    #[test]
    fn exact_over_the_face_and_beside_an_edge() {
        let (a, b, c) = (
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        );
        let over = Point3::new(0.2, 0.3, 0.5);
        let bound = segment_triangle_lower_bound(&over, &over, &a, &b, &c).unwrap();
        assert!((bound - 0.5).abs() < 1e-9, "{bound}");
        let beside = Point3::new(0.5, -0.3, 0.4);
        let bound = segment_triangle_lower_bound(&beside, &beside, &a, &b, &c).unwrap();
        assert!((bound - 0.5).abs() < 1e-9, "{bound}");
        // A segment parallel to the plane, beside the hypotenuse: distance √(h² + o²).
        let (p0, p1) = (Point3::new(1.0, 1.0, 0.3), Point3::new(2.0, 2.0, 0.3));
        let exact = segment_triangle_candidate(&p0, &p1, &a, &b, &c)
            .squared
            .sqrt();
        let bound = segment_triangle_lower_bound(&p0, &p1, &a, &b, &c).unwrap();
        assert!(bound <= exact && exact - bound < 1e-9, "{bound} {exact}");
    }

    /// A sliver (sine of its angle below the threshold) is not bounded; a degenerate
    /// triangle neither.
    #[test]
    fn slivers_are_not_bounded() {
        let p = Point3::new(0.0, 0.0, 1.0);
        let (a, b) = (Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0));
        let sliver = Point3::new(0.5, 1e-6, 0.0);
        assert!(segment_triangle_lower_bound(&p, &p, &a, &b, &sliver).is_none());
        assert!(segment_triangle_lower_bound(&p, &p, &a, &b, &b).is_none());
    }
}
