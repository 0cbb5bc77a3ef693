//! Tests of the exports: the `.vtp` read back with an XML parser against the document,
//! and the tube OBJ's vertices and faces against the centreline geometry.

use nalgebra::Vector3;

use crate::study::tests::doc;
use crate::*;

/// A rod along a helix (radius 0.1 m, pitch 0.05 m per turn, 1.5 turns, 36 edges),
/// with irregular sectional values that exercise the number formatting.
fn helix_rod(name: &str, outer_radius: Option<f64>) -> RodResult {
    let n = 36;
    let mut rod = crate::tests::sample_rod();
    rod.name = name.into();
    rod.segments = n;
    let phi = |j: usize| 3.0 * std::f64::consts::PI * j as f64 / n as f64;
    rod.position_m = (0..=n)
        .map(|j| {
            [
                0.1 * phi(j).cos(),
                0.1 * phi(j).sin(),
                0.05 * phi(j) / std::f64::consts::TAU,
            ]
        })
        .collect();
    let wiggle = |j: usize, k: f64| (k * (j as f64 + 1.0)).sin() * 10f64.powf(k - 3.0);
    rod.s_m = (0..=n).map(|j| j as f64 / n as f64).collect();
    rod.force_n = (0..=n)
        .map(|j| [wiggle(j, 1.0), wiggle(j, 2.0), 1.0 / 3.0])
        .collect();
    rod.moment_nm = (0..=n)
        .map(|j| [wiggle(j, 3.0), -1e-7, wiggle(j, 0.5)])
        .collect();
    rod.tangential_force_n = (0..=n).map(|j| wiggle(j, 1.7)).collect();
    rod.shear_force_n = (0..=n).map(|j| wiggle(j, 2.3).abs()).collect();
    rod.bending_moment_nm = (0..=n).map(|j| wiggle(j, 0.3).abs()).collect();
    rod.torsion_nm = (0..=n).map(|j| -wiggle(j, 4.1)).collect();
    rod.total_moment_nm = vec![[0.0; 3]; n + 1];
    rod.hamiltonian_n = vec![0.0; n + 1];
    rod.curvature_1pm = vec![[0.0; 3]; n + 1];
    rod.edge_force_n = vec![[0.0; 3]; n];
    rod.outer_radius_m = outer_radius;
    rod
}

fn helix_doc() -> ResultDoc {
    let mut d = doc(1.0);
    d.rods = vec![helix_rod("hose_a", Some(0.012)), helix_rod("hose-b", None)];
    d.rods[1].position_m.iter_mut().for_each(|p| p[2] += 0.3);
    d
}

fn numbers(node: roxmltree::Node) -> Vec<f64> {
    node.text()
        .unwrap_or("")
        .split_whitespace()
        .map(|t| t.parse().unwrap())
        .collect()
}

#[test]
fn vtp_point_data_reads_back_exactly() {
    let d = helix_doc();
    let text = rods_vtp(&d);
    let xml = roxmltree::Document::parse(&text).expect("well-formed XML");
    let root = xml.root_element();
    assert_eq!(
        (root.tag_name().name(), root.attribute("type")),
        ("VTKFile", Some("PolyData"))
    );
    let piece = xml.descendants().find(|n| n.has_tag_name("Piece")).unwrap();
    assert_eq!(piece.attribute("NumberOfPoints"), Some("74"));
    assert_eq!(piece.attribute("NumberOfLines"), Some("2"));
    let array = |parent: &str, name: &str| {
        xml.descendants()
            .find(|n| n.has_tag_name(parent))
            .unwrap()
            .descendants()
            .find(|n| n.has_tag_name("DataArray") && n.attribute("Name") == Some(name))
            .unwrap_or_else(|| panic!("no {parent}/{name}"))
    };
    // Expected values, recomputed here per vertex of both rods.
    let norm = |v: &[f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let per_vertex = |f: &dyn Fn(&RodResult, usize) -> Vec<f64>| -> Vec<f64> {
        d.rods
            .iter()
            .flat_map(|r| (0..r.s_m.len()).flat_map(move |j| f(r, j)))
            .collect()
    };
    let expected: [(&str, usize, Vec<f64>); 9] = [
        ("s_m", 1, per_vertex(&|r, j| vec![r.s_m[j]])),
        ("force_N", 3, per_vertex(&|r, j| r.force_n[j].to_vec())),
        ("moment_Nm", 3, per_vertex(&|r, j| r.moment_nm[j].to_vec())),
        (
            "force_magnitude_N",
            1,
            per_vertex(&|r, j| vec![norm(&r.force_n[j])]),
        ),
        (
            "moment_magnitude_Nm",
            1,
            per_vertex(&|r, j| vec![norm(&r.moment_nm[j])]),
        ),
        (
            "tangential_force_N",
            1,
            per_vertex(&|r, j| vec![r.tangential_force_n[j]]),
        ),
        (
            "shear_force_N",
            1,
            per_vertex(&|r, j| vec![r.shear_force_n[j]]),
        ),
        (
            "bending_moment_Nm",
            1,
            per_vertex(&|r, j| vec![r.bending_moment_nm[j]]),
        ),
        ("torsion_Nm", 1, per_vertex(&|r, j| vec![r.torsion_nm[j]])),
    ];
    for (name, components, values) in &expected {
        let node = array("PointData", name);
        assert_eq!(
            node.attribute("NumberOfComponents"),
            Some(components.to_string().as_str())
        );
        assert_eq!(node.attribute("type"), Some("Float64"));
        assert_eq!(&numbers(node), values, "{name} must round-trip exactly");
    }
    assert_eq!(
        numbers(array("Points", "position_m")),
        per_vertex(&|r, j| r.position_m[j].to_vec())
    );
    let ids = numbers(array("PointData", "rod_id"));
    assert_eq!(ids, [vec![0.0; 37], vec![1.0; 37]].concat());
    assert_eq!(numbers(array("CellData", "rod_id")), [0.0, 1.0]);
    let connectivity = numbers(array("Lines", "connectivity"));
    assert_eq!(connectivity, (0..74).map(f64::from).collect::<Vec<_>>());
    assert_eq!(numbers(array("Lines", "offsets")), [37.0, 74.0]);
    // Rod names: VTK's ASCII string encoding (bytes, each string ended by 0).
    let bytes: Vec<u8> = numbers(array("FieldData", "rod_names"))
        .iter()
        .map(|b| *b as u8)
        .collect();
    let names: Vec<&str> = bytes
        .split(|b| *b == 0)
        .filter(|s| !s.is_empty())
        .map(|s| std::str::from_utf8(s).unwrap())
        .collect();
    assert_eq!(names, ["hose_a", "hose-b"]);
}

/// In a case unit (mm), the lengths of `rods.vtp` (points and arc length) are in that
/// unit and say so in their names; forces and moments stay in N and N·m.
#[test]
fn vtp_lengths_follow_the_export_unit() {
    let d = helix_doc();
    let text = rods_vtp_in(&d, &ExportUnit::new(1e-3, "mm"));
    let xml = roxmltree::Document::parse(&text).expect("well-formed XML");
    let array = |name: &str| {
        xml.descendants()
            .find(|n| n.has_tag_name("DataArray") && n.attribute("Name") == Some(name))
            .unwrap_or_else(|| panic!("no {name}"))
    };
    let close = |got: Vec<f64>, metres: Vec<f64>| {
        assert_eq!(got.len(), metres.len());
        for (g, m) in got.iter().zip(&metres) {
            assert!(
                (g - m * 1e3).abs() <= 1e-12 * (m * 1e3).abs().max(1.0),
                "{g} {m}"
            );
        }
    };
    close(
        numbers(array("s_mm")),
        d.rods.iter().flat_map(|r| r.s_m.clone()).collect(),
    );
    close(
        numbers(array("position_mm")),
        d.rods
            .iter()
            .flat_map(|r| r.position_m.iter().flatten().copied())
            .collect(),
    );
    assert_eq!(
        numbers(array("force_N")),
        d.rods
            .iter()
            .flat_map(|r| r.force_n.iter().flatten().copied())
            .collect::<Vec<_>>()
    );
    for metres in ["s_m", "position_m"] {
        assert!(!text.contains(&format!("Name=\"{metres}\"")), "{metres}");
    }
}

/// Distance of `p` from the line through `a` and `b`, and the parameter of the foot.
fn line_distance(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> (f64, f64) {
    let d = b - a;
    let t = (p - a).dot(&d) / d.norm_squared();
    ((p - a - d * t).norm(), t)
}

#[test]
fn tube_vertices_lie_at_the_radius_and_faces_point_outwards() {
    let d = helix_doc();
    let text = tubes_obj(&d);
    // (name, vertices, faces with 1-based global vertex indices) per object.
    type Object = (String, Vec<Vector3<f64>>, Vec<[usize; 3]>);
    let mut objects: Vec<Object> = Vec::new();
    let mut all: Vec<Vector3<f64>> = Vec::new();
    for line in text.lines() {
        let mut parts = line.split_whitespace();
        match parts.next() {
            Some("o") => objects.push((parts.next().unwrap().into(), Vec::new(), Vec::new())),
            Some("v") => {
                let v: Vec<f64> = parts.map(|t| t.parse().unwrap()).collect();
                let v = Vector3::new(v[0], v[1], v[2]);
                all.push(v);
                objects.last_mut().unwrap().1.push(v);
            }
            Some("f") => {
                let f: Vec<usize> = parts.map(|t| t.parse().unwrap()).collect();
                objects.last_mut().unwrap().2.push([f[0], f[1], f[2]]);
            }
            _ => {}
        }
    }
    assert_eq!(objects.len(), 2);
    assert!(
        text.contains("hose-b: no outer radius"),
        "the default radius is stated"
    );
    for ((name, vertices, faces), rod) in objects.iter().zip(&d.rods) {
        assert_eq!(name, &rod.name);
        let n = rod.segments;
        assert_eq!(
            vertices.len(),
            (n + 1) * TUBE_SIDES + 2,
            "{name}: rings and cap centres"
        );
        assert_eq!(
            faces.len(),
            2 * n * TUBE_SIDES + 2 * TUBE_SIDES,
            "{name}: faces"
        );
        let radius = rod
            .outer_radius_m
            .unwrap_or(DEFAULT_RADIUS_FRACTION * rod.length_m);
        let centre: Vec<Vector3<f64>> = rod.position_m.iter().map(|p| Vector3::from(*p)).collect();
        for (i, v) in vertices[..(n + 1) * TUBE_SIDES].iter().enumerate() {
            let j = i / TUBE_SIDES;
            // At the radius from the line of every edge at the ring's vertex.
            for e in [j.saturating_sub(1), j.min(n - 1)] {
                let (distance, t) = line_distance(v, &centre[e], &centre[e + 1]);
                assert!(
                    (distance - radius).abs() < 1e-9 * radius,
                    "{name} ring {j}: {distance}"
                );
                if j == 0 || j == n {
                    let end = if j == 0 { 0.0 } else { 1.0 };
                    assert!(
                        (t - end).abs() < 1e-9,
                        "end ring {j} square to its edge: {t}"
                    );
                }
            }
            // And nowhere closer to the centreline polyline.
            let nearest = (0..n)
                .map(|e| {
                    let (distance, t) = line_distance(v, &centre[e], &centre[e + 1]);
                    if (0.0..=1.0).contains(&t) {
                        distance
                    } else {
                        (v - centre[e + t.clamp(0.0, 1.0) as usize]).norm()
                    }
                })
                .fold(f64::INFINITY, f64::min);
            assert!(
                nearest > radius * (1.0 - 1e-9),
                "{name}: vertex {i} at {nearest} < {radius}"
            );
        }
        assert_eq!(vertices[vertices.len() - 2], centre[0]);
        assert_eq!(vertices[vertices.len() - 1], centre[n]);
        // Counter-clockwise seen from outside: the normal points away from the
        // centreline (sides) or along the rod out of the tube (caps).
        for (k, f) in faces.iter().enumerate() {
            let [a, b, c] = f.map(|i| all[i - 1]);
            let normal = (b - a).cross(&(c - a));
            let middle = (a + b + c) / 3.0;
            let outward = if k < 2 * n * TUBE_SIDES {
                let e = k / (2 * TUBE_SIDES);
                let (_, t) = line_distance(&middle, &centre[e], &centre[e + 1]);
                middle - (centre[e] + (centre[e + 1] - centre[e]) * t)
            } else if f[0] == all.iter().position(|v| *v == centre[0]).unwrap() + 1 {
                centre[0] - centre[1]
            } else {
                centre[n] - centre[n - 1]
            };
            assert!(
                normal.dot(&outward) > 0.0,
                "{name}: face {k} points inwards"
            );
        }
    }
}

#[test]
fn write_results_adds_the_vtp_and_the_tubes() {
    let d = helix_doc();
    let tmp = tempfile::tempdir().unwrap();
    let written = write_results(tmp.path(), &d).unwrap();
    let names: Vec<String> = written
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "hose_a.csv",
            "hose-b.csv",
            "rods.vtp",
            "tubes.obj",
            "tubes.stl",
            "result.json"
        ]
    );
    assert_eq!(
        std::fs::read_to_string(tmp.path().join("rods.vtp")).unwrap(),
        rods_vtp(&d)
    );
    assert_eq!(
        std::fs::read_to_string(tmp.path().join("tubes.obj")).unwrap(),
        tubes_obj(&d)
    );
}

/// `write_result_files` builds the tube surfaces once for `tubes.obj` and `tubes.stl`
/// and takes `result.json`'s bytes from the caller: every file must still be what
/// each writer writes alone, and the tubes the surfaces of [`tube_mesh`] built afresh
/// per rod (OBJ coordinates read back to the same `f64`, STL corners to the same
/// `f32`), in the unit asked for.
#[test]
fn written_files_are_what_each_writer_writes_alone() {
    let d = helix_doc();
    let mm = ExportUnit::new(1e-3, "mm");
    let tmp = tempfile::tempdir().unwrap();
    let json = serde_json::to_vec_pretty(&d).unwrap();
    write_result_files(tmp.path(), &d, &json, &mm).unwrap();
    let read = |name: &str| std::fs::read(tmp.path().join(name)).unwrap();
    assert_eq!(read("result.json"), json);
    for rod in &d.rods {
        assert_eq!(
            read(&format!("{}.csv", rod.name)),
            rod_csv(rod).into_bytes()
        );
    }
    assert_eq!(read("rods.vtp"), rods_vtp_in(&d, &mm).into_bytes());
    assert_eq!(read("tubes.obj"), tubes_obj_in(&d, &mm).into_bytes());
    assert_eq!(read("tubes.stl"), tubes_stl(&d, &mm));
    // Independently: the surfaces of `tube_mesh`, one rod after the other.
    let fresh: Vec<TubeMesh> = d
        .rods
        .iter()
        .map(|r| tube_mesh(&r.position_m, tube_radius(r).0).unwrap())
        .collect();
    let obj = String::from_utf8(read("tubes.obj")).unwrap();
    let objects = obj_objects(&obj);
    for (rod, mesh) in d.rods.iter().zip(&fresh) {
        let (_, vertices) = objects.iter().find(|(n, _)| *n == rod.name).unwrap();
        assert_eq!(vertices.len(), mesh.vertices.len(), "{}", rod.name);
        for (read_back, v) in vertices.iter().zip(&mesh.vertices) {
            assert_eq!(*read_back, v / 1e-3, "{}: shortest round trip", rod.name);
        }
    }
    let stl = read("tubes.stl");
    let corners: Vec<f32> = stl[84..]
        .chunks(50)
        .flat_map(|record| {
            (3..12).map(move |k| f32::from_le_bytes(record[4 * k..4 * k + 4].try_into().unwrap()))
        })
        .collect();
    let expected: Vec<f32> = fresh
        .iter()
        .flat_map(|m| {
            m.faces
                .iter()
                .flat_map(move |f| f.map(|i| m.vertices[i] / 1e-3))
        })
        .flat_map(|p| [p.x as f32, p.y as f32, p.z as f32])
        .collect();
    assert_eq!(corners, expected);
}

#[test]
fn a_centreline_that_is_not_finite_gets_no_tube() {
    let mut d = helix_doc();
    d.rods[0].position_m[3][1] = f64::NAN;
    let text = tubes_obj(&d);
    assert!(text.contains("hose_a: centreline not finite"));
    assert_eq!(text.matches("\no ").count(), 1, "only hose-b");
    assert!(
        tube_rings(&[[0.0; 3], [0.0; 3]], 0.1).is_none(),
        "zero extent"
    );
}

/// Objects of an OBJ text: (name, vertices) in file order.
fn obj_objects(text: &str) -> Vec<(String, Vec<Vector3<f64>>)> {
    let mut objects: Vec<(String, Vec<Vector3<f64>>)> = Vec::new();
    for line in text.lines() {
        let mut parts = line.split_whitespace();
        match parts.next() {
            Some("o") => objects.push((parts.next().unwrap().into(), Vec::new())),
            Some("v") => {
                let v: Vec<f64> = parts.map(|t| t.parse().unwrap()).collect();
                objects
                    .last_mut()
                    .unwrap()
                    .1
                    .push(Vector3::new(v[0], v[1], v[2]));
            }
            _ => {}
        }
    }
    objects
}

/// A T: body "tee" at (0.1, 0.2, 0.3) m with three straight rods leaving its ports
/// 30 mm out along +x, −x and +y (radii 8, 8 and 5 mm); the +x rod's far end held by
/// connector "outlet", a clip "c1" on the +y rod at its middle vertex.
fn tee_doc() -> ResultDoc {
    let centre = [0.1, 0.2, 0.3];
    let mut d = doc(1.0);
    let rod = |name: &str, dir: [f64; 3], radius: f64| {
        let mut r = crate::tests::sample_rod();
        r.name = name.into();
        r.outer_radius_m = Some(radius);
        r.position_m = (0..3)
            .map(|j| {
                let a = 0.03 + 0.2 * j as f64;
                [0, 1, 2].map(|i| centre[i] + a * dir[i])
            })
            .collect();
        r
    };
    d.rods = vec![
        rod("east", [1.0, 0.0, 0.0], 0.008),
        rod("west", [-1.0, 0.0, 0.0], 0.008),
        rod("north", [0.0, 1.0, 0.0], 0.005),
    ];
    d.bodies.push(BodyResult {
        name: "tee".into(),
        fixed: false,
        position_m: centre,
        orientation_quaternion_wxyz: [1.0, 0.0, 0.0, 0.0],
        rotation_matrix: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        mass_kg: 0.1,
    });
    let reaction = |name: &str, kind: &str, rod: &ResultDoc, r: usize, end: &str| {
        let rod_result = &rod.rods[r];
        ReactionResult {
            name: name.into(),
            kind: kind.into(),
            rod: rod_result.name.clone(),
            end: end.into(),
            position_m: if end == "start" {
                rod_result.position_m[0]
            } else {
                rod_result.position_m[2]
            },
            force_n: [0.0, 0.0, 1.0],
            moment_nm: [0.0; 3],
            max_force_n: None,
            max_moment_nm: None,
        }
    };
    let reactions = vec![
        reaction("tee.a", "port", &d, 0, "start"),
        reaction("tee.b", "port", &d, 1, "start"),
        reaction("tee.c", "port", &d, 2, "start"),
        reaction("outlet", "connector", &d, 0, "end"),
    ];
    d.reactions = reactions;
    let north = &d.rods[2];
    d.clips.push(ClipResult {
        name: "c1".into(),
        rod: "north".into(),
        vertex: 1,
        s_m: north.s_m[1],
        position_m: north.position_m[1],
        joint: "fixed".into(),
        axis_world: None,
        value: None,
        rotation_wxyz: None,
        limits: None,
        at_limit: false,
        force_n: [0.0; 3],
        moment_nm: [0.0; 3],
    });
    d
}

#[test]
fn the_tube_obj_closes_the_t_and_shows_connectors_and_clips() {
    let d = tee_doc();
    let mm = ExportUnit::new(1e-3, "mm");
    let objects = obj_objects(&tubes_obj_in(&d, &mm));
    let names: Vec<&str> = objects.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "east",
            "west",
            "north",
            "junction_tee",
            "connector_outlet",
            "clip_c1"
        ]
    );
    let object = |name: &str| &objects.iter().find(|(n, _)| n == name).unwrap().1;
    let centre = Vector3::new(100.0, 200.0, 300.0);
    // Every vertex of a hose's start ring (at its port) lies on the rim of the
    // junction's cylinder towards that port: same plane, same radius, so the tubes and
    // the body meet without a gap. The body's vertices stay within the ports' reach.
    let junction = object("junction_tee");
    for (rod, dir, radius) in [
        ("east", Vector3::x(), 8.0),
        ("west", -Vector3::x(), 8.0),
        ("north", Vector3::y(), 5.0),
    ] {
        let port = centre + dir * 30.0;
        let start_ring = &object(rod)[..TUBE_SIDES];
        for v in start_ring {
            assert!(
                (v - port).dot(&dir).abs() < 1e-9,
                "{rod}: ring in the port plane"
            );
            assert!(
                ((v - port).norm() - radius).abs() < 1e-9,
                "{rod}: ring radius"
            );
        }
        // The junction has TUBE_SIDES vertices on that same rim.
        let on_rim = junction
            .iter()
            .filter(|v| {
                (*v - port).dot(&dir).abs() < 1e-9 && ((*v - port).norm() - radius).abs() < 1e-9
            })
            .count();
        assert_eq!(on_rim, TUBE_SIDES, "{rod}: the body reaches the port");
    }
    assert!(
        junction
            .iter()
            .all(|v| (v - centre).norm() <= 30.0f64.hypot(8.0) + 1e-9)
    );
    // The connector's collar surrounds the east hose's far end: every vertex of the
    // hose's end ring is inside the collar (radius 1.4 × 8 mm, from 8 mm before the end
    // to 16 mm beyond it).
    let end = centre + Vector3::x() * 430.0;
    let collar = object("connector_outlet");
    let along: Vec<f64> = collar.iter().map(|v| (v - end).x).collect();
    let reach = along
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(*x), b.max(*x))
        });
    assert!(
        (reach.0 + 8.0).abs() < 1e-9 && (reach.1 - 16.0).abs() < 1e-9,
        "{reach:?}"
    );
    let east = object("east");
    let end_ring = &east[2 * TUBE_SIDES..3 * TUBE_SIDES];
    for v in end_ring {
        let radial = (v - end) - Vector3::x() * (v - end).x;
        assert!(radial.norm() < CONNECTOR_RADIUS_FACTOR * 8.0);
    }
    // The clip's band sits on the north hose's middle vertex, across the hose.
    let middle = centre + Vector3::y() * 230.0;
    let band = object("clip_c1");
    for v in band {
        let d = v - middle;
        assert!(d.y.abs() <= 0.5 * CLIP_WIDTH_FACTOR * 5.0 + 1e-9);
        assert!(d.x.hypot(d.z) <= CLIP_RADIUS_FACTOR * 5.0 + 1e-9);
    }
}

#[test]
fn the_ball_of_a_junction_is_closed_and_round() {
    let ball = ball_mesh(&[1.0, 2.0, 3.0], 0.5);
    for v in &ball.vertices {
        assert!(((v - Vector3::new(1.0, 2.0, 3.0)).norm() - 0.5).abs() < 1e-12);
    }
    // Closed and consistently wound: every directed edge appears once, its reverse
    // once; the faces point outwards.
    let mut edges = std::collections::HashMap::new();
    for f in &ball.faces {
        for k in 0..3 {
            *edges.entry((f[k], f[(k + 1) % 3])).or_insert(0) += 1;
        }
        let [a, b, c] = f.map(|i| ball.vertices[i]);
        let normal = (b - a).cross(&(c - a));
        let outward = (a + b + c) / 3.0 - Vector3::new(1.0, 2.0, 3.0);
        assert!(normal.dot(&outward) > 0.0, "{f:?}");
    }
    for (&(a, b), &n) in &edges {
        assert_eq!(n, 1);
        assert_eq!(edges.get(&(b, a)), Some(&1));
    }
    assert_eq!(ball.faces.len(), 2 * TUBE_SIDES * (BALL_BANDS - 1));
}

#[test]
fn the_vtp_carries_bend_radius_outer_radius_contact_force_and_frames() {
    let mut d = helix_doc();
    // Curvature 1/0.25 m⁻¹ at vertex 3 of hose_a; a contact of 2 N along +z near
    // vertex 5 (s = 5/36 m); frames: a quarter turn about z on every edge.
    d.rods[0].curvature_1pm[3] = [3.0, 4.0, 0.5];
    d.contacts.push(ContactResult {
        rod: "hose_a".into(),
        s_m: 5.2 / 36.0,
        point_m: d.rods[0].position_m[5],
        normal: [0.0, 0.0, 1.0],
        force_n: 2.0,
        with: "floor".into(),
    });
    let (c, s) = (
        std::f64::consts::FRAC_PI_4.cos(),
        std::f64::consts::FRAC_PI_4.sin(),
    );
    for rod in &mut d.rods {
        rod.section_frames_wxyz = vec![[c, 0.0, 0.0, s]; rod.segments];
    }
    let text = rods_vtp_in(&d, &ExportUnit::new(1e-3, "mm"));
    let xml = roxmltree::Document::parse(&text).unwrap();
    let array = |name: &str| {
        let node = xml
            .descendants()
            .find(|n| n.has_tag_name("DataArray") && n.attribute("Name") == Some(name))
            .unwrap_or_else(|| panic!("no {name}"));
        numbers(node)
    };
    let bend = array("bend_radius_mm");
    assert_eq!(bend.len(), 74);
    assert!(
        (bend[3] - 200.0).abs() < 1e-12,
        "1/|(3, 4)| m in mm: {}",
        bend[3]
    );
    assert!(
        text.contains(">\ninf") || text.contains(" inf"),
        "straight vertices: inf"
    );
    let curvature = array("curvature_1pm");
    assert_eq!(&curvature[9..12], &[3.0, 4.0, 0.5]);
    let radius = array("outer_radius_mm");
    assert!(radius[..37].iter().all(|r| *r == 12.0));
    assert!(
        radius[37..]
            .iter()
            .all(|r| *r == 1000.0 * DEFAULT_RADIUS_FRACTION)
    );
    let contact = array("contact_force_N");
    assert_eq!(contact.len(), 3 * 74);
    assert_eq!(&contact[15..18], &[0.0, 0.0, 2.0]);
    assert_eq!(contact.iter().map(|x| x.abs()).sum::<f64>(), 2.0);
    // A quarter turn about z: d1 = y, d2 = −x, d3 = z at every vertex.
    let (d1, d2, d3) = (
        array("section_d1"),
        array("section_d2"),
        array("section_d3"),
    );
    for j in 0..74 {
        for (got, want) in [
            (&d1, [0.0, 1.0, 0.0]),
            (&d2, [-1.0, 0.0, 0.0]),
            (&d3, [0.0, 0.0, 1.0]),
        ] {
            for i in 0..3 {
                assert!((got[3 * j + i] - want[i]).abs() < 1e-12, "vertex {j}");
            }
        }
    }
    // Without frames (an older result.json) the frame arrays are left out.
    d.rods[1].section_frames_wxyz.clear();
    assert!(!rods_vtp(&d).contains("section_d1"));
}

/// `tubes.stl` written straight from the meshes is byte for byte
/// `write_binary_stl` of their triangles, in m and in mm, with a rod that has no tube.
#[test]
fn tubes_stl_is_the_binary_stl_of_the_triangles() {
    let mut d = helix_doc();
    let mut point = d.rods[0].clone();
    point.name = "point".into();
    point.position_m = vec![[0.1, 0.2, 0.3]; 3];
    d.rods.insert(1, point);
    let meshes = rod_tube_meshes(&d);
    assert!(meshes[0].is_some() && meshes[1].is_none() && meshes[2].is_some());
    for unit in [ExportUnit::metre(), ExportUnit::new(1e-3, "mm")] {
        let mut expected = Vec::new();
        strand_contact::write_binary_stl(
            &mut expected,
            &format!("strand tubes, unit {}, case {}", unit.symbol, d.case),
            &crate::cad::triangles_in(&meshes, unit.metres),
        )
        .unwrap();
        assert_eq!(crate::cad::tubes_stl_of(&d, &meshes, &unit), expected);
    }
}
