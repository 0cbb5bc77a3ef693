//! `--export-unit mm|m` (issue 12, "exports that fit CAD"): the real binary's
//! `tubes.obj`, `tubes.stl` and `rods.vtp` are in the chosen unit, and in mm they line
//! up with the environment's own files: hose 3 of `cases/cooler_hose_contact.ron` rests
//! on the top face of `hose3_support` (z = −77 in `assets/engine_bay/brackets.obj`,
//! mm), so its tube surface, read from the export with no rescaling, touches that face
//! and never goes through it.

mod common;

use std::path::Path;

use common::{case, read_json, strand};

/// Outer radius of hose 3, mm (cases/cooler_hose_contact.ron: ro = 18.4 mm).
const HOSE3_OUTER_RADIUS_MM: f64 = 18.4;
/// Vertices around a tube ring (strand_report::TUBE_SIDES).
const SIDES: f64 = 16.0;

/// The vertices of each object (`o name`) of an OBJ file.
fn obj_objects(text: &str) -> Vec<(String, Vec<[f64; 3]>)> {
    let mut out: Vec<(String, Vec<[f64; 3]>)> = Vec::new();
    for line in text.lines() {
        if let Some(name) = line.strip_prefix("o ") {
            out.push((name.trim().to_string(), Vec::new()));
        } else if let Some(rest) = line.strip_prefix("v ") {
            let v: Vec<f64> = rest
                .split_whitespace()
                .map(|t| t.parse().unwrap())
                .collect();
            out.last_mut().unwrap().1.push([v[0], v[1], v[2]]);
        }
    }
    out
}

fn object<'a>(objects: &'a [(String, Vec<[f64; 3]>)], name: &str) -> &'a [[f64; 3]] {
    &objects.iter().find(|(n, _)| n == name).unwrap().1
}

/// The top face of `hose3_support` as the environment file states it: (z, x range,
/// y range), mm.
fn support_top() -> (f64, [f64; 2], [f64; 2]) {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/engine_bay/brackets.obj"),
    )
    .unwrap();
    let objects = obj_objects(&text);
    let support = object(&objects, "hose3_support");
    let range = |i: usize| {
        support
            .iter()
            .fold([f64::INFINITY, f64::NEG_INFINITY], |[a, b], p| {
                [a.min(p[i]), b.max(p[i])]
            })
    };
    (range(2)[1], range(0), range(1))
}

/// The triangle corners of a binary STL and its header.
fn stl_corners(bytes: &[u8]) -> (String, Vec<[f64; 3]>) {
    let header = String::from_utf8_lossy(&bytes[..80])
        .trim_end_matches('\0')
        .to_string();
    let count = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
    assert_eq!(bytes.len(), 84 + 50 * count);
    let f = |at: usize| f64::from(f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()));
    let corners = (0..count)
        .flat_map(|t| (1..4).map(move |c| 84 + 50 * t + 12 * c))
        .map(|at| [f(at), f(at + 4), f(at + 8)])
        .collect();
    (header, corners)
}

fn solve(dir: &Path, unit: Option<&str>) {
    let case = case("cooler_hose_contact.ron");
    let mut args = vec!["solve", case.as_str(), "--out", dir.to_str().unwrap()];
    if let Some(unit) = unit {
        args.extend(["--export-unit", unit]);
    }
    let (exit, _, err) = strand(&args);
    assert_eq!(exit, Some(0), "{err}");
}

#[test]
fn tube_exports_in_mm_rest_on_the_environment_file_and_m_is_a_thousandth() {
    let tmp = tempfile::tempdir().unwrap();
    let (top, xs, ys) = support_top();
    assert_eq!(top, -77.0, "brackets.obj changed");
    // Deepest point a ring of SIDES vertices at the radius can leave uncovered.
    let facet = HOSE3_OUTER_RADIUS_MM * (1.0 - (std::f64::consts::PI / SIDES).cos());
    let mut hose3_mm: Option<Vec<[f64; 3]>> = None;
    for (unit, mm_per_unit) in [(None, 1.0), (Some("mm"), 1.0), (Some("m"), 1000.0)] {
        let dir = tmp.path().join(unit.unwrap_or("default"));
        solve(&dir, unit);
        let symbol = unit.unwrap_or("mm");
        let obj = std::fs::read_to_string(dir.join("tubes.obj")).unwrap();
        assert!(
            obj.lines()
                .next()
                .unwrap()
                .contains(&format!(", {symbol};")),
            "{}",
            obj.lines().next().unwrap()
        );
        let objects = obj_objects(&obj);
        let hose3: Vec<[f64; 3]> = object(&objects, "hose3")
            .iter()
            .map(|p| p.map(|x| x * mm_per_unit))
            .collect();
        // Above the support's footprint the tube touches its top face and does not
        // pass through it.
        let over: Vec<f64> = hose3
            .iter()
            .filter(|p| (xs[0]..=xs[1]).contains(&p[0]) && (ys[0]..=ys[1]).contains(&p[1]))
            .map(|p| p[2] - top)
            .collect();
        assert!(
            !over.is_empty(),
            "{unit:?}: no tube vertex over the support"
        );
        let lowest = over.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(
            (-1e-5..=facet + 1e-5).contains(&lowest),
            "{unit:?}: lowest tube vertex {lowest} mm from the support's top (facet depth {facet} mm)"
        );
        match &hose3_mm {
            None => hose3_mm = Some(hose3.clone()),
            Some(reference) => {
                assert_eq!(reference.len(), hose3.len());
                for (a, b) in reference.iter().zip(&hose3) {
                    for i in 0..3 {
                        assert!(
                            (a[i] - b[i]).abs() <= 1e-9 * a[i].abs().max(1.0),
                            "{a:?} {b:?}"
                        );
                    }
                }
            }
        }
        // The STL (no unit field: the header says it) sits on the same face.
        let (header, corners) = stl_corners(&std::fs::read(dir.join("tubes.stl")).unwrap());
        assert!(header.contains(&format!("unit {symbol}")), "{header}");
        let lowest = corners
            .iter()
            .map(|p| p.map(|x| x * mm_per_unit))
            .filter(|p| (xs[0]..=xs[1]).contains(&p[0]) && (ys[0]..=ys[1]).contains(&p[1]))
            .map(|p| p[2] - top)
            .fold(f64::INFINITY, f64::min);
        assert!(
            (-1e-3..=facet + 1e-3).contains(&lowest),
            "{unit:?}: STL {lowest}"
        );
        // The VTP's points are the centreline of result.json (m) in the unit.
        let doc = read_json(&dir.join("result.json"));
        let first_m: Vec<f64> = doc["rods"][0]["position_m"][0]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let vtp = std::fs::read_to_string(dir.join("rods.vtp")).unwrap();
        let xml = roxmltree::Document::parse(&vtp).unwrap();
        let points = xml
            .descendants()
            .find(|n| n.attribute("Name") == Some(format!("position_{symbol}").as_str()))
            .unwrap_or_else(|| panic!("{unit:?}: no position_{symbol} array"));
        let first: Vec<f64> = points
            .text()
            .unwrap()
            .split_whitespace()
            .take(3)
            .map(|t| t.parse().unwrap())
            .collect();
        for i in 0..3 {
            let expected = first_m[i] * 1000.0 / mm_per_unit;
            assert!((first[i] - expected).abs() <= 1e-9 * expected.abs().max(1.0));
        }
    }
}

#[test]
fn study_and_batch_take_the_export_unit() {
    let tmp = tempfile::tempdir().unwrap();
    let case = case("cooler_hose.ron");
    let study = tmp.path().join("study");
    let (exit, _, err) = strand(&[
        "study",
        &case,
        "--variants",
        "base",
        "--out",
        study.to_str().unwrap(),
        "--export-unit",
        "m",
    ]);
    assert_eq!(exit, Some(0), "{err}");
    let batch = tmp.path().join("batch");
    let (exit, _, err) = strand(&[
        "batch",
        &case,
        "--vary",
        "hose2.length=+0mm,+10mm",
        "--out",
        batch.to_str().unwrap(),
        "--jobs",
        "1",
        "--keep",
        "all",
        "--export-unit",
        "m",
    ]);
    assert_eq!(exit, Some(0), "{err}");
    let mut dirs = vec![study.join("base")];
    for entry in std::fs::read_dir(batch.join("variants")).unwrap() {
        dirs.push(entry.unwrap().path());
    }
    assert_eq!(dirs.len(), 3, "{dirs:?}");
    for dir in dirs {
        let obj = std::fs::read_to_string(dir.join("tubes.obj")).unwrap();
        assert!(obj.lines().next().unwrap().contains(", m;"), "{dir:?}");
        // The hoses span about 0.5 m: in metres no coordinate reaches 1.
        let largest = obj_objects(&obj)
            .iter()
            .flat_map(|(_, v)| v.iter().flatten().copied())
            .fold(0.0f64, |a, x| a.max(x.abs()));
        assert!(largest > 0.05 && largest < 1.0, "{dir:?}: {largest}");
    }
    // Bad values are input errors (exit 2) naming the choices.
    let (exit, _, err) = strand(&["solve", &case, "--export-unit", "inch"]);
    assert_eq!(exit, Some(2));
    assert!(err.contains("mm") && err.contains("inch"), "{err}");
}
