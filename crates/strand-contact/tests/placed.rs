//! A mesh moved rigidly by `ObstacleMesh::placed` (its BVH kept in its own frame)
//! answers every query as a mesh built from the moved triangles does: nearest points,
//! local contacts, inside tests, triangles and the bounding box.

use nalgebra::{Isometry3, Point3, Vector3};
use strand_contact::ObstacleMesh;

type P = Point3<f64>;

/// A closed, consistently wound box `[0, 0.3] × [0, 0.2] × [0, 0.1]` m, as vertices
/// and triangles.
fn closed_box() -> (Vec<P>, Vec<[u32; 3]>) {
    let (x, y, z) = (0.3, 0.2, 0.1);
    let v: Vec<P> = (0..8)
        .map(|i| {
            P::new(
                if i & 1 == 0 { 0.0 } else { x },
                if i & 2 == 0 { 0.0 } else { y },
                if i & 4 == 0 { 0.0 } else { z },
            )
        })
        .collect();
    let quads = [
        [0, 2, 3, 1], // bottom (-z)
        [4, 5, 7, 6], // top (+z)
        [0, 1, 5, 4], // front (-y)
        [2, 6, 7, 3], // back (+y)
        [0, 4, 6, 2], // left (-x)
        [1, 3, 7, 5], // right (+x)
    ];
    let mut t = Vec::new();
    for [a, b, c, d] in quads {
        t.push([a, b, c]);
        t.push([a, c, d]);
    }
    (v, t)
}

/// A fixed pseudo-random sequence in [-1, 1) (no dependency on a random crate).
fn noise(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

#[test]
fn a_placed_mesh_answers_as_the_mesh_built_from_moved_triangles() {
    let (vertices, triangles) = closed_box();
    let base = ObstacleMesh::try_from_triangles("box", vertices.clone(), &triangles).unwrap();
    // Two rigid motions composed, as a part placed and then moved by a motion.
    let first = Isometry3::new(Vector3::new(0.02, -0.01, 0.03), Vector3::new(0.1, 0.0, 0.0));
    let second = Isometry3::new(Vector3::new(-0.05, 0.12, 0.4), Vector3::new(0.3, -0.7, 1.1));
    let pose = second * first;
    let placed = base.placed(&first).placed(&second);
    let moved: Vec<P> = vertices.iter().map(|p| pose * p).collect();
    let built = ObstacleMesh::try_from_triangles("box", moved.clone(), &triangles).unwrap();

    let close = |a: &P, b: &P| (a - b).norm() < 1e-12;
    for t in 0..built.triangle_count() {
        let (a, b) = (placed.triangle(t), built.triangle(t));
        assert!((0..3).all(|k| close(&a[k], &b[k])), "triangle {t}");
    }
    let (pa, pb) = (placed.bounding_box(), built.bounding_box());
    assert!(
        close(&pa[0], &pb[0]) && close(&pa[1], &pb[1]),
        "{pa:?} vs {pb:?}"
    );
    // The base mesh itself is not moved.
    assert!(base.placement().is_none());
    assert!(close(
        &base.triangle(0)[0],
        &vertices[triangles[0][0] as usize]
    ));

    let centre = pose * P::new(0.15, 0.1, 0.05);
    let mut seed = 7;
    let mut inside = 0;
    let mut compared = 0;
    for _ in 0..400 {
        let mut point =
            || centre + Vector3::new(noise(&mut seed), noise(&mut seed), noise(&mut seed)) * 0.25;
        let (p0, p1) = (point(), point());
        // Segments and points, near and far.
        for (a, b) in [(p0, p1), (p0, p0)] {
            let (x, y) = (
                placed.segment_proximity(&a, &b, 0.5),
                built.segment_proximity(&a, &b, 0.5),
            );
            match (x, y) {
                (Some(x), Some(y)) => {
                    assert!((x.distance - y.distance).abs() < 1e-12, "{x:?} vs {y:?}");
                    // A segment crossing the surface has several nearest points (each
                    // crossing); elsewhere the nearest point is unique.
                    if y.distance > 1e-9 {
                        assert!(
                            close(&x.point_on_segment, &y.point_on_segment),
                            "{x:?} vs {y:?}"
                        );
                        assert!(close(&x.point_on_mesh, &y.point_on_mesh), "{x:?} vs {y:?}");
                    }
                    match (x.normal, y.normal) {
                        (Some(n), Some(m)) => {
                            assert!((n.into_inner() - m.into_inner()).norm() < 1e-9)
                        }
                        (None, None) => {}
                        other => panic!("normals differ: {other:?}"),
                    }
                }
                (None, None) => {}
                other => panic!("one finds the mesh, the other not: {other:?}"),
            }
            let (x, y) = (
                placed.local_contacts(&a, &b, 0.05),
                built.local_contacts(&a, &b, 0.05),
            );
            if y.iter().all(|c| c.proximity.distance > 1e-9) {
                assert_eq!(x.len(), y.len());
                for (x, y) in x.iter().zip(&y) {
                    assert_eq!(x.patch, y.patch);
                    assert!((x.proximity.distance - y.proximity.distance).abs() < 1e-12);
                    assert!(close(
                        &x.proximity.point_on_mesh,
                        &y.proximity.point_on_mesh
                    ));
                }
                compared += usize::from(!y.is_empty());
            }
        }
        let (x, y) = (placed.encloses(&p0), built.encloses(&p0));
        assert_eq!(x, y, "inside {p0}");
        inside += usize::from(x);
    }
    // The sample reaches inside and outside the box, and local contacts near it.
    assert!(inside > 10 && inside < 390, "{inside} of 400 inside");
    assert!(compared > 50, "{compared} local contacts compared");
}
