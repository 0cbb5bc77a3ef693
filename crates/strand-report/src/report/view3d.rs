//! The report's 3D view: an inline SVG with an orthographic projection of the hoses
//! (each edge a line as wide as the tube's outer diameter, coloured by a chosen
//! quantity: `|f|` in N, `|m|` in N·m or the bend radius in mm), the environment
//! surfaces near the hoses (grey, shaded by a head light, half transparent) and
//! outlines (light grey), the fittings (junction bodies, connectors and clips as grey
//! cylinders and balls of their size, [`crate::fittings`]) and the contacts (dots
//! with the force direction), sorted far to near (painter's algorithm).
//!
//! Self-contained: the scene data is an inline JSON block (`#v3d-data`, mm) and a
//! few lines of inline JavaScript (`view3d.js`, no libraries, no network) turn the
//! view on drag, pan on shift-drag, zoom on the wheel, switch the quantity and the
//! result, offer preset views and show a readout of the hovered edge (hose, s, `|f|`,
//! `|m|`, bend radius). The first frame (the isometric preset, `|f|`, the reference
//! result) is drawn here with the same formulas, so the page shows it without
//! scripts and prints it; the 2D projections remain below.
//!
//! Why SVG and not WebGL: a few thousand lines per frame are redrawn fast enough,
//! the output stays text (parsed by the tests, printable, searchable), needs no
//! bundled library and works where WebGL is disabled.

use std::fmt::Write;

use serde::Serialize;

use super::ReportRun;
use super::format::sig;
use crate::findings::bend_radii;
use crate::fittings::FittingPiece;
use crate::plot::{
    CONTACT_COLOUR, Figure, VIRIDIS, close_figure, colour_bar, escape, open_figure, viridis,
};
use crate::study::magnitude;

/// Width and height of the view, px.
pub(crate) const WIDTH: f64 = 900.0;
/// Height of the view, px.
pub(crate) const HEIGHT: f64 = 620.0;
/// Right edge of the drawing area (the legend is to its right), px.
const DRAW_WIDTH: f64 = 780.0;

/// The preset views: name, yaw and pitch in degrees (see [`Axes::new`]).
pub(crate) const PRESETS: [(&str, f64, f64); 4] = [
    ("isometric", -35.0, 30.0),
    ("side (x–z)", 0.0, 0.0),
    ("top (x–y)", 0.0, 90.0),
    ("front (y–z)", 90.0, 0.0),
];

/// The colour quantities: key in the data, label, unit.
const QUANTITIES: [(&str, &str, &str); 6] = [
    ("f", "|f| internal force", "N"),
    ("m", "|m| internal moment", "N·m"),
    ("rb", "bend radius", "mm"),
    (
        "u",
        "bend-radius utilisation (min_bend_radius / bend radius)",
        "1",
    ),
    ("d", "moved from the reference", "mm"),
    ("c", "clearance to the environment", "mm"),
];

/// Screen axes of a view: right `u`, up `v` and depth `d` (into the screen), world
/// frame. Yaw `a` turns the view about the world z axis, pitch `e` tilts it to look
/// down: `u = (cos a, sin a, 0)`, `w = (−sin a, cos a, 0)`, `v = sin e · w + cos e · z`,
/// `d = cos e · w − sin e · z`. Yaw 0, pitch 0 is the side view (x right, z up, along
/// +y); pitch 90° the top view (x right, y up).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Axes {
    pub(crate) u: [f64; 3],
    pub(crate) v: [f64; 3],
    pub(crate) d: [f64; 3],
}

impl Axes {
    /// The axes at `yaw` and `pitch`, degrees.
    pub(crate) fn new(yaw: f64, pitch: f64) -> Self {
        let (a, e) = (yaw.to_radians(), pitch.to_radians());
        let w = [-a.sin(), a.cos(), 0.0];
        Axes {
            u: [a.cos(), a.sin(), 0.0],
            v: [e.sin() * w[0], e.sin() * w[1], e.cos()],
            d: [e.cos() * w[0], e.cos() * w[1], -e.sin()],
        }
    }
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `v` in mm rounded to 1 µm (the data's precision).
fn mm(v: f64) -> f64 {
    (v * 1e6).round() / 1e3
}

fn mm3(p: &[f64; 3]) -> [f64; 3] {
    p.map(mm)
}

/// One hose of one result, mm.
#[derive(Serialize)]
struct Rod {
    name: String,
    /// Outer radius, mm (0 when unknown: drawn 2 px wide).
    r: f64,
    /// Vertex positions, mm.
    p: Vec<[f64; 3]>,
    /// Arc length from the start, mm.
    s: Vec<f64>,
    /// `|f|`, N.
    f: Vec<f64>,
    /// `|m|`, N·m.
    m: Vec<f64>,
    /// Bend radius, mm (`null` where straight).
    rb: Vec<Option<f64>>,
    /// Distance of each vertex from the same vertex of the same hose in the reference
    /// result, mm (`null` where the reference has no such hose or another number of
    /// vertices).
    d: Vec<Option<f64>>,
    /// Bend-radius utilisation: the allowed minimum bend radius over the bend radius
    /// (1 at the limit, above 1 violated, 0 where straight); `null` without a limit.
    u: Vec<Option<f64>>,
    /// Clearance of the tube at each vertex to the nearest environment mesh, mm
    /// (`null` beyond the search, or without an environment).
    c: Vec<Option<f64>>,
}

/// `|a − b|`, mm, of two positions in m (rounded as the data).
fn distance_mm(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    mm(((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt())
}

/// The per-vertex distance of `rod` from the hose of the same name in `reference`.
fn moved(rod: &crate::result::RodResult, reference: Option<&ReportRun>) -> Vec<Option<f64>> {
    let other = reference.and_then(|r| {
        r.doc
            .rods
            .iter()
            .find(|o| o.name == rod.name && o.position_m.len() == rod.position_m.len())
    });
    match other {
        Some(o) => rod
            .position_m
            .iter()
            .zip(&o.position_m)
            .map(|(a, b)| Some(distance_mm(a, b)).filter(|d| d.is_finite()))
            .collect(),
        None => vec![None; rod.position_m.len()],
    }
}

/// One contact, mm and N.
#[derive(Serialize)]
struct ContactPoint {
    rod: String,
    p: [f64; 3],
    /// The unit normal (force direction on the hose) scaled to 1 mm.
    n: [f64; 3],
    f: f64,
    /// The obstacle (mesh or other hose).
    with: String,
}

/// One solid piece of a fitting (junction body, connector, clip; see
/// [`crate::fittings`]) drawn as a line as wide as the piece (a ball: a dot), mm.
#[derive(Serialize)]
struct Part {
    /// `"junction"`, `"connector"` or `"clip"`.
    kind: &'static str,
    name: String,
    a: [f64; 3],
    b: [f64; 3],
    /// Diameter, mm.
    w: f64,
}

/// The outline colour of result `k` when overlaid: black for the reference, then the
/// line palette (skipping its black).
fn overlay_colour(k: usize) -> &'static str {
    OVERLAY_COLOURS[k % OVERLAY_COLOURS.len()]
}

/// Outline colours of overlaid results ([`overlay_colour`]).
const OVERLAY_COLOURS: [&str; 7] = [
    "#000000",
    crate::plot::LINE_COLOURS[0],
    crate::plot::LINE_COLOURS[1],
    crate::plot::LINE_COLOURS[2],
    crate::plot::LINE_COLOURS[3],
    crate::plot::LINE_COLOURS[4],
    crate::plot::LINE_COLOURS[5],
];

/// Fill colour of each kind of fitting.
const PART_COLOURS: [(&str, &str); 3] = [
    ("junction", "#6e6e6e"),
    ("connector", "#3a3a3a"),
    ("clip", "#111111"),
];

fn part_colour(kind: &str) -> &'static str {
    PART_COLOURS
        .iter()
        .find(|(k, _)| *k == kind)
        .map_or("#000000", |(_, c)| c)
}

fn parts(doc: &crate::result::ResultDoc) -> Vec<Part> {
    let mut out = Vec::new();
    for fitting in crate::fittings::fittings(doc) {
        for piece in fitting.pieces {
            let (a, b, r) = match piece {
                FittingPiece::Cylinder {
                    start_m,
                    end_m,
                    radius_m,
                } => (start_m, end_m, radius_m),
                FittingPiece::Ball { centre_m, radius_m } => (centre_m, centre_m, radius_m),
            };
            out.push(Part {
                kind: fitting.kind.as_str(),
                name: fitting.name.clone(),
                a: mm3(&a),
                b: mm3(&b),
                w: mm(2.0 * r),
            });
        }
    }
    out
}

#[derive(Serialize)]
struct Run {
    label: String,
    rods: Vec<Rod>,
    contacts: Vec<ContactPoint>,
    parts: Vec<Part>,
    /// The meshes this result outlines elsewhere than the scene's `env` (a part that
    /// moved: the poses of a motion), drawn instead of those.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    env: Vec<Mesh>,
}

#[derive(Serialize)]
struct Mesh {
    name: String,
    /// Segments `[x0, y0, z0, x1, y1, z1]`, mm.
    seg: Vec<[f64; 6]>,
    /// Surface polygons near the hoses, corners in mm (drawn shaded).
    poly: Vec<Vec<[f64; 3]>>,
}

/// Opacity of the shaded environment (the hoses behind a part stay visible).
const SURFACE_OPACITY: f64 = 0.22;

/// The shade of a surface polygon seen along the view direction `d`: the grey of
/// `|n · d|` (head light, both sides lit), `n` its unit normal by Newell's method;
/// `None` for a polygon without area. The script computes it the same way.
fn shade(poly: &[[f64; 3]], d: &[f64; 3]) -> Option<String> {
    let mut n = [0.0; 3];
    for (i, a) in poly.iter().enumerate() {
        let b = &poly[(i + 1) % poly.len()];
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    let length = dot(&n, &n).sqrt();
    if length.is_nan() || length <= 0.0 {
        return None;
    }
    let light = (dot(&n, d) / length).abs();
    let level = |base: f64| (base * (0.55 + 0.45 * light)).round() as u8;
    Some(format!(
        "#{:02x}{:02x}{:02x}",
        level(196.0),
        level(204.0),
        level(214.0)
    ))
}

#[derive(Serialize)]
struct View {
    yaw: f64,
    pitch: f64,
    quantity: &'static str,
    /// Centre of the scene, mm.
    centre: [f64; 3],
    /// px per mm at zoom 1.
    scale: f64,
    width: f64,
    height: f64,
}

#[derive(Serialize)]
struct Quantity {
    label: &'static str,
    unit: &'static str,
}

/// Everything the script needs.
#[derive(Serialize)]
struct Scene {
    runs: Vec<Run>,
    env: Vec<Mesh>,
    /// Colour range per quantity `[low, high]` over every result (bend radius: from
    /// the tightest to at most ten times it).
    ranges: std::collections::BTreeMap<&'static str, [f64; 2]>,
    quantities: std::collections::BTreeMap<&'static str, Quantity>,
    view: View,
    viridis: [[f64; 3]; 5],
    #[serde(rename = "contactColour")]
    contact_colour: &'static str,
    /// Colour of each kind of fitting.
    #[serde(rename = "partColours")]
    part_colours: std::collections::BTreeMap<&'static str, &'static str>,
    #[serde(rename = "surfaceOpacity")]
    surface_opacity: f64,
    /// For a motion: the label of each result's pose (the slider plays them).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    poses: Vec<String>,
    /// Outline colour of each result when overlaid, cyclic.
    #[serde(rename = "overlayColours")]
    overlay_colours: [&'static str; 7],
    /// How far clearances were searched, mm (a vertex without a value is farther than
    /// this from every mesh).
    #[serde(rename = "clearanceSearch")]
    clearance_search: f64,
}

fn scene(runs: &[ReportRun]) -> Scene {
    let runs_data: Vec<Run> = runs
        .iter()
        .map(|run| Run {
            label: run.label.to_string(),
            rods: run
                .doc
                .rods
                .iter()
                .map(|rod| Rod {
                    name: rod.name.clone(),
                    r: rod.outer_radius_m.map_or(0.0, mm),
                    p: rod.position_m.iter().map(mm3).collect(),
                    s: rod.s_m.iter().map(|s| mm(*s)).collect(),
                    f: rod.force_n.iter().map(magnitude).collect(),
                    m: rod.moment_nm.iter().map(magnitude).collect(),
                    rb: bend_radii(rod)
                        .into_iter()
                        .map(|r| Some(mm(r)).filter(|r| r.is_finite()))
                        .collect(),
                    d: moved(rod, runs.first()),
                    u: bend_radii(rod)
                        .into_iter()
                        .map(|r| {
                            rod.min_bend_radius_m
                                .map(|limit| (limit / r * 1e6).round() / 1e6)
                                .filter(|u| u.is_finite())
                        })
                        .collect(),
                    c: (0..rod.position_m.len())
                        .map(|j| {
                            rod.clearance_m
                                .get(j)
                                .copied()
                                .flatten()
                                .map(mm)
                                .filter(|c| c.is_finite())
                        })
                        .collect(),
                })
                .collect(),
            contacts: run
                .doc
                .contacts
                .iter()
                .map(|c| ContactPoint {
                    rod: c.rod.clone(),
                    p: mm3(&c.point_m),
                    n: c.normal.map(|v| (v * 1e6).round() / 1e6),
                    f: c.force_n,
                    with: c.with.clone(),
                })
                .collect(),
            parts: parts(run.doc),
            env: Vec::new(),
        })
        .collect();
    let mesh_of = |outline: &crate::result::EnvironmentOutline| Mesh {
        name: outline.name.clone(),
        poly: outline
            .surface_m
            .iter()
            .map(|p| p.iter().map(mm3).collect())
            .collect(),
        seg: outline
            .segments_m
            .iter()
            .map(|[a, b]| {
                let (a, b) = (mm3(a), mm3(b));
                [a[0], a[1], a[2], b[0], b[1], b[2]]
            })
            .collect(),
    };
    // The environment: each mesh once, from the first result that outlines it; a
    // result that outlines it elsewhere (a moved part) keeps its own.
    let mut env: Vec<Mesh> = Vec::new();
    let mut runs_data = runs_data;
    for (run, data) in runs.iter().zip(&mut runs_data) {
        for outline in &run.doc.environment {
            if outline.segments_m.is_empty() {
                continue;
            }
            let mesh = mesh_of(outline);
            match env.iter().find(|m| m.name == outline.name) {
                None => env.push(mesh),
                Some(first) if first.seg != mesh.seg => data.env.push(mesh),
                Some(_) => {}
            }
        }
    }
    let range = |values: Vec<f64>| {
        let finite = values.into_iter().filter(|v| v.is_finite());
        let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
        if lo <= hi { [lo, hi] } else { [0.0, 1.0] }
    };
    let all = |pick: &dyn Fn(&Rod) -> Vec<f64>| -> Vec<f64> {
        runs_data
            .iter()
            .flat_map(|r| r.rods.iter().flat_map(pick))
            .collect()
    };
    let mut ranges = std::collections::BTreeMap::new();
    ranges.insert("f", range(all(&|r| r.f.clone())));
    ranges.insert("m", range(all(&|r| r.m.clone())));
    let [tight, loose] = range(all(&|r| r.rb.iter().flatten().copied().collect()));
    ranges.insert("rb", [tight, loose.min(10.0 * tight)]);
    let [_, farthest] = range(all(&|r| r.d.iter().flatten().copied().collect()));
    ranges.insert("d", [0.0, farthest.max(1e-3)]);
    let [_, most] = range(all(&|r| r.u.iter().flatten().copied().collect()));
    ranges.insert("u", [0.0, most.max(1.0)]);
    let [_, widest] = range(all(&|r| r.c.iter().flatten().copied().collect()));
    ranges.insert("c", [0.0, widest.max(1e-3)]);
    let quantities = QUANTITIES
        .iter()
        .map(|(key, label, unit)| (*key, Quantity { label, unit }))
        .collect();
    // Centre and scale from the bounding sphere of the box of everything drawn, so
    // that turning the view never leaves the frame.
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    let hoses = runs_data.iter().flat_map(|r| {
        r.rods
            .iter()
            .flat_map(|rod| rod.p.iter().copied())
            .chain(r.parts.iter().flat_map(|p| [p.a, p.b]))
    });
    let outlines = env.iter().flat_map(|m| {
        m.seg
            .iter()
            .flat_map(|s| [[s[0], s[1], s[2]], [s[3], s[4], s[5]]])
    });
    for p in hoses.chain(outlines) {
        if p.iter().all(|v| v.is_finite()) {
            for i in 0..3 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
        }
    }
    let (centre, radius) = if lo[0] <= hi[0] {
        let centre = [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i]));
        let half = [0, 1, 2].map(|i| 0.5 * (hi[i] - lo[i]));
        (centre, dot(&half, &half).sqrt().max(1.0))
    } else {
        ([0.0; 3], 1.0)
    };
    let (_, yaw, pitch) = PRESETS[0];
    Scene {
        runs: runs_data,
        env,
        ranges,
        quantities,
        view: View {
            yaw,
            pitch,
            quantity: "f",
            centre,
            scale: 0.47 * DRAW_WIDTH.min(HEIGHT) / radius,
            width: DRAW_WIDTH,
            height: HEIGHT,
        },
        viridis: VIRIDIS,
        contact_colour: CONTACT_COLOUR,
        part_colours: PART_COLOURS.into_iter().collect(),
        surface_opacity: SURFACE_OPACITY,
        poses: Vec::new(),
        overlay_colours: OVERLAY_COLOURS,
        clearance_search: mm(crate::clearance_search_m(
            runs.iter()
                .flat_map(|r| r.doc.rods.iter().filter_map(|rod| rod.min_clearance_m)),
        )),
    }
}

/// The screen position `(x, y)` (px) and depth (mm, larger is farther) of `p` (mm).
fn project(view: &View, axes: &Axes, p: &[f64; 3]) -> (f64, f64, f64) {
    let q = [0, 1, 2].map(|i| p[i] - view.centre[i]);
    (
        view.width / 2.0 + view.scale * dot(&axes.u, &q),
        view.height / 2.0 - view.scale * dot(&axes.v, &q),
        dot(&axes.d, &q),
    )
}

/// The first frame, as the script draws it (environment and hose edges far to near,
/// then the contacts), into `svg`.
fn first_frame(svg: &mut String, scene: &Scene) {
    let view = &scene.view;
    let axes = Axes::new(view.yaw, view.pitch);
    let [lo, hi] = scene.ranges["f"];
    let mut items: Vec<(f64, String)> = Vec::new();
    for mesh in &scene.env {
        for poly in &mesh.poly {
            let Some(fill) = shade(poly, &axes.d) else {
                continue;
            };
            let mut points = String::new();
            let mut depth = 0.0;
            for p in poly {
                let q = project(view, &axes, p);
                let _ = write!(
                    points,
                    "{}{:.2},{:.2}",
                    if points.is_empty() { "" } else { " " },
                    q.0,
                    q.1
                );
                depth += q.2;
            }
            items.push((
                depth / poly.len() as f64,
                format!(
                    "<polygon class=\"v3d-surface\" data-name=\"{}\" points=\"{points}\" fill=\"{fill}\" fill-opacity=\"{SURFACE_OPACITY}\"/>",
                    escape(&mesh.name)
                ),
            ));
        }
        for s in &mesh.seg {
            let a = project(view, &axes, &[s[0], s[1], s[2]]);
            let b = project(view, &axes, &[s[3], s[4], s[5]]);
            items.push((
                0.5 * (a.2 + b.2),
                format!(
                    "<line class=\"v3d-env\" data-name=\"{}\" x1=\"{:.2}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"#b4b4b4\" stroke-width=\"1\"/>",
                    escape(&mesh.name),
                    a.0,
                    a.1,
                    b.0,
                    b.1
                ),
            ));
        }
    }
    if let Some(run) = scene.runs.first() {
        for rod in &run.rods {
            let width = (2.0 * rod.r * view.scale).max(2.0);
            for j in 1..rod.p.len() {
                let a = project(view, &axes, &rod.p[j - 1]);
                let b = project(view, &axes, &rod.p[j]);
                let f = 0.5 * (rod.f[j - 1] + rod.f[j]);
                let t = if hi > lo { (f - lo) / (hi - lo) } else { 0.0 };
                items.push((
                    0.5 * (a.2 + b.2),
                    format!(
                        "<line class=\"v3d-edge\" data-rod=\"{}\" data-j=\"{j}\" x1=\"{:.2}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"{}\" stroke-width=\"{width:.2}\" stroke-linecap=\"round\"/>",
                        escape(&rod.name),
                        a.0,
                        a.1,
                        b.0,
                        b.1,
                        viridis(t)
                    ),
                ));
            }
        }
        for part in &run.parts {
            let a = project(view, &axes, &part.a);
            let b = project(view, &axes, &part.b);
            items.push((
                0.5 * (a.2 + b.2),
                format!(
                    "<line class=\"v3d-part\" data-kind=\"{}\" data-name=\"{}\" x1=\"{:.2}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"{}\" stroke-width=\"{:.2}\" stroke-linecap=\"round\"/>",
                    part.kind,
                    escape(&part.name),
                    a.0,
                    a.1,
                    b.0,
                    b.1,
                    part_colour(part.kind),
                    (part.w * view.scale).max(3.0)
                ),
            ));
        }
    }
    // Far first; a stable sort keeps the script's order for equal depths.
    items.sort_by(|x, y| y.0.total_cmp(&x.0));
    for (_, item) in items {
        svg.push_str(&item);
        svg.push('\n');
    }
    if let Some(run) = scene.runs.first() {
        for c in &run.contacts {
            let p = project(view, &axes, &c.p);
            let tip = project(view, &axes, &[0, 1, 2].map(|i| c.p[i] + c.n[i]));
            let (dx, dy) = (tip.0 - p.0, tip.1 - p.1);
            let l = dx.hypot(dy);
            if l > 1e-9 * view.scale {
                let _ = writeln!(
                    svg,
                    "<line class=\"v3d-contact-arrow\" x1=\"{:.2}\" y1=\"{:.2}\" x2=\"{:.2}\" y2=\"{:.2}\" stroke=\"{CONTACT_COLOUR}\" stroke-width=\"2\"/>",
                    p.0 - 26.0 * dx / l,
                    p.1 - 26.0 * dy / l,
                    p.0,
                    p.1
                );
            }
            let _ = writeln!(
                svg,
                "<circle class=\"v3d-contact\" data-rod=\"{}\" data-with=\"{}\" data-force-n=\"{}\" cx=\"{:.2}\" cy=\"{:.2}\" r=\"4\" fill=\"{CONTACT_COLOUR}\" stroke=\"#ffffff\"/>",
                escape(&c.rod),
                escape(&c.with),
                c.f,
                p.0,
                p.1
            );
        }
    }
}

/// The colour legend at the right of the view (texts updated by the script).
fn legend(svg: &mut String, scene: &Scene) {
    const TOP: f64 = 70.0;
    const BAR: f64 = 420.0;
    let x = DRAW_WIDTH + 20.0;
    svg.push_str("<g class=\"v3d-legend\">\n");
    colour_bar(svg, x, TOP, 16.0, BAR);
    let [lo, hi] = scene.ranges["f"];
    let _ = writeln!(
        svg,
        "<text id=\"v3d-legend-title\" x=\"{:.1}\" y=\"{:.1}\" font-weight=\"bold\">|f| internal force [N]</text>\n<text id=\"v3d-legend-top\" x=\"{:.1}\" y=\"{:.1}\">{}</text>\n<text id=\"v3d-legend-bottom\" x=\"{:.1}\" y=\"{:.1}\">{}</text>",
        DRAW_WIDTH - 80.0,
        TOP - 24.0,
        x + 20.0,
        TOP + 4.0,
        sig(hi),
        x + 20.0,
        TOP + BAR + 4.0,
        sig(lo)
    );
    // Key of the fittings and contacts (fixed colours).
    let key = PART_COLOURS
        .iter()
        .copied()
        .chain([("contact", CONTACT_COLOUR)]);
    for (i, (kind, colour)) in key.enumerate() {
        let y = TOP + BAR + 34.0 + 18.0 * i as f64;
        let _ = writeln!(
            svg,
            "<rect class=\"v3d-key\" x=\"{x:.1}\" y=\"{:.1}\" width=\"16\" height=\"10\" fill=\"{colour}\"/><text x=\"{:.1}\" y=\"{:.1}\">{kind}</text>",
            y - 9.0,
            x + 20.0,
            y
        );
    }
    svg.push_str("</g>\n");
}

/// The scene as JSON safe inside an XHTML `<script>` (no `<`, `>` or `&`).
fn scene_json(scene: &Scene) -> String {
    serde_json::to_string(scene)
        .unwrap_or_else(|_| "{}".to_string())
        .replace('<', "\\u003c")
        .replace('>', "\\u003e")
        .replace('&', "\\u0026")
}

/// Appends the 3D view section's content: controls, the SVG with the first frame and
/// legend, the data and the script. With `poses` (a motion: one label per result) a
/// slider and a play button step through the results.
pub(crate) fn push_view3d(html: &mut String, runs: &[ReportRun], poses: Option<&[String]>) {
    let mut scene = scene(runs);
    scene.poses = poses.map(<[String]>::to_vec).unwrap_or_default();
    html.push_str("<div class=\"v3d-controls\">\n<label>colour by <select id=\"v3d-quantity\">");
    for (key, label, unit) in QUANTITIES {
        let _ = write!(
            html,
            "<option value=\"{key}\"{}>{} [{unit}]</option>",
            if key == "f" {
                " selected=\"selected\""
            } else {
                ""
            },
            escape(label)
        );
    }
    html.push_str("</select></label>\n<label>result <select id=\"v3d-result\">");
    for (k, run) in runs.iter().enumerate() {
        let _ = write!(
            html,
            "<option value=\"{k}\"{}>{}</option>",
            if k == 0 { " selected=\"selected\"" } else { "" },
            escape(run.label)
        );
    }
    html.push_str("</select></label>\n");
    if let Some(poses) = poses.filter(|p| p.len() > 1) {
        let _ = writeln!(
            html,
            "<label>pose <input type=\"range\" id=\"v3d-pose\" min=\"0\" max=\"{}\" step=\"1\" value=\"0\"/></label> <button type=\"button\" id=\"v3d-play\">play</button> <span id=\"v3d-pose-label\" class=\"readout\">{}</span>",
            poses.len() - 1,
            escape(&poses[0])
        );
    }
    if runs.len() > 1 {
        // One toggle per result: drawn dashed in its colour behind the shown one.
        html.push_str("<span class=\"v3d-toggles\">overlay (dashed):");
        for (k, run) in runs.iter().enumerate() {
            let _ = write!(
                html,
                " <label><input type=\"checkbox\" class=\"v3d-toggle\" data-run=\"{k}\"{}/> <span style=\"color:{}\">■</span> {}</label>",
                if k == 0 { " checked=\"checked\"" } else { "" },
                overlay_colour(k),
                escape(run.label)
            );
        }
        html.push_str("</span>\n");
    }
    for (name, yaw, pitch) in PRESETS {
        let _ = write!(
            html,
            "<button type=\"button\" data-yaw=\"{yaw}\" data-pitch=\"{pitch}\">{}</button>",
            escape(name)
        );
    }
    html.push_str("\n<span id=\"v3d-readout\" class=\"readout\">Hover a hose for its values; drag to turn, shift-drag to pan, wheel to zoom.</span>\n</div>\n");
    html.push_str("<figure class=\"v3d\">");
    open_figure(html, &Figure::new(WIDTH, HEIGHT, "").id("v3d-svg"));
    html.push_str("<g id=\"v3d-scene\">\n");
    first_frame(html, &scene);
    html.push_str("</g>\n");
    legend(html, &scene);
    close_figure(html);
    let _ = writeln!(
        html,
        "<figcaption>Orthographic 3D view of the hoses (tube width to scale) with the environment outlines and contacts; {} shown first (isometric, coloured by |f|).</figcaption></figure>",
        escape(runs.first().map_or("none", |r| r.label))
    );
    let _ = writeln!(
        html,
        "<script type=\"application/json\" id=\"v3d-data\">{}</script>",
        scene_json(&scene)
    );
    let _ = writeln!(
        html,
        "<script>//<![CDATA[\n{}//]]></script>",
        include_str!("view3d.js")
    );
}
