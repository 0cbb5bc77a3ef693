//! Exact closest points between two segments.

use nalgebra::Point3;

use super::{Candidate, TIE_TOLERANCE, clamp_unit, pick};

/// The closest points of segment `P(s) = p0 + s (p1 − p0)` and segment
/// `Q(t) = q0 + t (q1 − q0)`, `s, t ∈ [0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentSegment {
    /// Parameter of the closest point on the first segment, in `[0, 1]`.
    pub s: f64,
    /// Parameter of the closest point on the second segment, in `[0, 1]`.
    pub t: f64,
    /// The closest point on the first segment, `P(s)`, m.
    pub point_on_first: Point3<f64>,
    /// The closest point on the second segment, `Q(t)`, m.
    pub point_on_second: Point3<f64>,
    /// Distance between the two points, m (≥ 0).
    pub distance: f64,
}

/// Exact closest points of segments `[p0, p1]` and `[q0, q1]` (positions in m).
///
/// Parallel segments whose projections overlap have an interval of closest pairs: the
/// midpoint of the overlap (in `s`) is returned. A zero-length segment is a point
/// (`s = 0` or `t = 0`). Never returns NaN for finite input.
pub fn closest_segment_segment(
    p0: &Point3<f64>,
    p1: &Point3<f64>,
    q0: &Point3<f64>,
    q1: &Point3<f64>,
) -> SegmentSegment {
    let (s, t) = segment_segment_parameters(p0, p1, q0, q1).value;
    let point_on_first = p0 + (p1 - p0) * s;
    let point_on_second = q0 + (q1 - q0) * t;
    SegmentSegment {
        s,
        t,
        point_on_first,
        point_on_second,
        distance: (point_on_first - point_on_second).norm(),
    }
}

/// The closest parameters `(s, t)` with their squared distance and the length of the
/// interval of closest pairs they are the midpoint of (0 if isolated).
pub(crate) fn segment_segment_parameters(
    p0: &Point3<f64>,
    p1: &Point3<f64>,
    q0: &Point3<f64>,
    q1: &Point3<f64>,
) -> Candidate<(f64, f64)> {
    let d1 = p1 - p0;
    let d2 = q1 - q0;
    let r = p0 - q0;
    let a = d1.norm_squared();
    let e = d2.norm_squared();
    let b = d1.dot(&d2);
    let c = d1.dot(&r);
    let f = d2.dot(&r);

    let evaluate = |s: f64, t: f64, interval: f64| Candidate {
        squared: (r + d1 * s - d2 * t).norm_squared(),
        interval,
        value: (s, t),
    };
    // Best parameter on one segment for a fixed parameter on the other.
    let best_t = |s: f64| {
        if e > 0.0 {
            clamp_unit((b * s + f) / e)
        } else {
            0.0
        }
    };
    let best_s = |t: f64| {
        if a > 0.0 {
            clamp_unit((b * t - c) / a)
        } else {
            0.0
        }
    };

    let mut candidates = [evaluate(0.0, best_t(0.0), 0.0); 6];
    let mut count = 1;
    let mut push = |candidate| {
        candidates[count] = candidate;
        count += 1;
    };
    // The edges of the parameter square [0, 1]² (its corners are covered by clamping).
    push(evaluate(1.0, best_t(1.0), 0.0));
    push(evaluate(best_s(0.0), 0.0, 0.0));
    push(evaluate(best_s(1.0), 1.0, 0.0));
    if a > 0.0 && e > 0.0 {
        // The interior stationary point of non-parallel lines.
        let denominator = a * e - b * b;
        if denominator > 0.0 {
            let s = (b * f - c * e) / denominator;
            let t = (a * f - b * c) / denominator;
            if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
                push(evaluate(s, t, 0.0));
            }
        }
        // Parallel segments: the midpoint of the overlap of the projections.
        let (s_q0, s_q1) = (-c / a, (b - c) / a);
        let low = s_q0.min(s_q1).max(0.0);
        let high = s_q0.max(s_q1).min(1.0);
        if low <= high {
            let s = 0.5 * (low + high);
            push(evaluate(s, best_t(s), high - low));
        }
    }
    let size = a.max(e).sqrt();
    pick(&candidates[..count], TIE_TOLERANCE * size)
}
