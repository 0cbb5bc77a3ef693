//! `DIR/summary.svg`: the peak internal force `|f|` and moment `|m|` of every rod
//! against the first varied parameter, in two stacked panels (plain SVG 1.1, no
//! external resources). Colour tells the rod ([`strand_report::LINE_COLOURS`]); with
//! two or more parameters there is one line per value of the second parameter (its
//! dash pattern, named in the legend), the further parameters at their values nearest
//! the case's (said in the title). Failed variants are red crosses on the axis, and
//! the legend names them only when there are some. Each curve is a
//! `<path class="curve">` with `data-panel` (`force`, `moment`), `data-rod` and
//! `data-slice` (the second parameter's value as written, empty with one parameter).
//! Drawn with the shared [`strand_report::plot`] module (figure, axes, curves, legend).
use std::fmt::Write;

use strand_report::plot::{
    Figure, Layout, Legend, LineStyle, close_figure, curve, escape, line_colour, open_figure,
};

use super::manifest::Manifest;
use super::summary::{Outcome, peak};

/// Two panels (peak force over peak moment), the legend at the right.
const LAYOUT: Layout = Layout {
    width: 820.0,
    left: 84.0,
    right: 640.0,
    legend_x: 660.0,
    top: 56.0,
    panel_height: 220.0,
    gap: 76.0,
    bottom: 60.0,
};

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
    let mut svg = String::new();
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
    let figure = Figure::new(LAYOUT.width, LAYOUT.height(2), &title)
        .class("summary")
        .standalone();
    open_figure(&mut svg, &figure);
    if !fixed.is_empty() {
        let _ = writeln!(
            svg,
            "<text class=\"fixed\" x=\"{}\" y=\"40\">other parameters at their values nearest the case: {}</text>",
            LAYOUT.left,
            escape(&fixed.join(", "))
        );
    }
    for (p, (kind, label)) in [("force", "peak |f| [N]"), ("moment", "peak |m| [N·m]")]
        .iter()
        .enumerate()
    {
        let force = p == 0;

        let (_, y_hi) = range(
            lines
                .iter()
                .flatten()
                .flat_map(|(_, o)| rods.iter().map(|r| value(o, r, force)))
                .chain([0.0]),
        );
        let (y_step, _, y1) = strand_report::axis_ticks(0.0, y_hi);
        let panel = LAYOUT.panel(p, [x0, x1], [0.0, y1]);
        panel.draw_axes(&mut svg, x_step, y_step, &axis_title(first), label, "");
        let _ = writeln!(svg, "<g class=\"curves\" data-panel=\"{kind}\">");
        for (k, line) in lines.iter().enumerate() {
            let slice = second.map_or(String::new(), |p| p.texts[k].clone());
            for (r, rod) in rods.iter().enumerate() {
                let style = LineStyle {
                    colour: line_colour(r),
                    width: 1.8,
                    dash: strand_report::dash_pattern(k),
                };
                let points = line.iter().map(|(x, o)| (*x, value(o, rod, force)));
                let data = [("panel", *kind), ("rod", *rod), ("slice", slice.as_str())];
                curve(&mut svg, &panel, &data, &style, points);
            }
        }
        for (x, o) in lines.iter().flatten() {
            if matches!(o, Outcome::Failed(_)) {
                let (px, py) = (panel.x(*x), panel.bottom());
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
    let mut legend = Legend::new(LAYOUT.legend_x, LAYOUT.top + 12.0);
    for (r, rod) in rods.iter().enumerate() {
        let style = LineStyle {
            colour: line_colour(r),
            width: 3.0,
            dash: None,
        };
        legend.line(&mut svg, &style, rod, None);
    }
    if let Some(p) = second {
        legend.skip(10.0);
        legend.heading(&mut svg, &format!("{}:", p.label));
        for (k, text) in p.texts.iter().enumerate() {
            let style = LineStyle {
                colour: "#333333",
                width: 2.0,
                dash: strand_report::dash_pattern(k),
            };
            legend.line(&mut svg, &style, text, Some("slice"));
        }
    }
    if lines
        .iter()
        .flatten()
        .any(|(_, o)| matches!(o, Outcome::Failed(_)))
    {
        legend.skip(6.0);
        legend.note(&mut svg, "× failed variant", "#cc0000", "failed-key");
    }
    let _ = writeln!(svg, "</g>");
    close_figure(&mut svg);
    svg
}
