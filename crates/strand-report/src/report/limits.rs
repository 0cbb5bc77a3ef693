//! The report's opening section: the findings (every violated limit, recomputed from
//! each document with [`crate::find`], so they agree with `result.json` and with
//! `strand solve`) or "no findings", and the limits each hose was checked against.

use std::fmt::Write;

use super::ReportRun;
use super::format::{Cell, push_table};
use crate::findings::{FindingValue, find, limits_stated};
use crate::plot::escape;

/// Appends the "Findings" section's content: a table of every violation of every run
/// (result, limit, hose, obstacle or connector, s from the hose's start, value and
/// limit in mm, N or N·m) or a
/// "no findings" note saying which limits were checked, then the limits per hose.
pub(crate) fn push_findings(html: &mut String, runs: &[ReportRun]) {
    let mut rows = Vec::new();
    for run in runs {
        for f in find(run.doc) {
            rows.push((
                vec![
                    ("result", run.label.to_string()),
                    ("rod", f.rod.clone()),
                    ("kind", f.kind.key().to_string()),
                ],
                vec![
                    Cell::text(run.label),
                    Cell::text(f.kind.words()),
                    Cell::text(&f.rod),
                    f.with.as_deref().map_or(Cell::None, Cell::text),
                    Cell::Num(1e3 * f.s_m),
                    f.stretch_m.map_or(Cell::None, |[a, b]| {
                        Cell::text(format!(
                            "{} – {}",
                            super::format::sig(1e3 * a),
                            super::format::sig(1e3 * b)
                        ))
                    }),
                    shown(f.value()),
                    shown(f.limit()),
                    Cell::text(unit_of(f.value())),
                ],
            ));
        }
    }
    let mut limits: Vec<&str> = runs.iter().flat_map(|r| limits_stated(r.doc)).collect();
    limits.sort_unstable();
    limits.dedup();
    if rows.is_empty() {
        let _ = writeln!(
            html,
            "<p class=\"finding-none\" id=\"no-findings\">No findings: {}.</p>",
            if limits.is_empty() {
                "the case states no limits (set <code>min_bend_radius</code> on a section, <code>min_clearance</code> on a rod or <code>max_force</code>/<code>max_moment</code> on a connector to have them checked)".to_string()
            } else {
                format!(
                    "every hose respects its limits ({}) in every result",
                    limits
                        .iter()
                        .map(|l| format!("<code>{l}</code>"))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            }
        );
    } else {
        let _ = writeln!(
            html,
            "<p class=\"finding-count\">{} limit violation(s):</p>",
            rows.len()
        );
        push_table(
            html,
            "findings",
            &[
                "result",
                "limit",
                "hose",
                "with",
                "s [mm]",
                "stretch s [mm]",
                "value",
                "limit",
                "unit",
            ],
            &rows,
        );
        html.push_str("<p class=\"note\">s: reference arc length from the hose's start at the worst point; bend radius: the smallest allowed (<code>min_bend_radius</code>), the stretch where it is exceeded; clearance: surface to surface (0 at contact), the required one (<code>min_clearance</code>); connector force and moment: magnitudes of the load the connector takes from the hose, the allowed ones (<code>max_force</code>, <code>max_moment</code>).</p>\n");
    }
    push_limits(html, runs);
}

/// A finding's number in the report's unit (lengths in mm).
fn shown(value: FindingValue) -> Cell {
    match value {
        FindingValue::Metres(v) => Cell::Num(1e3 * v),
        FindingValue::Newtons(v) | FindingValue::NewtonMetres(v) => Cell::Num(v),
    }
}

/// The unit of [`shown`]'s number.
fn unit_of(value: FindingValue) -> &'static str {
    match value {
        FindingValue::Metres(_) => "mm",
        FindingValue::Newtons(_) => "N",
        FindingValue::NewtonMetres(_) => "N·m",
    }
}

/// The limits of each hose of the reference result (other results: the same case).
fn push_limits(html: &mut String, runs: &[ReportRun]) {
    let Some(reference) = runs.first() else {
        return;
    };
    let rows: Vec<_> = reference
        .doc
        .rods
        .iter()
        .map(|rod| {
            (
                vec![
                    ("result", reference.label.to_string()),
                    ("rod", rod.name.clone()),
                ],
                vec![
                    Cell::text(&rod.name),
                    rod.section.as_deref().map_or(Cell::None, Cell::text),
                    Cell::Num(1e3 * rod.length_m),
                    rod.outer_radius_m
                        .map_or(Cell::None, |r| Cell::Num(2e3 * r)),
                    Cell::opt(rod.inner_radius_m.map(|r| 2e3 * r)),
                    Cell::opt(rod.mass_kg),
                    Cell::Int(rod.segments),
                    Cell::opt(rod.min_bend_radius_m.map(|r| 1e3 * r)),
                    Cell::opt(rod.min_clearance_m.map(|c| 1e3 * c)),
                ],
            )
        })
        .collect();
    let _ = writeln!(
        html,
        "<h3>Hoses: inputs and limits ({})</h3>",
        escape(reference.label)
    );
    push_table(
        html,
        "limits",
        &[
            "hose",
            "section",
            "length [mm]",
            "outer diameter [mm]",
            "inner diameter [mm]",
            "mass [kg]",
            "segments",
            "min bend radius [mm]",
            "min clearance [mm]",
        ],
        &rows,
    );
    let limited: Vec<_> = reference
        .doc
        .reactions
        .iter()
        .filter(|r| r.max_force_n.is_some() || r.max_moment_nm.is_some())
        .map(|r| {
            (
                vec![
                    ("result", reference.label.to_string()),
                    ("connector", r.name.clone()),
                ],
                vec![
                    Cell::text(&r.name),
                    Cell::text(format!("{} {}", r.rod, r.end)),
                    Cell::Num(crate::study::magnitude(&r.force_n)),
                    Cell::opt(r.max_force_n),
                    Cell::Num(crate::study::magnitude(&r.moment_nm)),
                    Cell::opt(r.max_moment_nm),
                ],
            )
        })
        .collect();
    if !limited.is_empty() {
        html.push_str("<h3>Connectors and their limits</h3>\n");
        push_table(
            html,
            "connector-limits",
            &[
                "connector",
                "holds",
                "|F| [N]",
                "max force [N]",
                "|M| [N·m]",
                "max moment [N·m]",
            ],
            &limited,
        );
    }
}
