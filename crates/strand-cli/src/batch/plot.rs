//! `DIR/summary.svg`: the peak internal force `|f|` and moment `|m|` of every rod
//! against the first varied parameter, in two stacked panels (plain SVG 1.1, no
//! external resources). With several parameters the plotted line is the one through
//! the case: the other parameters at their anchor values. Failed variants are red
//! crosses on the axis. Each curve is a `<path class="curve">` with `data-panel`
//! (`force`, `moment`) and `data-rod`.

use std::fmt::Write;

use super::manifest::Manifest;
use super::summary::{Outcome, peak};

const WIDTH: f64 = 820.0;
const LEFT: f64 = 84.0;
const RIGHT: f64 = 640.0;
const TOP: f64 = 56.0;
const PANEL: f64 = 220.0;
const GAP: f64 = 76.0;
const HEIGHT: f64 = TOP + 2.0 * PANEL + GAP + 60.0;
const COLOURS: [&str; 7] = strand_report::LINE_COLOURS;

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Axis range `[lo, hi]` padded so that a single value still spans some width.
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !(lo.is_finite() && hi.is_finite()) {
        (0.0, 1.0)
    } else if hi - lo <= 1e-12 * hi.abs().max(1.0) {
        (lo - 0.5 * lo.abs().max(1.0), hi + 0.5 * hi.abs().max(1.0))
    } else {
        (lo, hi)
    }
}

/// The plot of `manifest`'s variants with their `outcomes` (same order).
pub(crate) fn summary_svg(manifest: &Manifest, outcomes: &[Outcome]) -> String {
    let Some(first) = manifest.parameters.first() else {
        return String::new();
    };
    // The line through the case along the first parameter.
    let line: Vec<(f64, &Outcome)> = manifest
        .variants
        .iter()
        .zip(outcomes)
        .filter(|(v, _)| {
            v.index
                .iter()
                .zip(&manifest.parameters)
                .skip(1)
                .all(|(&k, p)| k == p.anchor)
        })
        .map(|(v, o)| (first.values[v.index[0]], o))
        .collect();
    let mut rods: Vec<&str> = Vec::new();
    for (_, o) in &line {
        if let Outcome::Solved(doc) = o {
            for r in &doc.rods {
                if !rods.contains(&r.name.as_str()) {
                    rods.push(&r.name);
                }
            }
        }
    }
    let value = |o: &Outcome, rod: &str, force: bool| match o {
        Outcome::Solved(doc) => doc
            .rods
            .iter()
            .find(|r| r.name == rod)
            .map_or(f64::NAN, |r| {
                peak(if force { &r.force_n } else { &r.moment_nm })
            }),
        _ => f64::NAN,
    };
    let (x0, x1) = range(line.iter().map(|(x, _)| *x));
    let sx = |x: f64| LEFT + (RIGHT - LEFT) * (x - x0) / (x1 - x0);
    let unit = if first.unit.is_empty() {
        String::new()
    } else {
        format!(" [{}]", first.unit)
    };
    let mut svg = String::new();
    let _ = writeln!(svg, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    let _ = writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{WIDTH}\" height=\"{HEIGHT}\" viewBox=\"0 0 {WIDTH} {HEIGHT}\" font-family=\"sans-serif\" font-size=\"12\">"
    );
    let title = format!("{}: peaks against {}", manifest.case, first.label);
    let _ = writeln!(svg, "<title>{}</title>", escape(&title));
    let _ = writeln!(
        svg,
        "<rect width=\"{WIDTH}\" height=\"{HEIGHT}\" fill=\"#ffffff\"/>"
    );
    let _ = writeln!(
        svg,
        "<text x=\"{LEFT}\" y=\"22\" font-size=\"14\" font-weight=\"bold\">{}</text>",
        escape(&title)
    );
    for (p, (kind, label)) in [("force", "peak |f| [N]"), ("moment", "peak |m| [N·m]")]
        .iter()
        .enumerate()
    {
        let force = p == 0;
        let top = TOP + p as f64 * (PANEL + GAP);
        let bottom = top + PANEL;
        let (_, y1) = range(
            line.iter()
                .flat_map(|(_, o)| rods.iter().map(|r| value(o, r, force)))
                .chain([0.0]),
        );
        let y1 = y1 * 1.05;
        let sy = |y: f64| bottom - PANEL * y / y1;
        let _ = writeln!(svg, "<g class=\"axes\">");
        let _ = writeln!(
            svg,
            "<rect x=\"{LEFT}\" y=\"{top}\" width=\"{}\" height=\"{PANEL}\" fill=\"none\" stroke=\"#333333\"/>",
            RIGHT - LEFT
        );
        for i in 0..=4 {
            let (xv, yv) = (x0 + (x1 - x0) * i as f64 / 4.0, y1 * i as f64 / 4.0);
            let _ = writeln!(
                svg,
                "<text x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>",
                sx(xv),
                bottom + 16.0,
                super::spec::canonical((xv * 1e4).round() / 1e4)
            );
            let _ = writeln!(
                svg,
                "<line x1=\"{LEFT}\" y1=\"{:.2}\" x2=\"{RIGHT}\" y2=\"{:.2}\" stroke=\"#e3e3e3\"/>",
                sy(yv),
                sy(yv)
            );
            let _ = writeln!(
                svg,
                "<text x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"end\">{}</text>",
                LEFT - 6.0,
                sy(yv) + 4.0,
                crate::summary::significant(yv, 3)
            );
        }
        let _ = writeln!(
            svg,
            "<text x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}{}</text>",
            0.5 * (LEFT + RIGHT),
            bottom + 36.0,
            escape(&first.label),
            escape(&unit)
        );
        let (cx, cy) = (LEFT - 56.0, top + 0.5 * PANEL);
        let _ = writeln!(
            svg,
            "<text x=\"{cx}\" y=\"{cy}\" text-anchor=\"middle\" transform=\"rotate(-90 {cx} {cy})\">{}</text>",
            escape(label)
        );
        let _ = writeln!(svg, "</g>");
        let _ = writeln!(svg, "<g class=\"curves\" data-panel=\"{kind}\">");
        for (r, rod) in rods.iter().enumerate() {
            let mut d = String::new();
            let mut pen = false;
            for (x, o) in &line {
                let y = value(o, rod, force);
                if !y.is_finite() {
                    pen = false;
                    continue;
                }
                let _ = write!(
                    d,
                    "{}{:.2} {:.2} ",
                    if pen { "L" } else { "M" },
                    sx(*x),
                    sy(y)
                );
                pen = true;
            }
            let _ = writeln!(
                svg,
                "<path class=\"curve\" data-panel=\"{kind}\" data-rod=\"{}\" d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.8\"/>",
                escape(rod),
                d.trim_end(),
                COLOURS[r % COLOURS.len()]
            );
        }
        for (x, o) in &line {
            if !matches!(o, Outcome::Solved(_)) {
                let (px, py) = (sx(*x), bottom);
                let _ = writeln!(
                    svg,
                    "<path class=\"failed\" d=\"M{:.2} {:.2} L{:.2} {:.2} M{:.2} {:.2} L{:.2} {:.2}\" stroke=\"#cc0000\" stroke-width=\"2\"/>",
                    px - 5.0,
                    py - 5.0,
                    px + 5.0,
                    py + 5.0,
                    px - 5.0,
                    py + 5.0,
                    px + 5.0,
                    py - 5.0
                );
            }
        }
        let _ = writeln!(svg, "</g>");
    }
    let _ = writeln!(svg, "<g class=\"legend\">");
    for (r, rod) in rods.iter().enumerate() {
        let y = TOP + 8.0 + 20.0 * r as f64;
        let _ = writeln!(
            svg,
            "<line x1=\"{}\" y1=\"{y}\" x2=\"{}\" y2=\"{y}\" stroke=\"{}\" stroke-width=\"3\"/>",
            RIGHT + 20.0,
            RIGHT + 48.0,
            COLOURS[r % COLOURS.len()]
        );
        let _ = writeln!(
            svg,
            "<text x=\"{}\" y=\"{}\">{}</text>",
            RIGHT + 56.0,
            y + 4.0,
            escape(rod)
        );
    }
    let y = TOP + 8.0 + 20.0 * rods.len() as f64 + 10.0;
    let _ = writeln!(
        svg,
        "<text x=\"{}\" y=\"{y}\" fill=\"#cc0000\">× failed variant</text>",
        RIGHT + 20.0
    );
    let _ = writeln!(svg, "</g>");
    let _ = writeln!(svg, "</svg>");
    svg
}
