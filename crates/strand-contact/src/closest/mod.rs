//! Exact closest points between segments and triangles.
//!
//! parry's GJK-based distance queries return witness points that are only about 1e-6
//! accurate; the contact constraints are linearised at these points, so the routines
//! here compute them exactly (up to rounding) by enumerating the faces of the
//! parameter domain: the squared distance is a convex quadratic in the parameters, so
//! its minimum is the stationary point of one face of the domain (an endpoint, an
//! edge, the interior). Every candidate is a feasible pair of points whose distance is
//! evaluated directly, so the returned distance always belongs to the returned points.
//!
//! When the minimisers form an interval (parallel segments overlapping, a segment
//! parallel to a triangle lying over it), the midpoint of that interval is returned:
//! an edge lying flat on a floor then gets its contact point in the middle, which
//! gives symmetric contact loads.

mod segment_segment;
mod segment_triangle;
mod segment_triangle_bound;

pub use segment_segment::{SegmentSegment, closest_segment_segment};
pub use segment_triangle::{SegmentTriangle, closest_segment_triangle};
pub(crate) use segment_triangle::{
    SegmentTriangleParameters, segment_triangle_candidate, segment_triangle_points,
};
pub(crate) use segment_triangle_bound::segment_triangle_lower_bound;

/// Candidates whose distance exceeds the smallest one by at most this fraction of the
/// geometry's size count as ties; among ties, the midpoint of an interval of
/// minimisers is preferred.
pub const TIE_TOLERANCE: f64 = 1e-12;

/// `x` clamped to `[0, 1]`; NaN maps to 0 (so degenerate inputs never produce NaN).
#[inline]
pub(crate) fn clamp_unit(x: f64) -> f64 {
    if x > 0.0 {
        if x < 1.0 { x } else { 1.0 }
    } else {
        0.0
    }
}

/// A feasible candidate of a closest-point search.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Candidate<T> {
    /// Squared distance between the candidate's two points, m².
    pub squared: f64,
    /// Length (in the segment's parameter `s`) of the interval whose midpoint the
    /// candidate is; 0 for an isolated candidate.
    pub interval: f64,
    /// The candidate's parameters.
    pub value: T,
}

/// Picks the candidate of smallest distance; candidates within `tolerance` (m) of it
/// are ties, among which the midpoint of the longest interval wins (a segment lying
/// over a face beats the piece of it beside one edge).
pub(crate) fn pick<T: Copy>(candidates: &[Candidate<T>], tolerance: f64) -> Candidate<T> {
    let mut best = candidates[0];
    for c in &candidates[1..] {
        if c.squared < best.squared {
            best = *c;
        }
    }
    let limit = (best.squared.sqrt() + tolerance).powi(2);
    for c in candidates {
        if c.interval > best.interval && c.squared <= limit {
            best = *c;
        }
    }
    best
}
