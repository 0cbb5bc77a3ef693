//! `DIR/summary.svg`: the peak internal force `|f|` and moment `|m|` of every rod
//! against the first varied parameter, in two stacked panels (plain SVG 1.1, no
//! external resources). Colour tells the rod ([`strand_report::LINE_COLOURS`]); with
//! two or more parameters there is one line per value of the second parameter (its
//! dash pattern, named in the legend), the further parameters at their values nearest
//! the case's (said in the title). Failed variants are red crosses on the axis, and
//! the legend names them only when there are some. Each curve is a
//! `<path class="curve">` with `data-panel` (`force`, `moment`), `data-rod` and
//! `data-slice` (the second parameter's value as written, empty with one parameter).
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

/// The x-axis label of parameter `p`: offsets (values written with a sign) say so.
fn axis_title(p: &super::manifest::Parameter) -> String {
    let offsets = p.texts.iter().any(|t| t.starts_with('+'))
        || (!p.texts.is_empty() && p.texts.iter().all(|t| t.starts_with('-')));
    let unit = if p.unit.is_empty() {
        String::new()
    } else {
        format!(" [{}]", p.unit)
    };
    if offsets {
        format!("change of {} from the case{unit}", p.label)
    } else {
        format!("{}{unit}", p.label)
    }
}

/// The plot of `manifest`'s variants with their `outcomes` (same order).
pub(crate) fn summary_svg(manifest: &Manifest, outcomes: &[Outcome]) -> String {
    let Some(first) = manifest.parameters.first() else {
        return String::new();
    };
    let second = manifest.parameters.get(1);
    // Lines along the first parameter: one per value of the second, the others at
    // their anchors.
    let slices = second.map_or(1, |p| p.values.len());
    let lines: Vec<Vec<(f64, &Outcome)>> = (0..slices)
        .map(|k| {
            manifest
                .variants
                .iter()
                .zip(outcomes)
                .filter(|(v, _)| {
                    v.index.get(1).is_none_or(|&i| i == k)
                        && v.index
                            .iter()
                            .zip(&manifest.parameters)
                            .skip(2)
                            .all(|(&i, p)| i == p.anchor)
                })
                .map(|(v, o)| (first.values[v.index[0]], o))
                .collect()
        })
        .collect();
    let mut rods: Vec<&str> = Vec::new();
    for (_, o) in lines.iter().flatten() {
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
    let (x_lo, x_hi) = range(lines.iter().flatten().map(|(x, _)| *x));
    let (x_step, x0, x1) = strand_report::axis_ticks(x_lo, x_hi);
    let sx = |x: f64| LEFT + (RIGHT - LEFT) * (x - x0) / (x1 - x0);
    let mut svg = String::new();
    let _ = writeln!(svg, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    let _ = writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{WIDTH}\" height=\"{HEIGHT}\" viewBox=\"0 0 {WIDTH} {HEIGHT}\" font-family=\"sans-serif\" font-size=\"12\">"
    );
    let mut title = format!("{}: peaks against {}", manifest.case, first.label);
    if let Some(p) = second {
        let _ = write!(title, ", one line per {}", p.label);
    }
    let fixed: Vec<String> = manifest
        .parameters
        .iter()
        .skip(2)
        .map(|p| format!("{} = {}", p.label, p.texts[p.anchor]))
        .collect();
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
    if !fixed.is_empty() {
        let _ = writeln!(
            svg,
            "<text class=\"fixed\" x=\"{LEFT}\" y=\"40\">other parameters at their values nearest the case: {}</text>",
            escape(&fixed.join(", "))
        );
    }
    for (p, (kind, label)) in [("force", "peak |f| [N]"), ("moment", "peak |m| [N·m]")]
        .iter()
        .enumerate()
    {
        let force = p == 0;
        let top = TOP + p as f64 * (PANEL + GAP);
        let bottom = top + PANEL;
        let (_, y_hi) = range(
            lines
                .iter()
                .flatten()
                .flat_map(|(_, o)| rods.iter().map(|r| value(o, r, force)))
                .chain([0.0]),
        );
        let (y_step, _, y1) = strand_report::axis_ticks(0.0, y_hi);
        let sy = |y: f64| bottom - PANEL * y / y1;
        let _ = writeln!(svg, "<g class=\"axes\">");
        let _ = writeln!(
            svg,
            "<rect x=\"{LEFT}\" y=\"{top}\" width=\"{}\" height=\"{PANEL}\" fill=\"none\" stroke=\"#333333\"/>",
            RIGHT - LEFT
        );
        let x_ticks = ((x1 - x0) / x_step).round() as usize;
        for i in 0..=x_ticks {
            let xv = x0 + x_step * i as f64;
            let _ = writeln!(
                svg,
                "<text class=\"x-tick\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>",
                sx(xv),
                bottom + 16.0,
                strand_report::axis_label(xv, x_step)
            );
        }
        let y_ticks = (y1 / y_step).round() as usize;
        for i in 0..=y_ticks {
            let yv = y_step * i as f64;
            let _ = writeln!(
                svg,
                "<line x1=\"{LEFT}\" y1=\"{:.2}\" x2=\"{RIGHT}\" y2=\"{:.2}\" stroke=\"#e3e3e3\"/>",
                sy(yv),
                sy(yv)
            );
            let _ = writeln!(
                svg,
                "<text class=\"y-tick\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"end\">{}</text>",
                LEFT - 6.0,
                sy(yv) + 4.0,
                strand_report::axis_label(yv, y_step)
            );
        }
        let _ = writeln!(
            svg,
            "<text class=\"x-title\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>",
            0.5 * (LEFT + RIGHT),
            bottom + 36.0,
            escape(&axis_title(first))
        );
        let (cx, cy) = (LEFT - 56.0, top + 0.5 * PANEL);
        let _ = writeln!(
            svg,
            "<text x=\"{cx}\" y=\"{cy}\" text-anchor=\"middle\" transform=\"rotate(-90 {cx} {cy})\">{}</text>",
            escape(label)
        );
        let _ = writeln!(svg, "</g>");
        let _ = writeln!(svg, "<g class=\"curves\" data-panel=\"{kind}\">");
        for (k, line) in lines.iter().enumerate() {
            let slice = second.map_or(String::new(), |p| p.texts[k].clone());
            let dash = strand_report::dash_pattern(k)
                .map_or(String::new(), |d| format!(" stroke-dasharray=\"{d}\""));
            for (r, rod) in rods.iter().enumerate() {
                let mut d = String::new();
                let mut pen = false;
                for (x, o) in line {
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
                    "<path class=\"curve\" data-panel=\"{kind}\" data-rod=\"{}\" data-slice=\"{}\" d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.8\"{dash}/>",
                    escape(rod),
                    escape(&slice),
                    d.trim_end(),
                    COLOURS[r % COLOURS.len()]
                );
            }
        }
        for (x, o) in lines.iter().flatten() {
            if matches!(o, Outcome::Failed(_)) {
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
    let mut y = TOP + 8.0;
    for (r, rod) in rods.iter().enumerate() {
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
        y += 20.0;
    }
    if let Some(p) = second {
        y += 10.0;
        let _ = writeln!(
            svg,
            "<text x=\"{}\" y=\"{y}\">{}:</text>",
            RIGHT + 20.0,
            escape(&p.label)
        );
        y += 18.0;
        for (k, text) in p.texts.iter().enumerate() {
            let dash = strand_report::dash_pattern(k)
                .map_or(String::new(), |d| format!(" stroke-dasharray=\"{d}\""));
            let _ = writeln!(
                svg,
                "<line class=\"slice\" x1=\"{}\" y1=\"{y}\" x2=\"{}\" y2=\"{y}\" stroke=\"#333333\" stroke-width=\"2\"{dash}/>",
                RIGHT + 20.0,
                RIGHT + 48.0
            );
            let _ = writeln!(
                svg,
                "<text x=\"{}\" y=\"{}\">{}</text>",
                RIGHT + 56.0,
                y + 4.0,
                escape(text)
            );
            y += 18.0;
        }
    }
    if lines
        .iter()
        .flatten()
        .any(|(_, o)| matches!(o, Outcome::Failed(_)))
    {
        let _ = writeln!(
            svg,
            "<text class=\"failed-key\" x=\"{}\" y=\"{}\" fill=\"#cc0000\">× failed variant</text>",
            RIGHT + 20.0,
            y + 10.0
        );
    }
    let _ = writeln!(svg, "</g>");
    let _ = writeln!(svg, "</svg>");
    svg
}
