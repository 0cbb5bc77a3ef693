//! `strand optimize` from Python: [`strand_study::optimize::optimize_case`], the
//! engine of the command line, with its documents kept instead of written.

use std::sync::Arc;

use strand_study::StudyError;
use strand_study::optimize::optimize_case;

use crate::case::{CaseSpec, PyCase};
use crate::solved::Solved;

/// A run: `optimum.json` (JSON text), the optimal case's file name
/// (`<case>_optimum.ron`) and text, the optimal case read from that text (named as
/// the file), and the optimum's solve (its result labelled `optimum`).
pub type OptimizeOutput = (String, String, String, PyCase, Solved);

/// Runs `strand optimize` on `spec`'s case (its variant, changes and pose applied)
/// with the options `vary`, `minimize` and `subject_to` (see
/// [`strand_study::optimize::optimize_case`]).
pub fn optimize(
    spec: &CaseSpec,
    vary: &[String],
    minimize: &str,
    subject_to: &[String],
) -> Result<OptimizeOutput, StudyError> {
    let case = &spec.current;
    let run = optimize_case(case, vary, minimize, subject_to, &mut |_| {})?;
    let outputs = run.outputs;
    let json = serde_json::to_string(&outputs.doc)
        .map_err(|e| StudyError::Io(format!("{}: optimum.json: {e}", case.origin)))?;
    let optimal = Arc::new(CaseSpec::from_text(
        outputs.case_text.clone(),
        &outputs.case_file,
        None,
    )?);
    let solved = Solved::new(
        Arc::clone(&optimal),
        None,
        outputs.result,
        run.optimum.solution.state,
        outputs.built,
    );
    let case = PyCase { spec: optimal };
    Ok((json, outputs.case_file, outputs.case_text, case, solved))
}
