//! Mesh diagnostics (counts of defects, closedness, bounding box) and the inside of
//! closed meshes, on meshes whose answers are known by construction.

use nalgebra::Point3;
use strand_contact::ObstacleMesh;

type P = Point3<f64>;

/// The 8 corners and 12 outward triangles of the box `[0, a] × [0, b] × [0, c]`.
fn closed_box(a: f64, b: f64, c: f64) -> (Vec<P>, Vec<[u32; 3]>) {
    let corners = (0..8)
        .map(|k| {
            P::new(
                if k & 1 == 0 { 0.0 } else { a },
                if k & 2 == 0 { 0.0 } else { b },
                if k & 4 == 0 { 0.0 } else { c },
            )
        })
        .collect();
    let quads = [
        [0, 2, 3, 1], // z = 0, normal −z
        [4, 5, 7, 6], // z = c, normal +z (the lid)
        [0, 1, 5, 4], // y = 0
        [2, 6, 7, 3], // y = b
        [0, 4, 6, 2], // x = 0
        [1, 3, 7, 5], // x = a
    ];
    let triangles = quads
        .iter()
        .flat_map(|[p, q, r, s]| [[*p, *q, *r], [*p, *r, *s]])
        .collect();
    (corners, triangles)
}

#[test]
fn a_closed_box_is_closed_and_encloses_its_inside() {
    let (v, t) = closed_box(0.3, 0.2, 0.1);
    let mesh = ObstacleMesh::try_from_triangles("box", v, &t).unwrap();
    let d = mesh.diagnostics();
    assert!(d.closed, "{d:?}");
    assert_eq!(
        (
            d.triangles,
            d.boundary_edges,
            d.non_manifold_edges,
            d.patches
        ),
        (12, 0, 0, 6)
    );
    assert_eq!(d.size_m(), [0.3, 0.2, 0.1]);
    assert!(d.warnings().is_empty(), "{:?}", d.warnings());
    // Inside, including points level with edges and vertices of the triangulation
    // (the diagonal of each face) and near the walls; outside beside every face.
    for p in [
        P::new(0.15, 0.1, 0.05),
        P::new(0.1, 0.2 / 3.0, 0.05),
        P::new(0.15, 0.1, 1e-6),
        P::new(0.3 - 1e-9, 0.2 - 1e-9, 0.1 - 1e-9),
    ] {
        assert!(mesh.encloses(&p), "{p} is inside");
    }
    for p in [
        P::new(-0.01, 0.1, 0.05),
        P::new(0.15, 0.1, 0.1 + 1e-6),
        P::new(0.15, 0.21, 0.05),
        P::new(0.5, 0.5, 0.5),
    ] {
        assert!(!mesh.encloses(&p), "{p} is outside");
    }
    // The same box wound inward is just as closed.
    let (v, t) = closed_box(0.3, 0.2, 0.1);
    let inward: Vec<[u32; 3]> = t.iter().map(|[a, b, c]| [*a, *c, *b]).collect();
    let mesh = ObstacleMesh::try_from_triangles("box", v, &inward).unwrap();
    assert!(mesh.encloses(&P::new(0.15, 0.1, 0.05)));
}

#[test]
fn an_open_box_has_no_inside() {
    let (v, mut t) = closed_box(0.3, 0.2, 0.1);
    t.drain(2..4); // no lid
    let mesh = ObstacleMesh::try_from_triangles("tray", v, &t).unwrap();
    let d = mesh.diagnostics();
    assert!(!d.closed);
    // The lid's rim: 4 edges of the top face.
    assert_eq!((d.triangles, d.boundary_edges), (10, 4));
    assert!(!mesh.encloses(&P::new(0.15, 0.1, 0.05)));
}

#[test]
fn slivers_degenerate_triangles_and_duplicate_vertices_are_counted() {
    // The closed box with every face given its own copies of its corners (as an OBJ
    // exported with split normals): 6 faces × 4 = 24 vertices, 16 of them duplicates.
    let (corners, t) = closed_box(1.0, 1.0, 1.0);
    let mut v = Vec::new();
    let mut triangles = Vec::new();
    for pair in t.chunks(2) {
        let base = v.len() as u32;
        let mut local = Vec::new();
        for tri in pair {
            let mut out = [0u32; 3];
            for (k, &i) in tri.iter().enumerate() {
                let at = local.iter().position(|&j| j == i).unwrap_or_else(|| {
                    local.push(i);
                    v.push(corners[i as usize]);
                    local.len() - 1
                });
                out[k] = base + at as u32;
            }
            triangles.push(out);
        }
    }
    // Two zero-area triangles (repeated vertex, collinear) and one sliver (2·area /
    // longest² = 1e-8) on the edge from (0, 0, 0) to (0, 1, 0) (vertices 0 and 1),
    // which floor and wall x = 0 already share: a non-manifold edge.
    assert_eq!((v[0], v[1]), (P::origin(), P::new(0.0, 1.0, 0.0)));
    let n = v.len() as u32;
    v.push(P::new(0.0, 0.5, 0.0));
    v.push(P::new(-1e-8, 0.5, 0.0));
    triangles.push([0, 0, 1]);
    triangles.push([0, n, 1]);
    triangles.push([0, 1, n + 1]);
    let mesh = ObstacleMesh::try_from_triangles("split", v, &triangles).unwrap();
    let d = mesh.diagnostics();
    assert_eq!(d.vertices, 26);
    assert_eq!(d.duplicate_vertices, 16, "{d:?}");
    assert_eq!(d.degenerate_skipped, 2, "{d:?}");
    assert_eq!(d.slivers, 1, "{d:?}");
    assert_eq!(d.triangles, 13);
    // The sliver's edge (0, 1) is used three times; its other two edges are open.
    assert_eq!((d.non_manifold_edges, d.boundary_edges), (1, 2), "{d:?}");
    assert!(!d.closed);
    let text = d.to_string();
    assert!(
        text.contains("13 triangles (2 degenerate skipped, 1 slivers)")
            && text.contains("26 vertices (16 duplicates, welded")
            && text.contains("size 1000.0 x 1000.0 x 1000.0 mm"),
        "{text}"
    );
    assert_eq!(d.warnings().len(), 4, "{:?}", d.warnings());
}
