//! Routes as initial guesses. A route is the polyline a user draws through the places
//! a hose passes (clips, openings, around parts); its corners are where the hose bends
//! smoothly in reality. Taken as drawn, every corner stores a bending energy of about
//! `EI θ²/h` that the solver first has to remove, and a route leaving a clamp at an
//! angle to the clamp starts with a kink there. [`RouteShape::Smoothed`] replaces the
//! polyline by a smooth curve through its vertices.

use nalgebra::Vector3;

use crate::initial::polyline_length;

/// How a rod's route becomes its initial centreline.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RouteShape {
    /// A smooth curve through the route's vertices ([`smooth_route`]), leaving a
    /// clamped end along the clamp: the default.
    Smoothed,
    /// The polyline as drawn (kinks at its vertices): for a route whose smoothed
    /// curve would pass through an obstacle it was drawn around.
    AsDrawn,
}

/// A smooth curve through the vertices of a `route` polyline: cubic Hermite pieces
/// whose tangents at interior vertices bisect the adjacent chords (Catmull–Rom with
/// unit chords) and, at a clamped end, follow the clamp's tangent `start_tangent` /
/// `end_tangent` (else the end chord), sampled densely. The tangents' lengths, a
/// common multiple of each piece's chord within [`ROUTE_TANGENT_SCALE`], give the curve
/// the rod's `length` (m) where that range can (a drawn route is usually a little
/// shorter than the hose, and rounding its corners inwards would shorten it more).
pub(crate) fn smooth_route(
    route: &[Vector3<f64>],
    start_tangent: Option<Vector3<f64>>,
    end_tangent: Option<Vector3<f64>>,
    length: f64,
) -> Vec<Vector3<f64>> {
    let chords: Vec<Vector3<f64>> = route.windows(2).map(|w| w[1] - w[0]).collect();
    if chords.iter().any(|c| c.norm() == 0.0) {
        return route.to_vec();
    }
    let unit = |v: Vector3<f64>| v.normalize();
    let mut tangents = Vec::with_capacity(route.len());
    tangents.push(start_tangent.map(unit).unwrap_or_else(|| unit(chords[0])));
    for pair in chords.windows(2) {
        let bisector = unit(pair[0]) + unit(pair[1]);
        tangents.push(if bisector.norm() > 1e-6 {
            unit(bisector)
        } else {
            unit(pair[1])
        });
    }
    tangents.push(
        end_tangent
            .map(unit)
            .unwrap_or_else(|| unit(chords[chords.len() - 1])),
    );
    // About 2000 points in all, at least 2 per piece: a dense CAD polyline is already
    // smooth and stays linear in its vertex count.
    let samples = (2048 / chords.len()).clamp(2, 64);
    let curve = |scale: f64| {
        let mut curve = vec![route[0]];
        for (i, chord) in chords.iter().enumerate() {
            let (a, b) = (route[i], route[i + 1]);
            let (m0, m1) = (
                tangents[i] * scale * chord.norm(),
                tangents[i + 1] * scale * chord.norm(),
            );
            for k in 1..=samples {
                let t = k as f64 / samples as f64;
                let (t2, t3) = (t * t, t * t * t);
                curve.push(
                    a * (2.0 * t3 - 3.0 * t2 + 1.0)
                        + m0 * (t3 - 2.0 * t2 + t)
                        + b * (-2.0 * t3 + 3.0 * t2)
                        + m1 * (t3 - t2),
                );
            }
        }
        curve
    };
    // The tangent scale that gives the curve the rod's length, within [½, 2].
    let (mut lo, mut hi) = (ROUTE_TANGENT_SCALE.0, ROUTE_TANGENT_SCALE.1);
    if polyline_length(&curve(lo)) >= length {
        return curve(lo);
    }
    if polyline_length(&curve(hi)) <= length {
        return curve(hi);
    }
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if polyline_length(&curve(mid)) < length {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    curve(0.5 * (lo + hi))
}

/// Range of the Hermite tangent scale of [`smooth_route`] (× the chord length): 1 is
/// Catmull–Rom, towards 0 the curve kinks again at the vertices, large scales
/// overshoot. On the convergence map of `strand bench --grid`, (0.8, 1.25) needs fewer
/// iterations than 1 alone or (0.5, 2).
const ROUTE_TANGENT_SCALE: (f64, f64) = (0.8, 1.25);

#[cfg(test)]
mod tests {
    use super::*;

    /// A V through (0,0,0), (0.5,0.2,0), (1,0,0): 1.0770 m long.
    fn v_route() -> Vec<Vector3<f64>> {
        vec![
            Vector3::zeros(),
            Vector3::new(0.5, 0.2, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
        ]
    }

    #[test]
    fn the_smoothed_route_passes_every_vertex_and_leaves_along_the_clamps() {
        let route = v_route();
        let along_x = Some(Vector3::x());
        let curve = smooth_route(&route, along_x, along_x, 1.1);
        for vertex in &route {
            let nearest = curve
                .iter()
                .map(|p| (p - vertex).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(nearest < 1e-15, "{vertex}: {nearest}");
        }
        for (a, b) in [
            (curve[0], curve[1]),
            (curve[curve.len() - 2], curve[curve.len() - 1]),
        ] {
            let direction = (b - a).normalize();
            // One sample of a cubic: the chord turns by O(1/samples) from the tangent.
            assert!(direction.dot(&Vector3::x()) > 0.999, "{direction}");
        }
        // At the middle vertex the curve runs along the bisector of the chords (+x).
        let middle = curve
            .iter()
            .position(|p| (p - route[1]).norm() < 1e-15)
            .unwrap();
        let through = (curve[middle + 1] - curve[middle - 1]).normalize();
        assert!(through.dot(&Vector3::x()) > 0.999, "{through}");
    }

    #[test]
    fn the_smoothed_route_has_the_rod_length_when_the_tangent_range_allows() {
        let route = v_route();
        let shortest = polyline_length(&smooth_route(&route, None, None, 0.0));
        let longest = polyline_length(&smooth_route(&route, None, None, 10.0));
        assert!(shortest < longest, "{shortest} {longest}");
        for target in [0.9 * shortest + 0.1 * longest, 0.5 * (shortest + longest)] {
            let length = polyline_length(&smooth_route(&route, None, None, target));
            assert!((length - target).abs() < 1e-9, "{length} vs {target}");
        }
    }

    #[test]
    fn a_dense_route_is_sampled_linearly_in_its_vertex_count() {
        // A CAD centreline of many vertices gets at most 2 points per piece (plus the
        // start), not 64: the work stays linear in the vertex count.
        for vertices in [1_000usize, 10_000] {
            let route: Vec<Vector3<f64>> = (0..vertices)
                .map(|i| {
                    let t = i as f64 / (vertices - 1) as f64;
                    Vector3::new(t, (3.0 * t).sin() * 0.1, 0.0)
                })
                .collect();
            let curve = smooth_route(&route, None, None, polyline_length(&route));
            assert_eq!(curve.len(), 2 * (vertices - 1) + 1);
        }
    }
}
