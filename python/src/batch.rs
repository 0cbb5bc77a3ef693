//! `strand._strand._batch`: `strand batch` of a case into a directory, through
//! [`strand_study::batch::Batch`] (the CLI's engine: runner, warm-start tree and
//! summary). The whole binding of the batch engine is this file.

use std::path::PathBuf;

use pyo3::prelude::*;
use strand_study::StudyError;
use strand_study::batch::{Batch, BatchSpec, Keep};

use crate::case::PyCase;
use crate::errors::{Stage, raise, to_py};

/// Runs the batch of `case` (its variant and changes applied) over `vary`
/// (`ITEM=VALUES` each) into `out` with the GIL released; returns `summary.csv` and
/// whether every variant converged.
#[pyfunction]
#[pyo3(name = "_batch", signature = (case, vary, out, jobs=None, segments=None, keep="summary"))]
pub fn batch(
    py: Python<'_>,
    case: &PyCase,
    vary: Vec<String>,
    out: PathBuf,
    jobs: Option<usize>,
    segments: Option<usize>,
    keep: &str,
) -> PyResult<(String, bool)> {
    let keep = match keep {
        "summary" => Keep::Summary,
        "results" => Keep::Results,
        "all" => Keep::All,
        other => {
            return Err(raise(
                "InputError",
                format!("keep={other:?}: use \"summary\", \"results\" or \"all\""),
            ));
        }
    };
    let current = &case.spec.current;
    // `strand batch --yes` (no confirmation prompt in a library); the exported
    // geometry of `--keep all` in the case's unit (no `--export-unit`).
    let spec = BatchSpec {
        vary,
        jobs,
        segments,
        keep,
        yes: true,
        ..BatchSpec::new(&current.origin, &out)
    };
    py.detach(|| {
        let report = Batch::plan_case(current.clone(), spec)?.run(&|_| {})?;
        let path = out.join("summary.csv");
        let summary_csv = std::fs::read_to_string(&path)
            .map_err(|e| StudyError::Io(format!("cannot read {}: {e}", path.display())))?;
        Ok((summary_csv, report.failures.is_empty()))
    })
    .map_err(|e| to_py(e, Stage::Files))
}
