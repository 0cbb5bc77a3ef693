//! One variant of a batch, built and solved: warm from the start predicted from its
//! solved neighbours, cold when it has none or when the warm start does not converge.
//!
//! A warm-started variant is built without the default guess and with its
//! neighbour's symbolic phase ([`Case::build_with_changes_for_start`]): computing the
//! hanging guess and checking it against the environment was about a tenth of a
//! batch's time, and a warm solve never reads it. The cold build, with its guess, is
//! made only when the warm solve fails; it builds the same model.

use strand_case::schema::VariantChange;
use strand_case::{BuiltCase, Case};
use strand_solve::{Solution, SolverSettings};
use strand_system::SystemState;

use super::predict::Solved;
use super::state::FailedVariant;

/// Where a warm-started variant begins: its solved `neighbour` (whose state stands in
/// for the build's `initial` and whose model lends its symbolic phase) and `predict`,
/// the variant's start from its built model.
pub(crate) struct WarmStart<'a, P> {
    /// The solved neighbour the start is predicted from.
    pub neighbour: &'a Solved,
    /// The start of the built variant.
    pub predict: P,
}

/// Builds the variant `id` (the case with `changes`, `segments` overriding every rod's
/// segments) and solves it: from `warm`'s prediction when given (without nested
/// iteration), else — or when that does not converge — cold from the build's default
/// guess. Returns the built variant, its converged solution and whether it came from
/// the warm start; a failure names the stage and, for a solve, its residual and
/// iterations (those of the warm attempt included).
pub(crate) fn build_and_solve<P: FnOnce(&BuiltCase) -> SystemState>(
    case: &Case,
    id: &str,
    changes: &[VariantChange],
    segments: Option<usize>,
    warm: Option<WarmStart<'_, P>>,
) -> Result<(BuiltCase, Solution, bool), FailedVariant> {
    let warm_given = warm.is_some();
    let mut spent = 0;
    if let Some(WarmStart { neighbour, predict }) = warm
        && let Ok(built) = case.build_with_changes_for_start(
            id,
            changes,
            segments,
            &neighbour.state,
            Some(&neighbour.built.model),
        )
    {
        let initial = predict(&built);
        let settings = SolverSettings {
            nested_iteration: false,
            ..built.settings.clone()
        };
        match built.solve_from(initial, &settings) {
            Ok(solution) if solution.report.converged => return Ok((built, solution, true)),
            Ok(solution) => spent = solution.report.iterations,
            Err(_) => {}
        }
    }
    // A build that fails fails here again, with the cold build's message.
    let built = case
        .build_with_changes(id, changes, segments)
        .map_err(|e| FailedVariant {
            id: id.to_string(),
            stage: "build".into(),
            reason: one_line(&e.to_string()),
            residual_n: None,
            iterations: None,
            warm_start: false,
            time_s: 0.0,
        })?;
    solve_cold(id, built, warm_given, spent)
}

/// The cold solve of `built` from its default guess, after a warm attempt (`warm`)
/// that spent `spent` iterations without converging.
fn solve_cold(
    id: &str,
    built: BuiltCase,
    warm: bool,
    spent: usize,
) -> Result<(BuiltCase, Solution, bool), FailedVariant> {
    let fail = |reason: String, solution: Option<&Solution>| FailedVariant {
        id: id.to_string(),
        stage: "solve".into(),
        reason,
        residual_n: solution.map(|s| s.report.residual.combined_n),
        iterations: solution.map(|s| s.report.iterations + spent),
        warm_start: warm,
        time_s: 0.0,
    };
    match built.solve_from(built.initial.clone(), &built.settings) {
        Ok(mut solution) if solution.report.converged => {
            solution.report.iterations += spent;
            Ok((built, solution, false))
        }
        Ok(solution) => {
            let report = &solution.report;
            let termination = match serde_json::to_value(report.termination) {
                Ok(serde_json::Value::String(s)) => s,
                _ => format!("{:?}", report.termination),
            };
            Err(fail(
                format!(
                    "not converged ({termination}): residual {:.3e} N > tolerance {:.3e} N after {} iterations{}",
                    report.residual.combined_n,
                    report.tolerance_n,
                    report.iterations,
                    if warm {
                        " (cold, after the warm start failed)"
                    } else {
                        ""
                    }
                ),
                Some(&solution),
            ))
        }
        Err(e) => Err(fail(format!("the solver could not start: {e}"), None)),
    }
}

/// A message on one line (the lines of a multi-line error joined by `; `), for tables.
fn one_line(text: &str) -> String {
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

#[cfg(test)]
#[path = "variant_tests.rs"]
mod tests;
