//! OBJ reader for the subset this crate writes (and what simple exporters write).

use std::path::Path;

use nalgebra::Point3;

use crate::{AssetError, TriangleMesh};

/// One named object of an OBJ file (`o` or `g` name; `""` before any name).
#[derive(Clone, Debug, PartialEq)]
pub struct ObjObject {
    /// The object's name.
    pub name: String,
    /// Its triangles, with only the vertices they use (in file units).
    pub mesh: TriangleMesh,
}

/// Reads an OBJ file: see [`parse_obj`].
pub fn read_obj(path: &Path) -> Result<Vec<ObjObject>, AssetError> {
    let text = std::fs::read_to_string(path).map_err(|e| AssetError::io(path, e))?;
    parse_obj(&text, path)
}

/// Parses OBJ text (`path` names it in errors): `v x y z`, `f` with 3 or more
/// corners (`i`, `i/t`, `i//n`, `i/t/n`, negative = relative; polygons are split
/// into fans), `o`/`g` names; comments and other statements (`vn`, `vt`, `s`,
/// `usemtl`, `mtllib`, …) are ignored. Objects without faces are dropped.
pub fn parse_obj(text: &str, path: &Path) -> Result<Vec<ObjObject>, AssetError> {
    let error = |line: usize, message: String| AssetError::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut vertices: Vec<Point3<f64>> = Vec::new();
    let mut groups: Vec<(String, Vec<[usize; 3]>)> = vec![(String::new(), Vec::new())];
    for (number, raw) in text.lines().enumerate() {
        let number = number + 1;
        let line = raw.split('#').next().unwrap_or("").trim();
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let coords: Vec<f64> = words
                    .take(3)
                    .map(str::parse)
                    .collect::<Result<_, _>>()
                    .map_err(|e| error(number, format!("bad vertex coordinate ({e}): {raw:?}")))?;
                if coords.len() < 3 {
                    return Err(error(number, format!("a vertex needs x y z: {raw:?}")));
                }
                vertices.push(Point3::new(coords[0], coords[1], coords[2]));
            }
            Some("f") => {
                let corners: Vec<usize> = words
                    .map(|w| vertex_index(w, vertices.len()))
                    .collect::<Result<_, _>>()
                    .map_err(|m| error(number, format!("{m}: {raw:?}")))?;
                if corners.len() < 3 {
                    return Err(error(number, format!("a face needs 3 corners: {raw:?}")));
                }
                let faces = &mut groups.last_mut().expect("one group").1;
                for k in 1..corners.len() - 1 {
                    faces.push([corners[0], corners[k], corners[k + 1]]);
                }
            }
            Some("o" | "g") => groups.push((words.collect::<Vec<_>>().join(" "), Vec::new())),
            _ => {}
        }
    }
    Ok(groups
        .into_iter()
        .filter(|(_, faces)| !faces.is_empty())
        .map(|(name, faces)| ObjObject {
            name,
            mesh: compact(&vertices, &faces),
        })
        .collect())
}

/// The 0-based vertex index of a face corner `i[/t[/n]]`.
fn vertex_index(word: &str, vertex_count: usize) -> Result<usize, String> {
    let first = word.split('/').next().unwrap_or("");
    let i: i64 = first
        .parse()
        .map_err(|_| format!("bad face index '{word}'"))?;
    let index = if i > 0 {
        i - 1
    } else {
        vertex_count as i64 + i
    };
    if i == 0 || index < 0 || index >= vertex_count as i64 {
        return Err(format!(
            "face index {i} refers to no vertex ({vertex_count} defined so far)"
        ));
    }
    Ok(index as usize)
}

/// A mesh with only the vertices `faces` use, in their file order.
fn compact(vertices: &[Point3<f64>], faces: &[[usize; 3]]) -> TriangleMesh {
    let mut map = vec![u32::MAX; vertices.len()];
    for face in faces {
        for &v in face {
            map[v] = 0;
        }
    }
    let mut mesh = TriangleMesh::new();
    for (v, slot) in map.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = mesh.push_vertex(vertices[v]);
        }
    }
    mesh.triangles = faces.iter().map(|f| f.map(|v| map[v])).collect();
    mesh
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use nalgebra::Point3;

    use super::parse_obj;
    use crate::{AssetError, ObjOptions, axis_box, cylinder, write_obj};

    #[test]
    fn written_objects_read_back_identically() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sub/parts.obj");
        let a = axis_box(Point3::new(0.0, 0.0, 0.0), Point3::new(0.25, 0.5, 0.125));
        let c = cylinder(0.0625, 0.5, 16, true);
        let options = ObjOptions {
            header: "units: mm\nsecond line".into(),
            scale: 1000.0,
            decimals: 6,
        };
        write_obj(&path, &[("block", &a), ("pipe", &c)], &options).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.starts_with("# units: mm\n# second line\no block\n"));
        // Line counts: one `v` per vertex and one `f` per triangle.
        let count = |p: &str| text.lines().filter(|l| l.starts_with(p)).count();
        assert_eq!(count("v "), a.vertices.len() + c.vertices.len());
        assert_eq!(count("f "), a.triangles.len() + c.triangles.len());
        let objects = parse_obj(&text, &path).unwrap();
        assert_eq!(objects.len(), 2);
        assert_eq!(objects[0].name, "block");
        assert_eq!(objects[1].name, "pipe");
        for (read, original) in objects.iter().zip([&a, &c]) {
            assert_eq!(read.mesh.triangles, original.triangles);
            for (p, q) in read.mesh.vertices.iter().zip(&original.vertices) {
                // 6 decimals of mm.
                assert!((p / 1000.0 - q).norm() < 1e-9);
            }
        }
        // No temporary file is left behind.
        assert_eq!(
            std::fs::read_dir(path.parent().unwrap()).unwrap().count(),
            1
        );
    }

    #[test]
    fn polygons_relative_indices_and_errors() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\ng quad\nf 1/1/1 2//2 -2 -1\n";
        let objects = parse_obj(text, Path::new("q.obj")).unwrap();
        assert_eq!(objects.len(), 1);
        assert_eq!(objects[0].mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert!((objects[0].mesh.surface_area() - 1.0).abs() < 1e-15);
        let bad = parse_obj("v 0 0 0\nf 1 2 3\n", Path::new("bad.obj")).unwrap_err();
        match &bad {
            AssetError::Parse { line, .. } => assert_eq!(*line, 2),
            other => panic!("unexpected {other:?}"),
        }
        assert!(
            bad.to_string()
                .starts_with("bad.obj:2: face index 2 refers to no vertex")
        );
        let name = write_obj(
            &tempfile::tempdir().unwrap().path().join("x.obj"),
            &[(
                "two words",
                &axis_box(Point3::origin(), Point3::new(1.0, 1.0, 1.0)),
            )],
            &ObjOptions::default(),
        );
        assert!(matches!(name, Err(AssetError::InvalidArgument { .. })));
    }
}
