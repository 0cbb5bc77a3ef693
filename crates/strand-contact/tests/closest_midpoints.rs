//! Intervals of closest points resolve to their midpoint (closed-form expectations),
//! and degenerate inputs never produce NaN.

use nalgebra::{Point3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use strand_contact::{closest_segment_segment, closest_segment_triangle};

type P = Point3<f64>;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12
}

#[test]
fn segment_flat_over_a_triangle_takes_the_middle() {
    let (a, b, c) = (
        P::new(0.0, 0.0, 0.0),
        P::new(1.0, 0.0, 0.0),
        P::new(0.0, 1.0, 0.0),
    );
    // Entirely over the triangle, at height 0.1: the whole segment is closest.
    let got = closest_segment_triangle(&P::new(0.1, 0.2, 0.1), &P::new(0.5, 0.2, 0.1), &a, &b, &c);
    assert!(close(got.s, 0.5), "{got:?}");
    assert!(close(got.distance, 0.1));
    assert!((got.point_on_triangle - P::new(0.3, 0.2, 0.0)).norm() <= 1e-12);
    // Half over the triangle (x in [0, 0.5] of [-0.5, 0.5]): s in [0.5, 1].
    let got = closest_segment_triangle(
        &P::new(-0.5, 0.2, -0.3),
        &P::new(0.5, 0.2, -0.3),
        &a,
        &b,
        &c,
    );
    assert!(close(got.s, 0.75), "{got:?}");
    assert!(close(got.distance, 0.3));
    // Lying in the plane across the triangle: distance 0 over x in [0, 0.8].
    let got = closest_segment_triangle(&P::new(-1.0, 0.2, 0.0), &P::new(1.0, 0.2, 0.0), &a, &b, &c);
    assert!(close(got.s, 0.7), "{got:?}");
    assert!(got.distance <= 1e-15);
}

#[test]
fn segment_parallel_to_a_triangle_edge_takes_the_middle_of_the_overlap() {
    let (a, b, c) = (
        P::new(0.0, 0.0, 0.0),
        P::new(1.0, 0.0, 0.0),
        P::new(0.0, 1.0, 0.0),
    );
    // Beside edge ab in the plane, x in [-0.5, 0.5]: overlap x in [0, 0.5].
    let got = closest_segment_triangle(
        &P::new(-0.5, -0.2, 0.0),
        &P::new(0.5, -0.2, 0.0),
        &a,
        &b,
        &c,
    );
    assert!(close(got.s, 0.75), "{got:?}");
    assert!(close(got.distance, 0.2));
    assert!(close(got.barycentric[1], 0.25) && close(got.barycentric[2], 0.0));
    // Below and beside edge ab, reversed direction.
    let got = closest_segment_triangle(
        &P::new(0.5, -0.3, -0.4),
        &P::new(-0.5, -0.3, -0.4),
        &a,
        &b,
        &c,
    );
    assert!(close(got.s, 0.25), "{got:?}");
    assert!(close(got.distance, 0.5));
}

#[test]
fn parallel_segments_take_the_middle_of_the_overlap() {
    let p0 = P::new(0.0, 0.0, 0.0);
    let p1 = P::new(1.0, 0.0, 0.0);
    let got = closest_segment_segment(&p0, &p1, &P::new(0.5, 1.0, 0.0), &P::new(2.0, 1.0, 0.0));
    assert!(close(got.s, 0.75) && close(got.t, 0.25 / 1.5), "{got:?}");
    assert!(close(got.distance, 1.0));
    // Reversed second segment, contained in the first.
    let got = closest_segment_segment(&p0, &p1, &P::new(0.6, 0.0, 2.0), &P::new(0.2, 0.0, 2.0));
    assert!(close(got.s, 0.4) && close(got.t, 0.5), "{got:?}");
    // Collinear and overlapping: distance 0 over x in [0.5, 1].
    let got = closest_segment_segment(&p0, &p1, &P::new(0.5, 0.0, 0.0), &P::new(3.0, 0.0, 0.0));
    assert!(close(got.s, 0.75) && got.distance <= 1e-15, "{got:?}");
    // Parallel without overlap: the unique nearest endpoints.
    let got = closest_segment_segment(&p0, &p1, &P::new(2.0, 1.0, 0.0), &P::new(3.0, 1.0, 0.0));
    assert!(close(got.s, 1.0) && close(got.t, 0.0), "{got:?}");
    assert!(close(got.distance, 2.0_f64.sqrt()));
}

/// Random exactly parallel pairs (directions on a grid): `s` is the midpoint of the
/// overlap of the projections, computed here from the endpoints' projections.
#[test]
fn random_parallel_overlaps_resolve_to_their_midpoint() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut checked = 0;
    for _ in 0..2000 {
        let grid = |rng: &mut ChaCha8Rng| f64::from(rng.random_range(-8..=8)) / 8.0;
        let p0 = P::new(grid(&mut rng), grid(&mut rng), grid(&mut rng));
        let d = Vector3::new(grid(&mut rng), grid(&mut rng), grid(&mut rng));
        if d.norm_squared() == 0.0 {
            continue;
        }
        let p1 = p0 + d;
        let q0 = P::new(grid(&mut rng), grid(&mut rng), grid(&mut rng));
        let q1 = q0 + d * (f64::from(rng.random_range(-8..=8)) / 4.0);
        if q1 == q0 {
            continue;
        }
        let project = |x: &P| (x - p0).dot(&d) / d.norm_squared();
        let (s0, s1) = (project(&q0), project(&q1));
        let (low, high) = (s0.min(s1).max(0.0), s0.max(s1).min(1.0));
        if low > high {
            continue;
        }
        let got = closest_segment_segment(&p0, &p1, &q0, &q1);
        assert!(
            close(got.s, 0.5 * (low + high)),
            "{got:?} vs [{low}, {high}]"
        );
        let line_distance = (q0 - p0 - d * project(&q0)).norm();
        assert!(close(got.distance, line_distance));
        checked += 1;
    }
    assert!(checked > 500, "only {checked} overlapping pairs");
}

#[test]
fn degenerate_inputs_give_finite_results() {
    let o = P::origin();
    let x = P::new(1.0, 0.0, 0.0);
    let y = P::new(0.0, 2.0, 0.0);
    let got = closest_segment_segment(&o, &o, &y, &y);
    assert_eq!((got.s, got.t), (0.0, 0.0));
    assert!(close(got.distance, 2.0));
    // Point over a collinear (zero-area) triangle: nearest point of its edges.
    let got = closest_segment_triangle(&y, &y, &o, &x, &P::new(2.0, 0.0, 0.0));
    assert!(close(got.distance, 2.0) && got.barycentric.iter().all(|b| b.is_finite()));
    // A triangle collapsed to a point.
    let got = closest_segment_triangle(&y, &P::new(0.0, 2.0, 3.0), &x, &x, &x);
    assert!(close(got.distance, 5.0_f64.sqrt()) && close(got.s, 0.0));
    // Tiny but non-zero sizes stay finite.
    let tiny = P::new(1e-300, 0.0, 0.0);
    let got = closest_segment_triangle(&o, &tiny, &o, &tiny, &P::new(0.0, 1e-300, 0.0));
    assert!(got.distance.is_finite() && got.s.is_finite());
}
