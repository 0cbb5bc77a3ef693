//! An [`Optimum`] as `optimum.json` ([`strand_report::OptimumDoc`]).

use strand_report::{OptimumDoc, OptimumObjective, OptimumParameter};

use super::{Optimum, Problem};

/// The document of `optimum`, a run of `problem` on case `case`; `optimal_case` is the
/// file name of the optimal case written next to it, `time_s` the run's wall time.
pub fn document(
    case: &str,
    problem: &Problem,
    optimum: &Optimum,
    optimal_case: &str,
    time_s: f64,
) -> OptimumDoc {
    let constraints = optimum.constraints.clone();
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
            unit: problem.objective.unit().to_string(),
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
        history: optimum.history.clone(),
        optimal_case: optimal_case.to_string(),
        time_s,
    }
}
