//! Exact closest points between a segment and a triangle.

use nalgebra::{Point3, Vector3};

use super::segment_segment::segment_segment_parameters;
use super::{Candidate, TIE_TOLERANCE, pick};

/// The closest points of segment `P(s) = p0 + s (p1 − p0)` and triangle `(a, b, c)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentTriangle {
    /// Parameter of the closest point on the segment, in `[0, 1]`.
    pub s: f64,
    /// Barycentric coordinates `(u, v, w)` of the closest point on the triangle,
    /// `u a + v b + w c`, each in `[0, 1]`, summing to 1.
    pub barycentric: [f64; 3],
    /// The closest point on the segment, `P(s)`, m.
    pub point_on_segment: Point3<f64>,
    /// The closest point on the triangle, m.
    pub point_on_triangle: Point3<f64>,
    /// Distance between the two points, m (≥ 0).
    pub distance: f64,
}

/// The closest parameters: `s` on the segment, barycentric coordinates on the triangle.
pub(crate) type SegmentTriangleParameters = (f64, [f64; 3]);

/// Exact closest points of segment `[p0, p1]` and triangle `(a, b, c)` (positions in m).
///
/// When the closest pairs form an interval (the segment parallel to the triangle's
/// plane over the triangle, or parallel to one of its edges), the midpoint of that
/// interval in `s` is returned. A zero-length segment is a point; a zero-area
/// triangle is treated through its edges. Never returns NaN for finite input.
pub fn closest_segment_triangle(
    p0: &Point3<f64>,
    p1: &Point3<f64>,
    a: &Point3<f64>,
    b: &Point3<f64>,
    c: &Point3<f64>,
) -> SegmentTriangle {
    let parameters = segment_triangle_candidate(p0, p1, a, b, c).value;
    segment_triangle_points(p0, p1, a, b, c, parameters)
}

/// The points and distance for closest parameters `(s, barycentric)`.
pub(crate) fn segment_triangle_points(
    p0: &Point3<f64>,
    p1: &Point3<f64>,
    a: &Point3<f64>,
    b: &Point3<f64>,
    c: &Point3<f64>,
    (s, barycentric): SegmentTriangleParameters,
) -> SegmentTriangle {
    let [u, v, w] = barycentric;
    let point_on_segment = p0 + (p1 - p0) * s;
    let point_on_triangle = Point3::from(a.coords * u + b.coords * v + c.coords * w);
    SegmentTriangle {
        s,
        barycentric,
        point_on_segment,
        point_on_triangle,
        distance: (point_on_segment - point_on_triangle).norm(),
    }
}

/// The closest parameters of segment `[p0, p1]` and triangle `(a, b, c)` with their
/// squared distance and the length (in `s`) of the interval of closest points they
/// are the midpoint of (0 for an isolated closest point).
pub(crate) fn segment_triangle_candidate(
    p0: &Point3<f64>,
    p1: &Point3<f64>,
    a: &Point3<f64>,
    b: &Point3<f64>,
    c: &Point3<f64>,
) -> Candidate<SegmentTriangleParameters> {
    let d = p1 - p0;
    let mut candidates = [Candidate {
        squared: f64::INFINITY,
        interval: 0.0,
        value: (0.0, [1.0, 0.0, 0.0]),
    }; 7];
    let mut count = 0;
    let mut push = |candidate| {
        candidates[count] = candidate;
        count += 1;
    };

    // Segment against the three edges (also covers the triangle's vertices).
    let edges = [(a, b, [2, 0, 1]), (b, c, [0, 1, 2]), (c, a, [1, 2, 0])];
    for (from, to, [zero, one_minus_t, t_index]) in edges {
        let edge = segment_segment_parameters(p0, p1, from, to);
        let (s, t) = edge.value;
        let mut barycentric = [0.0; 3];
        barycentric[zero] = 0.0;
        barycentric[one_minus_t] = 1.0 - t;
        barycentric[t_index] = t;
        push(Candidate {
            squared: edge.squared,
            interval: edge.interval,
            value: (s, barycentric),
        });
    }

    let normal = (b - a).cross(&(c - a));
    let area2 = normal.norm_squared();
    if area2.is_finite() && area2 > f64::MIN_POSITIVE {
        let face = Face::new(a, b, c, normal);
        let (g0, g1) = (face.edge_functions(p0), face.edge_functions(p1));
        let at = |s: f64| g0 + (g1 - g0) * s;
        let mut evaluate = |s: f64, g: Vector3<f64>, interval: f64| {
            if let Some((barycentric, point_on_triangle)) = face.point(g) {
                let point_on_segment = p0 + d * s;
                push(Candidate {
                    squared: (point_on_segment - point_on_triangle).norm_squared(),
                    interval,
                    value: (s, barycentric),
                });
            }
        };
        // Endpoints over the face.
        evaluate(0.0, g0, 0.0);
        evaluate(1.0, g1, 0.0);
        // The segment crossing the triangle's plane.
        let (h0, h1) = (normal.dot(&(p0 - a)), normal.dot(&(p1 - a)));
        if h0 != h1 && ((h0 <= 0.0 && h1 >= 0.0) || (h0 >= 0.0 && h1 <= 0.0)) {
            let s = (h0 / (h0 - h1)).clamp(0.0, 1.0);
            evaluate(s, at(s), 0.0);
        }
        // The part of the segment over the face; its midpoint is the answer when the
        // segment is parallel to the plane.
        if let Some((low, high)) = inside_interval(&g0, &g1) {
            let s = 0.5 * (low + high);
            evaluate(s, at(s), high - low);
        }
    }

    let size = [d, b - a, c - b, a - c]
        .iter()
        .map(|v| v.norm_squared())
        .fold(0.0, f64::max)
        .sqrt();
    pick(&candidates[..count], TIE_TOLERANCE * size)
}

/// A non-degenerate triangle's plane with its edge functions.
struct Face<'a> {
    vertices: [&'a Point3<f64>; 3],
    normal: Vector3<f64>,
}

impl<'a> Face<'a> {
    fn new(
        a: &'a Point3<f64>,
        b: &'a Point3<f64>,
        c: &'a Point3<f64>,
        normal: Vector3<f64>,
    ) -> Self {
        Self {
            vertices: [a, b, c],
            normal,
        }
    }

    /// `|normal|²` times the barycentric coordinates of the projection of `p` onto the
    /// plane (unchanged by moving `p` along the normal, and linear in `p`).
    fn edge_functions(&self, p: &Point3<f64>) -> Vector3<f64> {
        let [a, b, c] = self.vertices;
        Vector3::new(
            self.normal.dot(&(c - b).cross(&(p - b))),
            self.normal.dot(&(a - c).cross(&(p - c))),
            self.normal.dot(&(b - a).cross(&(p - a))),
        )
    }

    /// Barycentric coordinates and the point of the triangle for edge-function values
    /// `g`, if they are all ≥ 0 (the projection lies on the triangle). They are
    /// normalised by their sum, so the point lies on the triangle even when rounding
    /// made `g` inconsistent (nearly degenerate triangles).
    fn point(&self, g: Vector3<f64>) -> Option<([f64; 3], Point3<f64>)> {
        let sum = g.x + g.y + g.z;
        if g.iter().any(|x| *x < 0.0) || !(sum > 0.0 && sum.is_finite()) {
            return None;
        }
        let [u, v, w] = [g.x / sum, g.y / sum, g.z / sum];
        let [a, b, c] = self.vertices;
        let point = Point3::from(a.coords * u + b.coords * v + c.coords * w);
        Some(([u, v, w], point))
    }
}

/// The interval of `s ∈ [0, 1]` where every edge function `g0 + s (g1 − g0)` is ≥ 0.
fn inside_interval(g0: &Vector3<f64>, g1: &Vector3<f64>) -> Option<(f64, f64)> {
    let (mut low, mut high) = (0.0_f64, 1.0_f64);
    for i in 0..3 {
        let (start, end) = (g0[i], g1[i]);
        if start == end {
            if start < 0.0 {
                return None;
            }
            continue;
        }
        let root = start / (start - end);
        if end > start {
            low = low.max(root);
        } else {
            high = high.min(root);
        }
    }
    (low <= high).then_some((low, high))
}
