//! One solve and its result document: a case solved cold from its own initial guess,
//! a variant warm-started from the case's solution, and the [`ResultDoc`] of a solve
//! with contacts, clearances, limits and findings filled in, written like `strand
//! solve` writes it.
//!
//! A variant is warm-started from the converged solution of the case itself: every
//! rod's solved state is resampled onto the variant's rod by reference arc-length
//! fraction ([`strand_case::warm_start`]) and Newton runs without nested iteration.
//! When the base case did not converge the variant starts cold.

use std::path::{Path, PathBuf};

use strand_case::{BuiltCase, warm_start};
use strand_report::{ExportUnit, ResultDoc, Timing, collect, name_connectors, write_results_in};
use strand_solve::{Solution, SolverSettings};
use strand_system::SystemState;

use crate::error::{Result, StudyError};
use crate::format::number;

/// Checks that no hose of `built` starts inside a part or another hose, as `strand
/// check` and `strand solve` do before the first step (an input error naming the
/// place).
pub fn check_start(built: &BuiltCase) -> Result<()> {
    built
        .check_start()
        .map_err(|e| StudyError::solver(&built.origin, e))
}

/// Solves `built` from its own initial guess with its own settings. The solution says
/// whether it converged (`report.converged`) and its residual (N).
pub fn solve_cold(built: &BuiltCase) -> Result<Solution> {
    built
        .solve_from(built.initial.clone(), &built.settings)
        .map_err(|e| StudyError::solver(&built.origin, e))
}

/// Solves variant `built` from `base_state` (a solved state of `base`) resampled onto
/// its rods, without nested iteration (the start is already close).
pub fn solve_warm(
    base: &BuiltCase,
    base_state: &SystemState,
    built: &BuiltCase,
) -> Result<Solution> {
    let initial = warm_start(&base.model, base_state, &built.model);
    let settings = SolverSettings {
        nested_iteration: false,
        ..built.settings.clone()
    };
    built
        .solve_from(initial, &settings)
        .map_err(|e| StudyError::solver(&built.origin, e))
}

/// Solves variant `built` warm-started from `base_solution` if that converged,
/// otherwise cold. Returns the solution and whether it was warm-started.
pub fn solve_variant(
    base: &BuiltCase,
    base_solution: &Solution,
    built: &BuiltCase,
) -> Result<(Solution, bool)> {
    if base_solution.report.converged {
        Ok((solve_warm(base, &base_solution.state, built)?, true))
    } else {
        Ok((solve_cold(built)?, false))
    }
}

/// The warning (printed after `warning: `) that variant `name` of the case read from
/// `origin` starts from its own initial guess because the case itself did not
/// converge (residual `residual_n` N after `iterations`).
pub fn cold_start_warning(origin: &str, name: &str, residual_n: f64, iterations: usize) -> String {
    format!(
        "{origin}: the case itself did not converge (residual {} N after {iterations} iterations); \
         variant '{name}' starts from its own initial guess instead of a warm start",
        number(residual_n),
    )
}

/// `None` for a converged `doc`, else what `strand solve` warns about it (after
/// `warning: `): the case file `origin`, the `variant`, why the solve stopped and at
/// which residual (N), and for a stall whether it reached the model's round-off floor.
pub fn not_converged(origin: &str, variant: Option<&str>, doc: &ResultDoc) -> Option<String> {
    if doc.converged {
        return None;
    }
    // A stall: the residual it reached is this model's floor at this start.
    let floor = match doc.termination.as_str() {
        "stagnated" if doc.residual_n <= strand_solve::ROUND_OFF_STALL * doc.residual_floor_n => {
            format!(
                "; the residual stopped decreasing at {} N, the round-off floor of this \
                 model (estimated {} N): the state is the equilibrium to round-off; set \
                 tolerance_n to at least {} N to accept it",
                number(doc.residual_n),
                number(doc.residual_floor_n),
                number(doc.residual_n)
            )
        }
        "stagnated" => format!(
            "; the residual stopped decreasing at {} N while the energy stayed constant",
            number(doc.residual_n)
        ),
        "floor_above_loads" => format!(
            "; the round-off floor of this model ({} N) is not small against its loads \
             ({} N): its stiffnesses are too far apart for double precision (a section's \
             ea, ga, ei or gj far above what its material gives), so the state is no \
             equilibrium of these loads; check the sections' stiffnesses",
            number(doc.residual_floor_n),
            number(doc.applied_load_n)
        ),
        _ => String::new(),
    };
    Some(format!(
        "{origin}{}: not converged ({}; residual {} N > tolerance {} N after {} iterations{floor})",
        variant
            .map(|v| format!(" (variant '{v}')"))
            .unwrap_or_default(),
        doc.termination,
        number(doc.residual_n),
        number(doc.tolerance_n),
        doc.iterations
    ))
}

/// Mean stretch of a rod's centreline (its length over the reference length, less 1)
/// above which `strand solve` asks whether the length is right: cables and hoses do
/// not stretch by percents under their own weight; a rod a few percent shorter than
/// the path between its supports does (a 590 mm cable between pins 640 mm apart:
/// 7.9 %, 1.7 kN of tension).
pub const STRETCH_WARNING: f64 = 0.02;

/// Per rod of `doc` whose centreline is more than [`STRETCH_WARNING`] longer than its
/// reference length: what `strand solve` warns about it (after `warning: `), with the
/// case file `origin`, the stretch and the largest tension (N).
pub fn stretched_rods(origin: &str, doc: &ResultDoc) -> Vec<String> {
    doc.rods
        .iter()
        .filter_map(|rod| {
            let centreline: f64 = rod
                .position_m
                .windows(2)
                .map(|w| {
                    let d = [w[1][0] - w[0][0], w[1][1] - w[0][1], w[1][2] - w[0][2]];
                    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
                })
                .sum();
            let stretch = centreline / rod.length_m - 1.0;
            (stretch > STRETCH_WARNING).then(|| {
                let tension = rod.tangential_force_n.iter().copied().fold(0.0, f64::max);
                format!(
                    "{origin}: rod '{}' is stretched: its centreline is {} % longer than its \
                     length, with up to {} N of tension; is its `length` right (too short \
                     for the path between its supports)?",
                    rod.name,
                    number(100.0 * stretch),
                    number(tension)
                )
            })
        })
        .collect()
}

/// Contacts, clearances and the environment meshes' diagnostics and outlines (near
/// the hoses) of `solution` into `doc`, then the case's limits and the findings
/// against them ([`crate::findings::add_findings`]).
pub fn add_contacts(doc: &mut ResultDoc, built: &BuiltCase, solution: &Solution) -> Result<()> {
    strand_report::collect_environment(doc, &built.environment);
    strand_report::collect_outlines(doc, &built.environment);
    if let Some(contact) = built.contact() {
        strand_report::collect_contacts(doc, &built.model, solution, &contact)
            .map_err(|e| StudyError::Io(format!("{}: contacts: {e}", built.origin)))?;
    }
    crate::findings::add_findings(doc, built, solution)
}

/// The result document of `solution` of `built`, as `strand solve` writes it:
/// sectional quantities, reactions (connectors named), contacts, clearances,
/// limits and findings; `variant` names the variant (or pose), `base_iterations`
/// the Newton iterations of the case it was warm-started from (`None`: cold).
pub fn result_doc(
    built: &BuiltCase,
    solution: &Solution,
    timing: Timing,
    variant: Option<&str>,
    base_iterations: Option<usize>,
) -> Result<ResultDoc> {
    let mut doc = collect(&built.name, &built.model, solution, timing);
    add_contacts(&mut doc, built, solution)?;
    name_connectors(&mut doc, &built.connector_names);
    doc.variant = variant.map(str::to_string);
    doc.warm_start = base_iterations.is_some();
    doc.base_iterations = base_iterations;
    Ok(doc)
}

/// CAD out: the unit of the exported geometry (`rods.vtp`, `tubes.obj`, `tubes.stl`)
/// of `solve`, `study` and `batch`: `chosen` (`--export-unit`) if given, else the
/// case's length unit.
pub fn export_unit(built: &BuiltCase, chosen: Option<&ExportUnit>) -> ExportUnit {
    chosen
        .cloned()
        .unwrap_or_else(|| ExportUnit::new(built.length_unit.metres(), built.length_unit.symbol()))
}

/// Writes `doc` (a result of `built`) into `dir`: `result.json` (last), one CSV per
/// rod, `rods.vtp`, `tubes.obj`, `tubes.stl`, each atomically. Returns the written
/// paths. The geometry is in `unit` (default: the case's length unit, [`export_unit`]).
pub fn write_result(
    dir: &Path,
    doc: &ResultDoc,
    built: &BuiltCase,
    unit: Option<&ExportUnit>,
) -> Result<Vec<PathBuf>> {
    write_results_in(dir, doc, &export_unit(built, unit))
        .map_err(|e| StudyError::Io(format!("{}: results not written: {e}", built.origin)))
}

/// Creates `dir` and writes each `(name, content)` into it atomically (a temporary
/// file renamed: never a half-written file).
pub fn write_files(dir: &Path, files: &[(&str, &[u8])]) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| {
        StudyError::Io(format!(
            "{}: cannot create the output directory: {e}",
            dir.display()
        ))
    })?;
    for (name, content) in files {
        strand_report::write_atomic(&dir.join(name), content)
            .map_err(|e| StudyError::Io(format!("{}: {e}", dir.display())))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use strand_case::Case;
    use strand_report::{ResultDoc, Timing};
    use strand_solve::ROUND_OFF_STALL;

    use super::{not_converged, result_doc, solve_cold};

    /// The bundled Elastica case's `result.json`, solved as `strand solve` does.
    fn elastica_doc() -> ResultDoc {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../cases/elastica_fig3.ron");
        let built = Case::from_path(path).unwrap().build(None).unwrap();
        let solution = solve_cold(&built).unwrap();
        result_doc(&built, &solution, Timing::default(), None, None).unwrap()
    }

    #[test]
    fn a_stall_is_called_the_round_off_floor_only_within_its_multiple_of_the_estimate() {
        let mut doc = elastica_doc();
        assert!(doc.converged && doc.residual_floor_n > 0.0);
        assert_eq!(not_converged("elastica_fig3.ron", None, &doc), None);
        doc.converged = false;
        doc.termination = "stagnated".into();
        // Within the multiple: the state is the equilibrium to round-off, and the
        // warning says which tolerance accepts it.
        doc.residual_n = 0.9 * ROUND_OFF_STALL * doc.residual_floor_n;
        let warning = not_converged("elastica_fig3.ron", Some("v1"), &doc).unwrap();
        assert!(warning.starts_with("elastica_fig3.ron (variant 'v1'): not converged (stagnated"));
        assert!(warning.contains("round-off floor"), "{warning}");
        assert!(warning.contains("set tolerance_n to at least"), "{warning}");
        // Beyond it: a stall, not the floor.
        doc.residual_n = 1.1 * ROUND_OFF_STALL * doc.residual_floor_n;
        let warning = not_converged("elastica_fig3.ron", None, &doc).unwrap();
        assert!(!warning.contains("round-off"), "{warning}");
        assert!(
            warning.contains("while the energy stayed constant"),
            "{warning}"
        );
    }
}
