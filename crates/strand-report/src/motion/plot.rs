//! `DIR/motion.svg`: the outputs of a motion against its parameter, stacked panels
//! drawn with [`crate::plot`]: peak `|f|` and peak `|m|` per
//! hose, the smallest bend radius per hose and the smallest clearance per obstacle,
//! with every event marked by a vertical line across the panels
//! (`<line class="event" data-kind=...>`). Curves are `<path class="curve">` with
//! `data-panel` and `data-series` attributes.

use std::fmt::Write;

use super::MotionRow;
use super::events::MotionEventRecord;
use super::table::{clearance_to, min_bend_radius, peak, union};
use crate::plot::{
    Figure, Layout, Legend, LineStyle, WIDE, close_figure, curve, escape, line_colour, open_figure,
    tick_range,
};

/// One panel per output, the legend of each at its right.
const LAYOUT: Layout = Layout {
    panel_height: 200.0,
    bottom: 98.0,
    ..WIDE
};

/// One panel's series: name and `(parameter, value)` points.
type Series = (String, Vec<(f64, f64)>);

/// The motion plot of `rows` (in order of the parameter) with `events` marked;
/// `parameter` and `unit` name the axis, lengths in the case's unit (`metres` m per
/// unit named `length_unit`).
pub fn motion_svg(
    title: &str,
    parameter: &str,
    unit: &str,
    rows: &[MotionRow],
    events: &[MotionEventRecord],
    metres: f64,
    length_unit: &str,
) -> String {
    let solved: Vec<(f64, &crate::ResultDoc)> = rows
        .iter()
        .filter_map(|r| r.doc.map(|d| (r.value, d)))
        .collect();
    let rods = union(solved.iter().map(|(_, d)| *d), |d| {
        d.rods.iter().map(|r| r.name.as_str()).collect()
    });
    let obstacles = union(solved.iter().map(|(_, d)| *d), |d| {
        d.clearance.iter().map(|c| c.with.as_str()).collect()
    });
    let per_rod = |f: &dyn Fn(&crate::RodResult) -> f64| -> Vec<Series> {
        rods.iter()
            .map(|r| {
                let points = solved
                    .iter()
                    .map(|(v, d)| (*v, d.rods.iter().find(|x| x.name == *r).map_or(f64::NAN, f)))
                    .collect();
                (r.to_string(), points)
            })
            .collect()
    };
    let mut panels: Vec<(String, String, Vec<Series>)> = vec![
        (
            "force".into(),
            "peak |f| [N]".into(),
            per_rod(&|r| peak(&r.force_n)),
        ),
        (
            "moment".into(),
            "peak |m| [N·m]".into(),
            per_rod(&|r| peak(&r.moment_nm)),
        ),
        (
            "bend_radius".into(),
            format!("min bend radius [{length_unit}]"),
            per_rod(&|r| {
                let b = min_bend_radius(&r.curvature_1pm) / metres;
                if b.is_finite() { b } else { f64::NAN }
            }),
        ),
    ];
    if !obstacles.is_empty() {
        let series = obstacles
            .iter()
            .map(|o| {
                let points = solved
                    .iter()
                    .map(|(v, d)| (*v, clearance_to(d, o).map_or(f64::NAN, |c| c / metres)))
                    .collect();
                (o.to_string(), points)
            })
            .collect();
        panels.push((
            "clearance".into(),
            format!("min clearance [{length_unit}]"),
            series,
        ));
    }
    let (x_min, x_max) = rows
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
            (a.min(r.value), b.max(r.value))
        });
    let (x_min, x_max) = if x_min < x_max {
        (x_min, x_max)
    } else {
        (x_min - 1.0, x_min + 1.0)
    };
    // Ticks at whole multiples of a nice step, the axis rounded outwards to them.
    let (x_step, x_min, x_max) = tick_range(x_min, x_max);
    let mut svg = String::new();
    let figure = Figure::new(LAYOUT.width, LAYOUT.height(panels.len()), title).class("motion");
    open_figure(&mut svg, &figure);
    let x_label = format!("{parameter} [{unit}]");
    for (k, (id, label, series)) in panels.iter().enumerate() {
        let values = series
            .iter()
            .flat_map(|(_, p)| p.iter().map(|(_, y)| *y))
            .filter(|y| y.is_finite());
        let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
            (a.min(y), b.max(y))
        });
        let (lo, hi) = if lo <= hi { (lo, hi) } else { (0.0, 1.0) };
        let (y_step, y_min, y_max) = tick_range(lo, hi);
        let panel = LAYOUT.panel(k, [x_min, x_max], [y_min, y_max]);
        panel.draw_axes(&mut svg, x_step, y_step, &x_label, label, label);
        let mut legend = Legend::new(LAYOUT.legend_x, panel.top + 18.0);
        legend.row = 16.0;
        for (s, (name, points)) in series.iter().enumerate() {
            let style = LineStyle {
                colour: line_colour(s),
                width: 1.6,
                dash: None,
            };
            curve(
                &mut svg,
                &panel,
                &[("panel", id), ("series", name)],
                &style,
                points.iter().copied(),
            );
            legend.line(
                &mut svg,
                &LineStyle {
                    width: 2.0,
                    ..style
                },
                name,
                None,
            );
        }
        for e in events {
            if !(x_min..=x_max).contains(&e.at) {
                continue;
            }
            let x = panel.x(e.at);
            let _ = writeln!(
                svg,
                "<line class=\"event\" data-kind=\"{}\" x1=\"{x:.2}\" y1=\"{:.2}\" x2=\"{x:.2}\" y2=\"{:.2}\" stroke=\"#555555\" stroke-dasharray=\"3 3\"><title>{}: {} at {} {}</title></line>",
                escape(&e.kind),
                panel.top,
                panel.top + panel.height,
                escape(&e.kind),
                escape(&e.what),
                e.at,
                escape(unit)
            );
        }
    }
    close_figure(&mut svg);
    svg
}
