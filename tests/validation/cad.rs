//! CAD in, CAD out (issue 17): environment meshes as binary and ASCII STL give the
//! same solution and contacts as the OBJ they were converted from.

use std::path::{Path, PathBuf};

use nalgebra::Point3;
use strand_solve::SolverSettings;

/// The engine-bay parts of `cases/cooler_hose_contact.ron`.
const PARTS: [&str; 5] = ["radiator", "fan_shroud", "engine", "oil_cooler", "brackets"];

fn assets() -> PathBuf {
    crate::common::cases_dir().join("../assets/engine_bay")
}

/// The triangles of an OBJ part (mm), every coordinate rounded to `f32` (what a binary
/// STL can hold), so that all three formats describe the same exact mesh.
fn rounded_triangles(part: &str) -> (Vec<Point3<f64>>, Vec<[u32; 3]>) {
    let objects = strand_assets::read_obj(&assets().join(format!("{part}.obj"))).unwrap();
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for object in objects {
        let offset = vertices.len() as u32;
        vertices.extend(
            object
                .mesh
                .vertices
                .iter()
                .map(|p| p.map(|x| f64::from(x as f32))),
        );
        triangles.extend(object.mesh.triangles.iter().map(|t| t.map(|i| i + offset)));
    }
    (vertices, triangles)
}

/// Writes every part as `{part}.obj`, `{part}_binary.stl` and `{part}_ascii.stl`.
fn convert(dir: &Path) {
    for part in PARTS {
        let (vertices, triangles) = rounded_triangles(part);
        let mut obj = String::new();
        for p in &vertices {
            obj += &format!("v {:?} {:?} {:?}\n", p.x, p.y, p.z);
        }
        for t in &triangles {
            obj += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        std::fs::write(dir.join(format!("{part}.obj")), obj).unwrap();
        let corners: Vec<[Point3<f64>; 3]> = triangles
            .iter()
            .map(|t| t.map(|i| vertices[i as usize]))
            .collect();
        let mut binary = Vec::new();
        strand_contact::write_binary_stl(&mut binary, part, &corners).unwrap();
        std::fs::write(dir.join(format!("{part}_binary.stl")), binary).unwrap();
        let mut ascii = Vec::new();
        strand_contact::write_ascii_stl(&mut ascii, part, &corners).unwrap();
        std::fs::write(dir.join(format!("{part}_ascii.stl")), ascii).unwrap();
    }
}

/// The cooler-hose contact case with its environment read from `dir/{part}{suffix}`.
fn case_with(dir: &Path, suffix: &str, key: &str) -> PathBuf {
    let original = crate::common::cases_dir().join("cooler_hose_contact.ron");
    let mut text = std::fs::read_to_string(&original).unwrap();
    for part in PARTS {
        let from = format!("obj: \"../assets/engine_bay/{part}.obj\"");
        assert!(text.contains(&from), "{from}");
        let to = dir.join(format!("{part}{suffix}"));
        text = text.replace(&from, &format!("{key}: {:?}", to.to_str().unwrap()));
    }
    let path = dir.join(format!("case{}.ron", suffix.replace('.', "_")));
    std::fs::write(&path, text).unwrap();
    path
}

struct Solved {
    positions: Vec<Point3<f64>>,
    contacts: Vec<(String, f64)>,
    diagnostics: Vec<strand_contact::MeshDiagnostics>,
}

fn solve(path: &Path) -> Solved {
    let built = strand_case::Case::from_path(path)
        .unwrap()
        .build(None)
        .unwrap();
    let contact = built.contact().unwrap();
    let solution = built
        .solve_from(built.initial.clone(), &SolverSettings::default())
        .unwrap();
    assert!(solution.report.converged, "{:?}", solution.report);
    let forces = contact
        .forces(&built.model, &solution.state, &solution.constraints)
        .unwrap();
    Solved {
        positions: solution
            .state
            .rods
            .iter()
            .flat_map(|r| r.positions.iter().map(|p| Point3::from(*p)))
            .collect(),
        contacts: forces
            .iter()
            .filter(|f| f.force_n > 0.0)
            .map(|f| {
                (
                    contact.obstacle_name(&built.model, &f.gap.with).to_string(),
                    f.force_n,
                )
            })
            .collect(),
        diagnostics: built
            .environment
            .iter()
            .map(|m| m.diagnostics().clone())
            .collect(),
    }
}

#[test]
fn the_cooler_case_with_stl_environments_solves_as_with_obj() {
    let dir = tempfile::tempdir().unwrap();
    convert(dir.path());
    let obj = solve(&case_with(dir.path(), ".obj", "obj"));
    assert!(!obj.contacts.is_empty(), "hose 3 rests on its bracket");
    for (suffix, key) in [("_binary.stl", "stl"), ("_ascii.stl", "mesh")] {
        let stl = solve(&case_with(dir.path(), suffix, key));
        let worst = obj
            .positions
            .iter()
            .zip(&stl.positions)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        assert!(worst <= 1e-12, "{suffix}: positions differ by {worst} m");
        assert_eq!(obj.contacts.len(), stl.contacts.len(), "{suffix}");
        for ((with_a, force_a), (with_b, force_b)) in obj.contacts.iter().zip(&stl.contacts) {
            assert_eq!(with_a, with_b);
            assert!(
                (force_a - force_b).abs() <= 1e-9 * force_a.abs(),
                "{suffix}"
            );
        }
        // Welded STL corners: the same topology as the indexed OBJ (whose own exact
        // duplicates are welded for the edge checks too).
        for (a, b) in obj.diagnostics.iter().zip(&stl.diagnostics) {
            assert_eq!(a.vertices - a.duplicate_vertices, b.vertices, "{suffix}");
            let same = |d: &strand_contact::MeshDiagnostics| {
                (
                    d.triangles,
                    d.degenerate_skipped,
                    d.boundary_edges,
                    d.non_manifold_edges,
                    d.misoriented_edges,
                    d.closed,
                    d.patches,
                    d.bounding_box_m,
                )
            };
            assert_eq!(same(a), same(b), "{suffix}");
        }
    }
}

/// Distance from `p` to the nearest line through an edge at the vertex of `line`
/// nearest to `p` (a ring vertex of a mitred tube is at exactly the radius from both),
/// or 0 for `p` at a vertex (a cap centre).
fn distance_to_adjacent_lines(p: &Point3<f64>, line: &[Point3<f64>]) -> f64 {
    let j = (0..line.len())
        .min_by(|&a, &b| (p - line[a]).norm().total_cmp(&(p - line[b]).norm()))
        .unwrap();
    if (p - line[j]).norm() < 1e-9 {
        return 0.0;
    }
    let edges = [j.checked_sub(1), (j + 1 < line.len()).then_some(j)];
    edges
        .into_iter()
        .flatten()
        .map(|e| {
            let d = (line[e + 1] - line[e]).normalize();
            let v = p - line[e];
            (v - d * v.dot(&d)).norm()
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn the_stl_export_reloads_as_a_mesh_at_the_hose_radius_from_the_centreline() {
    let path = crate::common::cases_dir().join("moulded_clipped_hose.ron");
    let built = strand_case::Case::from_path(&path)
        .unwrap()
        .build(None)
        .unwrap();
    let solution = built
        .solve_from(built.initial.clone(), &SolverSettings::default())
        .unwrap();
    assert!(solution.report.converged);
    let doc = strand_report::collect(
        &built.name,
        &built.model,
        &solution,
        strand_report::Timing::default(),
    );
    let dir = tempfile::tempdir().unwrap();
    let mm = strand_report::ExportUnit::new(1e-3, "mm");
    let written = strand_report::write_results_in(dir.path(), &doc, &mm).unwrap();
    let stl = dir.path().join("tubes.stl");
    assert!(written.contains(&stl));
    // Reloaded as an environment mesh in mm, as a CAD system (or a case) would.
    let mesh =
        strand_contact::ObstacleMesh::load(&stl, 1e-3, &nalgebra::Isometry3::identity()).unwrap();
    let diagnostics = mesh.diagnostics();
    assert!(diagnostics.closed, "{diagnostics}");
    let radius = 12.9e-3;
    let centreline: Vec<Point3<f64>> = solution.state.rods[0]
        .positions
        .iter()
        .map(|p| Point3::from(*p))
        .collect();
    // Sampled along the centreline (4 points per edge, ends excluded: the caps), the
    // surface is at the radius: at most the radius (ring vertices), at least the
    // inscribed polygon's apothem r cos(π/16), less 1e-4 r where the two triangles of a
    // mitred quad at a bend cut a little deeper; f32 coordinates (about 3e-5 mm).
    let apothem = radius * (std::f64::consts::PI / strand_report::TUBE_SIDES as f64).cos();
    let tolerance = 1e-7;
    let mut samples = 0;
    for w in centreline.windows(2) {
        for k in 0..4 {
            let p = w[0] + (w[1] - w[0]) * (k as f64 / 4.0);
            if (p - centreline[0]).norm() < 2.0 * radius
                || (p - centreline[centreline.len() - 1]).norm() < 2.0 * radius
            {
                continue;
            }
            let d = mesh.point_proximity(&p, 1.0).unwrap().distance;
            assert!(
                d >= apothem - 1e-4 * radius && d <= radius + tolerance,
                "surface {d} m from the centreline at {p}"
            );
            samples += 1;
        }
    }
    assert!(samples > 100, "{samples}");
    // Every ring vertex of the surface lies at the radius from the centreline.
    let mut rings = 0;
    for t in 0..mesh.triangle_count() {
        for corner in mesh.triangle(t) {
            let d = distance_to_adjacent_lines(&corner, &centreline);
            if d > 0.0 {
                assert!((d - radius).abs() <= tolerance, "ring vertex at {d} m");
                rings += 1;
            }
        }
    }
    assert!(rings > 0);
    // The OBJ and VTP are in mm too.
    let obj = std::fs::read_to_string(dir.path().join("tubes.obj")).unwrap();
    assert!(
        obj.lines().next().unwrap().contains(", mm;"),
        "{}",
        &obj[..200]
    );
    let vtp = std::fs::read_to_string(dir.path().join("rods.vtp")).unwrap();
    assert!(vtp.contains("Name=\"position_mm\""));
}
