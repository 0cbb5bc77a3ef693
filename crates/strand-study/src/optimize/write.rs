//! The files of a run of `strand optimize` in its output folder: `optimum.json`,
//! `history.csv`, `history.svg`, the optimal case `<case>_optimum.ron` (ready to
//! solve) and the optimum's results (`result.json`, per-rod CSV, geometry), so that
//! the folder is an input of `strand report`.

use std::path::Path;

use strand_case::{BuiltCase, Case};
use strand_report::{ExportUnit, OptimumDoc, ResultDoc, Timing, optimum_svg, significant};

use super::{Optimum, Problem, document};
use crate::error::{Result, StudyError};
use crate::solve::{result_doc, write_files, write_result};

/// The optimal case file of `optimum` (a run on `case`, `doc` its document): the
/// case with the optimum's changes, its relative paths rebased onto the case's folder,
/// under a comment with the objective and the values; checked to parse and build.
pub fn optimal_case(case: &Case, optimum: &Optimum, doc: &OptimumDoc) -> Result<String> {
    let internal =
        |message: String| StudyError::Io(format!("{}: the optimal case: {message}", case.origin));
    let file = case
        .file_with_changes("optimum", &optimum.changes)
        .map_err(|e| internal(e.to_string()))?;
    let folder = Path::new(&case.origin)
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let folder = std::fs::canonicalize(&folder).unwrap_or(folder);
    let file = file.rebased(&folder);
    let config =
        ron::ser::PrettyConfig::new().extensions(ron::extensions::Extensions::IMPLICIT_SOME);
    let body = ron::ser::to_string_pretty(&file, config).map_err(|e| internal(e.to_string()))?;
    let values: Vec<String> = doc
        .variables
        .iter()
        .filter_map(|v| doc.parameters.get(v).map(|p| (v, p)))
        .map(|(v, p)| format!("{v} = {} {}", significant(p.value, 7), p.unit))
        .collect();
    // Only a converged run found an optimum; otherwise the file holds its best point.
    let what = if doc.converged {
        "The optimal design"
    } else {
        "NOT an optimum (the run did not converge): the best point found"
    };
    let text = format!(
        "// {what} of {} by `strand optimize` (minimise {}: {} {}; {}):\n// {}\n{body}\n",
        case.origin,
        doc.objective.name,
        significant(doc.objective.value, 5),
        doc.objective.unit,
        doc.termination,
        values.join(", ")
    );
    // Ready to solve: it parses and builds as written.
    Case::from_str(&text, "optimum.ron")
        .and_then(|c| c.build(None).map(|_| ()))
        .map_err(|e| internal(format!("does not build: {e}")))?;
    Ok(text)
}

/// What a run of `strand optimize` writes, before it is written: `optimum.json`'s
/// document, the optimal case (file name and text, [`optimal_case`]), and the
/// optimum's built case and result document (`result.json`).
pub struct OptimumOutputs {
    /// `optimum.json`.
    pub doc: OptimumDoc,
    /// The optimal case's file name (`<case>_optimum.ron`).
    pub case_file: String,
    /// The optimal case's text.
    pub case_text: String,
    /// The optimal case built (its variant label `optimum`).
    pub built: BuiltCase,
    /// The optimum's result (its variant label `optimum`).
    pub result: ResultDoc,
}

/// The outputs of `optimum`, a run of `problem` on `case` that took `time_s` (s,
/// `optimum.json`'s `time_s`).
pub fn optimum_outputs(
    case: &Case,
    problem: &Problem,
    optimum: &Optimum,
    time_s: f64,
) -> Result<OptimumOutputs> {
    let case_file = format!("{}_optimum.ron", case.name);
    let doc = document(&case.name, problem, optimum, &case_file, time_s);
    let case_text = optimal_case(case, optimum, &doc)?;
    let built = case.build_with_changes("optimum", &optimum.changes, None)?;
    let result = result_doc(
        &built,
        &optimum.solution,
        Timing::default(),
        Some("optimum"),
        None,
    )?;
    Ok(OptimumOutputs {
        doc,
        case_file,
        case_text,
        built,
        result,
    })
}

/// Writes the files of a run of `strand optimize` (its `outputs`, see
/// [`optimum_outputs`]) into `dir`, each atomically: `history.csv`, `history.svg`,
/// `<case>_optimum.ron`, the optimum's results (geometry in `unit`, default the
/// case's length unit), and `optimum.json` last (a folder with `optimum.json` is
/// complete).
pub fn write_optimum(
    dir: &Path,
    outputs: &OptimumOutputs,
    unit: Option<&ExportUnit>,
) -> Result<()> {
    let doc = &outputs.doc;
    let json = serde_json::to_string_pretty(doc)
        .map_err(|e| StudyError::Io(format!("{}: {e}", dir.display())))?;
    write_files(
        dir,
        &[
            ("history.csv", doc.history_csv().as_bytes()),
            ("history.svg", optimum_svg(doc).as_bytes()),
            (&outputs.case_file, outputs.case_text.as_bytes()),
        ],
    )?;
    write_result(dir, &outputs.result, &outputs.built, unit)?;
    write_files(dir, &[("optimum.json", json.as_bytes())])?;
    Ok(())
}
