//! Tests of STL reading and writing against the indexed mesh (and its OBJ) they came
//! from.

use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};

use super::*;

/// A closed, outward-wound box `[0, 2] × [0, 1] × [0, 0.5]` as an indexed mesh.
fn indexed_box() -> (Vec<Point3<f64>>, Vec<[u32; 3]>) {
    let v = (0..8)
        .map(|k| {
            Point3::new(
                2.0 * f64::from(k & 1),
                f64::from((k >> 1) & 1),
                0.5 * f64::from((k >> 2) & 1),
            )
        })
        .collect();
    let t = vec![
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
    ];
    (v, t)
}

fn soup(vertices: &[Point3<f64>], triangles: &[[u32; 3]]) -> Vec<[Point3<f64>; 3]> {
    triangles
        .iter()
        .map(|t| t.map(|i| vertices[i as usize]))
        .collect()
}

fn write_file(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn binary(triangles: &[[Point3<f64>; 3]], header: &str) -> Vec<u8> {
    let mut out = Vec::new();
    write_binary_stl(&mut out, header, triangles).unwrap();
    out
}

fn ascii(triangles: &[[Point3<f64>; 3]]) -> Vec<u8> {
    let mut out = Vec::new();
    write_ascii_stl(&mut out, "part", triangles).unwrap();
    out
}

fn obj(vertices: &[Point3<f64>], triangles: &[[u32; 3]]) -> String {
    let mut text = String::new();
    for p in vertices {
        text += &format!("v {:?} {:?} {:?}\n", p.x, p.y, p.z);
    }
    for t in triangles {
        text += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    text
}

#[test]
fn binary_and_ascii_stl_weld_to_the_indexed_mesh_and_its_obj() {
    let dir = tempfile::tempdir().unwrap();
    let (vertices, triangles) = indexed_box();
    let corners = soup(&vertices, &triangles);
    let pose = Isometry3::from_parts(
        Translation3::new(0.1, -0.2, 0.3),
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.4),
    );
    let obj_path = write_file(
        dir.path(),
        "part.obj",
        obj(&vertices, &triangles).as_bytes(),
    );
    // A binary header starting with `solid`, as many CAD systems write it.
    let mut solid_header = binary(&corners, "x");
    solid_header[..5].copy_from_slice(b"solid");
    let files = [
        ("bin.stl", binary(&corners, "strand test")),
        ("solid_header.stl", solid_header),
        ("ascii.stl", ascii(&corners)),
        ("ascii_without_extension.mesh", ascii(&corners)),
    ];
    let reference = ObstacleMesh::load(&obj_path, 1e-3, &pose).unwrap();
    assert_eq!(reference.diagnostics().vertices, 8);
    assert!(reference.diagnostics().closed);
    for (name, bytes) in files {
        let path = write_file(dir.path(), name, &bytes);
        let mesh = ObstacleMesh::load(&path, 1e-3, &pose).unwrap();
        // Same welded topology, same placement (the box's coordinates are exact in f32).
        assert_eq!(mesh.diagnostics(), reference.diagnostics(), "{name}");
        assert_eq!(mesh.vertex_count(), 8, "{name}");
        assert_eq!(mesh.bounding_box(), reference.bounding_box(), "{name}");
        assert_eq!(
            mesh.name(),
            Path::new(name).file_stem().unwrap().to_str().unwrap()
        );
    }
    let expected = [
        (vec![0u8; 100], MeshFormat::BinaryStl),
        (b"v 0 0 0\n".to_vec(), MeshFormat::Obj),
        (b"  solid x\nendsolid x\n".to_vec(), MeshFormat::AsciiStl),
    ];
    for (bytes, format) in expected {
        assert_eq!(detect_format(&bytes, Some("obj")), format);
    }
    assert_eq!(
        detect_format(b"v 0 0 0\n", Some("STL")),
        MeshFormat::BinaryStl
    );
}

#[test]
fn ascii_coordinates_are_read_as_f64_and_binary_ones_as_f32() {
    let dir = tempfile::tempdir().unwrap();
    let t = [[
        Point3::new(0.1, 0.2, 0.3),
        Point3::new(1.1, 0.2, 0.3),
        Point3::new(0.1, 1.7, 0.3),
    ]];
    let a = ObstacleMesh::load_stl(
        write_file(dir.path(), "a.stl", &ascii(&t)),
        1.0,
        &Isometry3::identity(),
    )
    .unwrap();
    assert_eq!(a.bounding_box()[0], Point3::new(0.1, 0.2, 0.3));
    let b = ObstacleMesh::load_stl(
        write_file(dir.path(), "b.stl", &binary(&t, "b")),
        1.0,
        &Isometry3::identity(),
    )
    .unwrap();
    assert_eq!(
        b.bounding_box()[0],
        Point3::new(f64::from(0.1f32), f64::from(0.2f32), f64::from(0.3f32))
    );
}

#[test]
fn corners_weld_within_the_stated_tolerance_only() {
    let (vertices, triangles) = indexed_box();
    let mut corners = soup(&vertices, &triangles);
    let diagonal = (2.0f64 * 2.0 + 1.0 + 0.25).sqrt();
    // Within tolerance: still one closed box of 8 vertices.
    corners[0][0].x += 0.5 * STL_WELD_RELATIVE_TOLERANCE * diagonal;
    let (welded, _) = weld(&corners);
    assert_eq!(welded.len(), 8);
    // Beyond it: a ninth vertex, and the box opens.
    corners[0][0].x += 2.0 * STL_WELD_RELATIVE_TOLERANCE * diagonal;
    let (welded, t) = weld(&corners);
    assert_eq!(welded.len(), 9);
    let mesh = ObstacleMesh::try_from_triangles("box", welded, &t).unwrap();
    assert!(!mesh.diagnostics().closed);
    assert!(mesh.diagnostics().boundary_edges > 0);
}

fn error(name: &str, bytes: &[u8]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = write_file(dir.path(), name, bytes);
    let message = ObstacleMesh::load(&path, 1.0, &Isometry3::identity())
        .expect_err("a broken file")
        .to_string();
    assert!(message.contains(name), "{message}");
    assert!(message.contains("hint:"), "{message}");
    message
}

#[test]
fn broken_stl_files_are_errors_naming_the_file_and_the_problem() {
    let (vertices, triangles) = indexed_box();
    let corners = soup(&vertices, &triangles);
    let good = binary(&corners, "box");

    let cut = error("cut.stl", &good[..good.len() - 20]);
    assert!(
        cut.contains("truncated binary STL")
            && cut.contains("claims 12 triangles")
            && cut.contains("11 whole triangles"),
        "{cut}"
    );
    let mut claims_more = good.clone();
    claims_more[80..84].copy_from_slice(&1000u32.to_le_bytes());
    let message = error("claims_more.stl", &claims_more);
    assert!(message.contains("claims 1000 triangles"), "{message}");
    let mut extra = good.clone();
    extra.extend_from_slice(&[0; 7]);
    assert!(error("extra.stl", &extra).contains("inconsistent binary STL"));
    assert!(error("short.stl", &good[..40]).contains("less than the 84-byte header"));

    let mut nan = good.clone();
    let at = 84 + 50 * 3 + 12 + 12 + 4; // triangle 4, corner 2, y
    nan[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let message = error("nan.stl", &nan);
    assert!(
        message.contains("triangle 4 corner 2") && message.contains("NaN"),
        "{message}"
    );

    let text = String::from_utf8(ascii(&corners)).unwrap();
    let message = error(
        "nan_ascii.stl",
        text.replacen("vertex 2.0", "vertex NaN", 1).as_bytes(),
    );
    assert!(
        message.contains("non-finite") && message.contains("facet at line"),
        "{message}"
    );
    let message = error(
        "bad_ascii.stl",
        text.replacen("vertex 2.0 ", "vertex 2.0 x", 1).as_bytes(),
    );
    assert!(
        message.contains("line ") && message.contains("vertex x y z"),
        "{message}"
    );
    let cut_text = &text[..text.len() / 2];
    let cut_text = &cut_text[..cut_text.rfind("endloop").unwrap()];
    assert!(error("cut_ascii.stl", cut_text.as_bytes()).contains("not closed by `endfacet`"));
    let message = error("empty.stl", &binary(&[], "nothing"));
    assert!(
        message.contains("no triangles") && message.contains("0 triangles"),
        "{message}"
    );
}

#[test]
fn the_format_is_told_by_content_with_odd_white_space_and_text() {
    for (bytes, extension, format) in [
        (
            &b"\x0b\x0c \r\n\tsolid x\n"[..],
            Some("obj"),
            MeshFormat::AsciiStl,
        ),
        (
            "\u{a0}solid x\n".as_bytes(),
            Some("obj"),
            MeshFormat::AsciiStl,
        ),
        ("# π\nv 0 0 0\n".as_bytes(), Some("obj"), MeshFormat::Obj),
        (b"v 0 0 0\n", None, MeshFormat::Obj),
        (b"v 0 0 0\n", Some("STL"), MeshFormat::BinaryStl),
        (b"v 0 0\x000\n", Some("obj"), MeshFormat::BinaryStl),
        ("# π\x00".as_bytes(), Some("obj"), MeshFormat::BinaryStl),
        (b"# \xff\n", Some("obj"), MeshFormat::BinaryStl),
        (b"  sol", Some("obj"), MeshFormat::Obj),
        (b"", Some("obj"), MeshFormat::Obj),
    ] {
        assert_eq!(detect_format(bytes, extension), format, "{bytes:?}");
    }
}

#[test]
fn a_damaged_obj_is_not_reported_as_a_truncated_stl() {
    // Text with a stray byte that is not UTF-8, named .obj, of no binary STL's size:
    // the error says the OBJ is not text and where, not "truncated binary STL".
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("part.obj");
    std::fs::write(
        &path,
        b"garbage\x00\xff\xfe binary junk\nv 1 2\nf 1 2 3 4 5\n",
    )
    .unwrap();
    let message = ObstacleMesh::load(&path, 1.0, &Isometry3::identity())
        .unwrap_err()
        .to_string();
    assert!(!message.contains("truncated binary STL"), "{message}");
    assert!(
        message.contains("an OBJ file is text, but byte 7 (0x00)"),
        "{message}"
    );
    assert!(
        message.contains("export the part again as OBJ or STL"),
        "{message}"
    );
    // The same bytes named .stl are a broken STL, as before.
    let stl = dir.path().join("part.stl");
    std::fs::copy(&path, &stl).unwrap();
    let message = ObstacleMesh::load(&stl, 1.0, &Isometry3::identity())
        .unwrap_err()
        .to_string();
    assert!(message.contains("truncated binary STL"), "{message}");
}

#[test]
fn a_vertex_far_beyond_any_part_is_an_error_not_a_degenerate_mesh() {
    // A vertex at 1e300 m: its triangle's squared lengths overflow, and it was
    // reported as "degenerate"; now the vertex and the likely cause are named.
    let triangle = [[0u32, 1, 2]];
    let at = |x: f64| {
        vec![
            Point3::new(x, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ]
    };
    match ObstacleMesh::try_from_triangles("far", at(1e300), &triangle) {
        Err(MeshError::VertexTooFar { vertex: 1, .. }) => {}
        other => panic!("{other:?}"),
    }
    // A part 1e8 m out (within the limit) is a mesh.
    assert!(ObstacleMesh::try_from_triangles("near", at(1e8), &triangle).is_ok());
}
