//! The report's provenance section: for every result, the Strand version that solved
//! it, the case file and its content hash, when it was solved and the solver settings
//! (from `result.json`'s `provenance`), and a warning at the top of the page when the
//! results come from different cases ([`crate::mixed_cases`]).

use std::fmt::Write;

use super::ReportRun;
use super::format::{Cell, push_table};
use crate::plot::escape;

/// The warning paragraph (`id="mixed-cases"`) when `runs` come from different cases.
pub(crate) fn push_mixed_warning(html: &mut String, runs: &[ReportRun]) {
    let docs: Vec<(&str, &crate::ResultDoc)> = runs.iter().map(|r| (r.label, r.doc)).collect();
    if let Some(warning) = crate::provenance::mixed_cases(&docs) {
        let _ = writeln!(
            html,
            "<p class=\"warning\" id=\"mixed-cases\">Warning: {}.</p>",
            escape(&warning)
        );
    }
}

/// The provenance table of every result, then the solver settings of each result
/// that states them (a collapsed table of every setting).
pub(crate) fn push_provenance(html: &mut String, runs: &[ReportRun]) {
    let rows: Vec<_> = runs
        .iter()
        .map(|run| {
            let p = run.doc.provenance.as_ref();
            let text = |f: &dyn Fn(&crate::Provenance) -> Option<String>| {
                p.and_then(f).map_or(Cell::None, Cell::text)
            };
            (
                vec![("result", run.label.to_string())],
                vec![
                    Cell::text(run.label),
                    Cell::text(&run.doc.case),
                    text(&|p| Some(p.case_path.clone())),
                    text(&|p| p.case_fnv1a64.clone()),
                    text(&|p| Some(p.strand_version.clone())),
                    text(&|p| Some(p.created_utc.clone())),
                ],
            )
        })
        .collect();
    push_table(
        html,
        "provenance",
        &[
            "result",
            "case",
            "case file",
            "case file hash (FNV-1a 64)",
            "Strand version",
            "solved (UTC)",
        ],
        &rows,
    );
    if runs.iter().any(|r| r.doc.provenance.is_none()) {
        html.push_str("<p class=\"note\">–: the result.json was written by a Strand version that did not record it.</p>\n");
    }
    for run in runs {
        let Some(serde_json::Value::Object(settings)) =
            run.doc.provenance.as_ref().map(|p| &p.solver_settings)
        else {
            continue;
        };
        let rows: Vec<_> = settings
            .iter()
            .map(|(key, value)| {
                (
                    vec![("result", run.label.to_string())],
                    vec![Cell::text(key), Cell::text(value.to_string())],
                )
            })
            .collect();
        let _ = writeln!(
            html,
            "<details class=\"settings\"><summary>Solver settings of {} ({} values)</summary>",
            escape(run.label),
            rows.len()
        );
        push_table(html, "solver-settings", &["setting", "value"], &rows);
        html.push_str("</details>\n");
    }
}
