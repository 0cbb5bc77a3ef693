//! `optimum.json` as other tools read it ([`OptimumDoc`], written by `strand
//! optimize`), its history as CSV ([`OptimumDoc::history_csv`]) and as an SVG
//! ([`optimum_svg`]): the objective per trial point (accepted points joined, rejected
//! ones hollow) over the variables, each as a fraction of its bounds.
//!
//! ```text
//! {"converged": true, "termination": "converged",
//!  "parameters": {"hose2.length": {"value": 281.4, "unit": "mm", "lower": 150, "upper": 300}},
//!  "objective": {"name": "peak_force", "value": 6.59, "unit": "N", "attained_by": […]},
//!  "active_constraints": [{"name": "clearance>=10mm", "output": "hose3.clearance_m.brackets",
//!                          "multiplier": …, "d_objective_d_bound": …, …}],
//!  "solves": 9, "history": […], …}
//! ```

use std::collections::BTreeMap;
use std::fmt::Write;

use serde::{Deserialize, Serialize};

use crate::svg::{Panel, axis_ticks, escape, path_data, tick_range};

/// A design variable at the optimum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OptimumParameter {
    /// The value (the case's value plus the offset; the offset when `offset`).
    pub value: f64,
    /// Its unit (`mm`, `kg`, …).
    pub unit: String,
    /// The lower bound, same unit.
    pub lower: f64,
    /// The upper bound, same unit.
    pub upper: f64,
    /// The values are offsets from the case (the case states no value of the item).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub offset: bool,
}

/// The objective at the optimum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OptimumObjective {
    /// As given to `--minimize`.
    pub name: String,
    /// Its value.
    pub value: f64,
    /// Its unit.
    pub unit: String,
    /// The pieces that attain it (two or more at a kink of a min–max).
    pub attained_by: Vec<String>,
}

/// A constraint row or a variable bound at the optimum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OptimumConstraint {
    /// As given to `--subject-to` (`clearance>=10mm`), or `<variable> >= <bound>`.
    pub name: String,
    /// `constraint`, `lower_bound` or `upper_bound`.
    pub kind: String,
    /// The output it bounds (empty for a variable bound).
    pub output: String,
    /// The output's (variable's) value, SI (variable unit).
    pub value: f64,
    /// The bound, same unit.
    pub bound: f64,
    /// Whether it holds.
    pub satisfied: bool,
    /// Whether it is active.
    pub active: bool,
    /// Its KKT multiplier (≥ 0) in `multiplier_unit`.
    pub multiplier: f64,
    /// How much the optimum's objective changes per unit the bound rises.
    pub d_objective_d_bound: f64,
    /// The multiplier's unit (objective unit per bound unit, e.g. `N/m`).
    pub multiplier_unit: String,
    /// The rod pressed on the obstacle (the row was the contact force).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub in_contact: bool,
}

/// One trial point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OptimumIterate {
    /// 0: the start.
    pub iteration: usize,
    /// Equilibrium solves so far.
    pub solves: usize,
    /// The variables' values, in the order of [`OptimumDoc::variables`].
    pub values: Vec<f64>,
    /// The objective (`None`: the equilibrium failed there).
    pub objective: Option<f64>,
    /// The largest constraint violation as a fraction of its bound.
    pub violation: Option<f64>,
    /// The trust radius after the trial, as a fraction of the bounds' widths.
    pub radius: f64,
    /// Actual over predicted fall of the merit.
    pub ratio: Option<f64>,
    /// Accepted or rejected.
    pub accepted: bool,
    /// What happened.
    pub note: String,
}

/// `optimum.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OptimumDoc {
    /// The case.
    pub case: String,
    /// Whether the run met its convergence test.
    pub converged: bool,
    /// `converged`, `infeasible`, `non_smooth`, `max_iterations`, `max_solves`.
    pub termination: String,
    /// The ending in words.
    pub message: String,
    /// The variables in the order given.
    pub variables: Vec<String>,
    /// The optimum's variables.
    pub parameters: BTreeMap<String, OptimumParameter>,
    /// The objective.
    pub objective: OptimumObjective,
    /// The active constraints and bounds.
    pub active_constraints: Vec<OptimumConstraint>,
    /// Every constraint row.
    pub constraints: Vec<OptimumConstraint>,
    /// Every output at the optimum (names as in `sensitivity.json`).
    pub outputs: BTreeMap<String, f64>,
    /// Equilibrium solves in all.
    pub solves: usize,
    /// Trial points.
    pub iterations: usize,
    /// Newton iterations of all solves.
    pub newton_iterations: usize,
    /// The optimum's equilibrium residual, N.
    pub residual_n: f64,
    /// Where the gradient model failed (peak switches, contact changes).
    pub non_smooth: Vec<String>,
    /// Every trial point.
    pub history: Vec<OptimumIterate>,
    /// The optimal case's file (next to `optimum.json`).
    pub optimal_case: String,
    /// Wall time of the run, s.
    pub time_s: f64,
}

fn number(x: Option<f64>) -> String {
    x.filter(|v| v.is_finite())
        .map(|v| format!("{v:e}"))
        .unwrap_or_default()
}

impl OptimumDoc {
    /// `history.csv`: `iteration,solves,<variable> [unit]…,objective [unit],violation,
    /// radius,ratio,accepted,note`.
    pub fn history_csv(&self) -> String {
        let mut s = String::from("iteration,solves");
        for v in &self.variables {
            let unit = self.parameters.get(v).map_or("", |p| p.unit.as_str());
            let _ = write!(s, ",{v} [{unit}]");
        }
        let _ = writeln!(
            s,
            ",{} [{}],violation,radius,ratio,accepted,note",
            self.objective.name, self.objective.unit
        );
        for h in &self.history {
            let _ = write!(s, "{},{}", h.iteration, h.solves);
            for v in &h.values {
                let _ = write!(s, ",{v:e}");
            }
            let _ = writeln!(
                s,
                ",{},{},{:e},{},{},\"{}\"",
                number(h.objective),
                number(h.violation),
                h.radius,
                number(h.ratio),
                h.accepted,
                h.note.replace('"', "'")
            );
        }
        s
    }
}

const WIDTH: f64 = 820.0;
const LEFT: f64 = 84.0;
const RIGHT: f64 = 640.0;
const TOP: f64 = 56.0;
const PANEL: f64 = 200.0;
const GAP: f64 = 76.0;

/// The history plot: the objective per trial point (accepted points joined by the
/// line, rejected and failed ones hollow), and below it every variable as a fraction
/// of its bounds. Plain SVG 1.1; each curve is a `<path class="curve">` with
/// `data-panel` (`objective`, `variables`) and, for variables, `data-variable`.
pub fn optimum_svg(doc: &OptimumDoc) -> String {
    let height = TOP + 2.0 * PANEL + GAP + 60.0;
    let mut svg = String::new();
    let _ = writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{WIDTH}\" height=\"{height}\" viewBox=\"0 0 {WIDTH} {height}\" font-family=\"sans-serif\" font-size=\"12\">"
    );
    let _ = writeln!(
        svg,
        "<rect width=\"{WIDTH}\" height=\"{height}\" fill=\"#ffffff\"/>\n<text x=\"{LEFT}\" y=\"24\" font-size=\"15\" font-weight=\"bold\">{}: minimise {} ({}; {} solves)</text>",
        escape(&doc.case),
        escape(&doc.objective.name),
        escape(&doc.termination),
        doc.solves
    );
    let iterations = doc.history.len().saturating_sub(1).max(1) as f64;
    let (x_step, _) = crate::svg::ticks(iterations);
    let x_max = (iterations / x_step).ceil() * x_step;
    let objectives: Vec<f64> = doc.history.iter().filter_map(|h| h.objective).collect();
    let lo = objectives.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = objectives.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (y_step, y_min, y_max) = axis_ticks(lo, hi);
    let top_panel = Panel {
        left: LEFT,
        right: RIGHT,
        top: TOP,
        height: PANEL,
        x_min: 0.0,
        x_max,
        y_min,
        y_max,
    };
    top_panel.draw_axes(
        &mut svg,
        x_step,
        y_step,
        "trial point",
        &format!("{} [{}]", doc.objective.name, doc.objective.unit),
        "objective",
    );
    let accepted = doc
        .history
        .iter()
        .filter(|h| h.accepted)
        .map(|h| (h.iteration as f64, h.objective.unwrap_or(f64::NAN)));
    let _ = writeln!(
        svg,
        "<path class=\"curve\" data-panel=\"objective\" d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"/>",
        path_data(&top_panel, accepted),
        crate::palette::LINE_COLOURS[0]
    );
    for h in &doc.history {
        let y = h.objective.unwrap_or(y_min);
        let fill = if h.accepted {
            crate::palette::LINE_COLOURS[0]
        } else {
            "#ffffff"
        };
        let _ = writeln!(
            svg,
            "<circle class=\"trial\" data-accepted=\"{}\" cx=\"{:.2}\" cy=\"{:.2}\" r=\"4\" fill=\"{fill}\" stroke=\"{}\" stroke-width=\"1.5\"><title>{}</title></circle>",
            h.accepted,
            top_panel.x(h.iteration as f64),
            top_panel.y(y),
            crate::palette::LINE_COLOURS[0],
            escape(&h.note)
        );
    }
    let (v_step, v_min, v_max) = tick_range(0.0, 1.0);
    let bottom = Panel {
        top: TOP + PANEL + GAP,
        y_min: v_min,
        y_max: v_max,
        ..top_panel
    };
    bottom.draw_axes(
        &mut svg,
        x_step,
        v_step,
        "trial point",
        "fraction of the bounds",
        "variables (0: lower bound, 1: upper bound)",
    );
    for (k, name) in doc.variables.iter().enumerate() {
        let Some(p) = doc.parameters.get(name) else {
            continue;
        };
        let colour = crate::palette::LINE_COLOURS[(k + 1) % crate::palette::LINE_COLOURS.len()];
        let points = doc.history.iter().map(|h| {
            (
                h.iteration as f64,
                h.values
                    .get(k)
                    .map_or(f64::NAN, |v| (v - p.lower) / (p.upper - p.lower)),
            )
        });
        let _ = writeln!(
            svg,
            "<path class=\"curve\" data-panel=\"variables\" data-variable=\"{}\" d=\"{}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"2\"/>",
            escape(name),
            path_data(&bottom, points)
        );
        let y = TOP + PANEL + GAP + 16.0 * k as f64 + 8.0;
        let _ = writeln!(
            svg,
            "<line x1=\"{:.0}\" y1=\"{y:.0}\" x2=\"{:.0}\" y2=\"{y:.0}\" stroke=\"{colour}\" stroke-width=\"2\"/><text x=\"{:.0}\" y=\"{:.0}\">{} ({}..{} {})</text>",
            RIGHT + 16.0,
            RIGHT + 40.0,
            RIGHT + 46.0,
            y + 4.0,
            escape(name),
            p.lower,
            p.upper,
            escape(&p.unit)
        );
    }
    svg.push_str("</svg>\n");
    svg
}
