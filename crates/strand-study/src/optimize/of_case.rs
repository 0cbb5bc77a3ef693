//! `strand optimize`'s run of a case, everything but printing and writing files: the
//! problem stated by the options, the optimisation and its outputs
//! ([`super::OptimumOutputs`]). The command line and the Python package are front
//! ends of [`optimize_case`].

use std::time::Instant;

use strand_case::Case;

use super::{
    OptimizeError, OptimizeSettings, Optimum, OptimumIterate, OptimumOutputs, Problem, optimize,
    optimum_outputs,
};
use crate::error::{ErrorKind, Result, StudyError};

/// What [`optimize_case`] reports while it runs.
pub enum OptimizeProgress<'a> {
    /// The problem, stated and checked, before the first solve.
    Start(&'a Problem),
    /// One trial point.
    Iterate(&'a Problem, &'a OptimumIterate),
}

/// A run of [`optimize_case`].
pub struct OptimizeRun {
    /// The problem the options state.
    pub problem: Problem,
    /// The optimum found.
    pub optimum: Optimum,
    /// Its documents: `optimum.json`, the optimal case, the optimum's result.
    pub outputs: OptimumOutputs,
}

/// `error` as the error of the study, its message and kind (exit status) kept;
/// `origin` (the case file) goes before the message when given.
fn study_error(error: OptimizeError, origin: Option<&str>) -> StudyError {
    let message = match origin {
        // A case error names its file itself.
        Some(origin) if !matches!(error, OptimizeError::Case(_)) => format!("{origin}: {error}"),
        _ => error.to_string(),
    };
    match error.kind() {
        ErrorKind::Input => StudyError::Input(message),
        ErrorKind::NotConverged => StudyError::NotConverged(message),
        ErrorKind::Io => StudyError::Io(message),
    }
}

/// Runs `strand optimize` on `case` with the options `vary` (each `ITEM=LO..HI`, the
/// bounds in the item's unit or as offsets, `+0mm..+50mm`), `minimize` (the
/// objective: `peak_force`, `peak_force:<rod>`, `max_reaction`, `energy` or an
/// output name of `sensitivity.json`) and `subject_to` (each a constraint such as
/// `clearance>=10mm` or `bend_radius:hose2>=min`), with the default settings;
/// `progress` sees the problem and then every trial point. The outputs' `time_s` is
/// the wall time from the call. Errors carry the command line's message and exit
/// status: an option or the case is wrong (input; the option's errors name it,
/// `--vary TEXT: …`), the starting design has no equilibrium (not converged), the
/// subproblem failed (internal). A run that ends without converging is no error: its
/// optimum says so (`converged` false).
pub fn optimize_case(
    case: &Case,
    vary: &[String],
    minimize: &str,
    subject_to: &[String],
    progress: &mut dyn FnMut(OptimizeProgress),
) -> Result<OptimizeRun> {
    let started = Instant::now();
    crate::limits::check_case(case)?;
    let problem = Problem::from_options(case, vary, minimize, subject_to)
        .map_err(|e| study_error(e, None))?;
    progress(OptimizeProgress::Start(&problem));
    let optimum = optimize(case, &problem, &OptimizeSettings::default(), &mut |it| {
        progress(OptimizeProgress::Iterate(&problem, it))
    })
    .map_err(|e| study_error(e, Some(&case.origin)))?;
    let outputs = optimum_outputs(case, &problem, &optimum, started.elapsed().as_secs_f64())?;
    Ok(OptimizeRun {
        problem,
        optimum,
        outputs,
    })
}
