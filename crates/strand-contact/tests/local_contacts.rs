//! Local contacts (one per smooth patch) of points and segments with meshes: grooves
//! and corners in one mesh give one contact per face with its exact normal and
//! distance; tessellated planes and convex ridges give one.

use nalgebra::{Point3, Vector3};
use strand_contact::{LocalContact, ObstacleMesh};

type P = Point3<f64>;
type V = Vector3<f64>;

/// A tessellated parallelogram `origin + a u + b v` (`n × n` cells), appended to
/// `(vertices, triangles)`.
fn push_face(mesh: &mut (Vec<P>, Vec<[u32; 3]>), origin: P, u: V, v: V, n: usize) {
    let base = mesh.0.len() as u32;
    for j in 0..=n {
        for i in 0..=n {
            mesh.0
                .push(origin + u * (i as f64 / n as f64) + v * (j as f64 / n as f64));
        }
    }
    let at = |i: usize, j: usize| base + (j * (n + 1) + i) as u32;
    for j in 0..n {
        for i in 0..n {
            mesh.1.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            mesh.1.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
}

/// A V-groove along x with opening angle `alpha` (rad), crease on the x axis, flanks
/// 0.1 m wide rising towards +z on both sides of y = 0. Returns the mesh and the two
/// flank normals (pointing into the groove).
fn groove(alpha: f64) -> (ObstacleMesh, [V; 2]) {
    let half = 0.5 * alpha;
    let (along, width) = (V::new(0.4, 0.0, 0.0), 0.1);
    let up_left = V::new(0.0, -half.sin(), half.cos()) * width;
    let up_right = V::new(0.0, half.sin(), half.cos()) * width;
    let origin = P::new(-0.2, 0.0, 0.0);
    let mut mesh = (Vec::new(), Vec::new());
    push_face(&mut mesh, origin, up_left, along, 6);
    push_face(&mut mesh, origin, along, up_right, 6);
    let normals = [
        V::new(0.0, half.cos(), half.sin()),
        V::new(0.0, -half.cos(), half.sin()),
    ];
    (
        ObstacleMesh::try_from_triangles("groove", mesh.0, &mesh.1).unwrap(),
        normals,
    )
}

fn normal_of(c: &LocalContact) -> V {
    c.proximity.normal.unwrap().into_inner()
}

#[test]
fn a_point_in_a_groove_touches_both_flanks_with_their_normals() {
    for alpha_deg in [60.0f64, 90.0, 120.0] {
        let alpha = alpha_deg.to_radians();
        let (mesh, normals) = groove(alpha);
        // A point on the bisector at height h above the crease: distance h sin(α/2)
        // to each flank.
        for h in [0.01, 0.03] {
            let p = P::new(0.013, 0.0, h);
            let contacts = mesh.local_contacts(&p, &p, 0.05);
            assert_eq!(contacts.len(), 2, "α = {alpha_deg}°, h = {h}: {contacts:?}");
            let expected = h * (0.5 * alpha).sin();
            for c in &contacts {
                assert!((c.proximity.distance - expected).abs() < 1e-15, "{c:?}");
                let n = normal_of(c);
                assert!(
                    normals.iter().any(|m| (n - m).norm() < 1e-12),
                    "normal {n:?} is not a flank normal"
                );
            }
            assert_ne!(contacts[0].patch, contacts[1].patch);
        }
        // Off the bisector, both flanks still: distances to the two planes.
        let p = P::new(-0.05, 0.004, 0.02);
        let contacts = mesh.local_contacts(&p, &p, 0.05);
        assert_eq!(contacts.len(), 2, "{contacts:?}");
        for c in &contacts {
            let n = normal_of(c);
            assert!((c.proximity.distance - n.dot(&p.coords)).abs() < 1e-15);
        }
    }
}

#[test]
fn only_the_reachable_flank_counts_and_keys_follow_the_flank() {
    let (mesh, normals) = groove(90f64.to_radians());
    // High on the right flank (y > 0): its foot on the left flank would lie beyond
    // the crease, so only the right flank is a local contact within 30 mm.
    let p = P::new(0.0, 0.06, 0.075);
    let contacts = mesh.local_contacts(&p, &p, 0.03);
    assert_eq!(contacts.len(), 1, "{contacts:?}");
    assert!((normal_of(&contacts[0]) - normals[1]).norm() < 1e-12);
    // The patch names the flank: moving along the groove over other triangles of the
    // same flank keeps it.
    let q = P::new(0.15, 0.06, 0.075);
    assert_eq!(
        mesh.local_contacts(&q, &q, 0.03)[0].patch,
        contacts[0].patch
    );
}

#[test]
fn a_corner_of_three_faces_gives_three_contacts() {
    // Floor z = 0 and walls x = 0, y = 0 (one mesh), a point at (a, b, c) inside.
    let mut mesh = (Vec::new(), Vec::new());
    let o = P::origin();
    let (ex, ey, ez) = (V::x() * 0.1, V::y() * 0.1, V::z() * 0.1);
    push_face(&mut mesh, o, ex, ey, 5);
    push_face(&mut mesh, o, ey, ez, 5);
    push_face(&mut mesh, o, ez, ex, 5);
    let mesh = ObstacleMesh::try_from_triangles("corner", mesh.0, &mesh.1).unwrap();
    assert_eq!(mesh.diagnostics().patches, 3);
    let p = P::new(0.011, 0.012, 0.013);
    let mut contacts = mesh.local_contacts(&p, &p, 0.05);
    assert_eq!(contacts.len(), 3, "{contacts:?}");
    contacts.sort_by(|a, b| a.proximity.distance.total_cmp(&b.proximity.distance));
    for (c, (axis, distance)) in contacts.iter().zip([(0, 0.011), (1, 0.012), (2, 0.013)]) {
        assert!((c.proximity.distance - distance).abs() < 1e-15);
        assert!((normal_of(c) - V::ith(axis, 1.0)).norm() < 1e-15);
    }
}

#[test]
fn a_tessellated_plane_and_a_convex_ridge_give_one_contact() {
    // A 0.4 m plane of 2·20·20 triangles: points above vertices, edges and cells.
    let mut plane = (Vec::new(), Vec::new());
    push_face(
        &mut plane,
        P::new(-0.2, -0.2, 0.0),
        V::x() * 0.4,
        V::y() * 0.4,
        20,
    );
    let plane = ObstacleMesh::try_from_triangles("plane", plane.0, &plane.1).unwrap();
    assert_eq!(plane.diagnostics().patches, 1);
    for p in [
        P::new(0.0, 0.0, 0.01),
        P::new(0.01, 0.0, 0.01),
        P::new(0.01, 0.01, 0.01),
        P::new(0.0123, -0.0456, 0.007),
        P::new(0.02 + 1e-9, 0.04 - 1e-12, 0.002),
    ] {
        let contacts = plane.local_contacts(&p, &p, 0.05);
        assert_eq!(contacts.len(), 1, "{p}: {contacts:?}");
        assert!((contacts[0].proximity.distance - p.z).abs() < 1e-15);
        // A segment lying flat over the plane: one contact, the whole stretch tied.
        let q = p + V::new(0.05, 0.03, 0.0);
        let along = plane.local_contacts(&p, &q, 0.05);
        assert_eq!(along.len(), 1, "{along:?}");
        assert_eq!(along[0].proximity.tie, [0.0, 1.0]);
    }
    // A ridge: the top edge of a roof (two faces at ±30° to the horizontal), seen
    // from straight above: one contact at the ridge.
    let mut roof = (Vec::new(), Vec::new());
    let (down_left, down_right) = (
        V::new(0.0, -0.1 * 30f64.to_radians().cos(), -0.05),
        V::new(0.0, 0.1 * 30f64.to_radians().cos(), -0.05),
    );
    push_face(
        &mut roof,
        P::new(-0.2, 0.0, 0.0),
        V::x() * 0.4,
        down_left,
        4,
    );
    push_face(
        &mut roof,
        P::new(-0.2, 0.0, 0.0),
        down_right,
        V::x() * 0.4,
        4,
    );
    let roof = ObstacleMesh::try_from_triangles("roof", roof.0, &roof.1).unwrap();
    assert_eq!(roof.diagnostics().patches, 2);
    let p = P::new(0.01, 0.0, 0.02);
    let contacts = roof.local_contacts(&p, &p, 0.05);
    assert_eq!(contacts.len(), 1, "{contacts:?}");
    assert!((contacts[0].proximity.distance - 0.02).abs() < 1e-15);
    // Beside the ridge, over the left face: that face only.
    let p = P::new(0.01, -0.03, 0.0);
    let contacts = roof.local_contacts(&p, &p, 0.05);
    assert_eq!(contacts.len(), 1, "{contacts:?}");
}

/// Seven facets of a drum of radius `radius` (m) along y, facet angle `alpha` (rad),
/// the ridge at angle 0 on top (x = 0, z = radius); ridge `i` at angle `i·alpha` from
/// the top towards +x.
fn drum_facets(radius: f64, alpha: f64) -> ObstacleMesh {
    let mut mesh: (Vec<P>, Vec<[u32; 3]>) = (Vec::new(), Vec::new());
    for i in -4..=4 {
        let t = i as f64 * alpha;
        let (x, z) = (radius * t.sin(), radius * t.cos());
        mesh.0.push(P::new(x, -0.1, z));
        mesh.0.push(P::new(x, 0.1, z));
    }
    for k in 0..8u32 {
        let (a, b, c, d) = (2 * k, 2 * k + 1, 2 * k + 2, 2 * k + 3);
        mesh.1.push([a, c, d]);
        mesh.1.push([a, d, b]);
    }
    ObstacleMesh::try_from_triangles("drum facets", mesh.0, &mesh.1).unwrap()
}

#[test]
fn a_segment_nearly_lying_on_a_narrow_face_is_nearly_tied_with_the_next_ridge() {
    let (radius, alpha) = (0.05, 1e-3);
    let mesh = drum_facets(radius, alpha);
    let ridge = |i: f64| P::new(radius * (i * alpha).sin(), 0.0, radius * (i * alpha).cos());
    // A segment 5 mm above the top ridge, turned `epsilon` less steeply than the face
    // between ridges 0 and 1: nearest at ridge 0; ridge 1 is `epsilon` times the face
    // width (50 µm) farther.
    for (epsilon, tied) in [(1e-6, true), (1e-4, false)] {
        let phi = -(0.5 * alpha - epsilon);
        let direction = V::new(phi.cos(), 0.0, phi.sin());
        let centre = P::new(0.0, 0.0, radius + 0.005);
        let (p0, p1) = (centre - 0.01 * direction, centre + 0.01 * direction);
        let contacts = mesh.local_contacts(&p0, &p1, 0.01);
        assert_eq!(contacts.len(), 1, "{contacts:?}");
        let c = &contacts[0];
        let foot = |q: P| (q - p0).dot(&(p1 - p0)) / (p1 - p0).norm_squared();
        // The nearest point: ridge 0, no stretch.
        assert!((c.proximity.s - foot(ridge(0.0))).abs() < 1e-9, "{c:?}");
        let [tie_low, tie_high] = c.proximity.tie;
        assert!(tie_high - tie_low < 1e-12, "{c:?}");
        let [low, high] = c.near_tie;
        assert!((low - c.proximity.s).abs() < 1e-12, "{c:?}");
        if tied {
            // 5e-11 m farther: nearly tied, the stretch reaches ridge 1.
            assert!((high - foot(ridge(1.0))).abs() < 1e-9, "{c:?}");
        } else {
            // 5e-9 m farther: not tied.
            assert!((high - c.proximity.s).abs() < 1e-12, "{c:?}");
        }
    }
}
