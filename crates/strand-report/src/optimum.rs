//! `optimum.json` as other tools read it ([`OptimumDoc`], written by `strand
//! optimize`), its history as CSV ([`OptimumDoc::history_csv`]) and as an SVG
//! ([`crate::optimum_svg`]): the objective per trial point (accepted points joined, rejected
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
