//! The code paths of `strand solve`, `strand batch` and `strand sensitivity` as plain
//! functions for other front ends (the Python package in `python/`): nothing here
//! prints or draws, every error is the [`Failure`] whose message `strand` prints after
//! `error: `, and the result documents are those `strand` writes as `result.json`.
//!
//! Lengths are in metres and forces in newtons inside results (every key of a
//! [`ResultDoc`] carries its unit); `--vary` values are in the case's length unit
//! unless a unit is written.
//!
//! ```
//! use strand_case::Case;
//! use strand_cli::library::{result_doc, solve_cold};
//! let case = Case::from_path(concat!(env!("CARGO_MANIFEST_DIR"), "/../../cases/elastica_fig2.ron")).unwrap();
//! strand_cli::library::check_case(&case).unwrap();
//! let built = case.build(Some(8)).unwrap();
//! let solution = solve_cold(&built).unwrap();
//! let doc = result_doc(&built, &solution, Default::default(), None, None).unwrap();
//! assert!(doc.converged && doc.residual_n <= doc.tolerance_n);
//! assert_eq!(doc.rods[0].position_m.len(), 9); // 8 segments, 9 vertices (m)
//! ```

use std::path::Path;
use std::time::Instant;

use strand_case::schema::VariantChange;
use strand_case::{BuiltCase, Case, warm_start};
use strand_report::{ResultDoc, SensitivityDoc, Timing, collect, name_connectors};
use strand_solve::{Solution, SolverSettings};
use strand_system::SystemState;

pub use crate::args::Keep;
pub use crate::commands::Failure;
use crate::commands::solver_failure;
use crate::summary::number;
use crate::{Exit, batch};

/// Checks `case` against the limits `strand` enforces before building (sizes of
/// names, numbers of segments, …), as every command does after reading a case.
pub fn check_case(case: &Case) -> Result<(), Failure> {
    crate::limits::check_case(case)
}

/// Checks that no hose of `built` starts inside a part or another hose, as `strand
/// check` and `strand solve` do before the first step (exit 2 naming the place).
pub fn check_start(built: &BuiltCase) -> Result<(), Failure> {
    built
        .check_start()
        .map_err(|e| solver_failure(&built.origin, e))
}

/// Solves `built` from its own initial guess with its own settings (`strand solve`).
/// A solve that ran but did not converge is `Ok`, with `report.converged == false`;
/// `Err` means it could not start (exit 2 for a hose starting inside a part or bad
/// solver settings, else 1).
pub fn solve_cold(built: &BuiltCase) -> Result<Solution, Failure> {
    built
        .solve_from(built.initial.clone(), &built.settings)
        .map_err(|e| solver_failure(&built.origin, e))
}

/// Solves `built` from `base_state`, a solved state of the case `base`, resampled
/// onto `built`'s rods by reference arc-length fraction, without nested iteration
/// (the start is already close): the warm start of `strand solve --variant`.
pub fn solve_warm(
    base: &BuiltCase,
    base_state: &SystemState,
    built: &BuiltCase,
) -> Result<Solution, Failure> {
    let initial = warm_start(&base.model, base_state, &built.model);
    let settings = SolverSettings {
        nested_iteration: false,
        ..built.settings.clone()
    };
    built
        .solve_from(initial, &settings)
        .map_err(|e| solver_failure(&built.origin, e))
}

/// The warning `strand solve --variant NAME` prints (after `warning: `) when the case
/// read from `origin` did not converge (residual `residual_n` N after `iterations`)
/// and variant `name` therefore starts cold.
pub fn cold_start_warning(origin: &str, residual_n: f64, iterations: usize, name: &str) -> String {
    format!(
        "{origin}: the case itself did not converge (residual {} N after {iterations} iterations); \
         variant '{name}' starts from its own initial guess instead of a warm start",
        number(residual_n),
    )
}

/// The result document `strand solve` writes as `result.json` for `solution` of
/// `built`: sectional quantities, reactions, contacts, clearances, environment,
/// findings and provenance. `variant` names a variant; `base_iterations` is the
/// iteration count of the solve it was warm-started from (`None`: a cold start).
pub fn result_doc(
    built: &BuiltCase,
    solution: &Solution,
    timing: Timing,
    variant: Option<&str>,
    base_iterations: Option<usize>,
) -> Result<ResultDoc, Failure> {
    let mut doc = collect(&built.name, &built.model, solution, timing);
    crate::commands::add_contacts(&mut doc, built, solution)?;
    name_connectors(&mut doc, &built.connector_names);
    doc.variant = variant.map(str::to_string);
    doc.warm_start = base_iterations.is_some();
    doc.base_iterations = base_iterations;
    Ok(doc)
}

/// `None` for a converged `doc`, else what `strand solve` warns about it: the case
/// file `origin`, the `variant`, why the solve stopped and at which residual (N), and
/// for a stall whether it reached the model's round-off floor.
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

/// The change `ITEM=VALUE` of `case` in the grammar of `strand batch --vary`
/// (`hose2.length=+30mm`: an offset; `tee.mass=1.5kg`: a value; a vector component
/// as `oil_cooler.position.z=+5mm`), with exactly one value. The error names the
/// case file and says what to write, as `strand batch` does.
pub fn parse_change(case: &Case, text: &str) -> Result<VariantChange, Failure> {
    let vary = batch::spec::Vary::parse(text, &case.file)
        .map_err(|e| batch::invalid(format!("{}: {e}", case.origin)))?;
    if vary.values.len() != 1 {
        return Err(batch::invalid(format!(
            "{}: {text}: a change takes one value, not {} (hint: run a batch over a range of values)",
            case.origin,
            vary.values.len()
        )));
    }
    Ok(vary.change(0))
}

/// What to run as a batch: the options of `strand batch` that change its results.
#[derive(Clone, Debug)]
pub struct BatchRequest<'a> {
    /// The varied parameters, `ITEM=VALUES` each (`hose2.length=+0mm..+99mm:1mm`).
    pub vary: &'a [String],
    /// The batch directory (`--out`): `batch.json`, `variants/`, `summary.csv`.
    pub out: &'a Path,
    /// Worker threads (`--jobs`; default: the available cores, at most).
    pub jobs: Option<usize>,
    /// Segments of every rod (`--segments`; default: the case's).
    pub segments: Option<usize>,
    /// Files kept per variant (`--keep`).
    pub keep: Keep,
}

/// A finished batch: `summary.csv` and whether every variant was solved.
#[derive(Clone, Debug, PartialEq)]
pub struct BatchRun {
    /// The text of `DIR/summary.csv`, one row per variant in grid order.
    pub summary_csv: String,
    /// Whether every variant converged (`strand batch` exits 0; else 3).
    pub all_solved: bool,
}

/// `strand batch` of `case` (already read and checked) with `request`, nothing
/// printed and no progress bar drawn unless stderr is a terminal: the same runner,
/// warm-start tree and summary. Re-running into the same directory resumes it.
pub fn batch(case: &Case, request: &BatchRequest) -> Result<BatchRun, Failure> {
    let options = batch::BatchOptions {
        case: Path::new(&case.origin),
        vary: request.vary,
        out: request.out,
        jobs: request.jobs,
        force_jobs: false,
        yes: true,
        keep: request.keep,
        shard: None,
        segments: request.segments,
        retry_failed: false,
        // Only the exported geometry (`--keep all`) depends on it, not the summary.
        export_unit: None,
    };
    let exit = batch::run_case(
        case,
        &options,
        Instant::now(),
        &mut std::io::sink(),
        &mut std::io::sink(),
    )?;
    let path = request.out.join("summary.csv");
    let summary_csv = std::fs::read_to_string(&path).map_err(|e| Failure {
        exit: Exit::Failure,
        message: format!("cannot read {}: {e}", path.display()),
    })?;
    Ok(BatchRun {
        summary_csv,
        all_solved: exit == Exit::Success,
    })
}

/// `strand sensitivity`'s document (`sensitivity.json`) for `case`, solved cold with
/// its own segments, with respect to the parameters `names` (`hose2.length`,
/// `tee.mass`, …). A case that does not converge is an error (exit 3): there is no
/// equilibrium to differentiate.
pub fn sensitivity(case: &Case, names: &[String]) -> Result<SensitivityDoc, Failure> {
    crate::sensitivity::parameters(case, names)?;
    let built = case.build(None)?;
    let solution = solve_cold(&built)?;
    crate::sensitivity::sensitivities(case, names, &solution)
}
