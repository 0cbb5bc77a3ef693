//! Side (x–z), top (x–y) and front (y–z) views of the hoses, as the paper's Fig. 6 b, c: every
//! edge coloured by the mean internal force magnitude `|f|` of its two vertices
//! (viridis, one scale for all results), the supports (connectors, junction bodies with
//! lines to their ports, clips), the contacts (a dot and the force arrow, in N) and the
//! environment outlines of [`crate::ResultDoc::environment`] (light grey). One scale for all results and both views (equal
//! aspect, mm), so that results can be compared by eye; results after the first show
//! the reference centrelines as grey dashed ghosts.

use std::fmt::Write;

use super::ReportRun;
use super::format::sig;
use crate::plot::{
    CONTACT_COLOUR, Figure, Panel, close_figure, colour_bar, escape, open_figure, ticks,
    viridis as colour,
};
use crate::result::ResultDoc;
use crate::study::magnitude;

const WIDTH: f64 = 600.0;
const HEIGHT: f64 = 520.0;
const LEFT: f64 = 70.0;
const PLOT_WIDTH: f64 = 420.0;
const TOP: f64 = 40.0;
const PLOT_HEIGHT: f64 = 420.0;

/// Every point that should be in view in `doc`, m.
fn points(doc: &ResultDoc) -> impl Iterator<Item = [f64; 3]> + '_ {
    let rods = doc.rods.iter().flat_map(|r| r.position_m.iter().copied());
    let supports = doc.reactions.iter().map(|r| r.position_m);
    let bodies = doc.bodies.iter().map(|b| b.position_m);
    let clips = doc.clips.iter().map(|c| c.position_m);
    let environment = doc
        .environment
        .iter()
        .flat_map(|e| e.segments_m.iter().flatten().copied());
    rods.chain(supports)
        .chain(bodies)
        .chain(clips)
        .chain(environment)
}

/// The panel of view axes `(a, b)` (0 = x, 1 = y, 2 = z) fitted to all runs at one
/// scale, and its tick step; coordinates in mm.
fn fit(runs: &[ReportRun], axes: [usize; 2], scale: f64) -> (Panel, f64) {
    let (lo, hi) = bounds(runs, axes);
    let step = ticks((hi[0] - lo[0]).max(hi[1] - lo[1])).0;
    let low = lo.map(|v| (v / step - 1e-9).floor() * step);
    let high = [0, 1].map(|i| ((hi[i] / step + 1e-9).ceil() * step).max(low[i] + step));
    let (width, height) = ((high[0] - low[0]) * scale, (high[1] - low[1]) * scale);
    let left = LEFT + 0.5 * (PLOT_WIDTH - width);
    let panel = Panel {
        left,
        right: left + width,
        top: TOP + 0.5 * (PLOT_HEIGHT - height),
        height,
        x_min: low[0],
        x_max: high[0],
        y_min: low[1],
        y_max: high[1],
    };
    (panel, step)
}

/// Bounding box of all runs' points in view axes, mm, with a 4 % margin.
fn bounds(runs: &[ReportRun], axes: [usize; 2]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in runs.iter().flat_map(|r| points(r.doc)) {
        for i in 0..2 {
            let v = 1e3 * p[axes[i]];
            if v.is_finite() {
                lo[i] = lo[i].min(v);
                hi[i] = hi[i].max(v);
            }
        }
    }
    if lo[0] > hi[0] {
        return ([0.0; 2], [1.0; 2]);
    }
    let margin = 0.04 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1.0);
    (lo.map(|v| v - margin), hi.map(|v| v + margin))
}

/// Appends one figure per run and view (side, top, front) to `html`.
pub(crate) fn push_projections(html: &mut String, runs: &[ReportRun]) {
    let f_max = runs
        .iter()
        .flat_map(|r| {
            r.doc
                .rods
                .iter()
                .flat_map(|rod| rod.force_n.iter().map(magnitude))
        })
        .filter(|v| v.is_finite())
        .fold(0.0f64, f64::max);
    let f_max = if f_max > 0.0 { f_max } else { 1.0 };
    let views = [
        ("side", [0, 2], "x [mm]", "z [mm]", "x right, z up"),
        (
            "top",
            [0, 1],
            "x [mm]",
            "y [mm]",
            "x right, y up, seen from above",
        ),
        (
            "front",
            [1, 2],
            "y [mm]",
            "z [mm]",
            "y right, z up, looking along −x",
        ),
    ];
    // One scale (px per mm) fitting every view of every run.
    let scale = views
        .iter()
        .map(|(_, axes, ..)| {
            let (lo, hi) = bounds(runs, *axes);
            let step = ticks((hi[0] - lo[0]).max(hi[1] - lo[1])).0;
            let span = |i: usize| ((hi[i] / step).ceil() - (lo[i] / step).floor()).max(1.0) * step;
            (PLOT_WIDTH / span(0)).min(PLOT_HEIGHT / span(1))
        })
        .fold(f64::INFINITY, f64::min);
    for (k, run) in runs.iter().enumerate() {
        for (view, axes, x_label, y_label, caption) in &views {
            let (panel, step) = fit(runs, *axes, scale);
            let mut svg = String::with_capacity(32 * 1024);
            let title = format!("{}: {view} view", run.label);
            let data = [("view", *view), ("result", run.label)];
            let figure = Figure::new(WIDTH, HEIGHT, &title)
                .class("projection")
                .data(&data);
            open_figure(&mut svg, &figure);
            panel.draw_axes(&mut svg, step, step, x_label, y_label, "");
            let at = |p: &[f64; 3]| (panel.x(1e3 * p[axes[0]]), panel.y(1e3 * p[axes[1]]));
            draw_environment(&mut svg, run.doc, &at);
            if k > 0 {
                draw_ghost(&mut svg, runs[0], &at);
            }
            draw_rods(&mut svg, run, f_max, &at);
            draw_supports(&mut svg, run.doc, &at);
            draw_contacts(&mut svg, run, &at, *axes);
            draw_colour_bar(&mut svg, f_max, (panel.right + 34.0).min(WIDTH - 70.0));
            close_figure(&mut svg);
            let _ = writeln!(
                html,
                "<figure data-view=\"{view}\" data-result=\"{}\">{svg}<figcaption>{}: {} view ({})</figcaption></figure>",
                escape(run.label),
                escape(run.label),
                view,
                caption
            );
        }
    }
}

fn draw_environment(svg: &mut String, doc: &ResultDoc, at: &dyn Fn(&[f64; 3]) -> (f64, f64)) {
    for outline in doc.environment.iter().filter(|e| !e.segments_m.is_empty()) {
        let mut d = String::new();
        for [a, b] in &outline.segments_m {
            let ((x0, y0), (x1, y1)) = (at(a), at(b));
            if [x0, y0, x1, y1].iter().all(|v| v.is_finite()) {
                let _ = write!(d, "M{x0:.2} {y0:.2} L{x1:.2} {y1:.2} ");
            }
        }
        let _ = writeln!(
            svg,
            "<path class=\"environment\" data-name=\"{}\" d=\"{}\" fill=\"none\" stroke=\"#b4b4b4\" stroke-width=\"1\" stroke-linecap=\"round\"/>",
            escape(&outline.name),
            d.trim_end()
        );
    }
}

fn draw_ghost(svg: &mut String, reference: ReportRun, at: &dyn Fn(&[f64; 3]) -> (f64, f64)) {
    for rod in &reference.doc.rods {
        let points: Vec<String> = rod
            .position_m
            .iter()
            .map(at)
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .map(|(x, y)| format!("{x:.2},{y:.2}"))
            .collect();
        let _ = writeln!(
            svg,
            "<polyline class=\"ghost\" data-rod=\"{}\" points=\"{}\" fill=\"none\" stroke=\"#b5b5b5\" stroke-width=\"1.5\" stroke-dasharray=\"5 4\"/>",
            escape(&rod.name),
            points.join(" ")
        );
    }
}

fn draw_rods(svg: &mut String, run: &ReportRun, f_max: f64, at: &dyn Fn(&[f64; 3]) -> (f64, f64)) {
    for rod in &run.doc.rods {
        let _ = writeln!(
            svg,
            "<g class=\"rod\" data-rod=\"{}\" data-result=\"{}\" stroke-width=\"3.5\" stroke-linecap=\"round\">",
            escape(&rod.name),
            escape(run.label)
        );
        for j in 1..rod.position_m.len() {
            let ((x0, y0), (x1, y1)) = (at(&rod.position_m[j - 1]), at(&rod.position_m[j]));
            if ![x0, y0, x1, y1].iter().all(|v| v.is_finite()) {
                continue;
            }
            let f = 0.5 * (magnitude(&rod.force_n[j - 1]) + magnitude(&rod.force_n[j]));
            let _ = writeln!(
                svg,
                "<line x1=\"{x0:.2}\" y1=\"{y0:.2}\" x2=\"{x1:.2}\" y2=\"{y1:.2}\" stroke=\"{}\"/>",
                colour(f / f_max)
            );
        }
        svg.push_str("</g>\n");
        if let Some(mid) = rod.position_m.get(rod.position_m.len() / 2) {
            let (x, y) = at(mid);
            if x.is_finite() && y.is_finite() {
                let _ = writeln!(
                    svg,
                    "<text class=\"rod-label\" x=\"{:.2}\" y=\"{:.2}\" font-size=\"11\" stroke=\"#ffffff\" stroke-width=\"3\" paint-order=\"stroke\">{}</text>",
                    x + 7.0,
                    y - 7.0,
                    escape(&rod.name)
                );
            }
        }
    }
}

fn draw_supports(svg: &mut String, doc: &ResultDoc, at: &dyn Fn(&[f64; 3]) -> (f64, f64)) {
    let finite = |(x, y): (f64, f64)| x.is_finite() && y.is_finite();
    for body in &doc.bodies {
        let (bx, by) = at(&body.position_m);
        if !finite((bx, by)) {
            continue;
        }
        let prefix = format!("{}.", body.name);
        for port in doc
            .reactions
            .iter()
            .filter(|r| r.kind == "port" && r.name.starts_with(&prefix))
        {
            let (px, py) = at(&port.position_m);
            if finite((px, py)) {
                let _ = writeln!(
                    svg,
                    "<line class=\"support\" data-kind=\"port\" x1=\"{bx:.2}\" y1=\"{by:.2}\" x2=\"{px:.2}\" y2=\"{py:.2}\" stroke=\"#555555\" stroke-width=\"4\"/>"
                );
            }
        }
        let _ = writeln!(
            svg,
            "<circle class=\"support\" data-kind=\"body\" data-name=\"{}\" cx=\"{bx:.2}\" cy=\"{by:.2}\" r=\"6\" fill=\"#555555\" stroke=\"#ffffff\"/>",
            escape(&body.name)
        );
    }
    for connector in doc.reactions.iter().filter(|r| r.kind == "connector") {
        let (x, y) = at(&connector.position_m);
        if finite((x, y)) {
            let _ = writeln!(
                svg,
                "<rect class=\"support\" data-kind=\"connector\" data-name=\"{}\" x=\"{:.2}\" y=\"{:.2}\" width=\"9\" height=\"9\" fill=\"#222222\"/>",
                escape(&connector.name),
                x - 4.5,
                y - 4.5
            );
        }
    }
    for clip in &doc.clips {
        let (x, y) = at(&clip.position_m);
        if finite((x, y)) {
            let _ = writeln!(
                svg,
                "<path class=\"support\" data-kind=\"clip\" data-name=\"{}\" d=\"M{:.2} {:.2} L{:.2} {:.2} L{:.2} {:.2} Z\" fill=\"#8c564b\" stroke=\"#ffffff\"/>",
                escape(&clip.name),
                x,
                y - 6.0,
                x + 5.5,
                y + 4.0,
                x - 5.5,
                y + 4.0
            );
        }
    }
}

/// Length of a contact-force arrow, px.
const ARROW: f64 = 26.0;

/// Marks every contact of `run`: a dot at the contact point (on the centreline) and,
/// where the contact normal is not along the line of sight, an arrow of the force on
/// the hose ending there; labelled with the force in N.
fn draw_contacts(
    svg: &mut String,
    run: &ReportRun,
    at: &dyn Fn(&[f64; 3]) -> (f64, f64),
    axes: [usize; 2],
) {
    for c in &run.doc.contacts {
        let (x, y) = at(&c.point_m);
        if !(x.is_finite() && y.is_finite()) {
            continue;
        }
        // The normal in screen directions (SVG y grows downwards).
        let (nx, ny) = (c.normal[axes[0]], -c.normal[axes[1]]);
        let length = nx.hypot(ny);
        let arrow = if length > 0.2 {
            let (dx, dy) = (nx / length, ny / length);
            let (x0, y0) = (x - ARROW * dx, y - ARROW * dy);
            // Head: two barbs 7 px back from the tip, ±4 px sideways.
            let (bx, by) = (x - 7.0 * dx, y - 7.0 * dy);
            format!(
                "<path d=\"M{x0:.2} {y0:.2} L{x:.2} {y:.2} M{:.2} {:.2} L{x:.2} {y:.2} L{:.2} {:.2}\" fill=\"none\" stroke=\"{CONTACT_COLOUR}\" stroke-width=\"2\"/>",
                bx - 4.0 * dy,
                by + 4.0 * dx,
                bx + 4.0 * dy,
                by - 4.0 * dx
            )
        } else {
            String::new()
        };
        let _ = writeln!(
            svg,
            "<g class=\"contact\" data-rod=\"{}\" data-with=\"{}\" data-force-n=\"{}\"><title>{} on {}: {} N</title>{arrow}<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"4\" fill=\"{CONTACT_COLOUR}\" stroke=\"#ffffff\" stroke-width=\"1\"/><text x=\"{:.2}\" y=\"{:.2}\" font-size=\"10\" fill=\"{CONTACT_COLOUR}\" stroke=\"#ffffff\" stroke-width=\"3\" paint-order=\"stroke\">{} N</text></g>",
            escape(&c.rod),
            escape(&c.with),
            c.force_n,
            escape(&c.rod),
            escape(&c.with),
            sig(c.force_n),
            x + 6.0,
            y + 14.0,
            sig(c.force_n)
        );
    }
}

/// The colour bar of `|f|` from 0 to `f_max` (N) at `bar_x` (px), with its labels.
fn draw_colour_bar(svg: &mut String, f_max: f64, bar_x: f64) {
    colour_bar(svg, bar_x, TOP, 14.0, PLOT_HEIGHT);
    for t in [0.0, 0.5, 1.0] {
        let y = TOP + PLOT_HEIGHT * (1.0 - t);
        let _ = writeln!(
            svg,
            "<text x=\"{:.1}\" y=\"{:.2}\">{}</text>",
            bar_x + 18.0,
            y + 4.0,
            sig(t * f_max)
        );
    }
    let _ = writeln!(
        svg,
        "<text x=\"{bar_x:.1}\" y=\"{:.1}\" font-weight=\"bold\">|f| [N]</text>",
        TOP - 8.0
    );
}
