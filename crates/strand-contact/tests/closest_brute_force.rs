//! Exact closest points against independent brute-force references on seeded random
//! inputs: generic, exactly and nearly parallel, intersecting, coplanar and degenerate.
//!
//! References: the segment–segment distance is minimised over `s` by golden-section
//! search of the (convex) point–segment distance; the segment–triangle distance by a
//! nested golden-section search over `s` and over the triangle's strips parallel to
//! an edge (the triangle is the union of the segments `u a + (1 − u) [c, b]`, and the
//! distance to them is convex in `u`). Neither shares code with the crate.

use nalgebra::{Point3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use strand_contact::{closest_segment_segment, closest_segment_triangle};

type P = Point3<f64>;

fn point_segment_distance(p: &P, a: &P, b: &P) -> f64 {
    let d = b - a;
    let len2 = d.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + d * t)).norm()
}

/// Minimum of a convex function on [0, 1] by golden-section search.
fn golden_min(f: impl Fn(f64) -> f64) -> f64 {
    let ratio = (5.0_f64.sqrt() - 1.0) / 2.0;
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    let mut x1 = hi - ratio * (hi - lo);
    let mut x2 = lo + ratio * (hi - lo);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..90 {
        if f1 <= f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - ratio * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + ratio * (hi - lo);
            f2 = f(x2);
        }
    }
    [f(0.0), f(1.0), f1, f2, f(0.5 * (lo + hi))]
        .into_iter()
        .fold(f64::INFINITY, f64::min)
}

fn along(p0: &P, p1: &P, s: f64) -> P {
    p0 + (p1 - p0) * s
}

fn reference_segment_segment(p0: &P, p1: &P, q0: &P, q1: &P) -> f64 {
    golden_min(|s| point_segment_distance(&along(p0, p1, s), q0, q1))
}

fn point_triangle_distance(p: &P, a: &P, b: &P, c: &P) -> f64 {
    golden_min(|u| {
        let from = P::from(a.coords * u + c.coords * (1.0 - u));
        let to = P::from(a.coords * u + b.coords * (1.0 - u));
        point_segment_distance(p, &from, &to)
    })
}

fn reference_segment_triangle(p0: &P, p1: &P, a: &P, b: &P, c: &P) -> f64 {
    golden_min(|s| point_triangle_distance(&along(p0, p1, s), a, b, c))
}

fn random_point(rng: &mut ChaCha8Rng) -> P {
    P::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    )
}

fn random_vector(rng: &mut ChaCha8Rng) -> Vector3<f64> {
    random_point(rng).coords
}

/// A point on a coarse grid (multiples of 1/8), so that parallel and coplanar
/// configurations are exact in floating point.
fn grid_point(rng: &mut ChaCha8Rng) -> P {
    P::new(
        f64::from(rng.random_range(-8..=8)) / 8.0,
        f64::from(rng.random_range(-8..=8)) / 8.0,
        f64::from(rng.random_range(-8..=8)) / 8.0,
    )
}

const KINDS: usize = 8;

/// Two segments of kind `kind % KINDS`.
fn segment_pair(rng: &mut ChaCha8Rng, kind: usize) -> [P; 4] {
    let p0 = random_point(rng);
    let p1 = random_point(rng);
    let d = p1 - p0;
    match kind % KINDS {
        // Generic.
        0 => [p0, p1, random_point(rng), random_point(rng)],
        // Parallel (to rounding), possibly reversed and overlapping.
        1 => {
            let q0 = p0 + random_vector(rng) * 0.5;
            [p0, p1, q0, q0 + d * rng.random_range(-1.5..1.5)]
        }
        // Exactly parallel on a grid.
        2 => {
            let (g0, g1) = (grid_point(rng), grid_point(rng));
            let offset = grid_point(rng).coords * 0.5;
            let k = f64::from(rng.random_range(-4..=4)) / 2.0;
            [g0, g1, g0 + offset, g0 + offset + (g1 - g0) * k]
        }
        // Nearly parallel.
        3 => {
            let q0 = p0 + random_vector(rng) * 0.3;
            [p0, p1, q0, q0 + d + random_vector(rng) * 1e-9]
        }
        // Intersecting.
        4 => {
            let x = along(&p0, &p1, rng.random_range(0.0..1.0));
            let w = random_vector(rng);
            let u = rng.random_range(0.0..1.0);
            [p0, p1, x + w * u, x - w * (1.0 - u)]
        }
        // Coplanar (z = 0).
        5 => {
            let flat = |p: P| P::new(p.x, p.y, 0.0);
            [
                flat(p0),
                flat(p1),
                flat(random_point(rng)),
                flat(random_point(rng)),
            ]
        }
        // A zero-length first or second segment.
        6 => {
            let q0 = random_point(rng);
            if rng.random_bool(0.5) {
                [p0, p0, q0, random_point(rng)]
            } else {
                [p0, p1, q0, q0]
            }
        }
        // Both zero-length, or collinear on a grid.
        _ => {
            if rng.random_bool(0.3) {
                let q0 = random_point(rng);
                [p0, p0, q0, q0]
            } else {
                let (g0, g1) = (grid_point(rng), grid_point(rng));
                let k0 = f64::from(rng.random_range(-4..=4)) / 4.0;
                let k1 = f64::from(rng.random_range(-4..=8)) / 4.0;
                [g0, g1, g0 + (g1 - g0) * k0, g0 + (g1 - g0) * k1]
            }
        }
    }
}

/// A segment and a triangle of kind `kind % KINDS`.
fn segment_triangle(rng: &mut ChaCha8Rng, kind: usize) -> [P; 5] {
    let (a, b, c) = (random_point(rng), random_point(rng), random_point(rng));
    let p0 = random_point(rng);
    let normal = (b - a).cross(&(c - a));
    match kind % KINDS {
        0 => [p0, random_point(rng), a, b, c],
        // Parallel to the plane (to rounding), often over the triangle.
        1 => {
            let inside = P::from((a.coords + b.coords + c.coords) / 3.0);
            let lift = normal.normalize() * rng.random_range(-0.5..0.5);
            let along_plane =
                (b - a) * rng.random_range(-1.0..1.0) + (c - a) * rng.random_range(-1.0..1.0);
            let start = inside + lift - along_plane * rng.random_range(0.0..1.0);
            [start, start + along_plane, a, b, c]
        }
        // Exactly parallel to the plane z = const, over a grid triangle; or
        // exactly parallel to one of its edges.
        2 => {
            let flat = |p: P| P::new(p.x, p.y, 0.0);
            let (a, b, c) = (
                flat(grid_point(rng)),
                flat(grid_point(rng)),
                flat(grid_point(rng)),
            );
            let (g0, g1) = (grid_point(rng), grid_point(rng));
            if rng.random_bool(0.5) {
                [g0, P::new(g1.x, g1.y, g0.z), a, b, c]
            } else {
                let k = f64::from(rng.random_range(-4..=4)) / 4.0;
                [g0, g0 + (b - a) * k, a, b, c]
            }
        }
        // Nearly parallel to the plane.
        3 => {
            let along_plane = (b - a) * 0.7 + (c - a) * 0.2 + normal * 1e-10;
            let start = a + normal.normalize() * rng.random_range(-0.1..0.1);
            [start, start + along_plane, a, b, c]
        }
        // Piercing the triangle.
        4 => {
            let (u, v) = (rng.random_range(0.0..1.0), rng.random_range(0.0..1.0));
            let (u, v) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            let x = a + (b - a) * u + (c - a) * v;
            let w = random_vector(rng);
            let k = rng.random_range(0.0..1.0);
            [x + w * k, x - w * (1.0 - k), a, b, c]
        }
        // Coplanar (z = 0).
        5 => {
            let flat = |p: P| P::new(p.x, p.y, 0.0);
            [flat(p0), flat(random_point(rng)), flat(a), flat(b), flat(c)]
        }
        // Zero-length segment.
        6 => [p0, p0, a, b, c],
        // Degenerate triangles: collinear or coincident vertices.
        _ => {
            let p1 = random_point(rng);
            if rng.random_bool(0.5) {
                let k = rng.random_range(-1.0..2.0);
                [p0, p1, a, b, a + (b - a) * k]
            } else {
                [p0, p1, a, a, if rng.random_bool(0.5) { a } else { b }]
            }
        }
    }
}

const CASES: usize = 4000;
const TOLERANCE: f64 = 1e-12;

#[test]
fn segment_segment_matches_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    let mut worst = 0.0_f64;
    for case in 0..CASES {
        let [p0, p1, q0, q1] = segment_pair(&mut rng, case);
        let got = closest_segment_segment(&p0, &p1, &q0, &q1);
        let reference = reference_segment_segment(&p0, &p1, &q0, &q1);
        let scale = 1.0 + (p1 - p0).norm() + (q1 - q0).norm();
        assert!(
            (0.0..=1.0).contains(&got.s) && (0.0..=1.0).contains(&got.t),
            "case {case}: {got:?}"
        );
        assert!((got.point_on_first - along(&p0, &p1, got.s)).norm() <= 1e-15 * scale);
        assert!((got.point_on_second - along(&q0, &q1, got.t)).norm() <= 1e-15 * scale);
        let between = (got.point_on_first - got.point_on_second).norm();
        assert!((got.distance - between).abs() <= 1e-15 * scale);
        let error = (got.distance - reference) / scale;
        worst = worst.max(error.abs());
        assert!(
            error.abs() <= TOLERANCE,
            "case {case} (kind {}): distance {} vs reference {reference}",
            case % KINDS,
            got.distance
        );
    }
    println!(
        "segment–segment: worst |distance − reference| / scale = {worst:.3e} over {CASES} cases"
    );
}

#[test]
fn segment_triangle_matches_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let mut worst = 0.0_f64;
    for case in 0..CASES {
        let [p0, p1, a, b, c] = segment_triangle(&mut rng, case);
        let got = closest_segment_triangle(&p0, &p1, &a, &b, &c);
        let reference = reference_segment_triangle(&p0, &p1, &a, &b, &c);
        let scale = 1.0 + (p1 - p0).norm() + (b - a).norm() + (c - a).norm();
        let [u, v, w] = got.barycentric;
        assert!((0.0..=1.0).contains(&got.s), "case {case}: {got:?}");
        assert!(
            [u, v, w].iter().all(|x| (0.0..=1.0).contains(x)),
            "case {case}: {got:?}"
        );
        assert!((u + v + w - 1.0).abs() <= 1e-14, "case {case}: {got:?}");
        let on_triangle = P::from(a.coords * u + b.coords * v + c.coords * w);
        assert!((got.point_on_triangle - on_triangle).norm() <= 1e-14 * scale);
        assert!((got.point_on_segment - along(&p0, &p1, got.s)).norm() <= 1e-15 * scale);
        let between = (got.point_on_segment - got.point_on_triangle).norm();
        assert!((got.distance - between).abs() <= 1e-15 * scale);
        let error = (got.distance - reference) / scale;
        worst = worst.max(error.abs());
        assert!(
            error.abs() <= TOLERANCE,
            "case {case} (kind {}): distance {} vs reference {reference}",
            case % KINDS,
            got.distance
        );
    }
    println!(
        "segment–triangle: worst |distance − reference| / scale = {worst:.3e} over {CASES} cases"
    );
}
