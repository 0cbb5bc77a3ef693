//! The history plot of `strand optimize` (`history.svg`), drawn with [`crate::plot`]:
//! the objective per trial point (accepted points joined by the line, rejected and
//! failed ones hollow) over every variable as a fraction of its bounds, with a legend
//! of the variables.
//!
//! Each curve is a `<path class="curve">` with `data-panel` (`objective`,
//! `variables`) and, for variables, `data-variable`; each trial point a
//! `<circle class="trial" data-accepted="…">` whose `<title>` is its note.

use std::fmt::Write;

use crate::optimum::OptimumDoc;
use crate::plot::{
    Figure, Layout, Legend, LineStyle, axis_ticks, close_figure, curve, escape, line_colour,
    open_figure, tick_range, ticks,
};

/// Two panels (objective over variables), the legend of the variables at the right
/// (room for labels like `oil_cooler.position.z (15..95 mm)`).
const LAYOUT: Layout = Layout {
    width: 940.0,
    left: 84.0,
    right: 640.0,
    legend_x: 656.0,
    top: 56.0,
    panel_height: 200.0,
    gap: 76.0,
    bottom: 60.0,
};

/// The history plot of `doc`. Plain SVG 1.1, self-contained.
pub fn optimum_svg(doc: &OptimumDoc) -> String {
    let mut svg = String::new();
    let title = format!(
        "{}: minimise {} ({}; {} solves)",
        doc.case, doc.objective.name, doc.termination, doc.solves
    );
    open_figure(
        &mut svg,
        &Figure::new(LAYOUT.width, LAYOUT.height(2), &title).class("optimum-history"),
    );
    let iterations = doc.history.len().saturating_sub(1).max(1) as f64;
    let (x_step, x_max) = ticks(iterations);
    let objectives: Vec<f64> = doc.history.iter().filter_map(|h| h.objective).collect();
    let lo = objectives.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = objectives.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (y_step, y_min, y_max) = axis_ticks(lo, hi);
    let top = LAYOUT.panel(0, [0.0, x_max], [y_min, y_max]);
    top.draw_axes(
        &mut svg,
        x_step,
        y_step,
        "trial point",
        &format!("{} [{}]", doc.objective.name, doc.objective.unit),
        "objective",
    );
    let colour = line_colour(0);
    let style = |colour| LineStyle {
        colour,
        width: 2.0,
        dash: None,
    };
    curve(
        &mut svg,
        &top,
        &[("panel", "objective")],
        &style(colour),
        doc.history
            .iter()
            .filter(|h| h.accepted)
            .map(|h| (h.iteration as f64, h.objective.unwrap_or(f64::NAN))),
    );
    for h in &doc.history {
        let fill = if h.accepted { colour } else { "#ffffff" };
        let _ = writeln!(
            svg,
            "<circle class=\"trial\" data-accepted=\"{}\" cx=\"{:.2}\" cy=\"{:.2}\" r=\"4\" fill=\"{fill}\" stroke=\"{colour}\" stroke-width=\"1.5\"><title>{}</title></circle>",
            h.accepted,
            top.x(h.iteration as f64),
            top.y(h.objective.unwrap_or(y_min)),
            escape(&h.note)
        );
    }
    let (v_step, v_min, v_max) = tick_range(0.0, 1.0);
    let bottom = LAYOUT.panel(1, [0.0, x_max], [v_min, v_max]);
    bottom.draw_axes(
        &mut svg,
        x_step,
        v_step,
        "trial point",
        "fraction of the bounds",
        "variables (0: lower bound, 1: upper bound)",
    );
    let mut legend = Legend::new(LAYOUT.legend_x, bottom.top + 12.0);
    for (k, name) in doc.variables.iter().enumerate() {
        let Some(p) = doc.parameters.get(name) else {
            continue;
        };
        let style = style(line_colour(k + 1));
        curve(
            &mut svg,
            &bottom,
            &[("panel", "variables"), ("variable", name)],
            &style,
            doc.history.iter().map(|h| {
                (
                    h.iteration as f64,
                    h.values
                        .get(k)
                        .map_or(f64::NAN, |v| (v - p.lower) / (p.upper - p.lower)),
                )
            }),
        );
        legend.line(
            &mut svg,
            &style,
            &format!("{name} ({}..{} {})", p.lower, p.upper, p.unit),
            None,
        );
    }
    close_figure(&mut svg);
    svg
}
