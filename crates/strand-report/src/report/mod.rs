//! The HTML design-review report: one self-contained page (inline SVG, CSS and one
//! small inline script for the 3D view ([`view3d`]); no fonts, images, links or network) comparing several results of a case, e.g. a base
//! design and its variants. The first result is the reference: drawn solid, the others
//! dashed, and the difference table is against it.
//!
//! The page is XHTML-compatible HTML5 (`<!DOCTYPE html>` followed by well-formed XML
//! in the XHTML namespace), so it opens in any browser and parses as XML. Sections:
//! findings (violated limits, [`limits`]), summary (convergence, residual, stability), sectional quantities along the arc
//! length per hose ([`plots`]), side and top projections coloured by `|f|`
//! ([`projection`]), and tables ([`tables`], [`checks`]). Lengths are shown in mm,
//! forces in N, moments in N·m; numbers with 4 significant digits.
//!
//! Arc length runs from a rod's start, or from its end when only the end is attached
//! to a junction port (as in the paper's Fig. 7: all hoses of a junction start there),
//! decided from the reference result's `reactions`.

mod checks;
mod format;
mod limits;
mod motion;
mod plots;
mod projection;
mod provenance;
mod studies;
mod tables;

pub(crate) use format::sig;
pub use motion::MotionAxis;
#[cfg(test)]
mod tests;
mod view3d;
#[cfg(test)]
mod view_tests;

use std::fmt::Write;

use crate::plot::escape;
use crate::result::{ResultDoc, RodResult};
use crate::study::ArcOrigin;

/// One result shown in the report.
#[derive(Clone, Copy, Debug)]
pub struct ReportRun<'a> {
    /// Label of the result in plots and tables (e.g. the variant name); labels should
    /// be unique.
    pub label: &'a str,
    /// The result document.
    pub doc: &'a ResultDoc,
}

/// A result document that cannot be drawn.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReportInputError {
    /// A per-vertex or per-edge array of a rod has the wrong length.
    #[error(
        "rod '{rod}': {array} has {found} entries but the rod has {expected} (segments + 1 vertices, segments edges); the result file is inconsistent, write it again with `strand solve`"
    )]
    ArrayLength {
        /// The rod.
        rod: String,
        /// The array's key in `result.json`.
        array: &'static str,
        /// Its length.
        found: usize,
        /// The expected length.
        expected: usize,
    },
}

/// Checks that every array of every rod of `doc` has `segments + 1` entries
/// (`segments` for `edge_force_N`), so that the report can index them.
pub fn check_result(doc: &ResultDoc) -> Result<(), ReportInputError> {
    for rod in &doc.rods {
        let n = rod.segments + 1;
        let lengths = [
            ("s_m", rod.s_m.len(), n),
            ("position_m", rod.position_m.len(), n),
            ("force_N", rod.force_n.len(), n),
            ("moment_Nm", rod.moment_nm.len(), n),
            ("tangential_force_N", rod.tangential_force_n.len(), n),
            ("shear_force_N", rod.shear_force_n.len(), n),
            ("bending_moment_Nm", rod.bending_moment_nm.len(), n),
            ("torsion_Nm", rod.torsion_nm.len(), n),
            ("curvature_1pm", rod.curvature_1pm.len(), n),
        ];
        if let Some((array, found, expected)) = lengths.into_iter().find(|(_, l, e)| l != e) {
            return Err(ReportInputError::ArrayLength {
                rod: rod.name.clone(),
                array,
                found,
                expected,
            });
        }
    }
    Ok(())
}

/// Where arc length of `rod` is measured from in the report: its end if only the end
/// is held by a junction port in `doc`, else its start.
pub(crate) fn report_origin(doc: &ResultDoc, rod: &str) -> ArcOrigin {
    let at_port = |end: &str| {
        doc.reactions
            .iter()
            .any(|r| r.rod == rod && r.kind == "port" && r.end == end)
    };
    if at_port("end") && !at_port("start") {
        ArcOrigin::End
    } else {
        ArcOrigin::Start
    }
}

/// Arc length of vertex `j` of `rod` from `origin`, m.
pub(crate) fn arc_at(rod: &RodResult, origin: ArcOrigin, j: usize) -> f64 {
    origin.measure(rod.s_m[j], rod.length_m)
}

/// Rod names in order of first appearance over all runs.
pub(crate) fn rod_names<'a>(runs: &[ReportRun<'a>]) -> Vec<&'a str> {
    let mut names: Vec<&str> = Vec::new();
    for run in runs {
        for rod in &run.doc.rods {
            if !names.contains(&rod.name.as_str()) {
                names.push(&rod.name);
            }
        }
    }
    names
}

const STYLE: &str = "
body { font-family: system-ui, -apple-system, 'Segoe UI', Roboto, sans-serif; color: #222; margin: 0; background: #f4f5f7; }
main { max-width: 1320px; margin: 0 auto; padding: 20px 28px 40px; background: #ffffff; }
h1 { font-size: 1.6em; margin: 0.2em 0 0.1em; }
h2 { font-size: 1.2em; margin: 1.6em 0 0.5em; padding-bottom: 4px; border-bottom: 2px solid #1f77b4; }
h3 { font-size: 1.0em; margin: 1.0em 0 0.4em; }
p.meta, p.note { color: #555; font-size: 0.9em; margin: 0.3em 0; }
table.data { border-collapse: collapse; font-size: 0.86em; margin: 0.3em 0 1em; }
table.data th, table.data td { border: 1px solid #d0d4da; padding: 3px 8px; }
table.data th { background: #eef1f5; text-align: left; font-weight: 600; }
table.data tbody tr:nth-child(even) { background: #fafbfc; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
td.ok { color: #1a7f37; font-weight: 600; }
td.bad { color: #c62828; font-weight: 700; }
td.none { text-align: center; color: #888; }
.grid { display: grid; grid-template-columns: repeat(auto-fill, minmax(560px, 1fr)); gap: 12px 20px; }
figure { margin: 0; }
figure svg { width: 100%; height: auto; display: block; border: 1px solid #e1e4e8; }
figcaption { font-size: 0.85em; color: #444; margin-top: 3px; }
.scroll { overflow-x: auto; }
p.finding-none { color: #1a7f37; font-weight: 600; }
p.finding-count { color: #c62828; font-weight: 700; }
table.findings td { color: #c62828; }
.v3d-controls { display: flex; flex-wrap: wrap; gap: 6px 14px; align-items: center; font-size: 0.9em; margin: 0.3em 0; }
.v3d-controls .readout { color: #333; font-variant-numeric: tabular-nums; }
figure.v3d svg { max-width: 900px; cursor: grab; }
p.warning { background: #fff4e5; border-left: 4px solid #e69f00; padding: 6px 10px; }
@media print {
  body { background: #ffffff; font-size: 10pt; }
  main { max-width: none; padding: 0; }
  .v3d-controls, details.settings { display: none; }
  .scroll { overflow: visible; }
  .grid { display: block; }
  figure, table, tr { break-inside: avoid; }
  h2, h3 { break-after: avoid; }
  figure svg { border: none; }
}
";

/// The report page for `runs` (the first is the reference) under `title`.
pub fn report_html(title: &str, runs: &[ReportRun]) -> String {
    report_page(title, runs, None, &[])
}

/// The design studies of one result folder shown in the report: its
/// `sensitivity.json` and `optimum.json`, if any.
#[derive(Clone, Copy, Debug, Default)]
pub struct ReportStudies<'a> {
    /// The folder's sensitivities.
    pub sensitivity: Option<&'a crate::SensitivityDoc>,
    /// The folder's optimisation.
    pub optimum: Option<&'a crate::OptimumDoc>,
}

/// [`report_html`] with a "Design studies" section: per run (the same order as
/// `runs`; missing entries have none) its sensitivity table and optimisation history.
pub fn report_html_with_studies(
    title: &str,
    runs: &[ReportRun],
    studies: &[ReportStudies],
) -> String {
    report_page(title, runs, None, studies)
}

/// The report page of a motion: `runs` are its poses in order of `axis.values`; the
/// page adds the worst pose of each quantity and plays the poses in the 3D view.
pub fn motion_report_html(title: &str, runs: &[ReportRun], axis: &MotionAxis) -> String {
    report_page(title, runs, Some(axis), &[])
}

fn report_page(
    title: &str,
    runs: &[ReportRun],
    axis: Option<&MotionAxis>,
    studies: &[ReportStudies],
) -> String {
    let mut html = String::with_capacity(64 * 1024);
    html.push_str("<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n");
    html.push_str("<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"/>\n");
    let _ = writeln!(html, "<title>{}</title>", escape(title));
    let _ = writeln!(html, "<style>{STYLE}</style>\n</head>\n<body>\n<main>");
    let _ = writeln!(html, "<h1>{}</h1>", escape(title));
    let mut cases: Vec<&str> = runs.iter().map(|r| r.doc.case.as_str()).collect();
    cases.dedup();
    let _ = writeln!(
        html,
        "<p class=\"meta\">Case {}; {} result(s), the first ({}) is the reference: solid lines, and differences are taken against it. Units: lengths in mm, forces in N, moments in N·m. Report made <span class=\"created\">{}</span> by Strand {}; where each result comes from (case file, its hash, when it was solved, the solver settings): Provenance, at the end.</p>",
        escape(&cases.join(", ")),
        runs.len(),
        escape(runs.first().map_or("none", |r| r.label)),
        crate::provenance::utc_now(),
        env!("CARGO_PKG_VERSION")
    );
    provenance::push_mixed_warning(&mut html, runs);

    html.push_str("<h2 id=\"findings-section\">Findings</h2>\n");
    limits::push_findings(&mut html, runs);

    if let Some(axis) = axis {
        html.push_str("<h2 id=\"motion-section\">Motion: worst poses</h2>\n");
        motion::push_worst_poses(&mut html, runs, axis);
    }

    html.push_str("<h2>Summary</h2>\n");
    tables::push_summary(&mut html, runs);

    html.push_str("<h2 id=\"view3d-section\">3D view</h2>\n");
    let poses = axis.map(motion::pose_labels);
    view3d::push_view3d(&mut html, runs, poses.as_deref());

    html.push_str("<h2>Sectional quantities along the arc length</h2>\n");
    html.push_str("<p class=\"note\">Per hose: internal force |f|, tangential force f_t and shear force f_s (top); internal moment |m|, bending moment m_b and torsional moment m_t (bottom). The reference result is solid, the others dashed.</p>\n<div class=\"grid\">\n");
    for name in rod_names(runs) {
        let origin = runs
            .first()
            .map_or(ArcOrigin::Start, |r| report_origin(r.doc, name));
        let _ = writeln!(
            html,
            "<figure data-rod=\"{}\">{}<figcaption>{}: arc length from the {}.</figcaption></figure>",
            escape(name),
            plots::hose_svg(name, runs, origin),
            escape(name),
            match origin {
                ArcOrigin::Start => "rod's start",
                ArcOrigin::End => "junction (the rod's end)",
            }
        );
    }
    html.push_str("</div>\n");

    html.push_str("<h2>Side, top and front views</h2>\n");
    let outlines = runs
        .iter()
        .any(|r| r.doc.environment.iter().any(|e| !e.segments_m.is_empty()));
    let contacts = runs.iter().any(|r| !r.doc.contacts.is_empty());
    let _ = writeln!(
        html,
        "<p class=\"note\">Hoses coloured by internal force magnitude |f| (one colour scale for all results); supports: connectors ■, junction bodies ● with their ports, clips ▲. {} {}</p>",
        if outlines {
            "Environment: outlines (rims and edges sharper than 30°) of the meshes within 100 mm of the hoses, in light grey."
        } else {
            "No environment meshes near the hoses."
        },
        if contacts {
            "Contacts: dots with the force on the hose (arrow, N)."
        } else {
            "No contact."
        }
    );
    html.push_str("<div class=\"grid\">\n");
    projection::push_projections(&mut html, runs);
    html.push_str("</div>\n");

    if studies
        .iter()
        .any(|s| s.sensitivity.is_some() || s.optimum.is_some())
    {
        html.push_str("<h2 id=\"studies-section\">Design studies</h2>\n");
        for (run, s) in runs.iter().zip(studies) {
            if let Some(doc) = s.optimum {
                studies::push_optimum(&mut html, run.label, doc);
            }
            if let Some(doc) = s.sensitivity {
                studies::push_sensitivity(&mut html, run.label, doc);
            }
        }
    }
    html.push_str("<h2>Peak values</h2>\n");
    tables::push_peaks(&mut html, runs);
    html.push_str("<h2>Differences against the reference</h2>\n");
    tables::push_differences(&mut html, runs);
    html.push_str("<h2>Reactions at connectors, junctions and clips</h2>\n");
    checks::push_reactions(&mut html, runs);
    html.push_str("<h2>Contacts and clearances</h2>\n");
    checks::push_contacts(&mut html, runs);
    html.push_str("<h2>Bend radius</h2>\n");
    checks::push_bend_radius(&mut html, runs);
    html.push_str("<h2 id=\"provenance-section\">Provenance</h2>\n");
    provenance::push_provenance(&mut html, runs);
    html.push_str("</main>\n</body>\n</html>\n");
    html
}
