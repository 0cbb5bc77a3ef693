//! Rod gaps: the broad phase and rod–rod gaps against O(n²) brute force, mesh gaps of
//! a rod over a floor (closed form), the documented linearisation against finite
//! differences, and the reports of rods starting inside obstacles.

#[path = "support/wavy_surface.rs"]
mod wavy_surface;

use nalgebra::{Point3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use strand_contact::gaps::{Aabb, overlapping_pairs};
use strand_contact::{
    GapError, Obstacle, ObstacleMesh, RodGeometry, closest_segment_segment, mesh_gaps,
    require_clearance, rod_rod_gaps,
};
use wavy_surface::wavy_surface;

type P = Point3<f64>;

fn random_point(rng: &mut ChaCha8Rng, half: f64) -> P {
    P::new(
        rng.random_range(-half..half),
        rng.random_range(-half..half),
        rng.random_range(-half..half),
    )
}

#[test]
fn broad_phase_finds_exactly_the_overlapping_pairs() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for round in 0..20 {
        let count = 50 + 20 * round;
        let boxes: Vec<Aabb> = (0..count)
            .map(|_| {
                let a = random_point(&mut rng, 1.0);
                let b = a + random_point(&mut rng, 0.15).coords;
                Aabb::of_segment(&a, &b, rng.random_range(0.0..0.02))
            })
            .collect();
        let mut expected = Vec::new();
        for i in 0..count {
            for j in i + 1..count {
                let overlap = (0..3).all(|k| {
                    boxes[i].min[k] <= boxes[j].max[k] && boxes[j].min[k] <= boxes[i].max[k]
                });
                if overlap {
                    expected.push((i, j));
                }
            }
        }
        assert_eq!(overlapping_pairs(&boxes), expected, "round {round}");
        assert!(round < 5 || !expected.is_empty());
    }
}

/// A random crumpled polyline (self-contacts likely).
fn random_rod(rng: &mut ChaCha8Rng, vertices: usize) -> Vec<P> {
    let mut p = random_point(rng, 0.5);
    let mut out = vec![p];
    for _ in 1..vertices {
        p += random_point(rng, 0.12).coords;
        out.push(p);
    }
    out
}

#[test]
fn rod_rod_gaps_match_brute_force_over_all_edge_pairs() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let polylines: Vec<Vec<P>> = (0..4).map(|k| random_rod(&mut rng, 30 + 10 * k)).collect();
    let radii = [0.01, 0.02, 0.005, 0.015];
    let rods: Vec<RodGeometry> = polylines
        .iter()
        .zip(radii)
        .map(|(v, radius)| RodGeometry {
            vertices: v,
            radius,
        })
        .collect();
    let margin = 0.03;
    // The caller excludes edges two apart on the same rod.
    let exclude = |ra: usize, ea: usize, rb: usize, eb: usize| ra == rb && eb - ea == 2;
    let gaps = rod_rod_gaps(&rods, margin, exclude).unwrap();

    let mut expected = Vec::new();
    for ra in 0..rods.len() {
        for ea in 0..rods[ra].vertices.len() - 1 {
            for rb in ra..rods.len() {
                for eb in 0..rods[rb].vertices.len() - 1 {
                    if (rb == ra && eb <= ea + 1) || exclude(ra, ea, rb, eb) {
                        continue;
                    }
                    let (a, b) = (rods[ra].vertices, rods[rb].vertices);
                    let c = closest_segment_segment(&a[ea], &a[ea + 1], &b[eb], &b[eb + 1]);
                    let gap = c.distance - rods[ra].radius - rods[rb].radius;
                    if gap <= margin {
                        expected.push((ra, ea, rb, eb, gap));
                    }
                }
            }
        }
    }
    assert!(
        expected.len() > 20,
        "only {} pairs in reach",
        expected.len()
    );
    assert!(expected.iter().any(|e| e.0 == e.2), "no self-contact pair");
    assert_eq!(gaps.len(), expected.len());
    for (gap, (ra, ea, rb, eb, value)) in gaps.iter().zip(&expected) {
        let Obstacle::Rod { rod, edge, t } = gap.with else {
            panic!("not a rod pair: {gap:?}");
        };
        assert_eq!((gap.rod, gap.edge, rod, edge), (*ra, *ea, *rb, *eb));
        assert!((gap.gap - value).abs() <= 1e-15);
        let a = rods[*ra].vertices;
        let b = rods[*rb].vertices;
        assert!((gap.point - (a[*ea] + (a[*ea + 1] - a[*ea]) * gap.s)).norm() <= 1e-14);
        assert!((gap.witness - (b[*eb] + (b[*eb + 1] - b[*eb]) * t)).norm() <= 1e-14);
        let direction = (gap.point - gap.witness).normalize();
        assert!((gap.normal.into_inner() - direction).norm() <= 1e-12);
    }
}

/// The solver's near-neighbour rule (closer than an arc length along the rod) on
/// coiled rods of many short edges: the broad phase skips the excluded run of each
/// edge without listing it and still finds every pair past it, as brute force does.
#[test]
fn rod_rod_gaps_with_an_arc_length_exclusion_match_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let polylines: Vec<Vec<P>> = (0..3)
        .map(|k| {
            // A coil of 1.5 turns (radius 40 mm, pitch 15 mm) with jittered vertices.
            let n = 150 + 50 * k;
            (0..=n)
                .map(|j| {
                    let a = 3.0 * std::f64::consts::PI * j as f64 / n as f64;
                    let jitter = random_point(&mut rng, 0.001).coords;
                    P::new(0.04 * a.cos() + 0.1 * k as f64, 0.04 * a.sin(), 0.0024 * a) + jitter
                })
                .collect()
        })
        .collect();
    let rods: Vec<RodGeometry> = polylines
        .iter()
        .map(|v| RodGeometry {
            vertices: v,
            radius: 0.004,
        })
        .collect();
    let arc: Vec<Vec<f64>> = polylines
        .iter()
        .map(|v| {
            let mut s = vec![0.0];
            for w in v.windows(2) {
                s.push(s.last().unwrap() + (w[1] - w[0]).norm());
            }
            s
        })
        .collect();
    let exclude = |ra: usize, ea: usize, rb: usize, eb: usize| {
        ra == rb && arc[ra][eb] - arc[ra][ea + 1] < 0.03
    };
    let margin = 0.01;
    let gaps = rod_rod_gaps(&rods, margin, exclude).unwrap();
    let mut expected = Vec::new();
    for ra in 0..rods.len() {
        for ea in 0..rods[ra].vertices.len() - 1 {
            for rb in ra..rods.len() {
                for eb in 0..rods[rb].vertices.len() - 1 {
                    if (rb == ra && eb <= ea + 1) || exclude(ra, ea, rb, eb) {
                        continue;
                    }
                    let (a, b) = (rods[ra].vertices, rods[rb].vertices);
                    let c = closest_segment_segment(&a[ea], &a[ea + 1], &b[eb], &b[eb + 1]);
                    if c.distance - rods[ra].radius - rods[rb].radius <= margin {
                        expected.push((ra, ea, rb, eb));
                    }
                }
            }
        }
    }
    assert!(expected.len() > 100, "only {} pairs", expected.len());
    let found: Vec<_> = gaps
        .iter()
        .map(|g| match g.with {
            Obstacle::Rod { rod, edge, .. } => (g.rod, g.edge, rod, edge),
            Obstacle::Mesh(_) => panic!("not a rod pair: {g:?}"),
        })
        .collect();
    assert_eq!(found, expected);
}

/// A straight rod above the flat floor z = 0 at height `h`: every edge gaps at `h − r`.
#[test]
fn a_rod_above_a_floor_has_the_closed_form_gaps() {
    let (vertices, faces) = wavy_surface(800, 1.0, 0.0);
    let floor = ObstacleMesh::try_from_triangles("floor", vertices, &faces).unwrap();
    let (h, r) = (0.05, 0.02);
    let rod: Vec<P> = (0..=10)
        .map(|k| P::new(0.1 + 0.07 * k as f64, 0.43, h))
        .collect();
    let rods = [RodGeometry {
        vertices: &rod,
        radius: r,
    }];
    let gaps = mesh_gaps(&rods, &[floor], 0.04).unwrap();
    assert_eq!(gaps.len(), 10);
    for (edge, gap) in gaps.iter().enumerate() {
        assert_eq!((gap.rod, gap.edge, gap.with), (0, edge, Obstacle::Mesh(0)));
        assert!((gap.gap - (h - r)).abs() <= 1e-15);
        assert!((gap.s - 0.5).abs() <= 1e-9, "{gap:?}");
        assert!((gap.normal.into_inner() - Vector3::z()).norm() <= 1e-12);
    }
    // Out of reach: gap 0.03 > margin 0.02.
    assert!(
        mesh_gaps(
            &rods,
            &[ObstacleMesh::try_from_triangles(
                "f",
                wavy_surface(8, 1.0, 0.0).0,
                &wavy_surface(8, 1.0, 0.0).1
            )
            .unwrap()],
            0.02
        )
        .unwrap()
        .is_empty()
    );
}

/// `d(gap) = n · ((1 − s) dr_j + s dr_j+1) − n · d(witness)` against central finite
/// differences, for rod–mesh (curved mesh, witness fixed) and rod–rod pairs.
#[test]
fn the_documented_linearisation_matches_finite_differences() {
    let (vertices, faces) = wavy_surface(20_000, 1.0, 0.08);
    let surface = ObstacleMesh::try_from_triangles("wavy", vertices, &faces).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let step = 1e-7;
    let mut checked = 0;
    for _ in 0..60 {
        let a = P::new(rng.random_range(0.2..0.8), rng.random_range(0.2..0.8), 0.15);
        let b = a + Vector3::new(
            rng.random_range(-0.05..0.05),
            rng.random_range(-0.05..0.05),
            rng.random_range(-0.03..0.03),
        );
        let c = b + Vector3::new(
            rng.random_range(-0.05..0.05),
            rng.random_range(-0.05..0.05),
            0.0,
        );
        let rod = vec![a, b, c];
        let gap_of = |rod: &[P]| {
            mesh_gaps(
                &[RodGeometry {
                    vertices: rod,
                    radius: 0.01,
                }],
                &[&surface],
                1.0,
            )
            .unwrap()
        };
        let base = gap_of(&rod);
        for gap in &base {
            // Skip points where the nearest feature changes within the step.
            let direction = Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
            let moved = |sign: f64| {
                let mut r = rod.clone();
                r[gap.edge] += direction * (sign * step);
                r[gap.edge + 1] += direction * (sign * step * 0.5);
                gap_of(&r)[gap.edge].gap
            };
            let numeric = (moved(1.0) - moved(-1.0)) / (2.0 * step);
            let predicted = gap.normal.dot(&(direction * ((1.0 - gap.s) + gap.s * 0.5)));
            assert!(
                (numeric - predicted).abs() <= 1e-5,
                "{numeric} vs {predicted}: {gap:?}"
            );
            checked += 1;
        }
    }
    assert!(checked >= 100, "{checked}");

    // Rod–rod: two crossing edges, both moved.
    let rod_a = vec![P::new(0.0, 0.0, 0.0), P::new(1.0, 0.1, 0.0)];
    let rod_b = vec![P::new(0.4, -0.5, 0.2), P::new(0.6, 0.5, 0.25)];
    let gap_of = |a: &[P], b: &[P]| {
        let rods = [
            RodGeometry {
                vertices: a,
                radius: 0.01,
            },
            RodGeometry {
                vertices: b,
                radius: 0.02,
            },
        ];
        rod_rod_gaps(&rods, 1.0, |_, _, _, _| false).unwrap()[0]
    };
    let g = gap_of(&rod_a, &rod_b);
    let Obstacle::Rod { t, .. } = g.with else {
        panic!()
    };
    let (da, db) = (Vector3::new(0.3, -0.2, 0.9), Vector3::new(-0.5, 0.4, 0.1));
    let moved = |sign: f64| {
        let (mut a, mut b) = (rod_a.clone(), rod_b.clone());
        a[1] += da * (sign * step);
        b[0] += db * (sign * step);
        gap_of(&a, &b).gap
    };
    let numeric = (moved(1.0) - moved(-1.0)) / (2.0 * step);
    let predicted = g.normal.dot(&(da * g.s)) - g.normal.dot(&(db * (1.0 - t)));
    assert!(
        (numeric - predicted).abs() <= 1e-6,
        "{numeric} vs {predicted}"
    );
}

#[test]
fn rods_starting_inside_an_obstacle_are_reported_with_their_location() {
    let (vertices, faces) = wavy_surface(200, 1.0, 0.0);
    let floor = ObstacleMesh::try_from_triangles("floor", vertices, &faces).unwrap();
    // Capsule overlapping the floor by 5 mm around x = 0.5.
    let rod = vec![
        P::new(0.3, 0.5, 0.03),
        P::new(0.5, 0.5, 0.005),
        P::new(0.7, 0.5, 0.03),
    ];
    let rods = [RodGeometry {
        vertices: &rod,
        radius: 0.01,
    }];
    let gaps = mesh_gaps(&rods, &[&floor], 0.05).unwrap();
    let error = require_clearance(&gaps, 1e-9).unwrap_err();
    let message = error.to_string();
    assert!(
        matches!(error, GapError::StartsInside { rod: 0, .. }),
        "{message}"
    );
    assert!(
        message.contains("overlaps by 5.000 mm")
            && message.contains("(0.500000, 0.500000, 0.005000)"),
        "{message}"
    );

    // The centreline crossing the floor: no direction, an error with the place.
    let through = vec![P::new(0.3, 0.5, 0.03), P::new(0.5, 0.5, -0.03)];
    let rods = [RodGeometry {
        vertices: &through,
        radius: 0.01,
    }];
    let error = mesh_gaps(&rods, &[&floor], 0.05).unwrap_err();
    assert!(
        matches!(error, GapError::CentrelineTouches { edge: 0, .. }),
        "{error}"
    );
    assert!(
        error.to_string().contains("(0.400000, 0.500000, 0.000000)"),
        "{error}"
    );

    // Bad input.
    let rods = [RodGeometry {
        vertices: &rod,
        radius: -1.0,
    }];
    assert!(matches!(
        mesh_gaps(&rods, &[&floor], 0.0),
        Err(GapError::InvalidRod { .. })
    ));
    let rods = [RodGeometry {
        vertices: &rod,
        radius: 0.01,
    }];
    assert!(matches!(
        rod_rod_gaps(&rods, f64::NAN, |_, _, _, _| false),
        Err(GapError::InvalidMargin { .. })
    ));
}
