//! Per-vertex clearance (`rods[*].clearance_m` in `result.json`, the 3D view's
//! "clearance" colouring and hover readout): for `cases/cooler_hose_contact.ron`,
//! solved by the real binary, every vertex's value equals an independent brute-force
//! distance — every triangle of every environment file (`assets/engine_bay/*.obj`,
//! mm, placed as the case places them: unscaled, unmoved) against the vertex, closest
//! point on a triangle by Ericson's Voronoi-region method, minus the outer radius —
//! and is `null` exactly where that distance exceeds the 100 mm search.

mod common;
#[path = "common/triangle.rs"]
mod triangle;

use std::path::Path;

use common::{case, read_json, strand};

use triangle::{V, closest_on_triangle, dot, obj_triangles as triangles, sub};

#[test]
fn vertex_clearances_match_a_brute_force_distance_to_every_triangle() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("contact");
    let case = case("cooler_hose_contact.ron");
    let (exit, _, err) = strand(&["solve", &case, "--out", dir.to_str().unwrap()]);
    assert_eq!(exit, Some(0), "{err}");
    let doc = read_json(&dir.join("result.json"));
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/engine_bay");
    let all: Vec<[V; 3]> = ["radiator", "fan_shroud", "engine", "oil_cooler", "brackets"]
        .iter()
        .flat_map(|part| triangles(&assets.join(format!("{part}.obj"))))
        .collect();
    assert_eq!(all.len(), 112 + 640 + 236 + 12 + 24);
    let (mut compared, mut beyond, mut touching) = (0, 0, 0);
    for rod in doc["rods"].as_array().unwrap() {
        let name = rod["name"].as_str().unwrap();
        let radius_mm = 1e3 * rod["outer_radius_m"].as_f64().unwrap();
        let positions = rod["position_m"].as_array().unwrap();
        let clearances = rod["clearance_m"].as_array().unwrap();
        assert_eq!(clearances.len(), positions.len(), "{name}");
        for (j, (p, c)) in positions.iter().zip(clearances).enumerate() {
            let p: V = [0, 1, 2].map(|i| 1e3 * p[i].as_f64().unwrap());
            let distance = all
                .iter()
                .map(|[a, b, c]| {
                    let q = closest_on_triangle(p, *a, *b, *c);
                    dot(sub(p, q), sub(p, q)).sqrt()
                })
                .fold(f64::INFINITY, f64::min);
            let expected = (distance - radius_mm).max(0.0);
            match c.as_f64() {
                Some(value) => {
                    assert!(
                        expected <= 100.0 + 1e-6,
                        "{name} {j}: {expected} mm reported"
                    );
                    assert!(
                        (1e3 * value - expected).abs() < 1e-6,
                        "{name} vertex {j}: clearance {} mm, brute force {expected} mm",
                        1e3 * value
                    );
                    compared += 1;
                    touching += usize::from(expected < 1e-3);
                }
                None => {
                    assert!(expected > 100.0 - 1e-6, "{name} {j}: {expected} mm missing");
                    beyond += 1;
                }
            }
        }
    }
    // The case has both kinds, and hose 3 rests on its support (two contacts).
    assert!(compared > 50 && beyond > 0, "{compared} {beyond}");
    assert!(touching >= 1, "no vertex at contact");
}
