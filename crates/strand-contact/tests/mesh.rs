//! Environment meshes: BVH queries against brute force over all triangles, interval
//! midpoints across triangles, validation and OBJ loading errors.

#[path = "support/wavy_surface.rs"]
mod wavy_surface;

use std::io::Write;

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use strand_contact::{MeshError, ObstacleMesh, closest_segment_triangle};
use wavy_surface::wavy_surface;

type P = Point3<f64>;

fn random_point(rng: &mut ChaCha8Rng, half: f64) -> P {
    P::new(
        rng.random_range(-half..half),
        rng.random_range(-half..half),
        rng.random_range(-half..half),
    )
}

/// Nearest distance over every triangle (no BVH).
fn brute_force(vertices: &[P], faces: &[[u32; 3]], p0: &P, p1: &P) -> f64 {
    faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|i| vertices[i as usize]);
            closest_segment_triangle(p0, p1, &a, &b, &c).distance
        })
        .fold(f64::INFINITY, f64::min)
}

fn check_against_brute_force(vertices: Vec<P>, faces: Vec<[u32; 3]>, seed: u64, half: f64) {
    let mesh = ObstacleMesh::try_from_triangles("soup", vertices.clone(), &faces).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..400 {
        let p0 = random_point(&mut rng, half);
        let p1 = p0 + random_point(&mut rng, 0.2).coords;
        let max_distance = rng.random_range(0.0..0.5);
        let reference = brute_force(&vertices, &faces, &p0, &p1);
        match mesh.segment_proximity(&p0, &p1, max_distance) {
            Some(found) => {
                hits += 1;
                assert!(
                    (found.distance - reference).abs() <= 1e-12,
                    "{found:?} vs {reference}"
                );
                assert!(found.distance <= max_distance);
                let [a, b, c] = mesh.triangle(found.triangle);
                let [u, v, w] = found.barycentric;
                let on_mesh = P::from(a.coords * u + b.coords * v + c.coords * w);
                assert!((on_mesh - found.point_on_mesh).norm() <= 1e-12);
                let on_segment = p0 + (p1 - p0) * found.s;
                assert!((on_segment - found.point_on_segment).norm() <= 1e-12);
                if let Some(n) = found.normal {
                    let expected = (found.point_on_segment - found.point_on_mesh) / found.distance;
                    assert!((n.into_inner() - expected).norm() <= 1e-9);
                }
            }
            None => {
                misses += 1;
                assert!(
                    reference > max_distance,
                    "missed a triangle at {reference} ≤ {max_distance}"
                );
            }
        }
    }
    assert!(hits > 40 && misses > 40, "hits {hits}, misses {misses}");
}

#[test]
fn bvh_query_matches_brute_force_on_a_triangle_soup() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    for k in 0..300u32 {
        let centre = random_point(&mut rng, 1.0);
        for _ in 0..3 {
            vertices.push(centre + random_point(&mut rng, 0.1).coords);
        }
        faces.push([3 * k, 3 * k + 1, 3 * k + 2]);
    }
    check_against_brute_force(vertices, faces, 4, 1.2);
}

#[test]
fn bvh_query_matches_brute_force_on_a_tessellated_surface() {
    let (vertices, faces) = wavy_surface(5000, 1.0, 0.05);
    let shifted: Vec<P> = vertices
        .iter()
        .map(|p| p - Vector3::new(0.5, 0.5, 0.0))
        .collect();
    check_against_brute_force(shifted, faces, 5, 0.6);
}

#[test]
fn an_edge_flat_over_a_tessellated_floor_touches_at_its_middle() {
    // A flat 1 m floor of 2·40² triangles; the edge spans many of them.
    let (vertices, faces) = wavy_surface(3200, 1.0, 0.0);
    let floor = ObstacleMesh::try_from_triangles("floor", vertices, &faces).unwrap();
    let (p0, p1) = (P::new(0.2, 0.3, 0.01), P::new(0.61, 0.47, 0.01));
    let found = floor.segment_proximity(&p0, &p1, 0.1).unwrap();
    assert!((found.s - 0.5).abs() <= 1e-9, "{found:?}");
    assert!((found.distance - 0.01).abs() <= 1e-15);
    assert!((found.normal.unwrap().into_inner() - Vector3::z()).norm() <= 1e-12);
    // Half of it beyond the floor's edge x = 1: the middle of the part over the floor.
    let found = floor
        .segment_proximity(&P::new(0.8, 0.5, -0.02), &P::new(1.2, 0.5, -0.02), 0.1)
        .unwrap();
    assert!((found.s - 0.25).abs() <= 1e-9, "{found:?}");
    assert!((found.normal.unwrap().into_inner() + Vector3::z()).norm() <= 1e-12);
}

#[test]
fn a_segment_through_the_surface_has_no_normal() {
    let (vertices, faces) = wavy_surface(200, 1.0, 0.0);
    let floor = ObstacleMesh::try_from_triangles("floor", vertices, &faces).unwrap();
    let found = floor
        .segment_proximity(&P::new(0.3, 0.3, -0.1), &P::new(0.35, 0.3, 0.1), 1.0)
        .unwrap();
    assert!(found.distance <= 1e-15 && found.normal.is_none());
    assert!((found.point_on_mesh - P::new(0.325, 0.3, 0.0)).norm() <= 1e-12);
    let point = floor.point_proximity(&P::new(0.5, 0.5, 0.3), 1.0).unwrap();
    assert!((point.distance - 0.3).abs() <= 1e-15);
}

#[test]
fn degenerate_triangles_are_skipped_and_counted() {
    let v = vec![
        P::new(0.0, 0.0, 0.0),
        P::new(1.0, 0.0, 0.0),
        P::new(0.0, 1.0, 0.0),
        P::new(2.0, 0.0, 0.0),
    ];
    // One good triangle, one with a repeated index, one collinear.
    let mesh = ObstacleMesh::try_from_triangles("m", v.clone(), &[[0, 1, 2], [0, 0, 1], [0, 1, 3]])
        .unwrap();
    assert_eq!((mesh.triangle_count(), mesh.skipped_degenerate()), (1, 2));
    assert_eq!(
        mesh.bounding_box(),
        [P::new(0.0, 0.0, 0.0), P::new(1.0, 1.0, 0.0)]
    );

    let error = ObstacleMesh::try_from_triangles("flat", v.clone(), &[[0, 1, 3]]).unwrap_err();
    assert!(matches!(error, MeshError::NoTriangles { .. }), "{error}");
    assert!(error.to_string().contains("flat") && error.to_string().contains("degenerate"));
    let error = ObstacleMesh::try_from_triangles("none", v.clone(), &[]).unwrap_err();
    assert!(matches!(error, MeshError::NoTriangles { .. }));
    let error = ObstacleMesh::try_from_triangles("bad", v.clone(), &[[0, 1, 4]]).unwrap_err();
    assert!(
        matches!(
            error,
            MeshError::IndexOutOfRange {
                index: 4,
                count: 4,
                ..
            }
        ),
        "{error}"
    );
    let mut nan = v;
    nan[2].y = f64::NAN;
    let error = ObstacleMesh::try_from_triangles("nan", nan, &[[0, 1, 3]]).unwrap_err();
    assert!(
        matches!(error, MeshError::NonFiniteVertex { vertex: 3, .. }),
        "{error}"
    );
}

fn write_obj(dir: &tempfile::TempDir, name: &str, text: &str) -> std::path::PathBuf {
    let path = dir.path().join(name);
    std::fs::File::create(&path)
        .unwrap()
        .write_all(text.as_bytes())
        .unwrap();
    path
}

#[test]
fn obj_files_are_merged_triangulated_scaled_and_placed() {
    let dir = tempfile::tempdir().unwrap();
    let text = "# a quad and a triangle in mm, two objects\n\
                mtllib missing.mtl\n\
                o quad\nv 0 0 0\nv 100 0 0\nv 100 200 0\nv 0 200 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\n\
                o tri\nv 0 0 50\nv 10 0 50\nv 0 10 50\nf 5 6 7\nl 1 2\n";
    let path = write_obj(&dir, "parts.obj", text);
    let pose = Isometry3::from_parts(
        Translation3::new(1.0, 2.0, 3.0),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2),
    );
    let mesh = ObstacleMesh::load_obj(&path, 1e-3, &pose).unwrap();
    assert_eq!(mesh.name(), "parts");
    assert_eq!((mesh.triangle_count(), mesh.skipped_degenerate()), (3, 0));
    // Rotated by 90° about z: file x → world y, file y → world −x.
    let [min, max] = mesh.bounding_box();
    assert!((min - P::new(0.8, 2.0, 3.0)).norm() <= 1e-12, "{min}");
    assert!((max - P::new(1.0, 2.1, 3.05)).norm() <= 1e-12, "{max}");
    // The quad's corner file (100, 200, 0) mm is at world (0.8, 2.1, 3.0).
    let near = mesh.point_proximity(&P::new(0.8, 2.1, 3.01), 1.0).unwrap();
    assert!((near.point_on_mesh - P::new(0.8, 2.1, 3.0)).norm() <= 1e-12);
}

#[test]
fn bad_obj_files_are_errors_naming_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let identity = Isometry3::identity();

    let missing = dir.path().join("nowhere.obj");
    let error = ObstacleMesh::load_obj(&missing, 1.0, &identity).unwrap_err();
    assert!(matches!(error, MeshError::Read { .. }));
    assert!(error.to_string().contains("nowhere.obj"), "{error}");

    let malformed = write_obj(
        &dir,
        "malformed.obj",
        "v 0 0 zero\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let error = ObstacleMesh::load_obj(&malformed, 1.0, &identity).unwrap_err();
    assert!(matches!(error, MeshError::Parse { .. }), "{error}");
    assert!(error.to_string().contains("malformed.obj"), "{error}");

    let points = write_obj(
        &dir,
        "points.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\np 3\n",
    );
    let error = ObstacleMesh::load_obj(&points, 1.0, &identity).unwrap_err();
    assert!(matches!(error, MeshError::NoTriangles { .. }), "{error}");
    assert!(error.to_string().contains("points.obj"), "{error}");

    let nan = write_obj(
        &dir,
        "nan.obj",
        "# header\nv 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n",
    );
    let error = ObstacleMesh::load_obj(&nan, 1.0, &identity).unwrap_err();
    let message = error.to_string();
    assert!(
        matches!(error, MeshError::NonFiniteVertex { vertex: 2, .. }),
        "{message}"
    );
    assert!(
        message.contains("nan.obj") && message.contains("line 3"),
        "{message}"
    );

    let inf = write_obj(&dir, "inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 inf\nf 1 2 3\n");
    let error = ObstacleMesh::load_obj(&inf, 1.0, &identity).unwrap_err();
    assert!(
        matches!(error, MeshError::NonFiniteVertex { vertex: 3, .. }),
        "{error}"
    );

    let good = write_obj(&dir, "good.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let error = ObstacleMesh::load_obj(&good, 0.0, &identity).unwrap_err();
    assert!(matches!(error, MeshError::InvalidScale { .. }), "{error}");
    // A folder is not readable as a file.
    let error = ObstacleMesh::load_obj(dir.path(), 1.0, &identity).unwrap_err();
    assert!(matches!(error, MeshError::Read { .. }), "{error}");
}
