//! Tests of what the report draws of the environment, the contacts, the findings and
//! the 3D view: positions read back from the SVG against positions computed here
//! independently (axis ticks, rotations), not by the drawing code.

use std::sync::Arc;

use nalgebra::{Point3, Rotation3, Vector3};
use strand_contact::ObstacleMesh;

use super::*;
use crate::result::{ClearanceResult, ContactResult};
use crate::study::tests::doc;

/// The box `[lo, hi]` (m) as a closed, outward-wound mesh named "box".
fn box_mesh(lo: [f64; 3], hi: [f64; 3]) -> ObstacleMesh {
    let v = |i: usize| {
        Point3::new(
            if i & 1 == 0 { lo[0] } else { hi[0] },
            if i & 2 == 0 { lo[1] } else { hi[1] },
            if i & 4 == 0 { lo[2] } else { hi[2] },
        )
    };
    let vertices: Vec<Point3<f64>> = (0..8).map(v).collect();
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let triangles: Vec<[u32; 3]> = quads
        .iter()
        .flat_map(|[a, b, c, d]| [[*a, *b, *c], [*a, *c, *d]])
        .collect();
    ObstacleMesh::try_from_triangles("box", vertices, &triangles).expect("a box")
}

/// Box below the rods of `doc(1)` (which run along x from 0 to 1 m at y = z = 0).
const BOX: ([f64; 3], [f64; 3]) = ([0.2, -0.05, -0.08], [0.5, 0.05, -0.02]);

/// `doc(1)` with the box's outline, a contact on "rod" at s = 0.25 m (pushed up by
/// 7.5 N) and a clearance of 0 to the box there.
fn with_box() -> ResultDoc {
    let mut d = doc(1.0);
    crate::collect_outlines(&mut d, &[Arc::new(box_mesh(BOX.0, BOX.1))]);
    d.contacts.push(ContactResult {
        rod: "rod".into(),
        s_m: 0.25,
        point_m: [0.25, 0.0, 0.0],
        normal: [0.0, 0.0, 1.0],
        force_n: 7.5,
        with: "box".into(),
    });
    d.clearance.push(ClearanceResult {
        rod: "rod".into(),
        with: "box".into(),
        distance_m: 0.0,
        s_m: 0.25,
    });
    d
}

fn render_one(d: &ResultDoc) -> String {
    report_html(
        "box",
        &[ReportRun {
            label: "base",
            doc: d,
        }],
    )
}

fn parse(html: &str) -> roxmltree::Document<'_> {
    roxmltree::Document::parse(html.strip_prefix("<!DOCTYPE html>\n").unwrap()).unwrap()
}

fn num(node: roxmltree::Node, attribute: &str) -> f64 {
    node.attribute(attribute).unwrap().parse().unwrap()
}

/// The linear map value → px of a projection's axis, fitted to its tick labels:
/// x ticks are `text-anchor="middle"` below the frame, y ticks `text-anchor="end"`.
fn tick_map(view: roxmltree::Node, anchor: &str) -> (f64, f64) {
    let ticks: Vec<(f64, f64)> = view
        .descendants()
        .filter(|n| n.has_tag_name("text") && n.attribute("text-anchor") == Some(anchor))
        .filter_map(|n| {
            let value: f64 = n.text()?.parse().ok()?;
            let px = if anchor == "middle" {
                num(n, "x")
            } else {
                num(n, "y") - 4.0
            };
            Some((value, px))
        })
        .collect();
    assert!(ticks.len() >= 2, "{ticks:?}");
    let (a, b) = (ticks[0], ticks[ticks.len() - 1]);
    let slope = (b.1 - a.1) / (b.0 - a.0);
    (a.1 - slope * a.0, slope)
}

/// The endpoints of the `M x y L x y` segments of path data `d`.
/// The 3D view's scene data (`#v3d-data`) of a parsed page.
fn scene_of(xml: &roxmltree::Document) -> serde_json::Value {
    let data = xml
        .descendants()
        .find(|n| n.attribute("id") == Some("v3d-data"))
        .unwrap();
    serde_json::from_str(data.text().unwrap()).unwrap()
}

fn path_points(d: &str) -> Vec<(f64, f64)> {
    let numbers: Vec<f64> = d
        .split(|c: char| c == 'M' || c == 'L' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().unwrap())
        .collect();
    numbers.chunks(2).map(|p| (p[0], p[1])).collect()
}

#[test]
fn box_corners_appear_where_the_axes_put_them_in_every_view() {
    let d = with_box();
    assert_eq!(d.environment.len(), 1);
    assert_eq!(d.environment[0].segments_m.len(), 12, "the box's 12 edges");
    let html = render_one(&d);
    let xml = parse(&html);
    for (view, axes) in [("side", [0, 2]), ("top", [0, 1]), ("front", [1, 2])] {
        let svg = xml
            .descendants()
            .find(|n| {
                n.attribute("class") == Some("projection") && n.attribute("data-view") == Some(view)
            })
            .unwrap();
        let (x0, sx) = tick_map(svg, "middle");
        let (y0, sy) = tick_map(svg, "end");
        let outline = svg
            .descendants()
            .find(|n| n.attribute("class") == Some("environment"))
            .expect("outline drawn");
        assert_eq!(outline.attribute("stroke"), Some("#b4b4b4"), "light grey");
        let points = path_points(outline.attribute("d").unwrap());
        assert_eq!(points.len(), 24);
        // Every corner of the box, in mm, where the ticks say.
        for i in 0..8 {
            let corner = [0, 1, 2].map(|k| 1e3 * if i >> k & 1 == 0 { BOX.0[k] } else { BOX.1[k] });
            let expected = (x0 + sx * corner[axes[0]], y0 + sy * corner[axes[1]]);
            assert!(
                points
                    .iter()
                    .any(|p| (p.0 - expected.0).abs() < 0.02 && (p.1 - expected.1).abs() < 0.02),
                "{view}: corner {corner:?} not at {expected:?}"
            );
        }
        // No outline point outside the box's projection.
        for p in &points {
            let value = ((p.0 - x0) / sx, (p.1 - y0) / sy);
            for (v, k) in [(value.0, axes[0]), (value.1, axes[1])] {
                assert!(
                    v > 1e3 * BOX.0[k] - 0.05 && v < 1e3 * BOX.1[k] + 0.05,
                    "{view}: {p:?}"
                );
            }
        }
        // The contact dot at its point, labelled with its force.
        let contact = svg
            .descendants()
            .find(|n| n.attribute("class") == Some("contact"))
            .expect("contact drawn");
        let dot = contact
            .descendants()
            .find(|n| n.has_tag_name("circle"))
            .unwrap();
        let point = [250.0, 0.0, 0.0];
        let at = (x0 + sx * point[axes[0]], y0 + sy * point[axes[1]]);
        assert!((num(dot, "cx") - at.0).abs() < 0.02 && (num(dot, "cy") - at.1).abs() < 0.02);
        assert_eq!(contact.attribute("data-force-n"), Some("7.5"));
        assert!(contact.descendants().any(|n| n.text() == Some("7.500 N")));
        // An arrow in the side and front views (normal +z in view); none from above.
        let arrow = contact.descendants().any(|n| n.has_tag_name("path"));
        assert_eq!(arrow, view != "top", "{view}");
    }
    assert!(!html.contains("TODO"));
    assert!(html.contains("Environment: outlines"));
}

#[test]
fn contacts_are_marked_on_the_hose_plot_at_their_arc_length_and_force() {
    let d = with_box();
    let html = render_one(&d);
    let xml = parse(&html);
    let plot = xml
        .descendants()
        .find(|n| {
            n.attribute("class") == Some("hose-plot") && n.attribute("data-rod") == Some("rod")
        })
        .unwrap();
    let marks: Vec<_> = plot
        .descendants()
        .filter(|n| n.attribute("class") == Some("contact"))
        .collect();
    assert_eq!(marks.len(), 1);
    let (x0, sx) = tick_map(plot, "middle");
    // The force panel is the first: its y ticks are the first "end" ticks.
    let line = marks[0]
        .descendants()
        .find(|n| n.has_tag_name("line"))
        .unwrap();
    assert!((num(line, "x1") - (x0 + sx * 250.0)).abs() < 0.02);
    assert_eq!(marks[0].attribute("data-s-mm"), Some("250"));
    assert_eq!(marks[0].attribute("data-force-n"), Some("7.5"));
    // The other hose has no contact and no mark.
    let other = xml
        .descendants()
        .find(|n| {
            n.attribute("class") == Some("hose-plot") && n.attribute("data-rod") == Some("other")
        })
        .unwrap();
    assert!(
        !other
            .descendants()
            .any(|n| n.attribute("class") == Some("contact"))
    );
}

/// The findings table's rows as (kind, hose, s [mm], value [mm], limit [mm]).
fn findings_rows(html: &str) -> Vec<(String, String, f64, f64, f64)> {
    let xml = parse(html);
    let Some(table) = xml
        .descendants()
        .find(|n| n.has_tag_name("table") && n.attribute("id") == Some("findings"))
    else {
        return Vec::new();
    };
    table
        .descendants()
        .filter(|n| n.has_tag_name("tr") && n.attribute("data-kind").is_some())
        .map(|row| {
            let cells: Vec<String> = row
                .children()
                .filter(|n| n.has_tag_name("td"))
                .map(|n| {
                    n.descendants()
                        .filter(|t| t.is_text())
                        .filter_map(|t| t.text())
                        .collect()
                })
                .collect();
            (
                row.attribute("data-kind").unwrap().to_string(),
                cells[2].clone(),
                cells[4].parse().unwrap(),
                cells[6].parse().unwrap(),
                cells[7].parse().unwrap(),
            )
        })
        .collect()
}

#[test]
fn findings_open_the_report_exactly_when_a_limit_is_violated() {
    let mut d = with_box();
    d.rods[0].curvature_1pm[1] = [3.0, 4.0, 0.0]; // bend radius 200 mm at s = 500 mm
    // No limits: no findings, and the page says none are stated.
    let html = render_one(&d);
    assert!(findings_rows(&html).is_empty());
    assert!(html.contains("id=\"no-findings\""));
    assert!(html.contains("the case states no limits"));
    // Loose limits: no findings.
    d.rods[0].min_bend_radius_m = Some(0.199);
    d.rods[0].min_clearance_m = Some(0.0);
    let html = render_one(&d);
    assert!(findings_rows(&html).is_empty());
    assert!(html.contains("every hose respects its limits"));
    // Tight ones: one row each, numbers in mm.
    d.rods[0].min_bend_radius_m = Some(0.201);
    d.rods[0].min_clearance_m = Some(0.005);
    let html = render_one(&d);
    assert!(!html.contains("id=\"no-findings\""));
    let rows = findings_rows(&html);
    assert_eq!(
        rows,
        vec![
            ("bend_radius".into(), "rod".into(), 500.0, 200.0, 201.0),
            ("clearance".into(), "rod".into(), 250.0, 0.0, 5.0),
        ]
    );
    // The findings come before everything else.
    let findings_at = html.find("id=\"findings-section\"").unwrap();
    let summary_at = html.find("<h2>Summary</h2>").unwrap();
    assert!(findings_at < summary_at);
}

#[test]
fn the_3d_view_draws_the_box_where_an_independent_rotation_puts_it() {
    let d = with_box();
    let html = render_one(&d);
    let xml = parse(&html);
    let scene = scene_of(&xml);
    let view = &scene["view"];
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    let (yaw, pitch, scale) = (f(&view["yaw"]), f(&view["pitch"]), f(&view["scale"]));
    let centre = Vector3::new(
        f(&view["centre"][0]),
        f(&view["centre"][1]),
        f(&view["centre"][2]),
    );
    let (w, h) = (f(&view["width"]), f(&view["height"]));
    // Screen right and up: the x and z axes turned by the pitch about x (tilting the
    // view down) and then by the yaw about z.
    let turn = Rotation3::from_axis_angle(&Vector3::z_axis(), yaw.to_radians())
        * Rotation3::from_axis_angle(&Vector3::x_axis(), -pitch.to_radians());
    let (right, up) = (turn * Vector3::x(), turn * Vector3::z());
    let screen = |p_mm: Vector3<f64>| {
        let q = p_mm - centre;
        (
            w / 2.0 + scale * right.dot(&q),
            h / 2.0 - scale * up.dot(&q),
        )
    };
    let env: Vec<_> = xml
        .descendants()
        .filter(|n| n.attribute("class") == Some("v3d-env"))
        .collect();
    assert_eq!(env.len(), 12);
    for i in 0..8 {
        let corner =
            Vector3::from_fn(|k, _| 1e3 * if i >> k & 1 == 0 { BOX.0[k] } else { BOX.1[k] });
        let (x, y) = screen(corner);
        assert!(
            env.iter().any(|n| {
                let ends = [
                    (num(*n, "x1"), num(*n, "y1")),
                    (num(*n, "x2"), num(*n, "y2")),
                ];
                ends.iter()
                    .any(|e| (e.0 - x).abs() < 0.02 && (e.1 - y).abs() < 0.02)
            }),
            "corner {corner:?} not at ({x}, {y})"
        );
    }
    // Hose edges: as wide as the tube (outer radius 10 mm), at their vertices.
    let edges: Vec<_> = xml
        .descendants()
        .filter(|n| {
            n.attribute("class") == Some("v3d-edge") && n.attribute("data-rod") == Some("rod")
        })
        .collect();
    assert_eq!(edges.len(), 2);
    for e in &edges {
        assert!((num(*e, "stroke-width") - 20.0 * scale).abs() < 0.01);
        let j: usize = e.attribute("data-j").unwrap().parse().unwrap();
        let (x, y) = screen(Vector3::new(500.0 * j as f64, 0.0, 0.0));
        assert!((num(*e, "x2") - x).abs() < 0.02 && (num(*e, "y2") - y).abs() < 0.02);
    }
    // The contact and the legend with its unit; the scene is inside the frame.
    assert_eq!(
        xml.descendants()
            .filter(|n| n.attribute("class") == Some("v3d-contact"))
            .count(),
        1
    );
    let title = xml
        .descendants()
        .find(|n| n.attribute("id") == Some("v3d-legend-title"))
        .unwrap();
    assert_eq!(title.text(), Some("|f| internal force [N]"));
    for n in env.iter().chain(&edges) {
        for (a, limit) in [("x1", w), ("y1", h), ("x2", w), ("y2", h)] {
            let v = num(*n, a);
            assert!((0.0..=limit).contains(&v), "{a} = {v}");
        }
    }
    // Colour quantities offered with their units.
    for option in [
        "|f| internal force [N]",
        "|m| internal moment [N·m]",
        "bend radius [mm]",
    ] {
        assert!(html.contains(option), "{option}");
    }
}

/// The view's script, run in Node.js against a minimal DOM, draws the same first frame
/// as strand did, and redraws for a preset without errors. Skipped (with a note) where
/// `node` is not installed.
#[test]
fn the_3d_script_redraws_the_first_frame_identically() {
    let Ok(version) = std::process::Command::new("node").arg("--version").output() else {
        eprintln!("node not found: the 3D script test is skipped");
        return;
    };
    assert!(version.status.success());
    let d = with_box();
    let html = render_one(&d);
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("report.html");
    std::fs::write(&page, &html).unwrap();
    let harness = dir.path().join("harness.js");
    std::fs::write(&harness, NODE_HARNESS).unwrap();
    let out = std::process::Command::new("node")
        .arg(&harness)
        .arg(&page)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "node failed:\n{stdout}\n{stderr}");
    assert!(stdout.contains("ok"), "{stdout}\n{stderr}");
}

/// Node.js harness: extracts the data and the script from the page, runs the script
/// against a minimal DOM (elements with attributes and children, events recorded),
/// and compares the lines it draws with the page's first frame.
const NODE_HARNESS: &str = r#"
const fs = require("fs");
const html = fs.readFileSync(process.argv[2], "utf8");
const data = html.match(/<script type="application\/json" id="v3d-data">([^<]*)<\/script>/)[1];
const script = html.match(/<script>\/\/<!\[CDATA\[\n([\s\S]*?)\/\/\]\]><\/script>/)[1];
function lines(cls) {
  const re = new RegExp('<line class="' + cls + '"[^>]*?x1="([-0-9.]+)" y1="([-0-9.]+)" x2="([-0-9.]+)" y2="([-0-9.]+)"', "g");
  const out = []; let m;
  while ((m = re.exec(html))) { out.push(m.slice(1).map(Number)); }
  return out;
}
class El {
  constructor(tag) { this.tag = tag; this.attrs = {}; this.children = []; this.listeners = {}; this.textContent = ""; }
  setAttribute(k, v) { this.attrs[k] = String(v); }
  getAttribute(k) { return k in this.attrs ? this.attrs[k] : null; }
  appendChild(c) { this.children.push(c); return c; }
  removeChild(c) { this.children.splice(this.children.indexOf(c), 1); }
  get firstChild() { return this.children[0] || null; }
  addEventListener(k, f) { this.listeners[k] = f; }
}
const byId = { "v3d-svg": new El("svg"), "v3d-scene": new El("g"), "v3d-readout": new El("span"),
  "v3d-legend-top": new El("text"), "v3d-legend-bottom": new El("text"), "v3d-legend-title": new El("text"),
  "v3d-quantity": new El("select"), "v3d-result": new El("select") };
byId["v3d-data"] = { textContent: data };
const iso = new El("button"); iso.setAttribute("data-yaw", "0"); iso.setAttribute("data-pitch", "90");
global.document = {
  getElementById: (id) => byId[id] || null,
  createElementNS: (ns, tag) => new El(tag),
  querySelectorAll: (selector) => (selector.startsWith("button") ? [iso] : []),
};
global.window = { addEventListener: () => {} };
eval(script);
const scene = byId["v3d-scene"].children;
function drawn(cls) {
  return scene.filter((n) => n.attrs["class"] === cls).map((n) => ["x1", "y1", "x2", "y2"].map((k) => Number(n.attrs[k])));
}
for (const cls of ["v3d-env", "v3d-edge", "v3d-part"]) {
  const a = lines(cls), b = drawn(cls);
  if (a.length !== b.length || (a.length === 0 && cls !== "v3d-part")) { throw new Error(cls + ": " + a.length + " vs " + b.length); }
  a.forEach((l, i) => l.forEach((v, k) => {
    if (Math.abs(v - b[i][k]) > 0.011) { throw new Error(cls + " " + i + ": " + l + " vs " + b[i]); }
  }));
}
const polys = [...html.matchAll(/<polygon class="v3d-surface"[^>]*? points="([^"]*)"/g)].map((m) => m[1]);
const drawnPolys = scene.filter((n) => n.attrs["class"] === "v3d-surface").map((n) => n.attrs.points);
if (polys.length !== drawnPolys.length || polys.length === 0) { throw new Error("surfaces: " + polys.length + " vs " + drawnPolys.length); }
polys.forEach((p, i) => {
  const a = p.split(/[ ,]/).map(Number), b = drawnPolys[i].split(/[ ,]/).map(Number);
  if (a.length !== b.length || a.some((v, k) => Math.abs(v - b[k]) > 0.011)) { throw new Error("surface " + i + ": " + p + " vs " + drawnPolys[i]); }
});
if (byId["v3d-svg"].attrs["data-interactive"] !== "true") { throw new Error("not interactive"); }
// A preset (top view) and the bend-radius quantity redraw without errors.
iso.listeners.click();
const top = drawn("v3d-edge");
if (top.some((l) => l.some((v) => !isFinite(v)))) { throw new Error("non-finite after preset"); }
byId["v3d-quantity"].value = "rb"; byId["v3d-quantity"].listeners.change();
if (!/bend radius/.test(byId["v3d-legend-title"].textContent)) { throw new Error("legend"); }
byId["v3d-quantity"].value = "c"; byId["v3d-quantity"].listeners.change();
if (!/clearance/.test(byId["v3d-legend-title"].textContent) || !/tight/.test(byId["v3d-legend-top"].textContent)) { throw new Error("clearance legend"); }
if (drawn("v3d-edge").some((l) => l.some((v) => !isFinite(v)))) { throw new Error("non-finite with clearance"); }
byId["v3d-svg"].listeners.mouseover({ target: scene.find((n) => n.attrs["class"] === "v3d-edge") });
if (!/s = .* mm, \|f\| = .* N.*, clearance = /.test(byId["v3d-readout"].textContent)) { throw new Error("readout: " + byId["v3d-readout"].textContent); }
byId["v3d-svg"].listeners.mouseover({ target: scene.find((n) => n.attrs["class"] === "v3d-contact") });
if (!/^contact of rod with box: 7\.500 N$/.test(byId["v3d-readout"].textContent)) { throw new Error("contact readout: " + byId["v3d-readout"].textContent); }
console.log("ok");
"#;

/// The 3D view's data: bend-radius utilisation (limit over radius) where a limit is
/// stated, the distance moved from the reference per vertex, and the box's surface
/// (its six faces inside the outline box) as polygons.
#[test]
fn the_3d_view_carries_utilisation_movement_and_surfaces() {
    let mut base = with_box();
    base.rods[0].curvature_1pm[1] = [3.0, 4.0, 0.0]; // bend radius 200 mm
    base.rods[0].min_bend_radius_m = Some(0.1);
    let mut moved = base.clone();
    moved.rods[0].position_m[2][2] += 0.003; // 3 mm up at the end
    let html = report_html(
        "box",
        &[
            ReportRun {
                label: "base",
                doc: &base,
            },
            ReportRun {
                label: "moved",
                doc: &moved,
            },
        ],
    );
    let xml = parse(&html);
    let scene = scene_of(&xml);
    let rod = &scene["runs"][1]["rods"][0];
    assert_eq!(rod["u"][1].as_f64(), Some(0.5));
    assert!(rod["u"][0].as_f64() == Some(0.0), "straight: 0");
    assert!(
        scene["runs"][0]["rods"][1]["u"][0].is_null(),
        "no limit: null"
    );
    let d: Vec<f64> = rod["d"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(d, [0.0, 0.0, 3.0]);
    // The box lies inside the outline region: its 12 triangles, unclipped.
    let polygons = scene["env"][0]["poly"].as_array().unwrap();
    assert_eq!(polygons.len(), 12);
    assert!(polygons.iter().all(|p| p.as_array().unwrap().len() == 3));
    // One overlay toggle per result, the reference's on.
    let toggles: Vec<_> = xml
        .descendants()
        .filter(|n| n.attribute("class") == Some("v3d-toggle"))
        .collect();
    assert_eq!(toggles.len(), 2);
    assert_eq!(toggles[0].attribute("checked"), Some("checked"));
    assert_eq!(toggles[1].attribute("checked"), None);
    assert_eq!(toggles[1].attribute("data-run"), Some("1"));
}

/// The per-vertex clearance reaches the 3D view's data in mm (`null` beyond the
/// search) with its colour range from 0 to the widest value, and the search distance
/// for the readout.
#[test]
fn the_3d_view_carries_the_clearance_per_vertex() {
    let mut d = with_box();
    d.rods[0].clearance_m = vec![Some(0.002), None, Some(0.0105)];
    d.rods[0].min_clearance_m = Some(0.15);
    let html = render_one(&d);
    let xml = parse(&html);
    let scene = scene_of(&xml);
    let c = &scene["runs"][0]["rods"][0]["c"];
    assert_eq!(c[0].as_f64(), Some(2.0));
    assert!(c[1].is_null());
    assert_eq!(c[2].as_f64(), Some(10.5));
    assert_eq!(scene["ranges"]["c"][0].as_f64(), Some(0.0));
    assert_eq!(scene["ranges"]["c"][1].as_f64(), Some(10.5));
    // Searched 1 % beyond the required 150 mm.
    assert_eq!(scene["clearanceSearch"].as_f64(), Some(151.501));
    assert!(html.contains("<option value=\"c\">clearance to the environment [mm]</option>"));
}
