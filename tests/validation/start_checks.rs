//! What a starting configuration may be (issue 10), through `strand check` and
//! `strand solve`, which must agree:
//! - a hose clamped shorter than its length and started straight (compressed edges)
//!   is accepted: nothing overlaps; its neighbours along the hose are excluded from
//!   self-contact by the current centreline length between them;
//! - a hose whose route crosses over itself 10 mm apart (less than its diameter) is
//!   rejected, naming where;
//! - a hose inside a closed box is rejected as starting inside it; inside an open box
//!   (no lid) it is accepted: an open mesh has no inside;
//! - the hint of a rejected start fits what the user gave: move the route, or (no
//!   route: the start was the solver's guess) give one.

use strand_cli::Exit;

use crate::common::strand;

/// The corners and outward quads of the box `[0, 400] × [-100, 100] × [-100, 100]` mm,
/// as OBJ text; `lid` includes the top face z = 100.
fn box_obj(lid: bool) -> String {
    box_along_x(lid, -50, 450)
}

/// [`box_obj`] spanning `x0..x1` mm along x.
fn box_along_x(lid: bool, x0: i32, x1: i32) -> String {
    let mut text = String::new();
    for k in 0..8 {
        let x = if k & 1 == 0 { x0 } else { x1 };
        let y = if k & 2 == 0 { -100 } else { 100 };
        let z = if k & 4 == 0 { -100 } else { 100 };
        text.push_str(&format!("v {x} {y} {z}\n"));
    }
    let mut faces = vec!["1 3 4 2", "1 2 6 5", "3 7 8 4", "1 5 7 3", "2 4 8 6"];
    if lid {
        faces.push("5 6 8 7");
    }
    for f in faces {
        text.push_str(&format!("f {f}\n"));
    }
    text
}

/// [`case_text`]: a 400 mm hose of 20 edges routed straight from the origin to its end
/// clamp at (400, 0, 0) mm, inside the box of [`box_obj`] (x −50..450 mm).
fn straight_400mm_hose() -> String {
    case_text(
        400.0,
        20,
        "(400, 0, 0)",
        "(1, 0, 0)",
        "[(0, 0, 0), (400, 0, 0)]",
    )
}

/// A case with one hose (radius 12.9 mm) clamped at `(0, 0, 0)` along +x and at
/// `end` (mm) along `end_tangent`, `length` mm in `segments` edges, routed along
/// `route`, with the environment mesh `obj` (OBJ text, mm).
fn case_text(length: f64, segments: usize, end: &str, end_tangent: &str, route: &str) -> String {
    format!(
        r#"(
            units: (length: "mm"),
            sections: {{ "s": Explicit(ea: 1e5, ga: 5e4, ei: 0.5, gj: 0.4, mass_per_length: 0.1,
                                      outer_radius: 12.9) }},
            rods: [(name: "hose", section: "s", length: {length}, segments: {segments},
                    start: Clamp(position: (0, 0, 0), tangent: (1, 0, 0), normal: (0, 0, 1)),
                    end: Clamp(position: {end}, tangent: {end_tangent}, normal: (0, 0, 1)),
                    route: Some({route}))],
            gravity: (0, 0, 0),
            environment: [(name: "part", obj: "part.obj", unit: "mm")],
        )"#
    )
}

/// Runs `strand check` and `strand solve` on the case; returns both results.
fn check_and_solve(case: &str, obj: &str) -> [(Exit, String, String); 2] {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("part.obj"), obj).unwrap();
    let path = tmp.path().join("case.ron");
    std::fs::write(&path, case).unwrap();
    let path = path.to_str().unwrap();
    let out = tmp.path().join("out");
    [
        strand(&["check", path]),
        strand(&["solve", path, "--out", out.to_str().unwrap()]),
    ]
}

/// Both commands reject the case with a message containing `needle`; returns the
/// message's `s = … mm`.
fn rejected(results: &[(Exit, String, String); 2], needle: &str) -> f64 {
    let mut at = Vec::new();
    for (exit, stdout, stderr) in results {
        assert_eq!(*exit, Exit::InvalidInput, "{stdout}{stderr}");
        assert!(stderr.contains(needle), "{stderr}");
        let s = stderr.split("s = ").nth(1).expect("an arc length");
        at.push(s.split(" mm").next().unwrap().parse::<f64>().unwrap());
    }
    assert_eq!(at[0], at[1], "check and solve name the same place");
    at[0]
}

/// A floor 300 mm below, far from the hose (the environment that turns contact on).
const FAR_FLOOR: &str =
    "v -1000 -1000 -300\nv 1000 -1000 -300\nv 1000 1000 -300\nv -1000 1000 -300\nf 1 2 3 4\n";

#[test]
fn a_compressed_straight_start_is_accepted_by_check_and_solve() {
    // 500 mm of hose between clamps 250 mm apart, started straight: edges at half
    // their length. Neighbours 40.5 mm (π r) apart along the reference length are only
    // 20.3 mm apart now (less than the 25.8 mm diameter) but are the same piece of
    // hose, not an overlap.
    let text = case_text(
        500.0,
        100,
        "(250, 0, 0)",
        "(1, 0, 0)",
        "[(0, 0, 0), (250, 0, 0)]",
    );
    let [check, solve] = check_and_solve(&text, FAR_FLOOR);
    assert_eq!(check.0, Exit::Success, "{}{}", check.1, check.2);
    assert!(check.1.starts_with("ok: "), "{}", check.1);
    assert_ne!(solve.0, Exit::InvalidInput, "{}{}", solve.1, solve.2);
    assert!(!solve.2.contains("starts inside"), "{}", solve.2);
}

#[test]
fn a_hose_crossing_over_itself_is_rejected_by_check_and_solve_with_the_place() {
    // Along x to (200, 0), round to (100, 100) and back across its start at x = 100,
    // 10 mm higher: the two pieces overlap by 2·12.9 − 10 = 15.8 mm near s = 100 mm.
    let route = "[(0, 0, 0), (200, 0, 0), (200, 100, 5), (100, 100, 10), (100, -100, 10), \
                 (300, -100, 10)]";
    let text = case_text(800.0, 160, "(300, -100, 10)", "(1, 0, 0)", route);
    let results = check_and_solve(&text, FAR_FLOOR);
    let s = rejected(&results, "rod 'hose' starts inside rod 'hose'");
    assert!(
        (s - 100.0).abs() <= 15.0,
        "the crossing is near s = 100 mm, not {s}"
    );
    let depth: f64 = results[0]
        .2
        .split("overlaps it by ")
        .nth(1)
        .and_then(|t| t.split(" mm").next())
        .unwrap()
        .parse()
        .unwrap();
    assert!((depth - 15.8).abs() <= 1.0, "overlap {depth} mm");
    // The start is the user's route: the hint says to move it.
    for (_, _, stderr) in &results {
        assert!(stderr.contains("hint: move the rod's `route`"), "{stderr}");
    }
}

#[test]
fn a_hose_without_a_route_that_no_guess_clears_is_told_to_give_one() {
    // A closed box across the taut hose's middle (x 100..300 mm, 200 mm square), its
    // clamps outside: every start the solver can guess (hanging, bowed, arched,
    // straight: all straight for a hose as long as its clamps are apart) passes through
    // it, and no way around it fits in 400 mm (over it, clear by the radius, at least
    // `2·√(80² + 112.9²) + 200 + 2·20` = 517 mm with the 20 mm edges along the clamps).
    // The user gave no route, so the hint asks for one rather than to move it, and says
    // how long the way around is.
    let text = straight_400mm_hose();
    let unrouted = text.replace("route: Some([(0, 0, 0), (400, 0, 0)])", "route: None");
    assert_ne!(unrouted, text, "the route was not found");
    let results = check_and_solve(&unrouted, &box_along_x(true, 100, 300));
    for (exit, stdout, stderr) in &results {
        assert_eq!(*exit, Exit::InvalidInput, "{stdout}{stderr}");
        assert!(
            stderr.contains("through an obstacle (touches mesh 'part')"),
            "{stderr}"
        );
        assert!(
            stderr.contains("hint: the rod has no `route`")
                && stderr.contains("give the rod a `route`"),
            "{stderr}"
        );
        assert!(!stderr.contains("move the rod's `route`"), "{stderr}");
        let way: f64 = stderr
            .split("the shortest way around the parts the solver finds is about ")
            .nth(1)
            .and_then(|rest| rest.split(" mm").next())
            .and_then(|mm| mm.parse().ok())
            .unwrap_or_else(|| panic!("no way's length in {stderr}"));
        let around = 2.0 * (80f64.powi(2) + 112.9f64.powi(2)).sqrt() + 240.0;
        assert!(around <= way && way <= 1.2 * around, "{way} mm: {stderr}");
        assert!(
            stderr.contains("between s = 0 mm and s = 400 mm"),
            "{stderr}"
        );
    }
    // The box around the clamps: no route can help, the hint says to move the support.
    let results = check_and_solve(&unrouted, &box_obj(true));
    rejected(&results, "rod 'hose' starts inside mesh 'part'");
    for (_, _, stderr) in &results {
        assert!(
            stderr.contains("move its connector, pin, clamp or port"),
            "{stderr}"
        );
        assert!(!stderr.contains("give the rod a `route`"), "{stderr}");
    }
}

#[test]
fn a_hose_inside_a_closed_box_is_rejected_and_inside_an_open_box_accepted() {
    let text = straight_400mm_hose();
    let closed = check_and_solve(&text, &box_obj(true));
    let s = rejected(&closed, "rod 'hose' starts inside mesh 'part'");
    assert_eq!(s, 0.0, "the first vertex is inside");
    assert!(
        closed[0].2.contains("point (0.0, 0.0, 0.0) mm"),
        "{}",
        closed[0].2
    );
    let [check, solve] = check_and_solve(&text, &box_obj(false));
    assert_eq!(check.0, Exit::Success, "{}{}", check.1, check.2);
    assert_eq!(solve.0, Exit::Success, "{}{}", solve.1, solve.2);
}

/// Two 1 m squares side by side (mm), each with its own corners (the two on the shared
/// edge duplicated), a face repeating a vertex and a collinear face (both zero area),
/// and a sliver along the first square's bottom edge (2·area / longest² = 1e-7).
const DEFECTIVE: &str = "\
v 0 0 -300\nv 1000 0 -300\nv 1000 1000 -300\nv 0 1000 -300\n\
v 1000 0 -300\nv 2000 0 -300\nv 2000 1000 -300\nv 1000 1000 -300\n\
v 500 -0.0001 -300\nv 1500 0 -300\n\
f 1 2 3\nf 1 3 4\nf 5 6 7\nf 5 7 8\n\
f 1 2 2\nf 5 10 6\n\
f 2 1 9\n";

#[test]
fn mesh_diagnostics_are_in_result_json_and_in_the_terminal() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("part.obj"), DEFECTIVE).unwrap();
    let path = tmp.path().join("case.ron");
    let text = straight_400mm_hose();
    std::fs::write(&path, text).unwrap();
    let out = tmp.path().join("out");
    let (exit, stdout, stderr) = strand(&[
        "solve",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(exit, Exit::Success, "{stdout}{stderr}");
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let d = &doc["environment"][0]["diagnostics"];
    assert_eq!(doc["environment"][0]["name"], "part");
    // 7 faces: 2 of zero area skipped; the sliver kept. 10 vertices, 2 of them at the
    // position of another. Welded, the two squares form a 2 × 1 m rectangle with 6 rim
    // edges; the sliver closes the first square's bottom edge (traversing it the
    // other way) and opens two of its own: 7 boundary edges, none non-manifold.
    let count = |key: &str| d[key].as_u64().unwrap();
    assert_eq!(
        [
            "triangles",
            "degenerate_skipped",
            "slivers",
            "vertices",
            "duplicate_vertices",
            "boundary_edges",
            "non_manifold_edges",
            "misoriented_edges",
        ]
        .map(count),
        [5, 2, 1, 10, 2, 7, 0, 0],
        "{d}"
    );
    assert_eq!(d["closed"], false);
    assert_eq!(d["duplicate_vertices_welded"], true);
    let size: Vec<f64> = serde_json::from_value(d["size_m"].clone()).unwrap();
    assert!((size[0] - 2.0).abs() < 1e-12 && (size[1] - 1.000_000_1).abs() < 1e-12);
    // The terminal shows the same counts and the box in the case's unit.
    assert!(
        stdout.contains(
            "part  5 triangles (2 degenerate skipped, 1 slivers), 10 vertices (2 duplicates), \
             0 non-manifold edges, open (7 boundary edges): no inside"
        ),
        "{stdout}"
    );
    assert!(stdout.contains("size 2000 x 1000 x 0 mm"), "{stdout}");
    // `check` shows them too.
    let (exit, stdout, _) = strand(&["check", path.to_str().unwrap()]);
    assert_eq!(exit, Exit::Success);
    assert!(
        stdout.contains("part  5 triangles (2 degenerate skipped, 1 slivers)"),
        "{stdout}"
    );
}
