//! Per-hose plots of the sectional quantities against arc length: a force panel
//! (`|f|`, `f_t`, `f_s` in N) over a moment panel (`|m|`, `m_b`, `m_t` in N·m), one
//! colour per quantity, the reference result solid and the others dashed (the study
//! plot's dash patterns). Each curve is a `<path class="curve">` with `data-rod`,
//! `data-result` and `data-quantity` attributes.

use std::fmt::Write;

use super::format::sig;
use super::{ReportRun, arc_at};
use crate::plot::{
    CONTACT_COLOUR, Figure, Layout, Legend, LineStyle, Panel, close_figure, curve, dash_pattern,
    diamond, escape, line_colour, open_figure, tick_range, ticks,
};
use crate::result::RodResult;
use crate::study::{ArcOrigin, magnitude};

/// Two panels (forces over moments), the legend at the right.
const LAYOUT: Layout = Layout {
    width: 600.0,
    left: 72.0,
    right: 440.0,
    legend_x: 458.0,
    top: 52.0,
    panel_height: 170.0,
    gap: 72.0,
    bottom: 52.0,
};

/// A plotted quantity: `data-quantity` key, legend label, values of one rod.
type Quantity = (&'static str, &'static str, fn(&RodResult) -> Vec<f64>);

/// The force panel's quantities, N.
const FORCES: [Quantity; 3] = [
    ("force", "|f|", |r| {
        r.force_n.iter().map(magnitude).collect()
    }),
    ("tangential_force", "f_t", |r| r.tangential_force_n.clone()),
    ("shear_force", "f_s", |r| r.shear_force_n.clone()),
];

/// The moment panel's quantities, N·m.
const MOMENTS: [Quantity; 3] = [
    ("moment", "|m|", |r| {
        r.moment_nm.iter().map(magnitude).collect()
    }),
    ("bending_moment", "m_b", |r| r.bending_moment_nm.clone()),
    ("torsion", "m_t", |r| r.torsion_nm.clone()),
];

/// The contacts on rod `name` in every run: (run index, arc length from `origin` in
/// mm, contact force in N).
fn contact_points(
    name: &str,
    runs: &[ReportRun],
    rods: &[(usize, &RodResult)],
    origin: ArcOrigin,
) -> Vec<(usize, f64, f64)> {
    rods.iter()
        .flat_map(|(k, rod)| {
            runs[*k]
                .doc
                .contacts
                .iter()
                .filter(move |c| c.rod == name)
                .map(move |c| (*k, 1e3 * origin.measure(c.s_m, rod.length_m), c.force_n))
        })
        .filter(|(_, s, f)| s.is_finite() && f.is_finite())
        .collect()
}

/// Marks every contact in the force panel: a thin vertical line at its arc length and
/// a diamond at its force, with a hover title.
fn draw_contacts(
    svg: &mut String,
    panel: &Panel,
    name: &str,
    runs: &[ReportRun],
    contacts: &[(usize, f64, f64)],
) {
    for &(k, s, force) in contacts {
        let (x, y) = (panel.x(s), panel.y(force));
        let _ = writeln!(
            svg,
            "<g class=\"contact\" data-rod=\"{}\" data-result=\"{}\" data-s-mm=\"{s}\" data-force-n=\"{force}\"><title>{}: contact at s = {} mm, {} N</title><line x1=\"{x:.2}\" y1=\"{:.2}\" x2=\"{x:.2}\" y2=\"{:.2}\" stroke=\"{CONTACT_COLOUR}\" stroke-width=\"0.8\" stroke-dasharray=\"2 3\"/><path d=\"{}\" fill=\"{CONTACT_COLOUR}\" stroke=\"#ffffff\" stroke-width=\"0.8\"/></g>",
            escape(name),
            escape(runs[k].label),
            escape(runs[k].label),
            sig(s),
            sig(force),
            panel.top,
            panel.top + panel.height,
            diamond(x, y, 5.0)
        );
    }
}

/// A legend label of at most 18 characters.
fn short(label: &str) -> String {
    if label.chars().count() > 18 {
        label.chars().take(17).chain(['…']).collect()
    } else {
        label.to_string()
    }
}

/// The SVG (no XML declaration; for inlining) of rod `name` in every run that has it,
/// arc length from `origin`, in mm.
pub(crate) fn hose_svg(name: &str, runs: &[ReportRun], origin: ArcOrigin) -> String {
    let rods: Vec<(usize, &RodResult)> = runs
        .iter()
        .enumerate()
        .filter_map(|(k, run)| run.doc.rods.iter().find(|r| r.name == name).map(|r| (k, r)))
        .collect();
    let finite = |v: &f64| v.is_finite();
    let x_max = rods
        .iter()
        .map(|(_, r)| 1e3 * r.length_m)
        .filter(finite)
        .fold(0.0, f64::max);
    let (x_step, x_top) = ticks(x_max);
    let mut svg = String::with_capacity(16 * 1024);
    let data = [("rod", name)];
    let figure = Figure::new(LAYOUT.width, LAYOUT.height(2), name)
        .class("hose-plot")
        .data(&data);
    open_figure(&mut svg, &figure);
    let x_label = match origin {
        ArcOrigin::Start => "arc length s [mm] from the start",
        ArcOrigin::End => "arc length s [mm] from the junction",
    };
    let mut legend = Legend::new(LAYOUT.legend_x, LAYOUT.top + 4.0);
    legend.row = 18.0;
    for (p, (quantities, unit, title)) in
        [(&FORCES, "[N]", "forces"), (&MOMENTS, "[N·m]", "moments")]
            .into_iter()
            .enumerate()
    {
        let top = LAYOUT.panel_top(p);
        // series[q][i]: quantity q of rods[i].
        let series: Vec<Vec<Vec<f64>>> = quantities
            .iter()
            .map(|(_, _, values)| rods.iter().map(|(_, r)| values(r)).collect())
            .collect();
        // Contact forces share the force panel (N): (run, s in mm, force in N).
        let contacts: Vec<(usize, f64, f64)> = if p == 0 {
            contact_points(name, runs, &rods, origin)
        } else {
            Vec::new()
        };
        let all = series
            .iter()
            .flatten()
            .flatten()
            .copied()
            .chain(contacts.iter().map(|c| c.2));
        let (low, high) = all
            .filter(|v| v.is_finite())
            .fold((0.0f64, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
        let (y_step, y_min, y_max) = tick_range(low, high);
        let panel = LAYOUT.panel(p, [0.0, x_top], [y_min, y_max]);
        let y_label = format!("{title} {unit}");
        panel.draw_axes(&mut svg, x_step, y_step, x_label, &y_label, title);
        panel.draw_zero_line(&mut svg);
        legend.at_least(top + 4.0);
        for (q, (key, label, _)) in quantities.iter().enumerate() {
            for (values, (k, rod)) in series[q].iter().zip(&rods) {
                let points = values
                    .iter()
                    .enumerate()
                    .map(|(j, v)| (1e3 * arc_at(rod, origin, j), *v));
                let style = LineStyle {
                    colour: line_colour(q),
                    width: if q == 0 { 2.2 } else { 1.4 },
                    dash: dash_pattern(*k),
                };
                curve(
                    &mut svg,
                    &panel,
                    &[("rod", name), ("result", runs[*k].label), ("quantity", key)],
                    &style,
                    points,
                );
            }
            let style = LineStyle {
                colour: line_colour(q),
                width: 2.0,
                dash: None,
            };
            legend.line(&mut svg, &style, label, None);
        }
        if p == 0 && !contacts.is_empty() {
            draw_contacts(&mut svg, &panel, name, runs, &contacts);
            legend.skip(4.0);
            legend.marker(
                &mut svg,
                |x, y| diamond(x, y, 5.0),
                CONTACT_COLOUR,
                "contact force",
            );
        }
        if p == 0 {
            legend.skip(10.0);
            legend.heading(&mut svg, "results");
            for (k, run) in runs.iter().enumerate() {
                let style = LineStyle {
                    colour: "#333333",
                    width: 2.0,
                    dash: dash_pattern(k),
                };
                legend.line(&mut svg, &style, &short(run.label), None);
            }
            legend.skip(12.0);
        }
    }
    close_figure(&mut svg);
    svg
}
