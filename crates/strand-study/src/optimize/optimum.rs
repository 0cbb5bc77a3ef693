//! An [`Optimum`] as `optimum.json` ([`strand_report::OptimumDoc`]).

use strand_report::{
    OptimumConstraint, OptimumDoc, OptimumIterate, OptimumObjective, OptimumParameter,
};

use super::problem::unit_of;
use super::{Optimum, Problem};

fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// The document of `optimum`, a run of `problem` on case `case`; `optimal_case` is the
/// file name of the optimal case written next to it, `time_s` the run's wall time.
pub fn document(
    case: &str,
    problem: &Problem,
    optimum: &Optimum,
    optimal_case: &str,
    time_s: f64,
) -> OptimumDoc {
    let objective_unit = problem.objective.unit();
    let mut constraints: Vec<OptimumConstraint> = optimum
        .constraints
        .iter()
        .map(|c| OptimumConstraint {
            name: c.name.clone(),
            kind: "constraint".into(),
            output: c.output.clone(),
            value: c.value,
            bound: c.bound,
            satisfied: c.satisfied,
            active: c.active,
            multiplier: c.multiplier,
            d_objective_d_bound: c.d_objective_d_bound,
            multiplier_unit: format!("{objective_unit}/{}", unit_of(&c.output)),
            in_contact: c.in_contact,
        })
        .collect();
    for b in &optimum.bounds {
        let v = problem.variables.iter().find(|v| v.name == b.variable);
        let unit = v.map_or("", |v| v.unit.as_str());
        constraints.push(OptimumConstraint {
            name: format!(
                "{} {} {}{unit}",
                b.variable,
                if b.upper { "<=" } else { ">=" },
                b.value
            ),
            kind: if b.upper {
                "upper_bound"
            } else {
                "lower_bound"
            }
            .into(),
            output: String::new(),
            value: b.value,
            bound: b.value,
            satisfied: true,
            active: true,
            multiplier: b.multiplier,
            d_objective_d_bound: if b.upper { -b.multiplier } else { b.multiplier },
            multiplier_unit: format!("{objective_unit}/{unit}"),
            in_contact: false,
        });
    }
    OptimumDoc {
        case: case.to_string(),
        converged: optimum.converged,
        termination: serde_json::to_value(optimum.termination)
            .ok()
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_default(),
        message: optimum.message.clone(),
        variables: problem.variables.iter().map(|v| v.name.clone()).collect(),
        parameters: problem
            .variables
            .iter()
            .zip(&optimum.values)
            .map(|(v, &value)| {
                (
                    v.name.clone(),
                    OptimumParameter {
                        value,
                        unit: v.unit.clone(),
                        lower: v.value(v.lower),
                        upper: v.value(v.upper),
                        offset: v.origin.is_none(),
                    },
                )
            })
            .collect(),
        objective: OptimumObjective {
            name: problem.objective.name(),
            value: optimum.objective,
            unit: objective_unit.to_string(),
            attained_by: optimum.attained_by.clone(),
        },
        active_constraints: constraints.iter().filter(|c| c.active).cloned().collect(),
        constraints,
        outputs: optimum
            .outputs
            .iter()
            .map(|o| (o.name.clone(), o.value))
            .collect(),
        solves: optimum.solves,
        iterations: optimum.iterations,
        newton_iterations: optimum.newton_iterations,
        residual_n: optimum.residual_n,
        non_smooth: optimum.non_smooth.clone(),
        history: optimum
            .history
            .iter()
            .map(|h| OptimumIterate {
                iteration: h.iteration,
                solves: h.solves,
                values: h.values.clone(),
                objective: finite(h.objective),
                violation: finite(h.violation),
                radius: h.radius,
                ratio: h.ratio.and_then(finite),
                accepted: h.accepted,
                note: h.note.clone(),
            })
            .collect(),
        optimal_case: optimal_case.to_string(),
        time_s,
    }
}
