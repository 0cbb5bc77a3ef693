//! `strand._strand._batch`: `strand batch` of a case into a directory, through
//! [`strand_cli::library::batch`] (the CLI's runner, warm-start tree and summary). The
//! whole binding of the batch engine is this file.

use std::path::PathBuf;

use pyo3::prelude::*;
use strand_cli::library::{self, BatchRequest, Keep};

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
    let request = BatchRequest {
        vary: &vary,
        out: &out,
        jobs,
        segments,
        keep,
    };
    let current = &case.spec.current;
    let run = py
        .detach(|| library::batch(current, &request))
        .map_err(|f| to_py(f, Stage::Files))?;
    Ok((run.summary_csv, run.all_solved))
}
