//! `rod_rod_minima_of` against its reference (every pair within the margin, then the
//! local-minimum filter), and its work counted at two discretisations.

use nalgebra::{Point3, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::super::rod_rod_gaps::PAIRS_EVALUATED;
use super::super::{RodGeometry, rod_rod_gaps_of};
use super::{rod_rod_local_minima, rod_rod_minima_of};

/// A random rod: `segments` edges of length `h` from a random start, its direction
/// turned by up to `turn` rad per edge (and now and then a kink of up to 2 rad).
fn random_rod(rng: &mut ChaCha8Rng, segments: usize, h: f64, turn: f64) -> Vec<Point3<f64>> {
    let mut point = Point3::new(
        rng.random_range(-0.1..0.1),
        rng.random_range(-0.1..0.1),
        rng.random_range(-0.1..0.1),
    );
    let mut direction = Vector3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    )
    .try_normalize(1e-6)
    .unwrap_or_else(Vector3::x);
    let mut axis: Vector3<f64> = Vector3::z();
    let mut points = vec![point];
    for _ in 0..segments {
        // A slowly wandering bending axis: smooth coils and waves.
        axis = (axis
            + 0.3
                * Vector3::<f64>::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                ))
        .try_normalize(1e-6)
        .unwrap_or_else(Vector3::z);
        let angle = if rng.random_bool(0.01) {
            rng.random_range(0.0..2.0)
        } else {
            turn * rng.random_range(0.0..1.0)
        };
        direction = UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle)
            * direction;
        point += direction * h;
        points.push(point);
    }
    points
}

/// The solver's exclusion, by arc length: along one rod, partners nearer than π r;
/// between rod `k`'s end and rod `k + 1`'s start (a junction) the edges within
/// `joined` of both.
fn exclusion(
    lengths: &[f64],
    radii: &[f64],
    segments: &[usize],
    joined: f64,
) -> impl FnMut(usize, usize, usize, usize) -> bool + use<> {
    let (lengths, radii, segments) = (lengths.to_vec(), radii.to_vec(), segments.to_vec());
    move |rod_a, edge_a, rod_b, edge_b| {
        if rod_a == rod_b {
            let between = (edge_b - edge_a - 1) as f64 * lengths[rod_a];
            return between < std::f64::consts::PI * radii[rod_a].max(radii[rod_b]);
        }
        let from_end = (segments[rod_a] - edge_a - 1) as f64 * lengths[rod_a];
        let from_start = edge_b as f64 * lengths[rod_b];
        rod_b == rod_a + 1 && from_end < joined && from_start < joined
    }
}

/// Random rods (thick and thin against their edges, smooth and kinked, crossing and
/// lying along each other), margins and owners: the same gaps as the reference, bit
/// for bit, or an error from both.
#[test]
fn the_minima_are_those_of_every_pair_within_the_margin() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut kept, mut listed, mut errors) = (0, 0, 0);
    let (mut evaluated, mut evaluated_reference) = (0, 0);
    for case in 0..300 {
        let count = rng.random_range(1..4);
        let mut vertices = Vec::new();
        let (mut lengths, mut radii, mut segments) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..count {
            let n = rng.random_range(2..300);
            let h = rng.random_range(0.0005..0.02);
            let turn = [0.0, 0.01, 0.05, 0.3][rng.random_range(0..4)];
            vertices.push(random_rod(&mut rng, n, h, turn));
            lengths.push(h);
            radii.push(rng.random_range(0.001..0.015));
            segments.push(n);
        }
        let rods: Vec<RodGeometry> = vertices
            .iter()
            .zip(&radii)
            .map(|(v, &radius)| RodGeometry {
                vertices: v,
                radius,
            })
            .collect();
        let largest = radii.iter().cloned().fold(0.0, f64::max);
        let margin = largest * rng.random_range(0.0..3.0);
        let joined = rng.random_range(0.0..0.05);
        let owners: Option<Vec<Vec<bool>>> = rng.random_bool(0.3).then(|| {
            segments
                .iter()
                .map(|&n| (0..n).map(|_| rng.random_bool(0.5)).collect())
                .collect()
        });
        let exclude = || exclusion(&lengths, &radii, &segments, joined);
        PAIRS_EVALUATED.with(|c| c.set(0));
        let reference = rod_rod_gaps_of(&rods, margin, exclude(), owners.as_deref()).map(|all| {
            listed += all.len();
            rod_rod_local_minima(all)
        });
        evaluated_reference += PAIRS_EVALUATED.with(|c| c.replace(0));
        let fast = rod_rod_minima_of(&rods, margin, exclude(), owners.as_deref());
        evaluated += PAIRS_EVALUATED.with(|c| c.get());
        match (reference, fast) {
            (Ok(reference), Ok(fast)) => {
                assert_eq!(reference, fast, "case {case}");
                kept += fast.len();
            }
            (Err(_), Err(_)) => errors += 1,
            (reference, fast) => panic!("case {case}: {reference:?} against {fast:?}"),
        }
    }
    println!(
        "{kept} kept of {listed} listed; {evaluated} pairs evaluated against \
         {evaluated_reference}; {errors} crossing cases"
    );
    // The cases are not trivial: many pairs within the margin, few kept, and runs
    // that spare evaluations (about a quarter of them on these wavy rods).
    assert!(kept > 1000 && listed > 4 * kept, "{kept} of {listed}");
    assert!(
        evaluated < evaluated_reference * 9 / 10,
        "{evaluated} of {evaluated_reference}"
    );
    assert!(
        errors < 150,
        "{errors} of 300 cases have touching centrelines"
    );
}

/// A rod of `segments` edges along a circle arc of radius 1 m through 3 rad (3 m),
/// radius 10 mm, with the solver's margin (2 r) and exclusion (π r): the margin
/// reaches past the exclusion, so every edge has `(4 r − π r) / h` partners within it.
fn arc_work(segments: usize, fast: bool) -> (u64, usize) {
    let vertices: Vec<Point3<f64>> = (0..=segments)
        .map(|j| {
            let angle = 3.0 * j as f64 / segments as f64;
            Point3::new(angle.cos(), angle.sin(), 0.0)
        })
        .collect();
    let radius = 0.01;
    let rods = [RodGeometry {
        vertices: &vertices,
        radius,
    }];
    let h = 3.0 / segments as f64;
    let exclude = exclusion(&[h], &[radius], &[segments], 0.0);
    PAIRS_EVALUATED.with(|c| c.set(0));
    let gaps = if fast {
        rod_rod_minima_of(&rods, 2.0 * radius, exclude, None)
    } else {
        rod_rod_gaps_of(&rods, 2.0 * radius, exclude, None).map(rod_rod_local_minima)
    }
    .unwrap();
    (PAIRS_EVALUATED.with(|c| c.get()), gaps.len())
}

/// With 4× the segments, the exact pair evaluations grow about 4×, not 16× as
/// listing every pair within the margin does (issue 11: quadratic self-contact at
/// fine discretisation).
#[test]
fn the_pairs_evaluated_grow_linearly_in_the_segments() {
    let (small, kept_small) = arc_work(1500, true);
    let (large, kept_large) = arc_work(6000, true);
    let (small_reference, _) = arc_work(1500, false);
    let (large_reference, _) = arc_work(6000, false);
    println!("{small} → {large} pairs (every pair: {small_reference} → {large_reference})");
    // One gap per edge at the end of its excluded run, the same with both.
    assert!(
        kept_small > 1000 && kept_large > 4000,
        "{kept_small}, {kept_large}"
    );
    assert_eq!((kept_small, kept_large), {
        let s = arc_work(1500, false).1;
        let l = arc_work(6000, false).1;
        (s, l)
    });
    let growth = large as f64 / small as f64;
    let reference_growth = large_reference as f64 / small_reference as f64;
    assert!(growth < 5.0, "pairs grow {growth}× for 4× the segments");
    assert!(
        reference_growth > 12.0,
        "every pair grows {reference_growth}×: the case does not test the quadratic"
    );
}
