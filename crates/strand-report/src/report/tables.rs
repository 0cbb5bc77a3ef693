//! The summary, peak-value and difference tables.

use super::format::{Cell, push_table};
use super::{ReportRun, arc_at, report_origin};
use crate::result::RodResult;
use crate::study::{ArcOrigin, magnitude};

/// Row keys `data-result` (and `data-rod`).
fn keys(result: &str, rod: Option<&str>) -> Vec<(&'static str, String)> {
    let mut keys = vec![("result", result.to_string())];
    if let Some(rod) = rod {
        keys.push(("rod", rod.to_string()));
    }
    keys
}

/// Convergence, residuals and stability of every run.
pub(crate) fn push_summary(html: &mut String, runs: &[ReportRun]) {
    let rows: Vec<_> = runs
        .iter()
        .map(|run| {
            let d = run.doc;
            (
                keys(run.label, None),
                vec![
                    Cell::text(run.label),
                    Cell::text(&d.case),
                    d.variant.as_deref().map_or(Cell::None, Cell::text),
                    Cell::Check(d.converged, "yes", "NO"),
                    Cell::text(&d.termination),
                    Cell::Num(d.residual_n),
                    Cell::Num(d.tolerance_n),
                    Cell::Num(d.force_residual_n),
                    Cell::Num(d.moment_residual_nm),
                    Cell::Int(d.iterations),
                    Cell::Check(d.stable, "yes", "UNSTABLE"),
                    Cell::Num(d.energy_j),
                    Cell::Int(d.unknowns),
                    Cell::Num(d.timing_s.solve),
                ],
            )
        })
        .collect();
    push_table(
        html,
        "summary",
        &[
            "result",
            "case",
            "variant",
            "converged",
            "termination",
            "residual [N]",
            "tolerance [N]",
            "force residual [N]",
            "moment residual [N·m]",
            "iterations",
            "stable",
            "energy [J]",
            "unknowns",
            "solve time [s]",
        ],
        &rows,
    );
}

/// The largest `|value|` of `values` with its vertex, keeping the sign (NaN wins, the
/// first on ties); `None` for no values.
pub(crate) fn extreme(values: impl IntoIterator<Item = f64>) -> Option<(f64, usize)> {
    let mut best: Option<(f64, usize)> = None;
    for (j, v) in values.into_iter().enumerate() {
        let better = match best {
            None => true,
            Some((b, _)) => !b.is_nan() && (v.is_nan() || v.abs() > b.abs()),
        };
        if better {
            best = Some((v, j));
        }
    }
    best
}

/// Peak `|f|` and `|m|` of a rod (N, N·m), `None` without vertices.
fn peak_magnitudes(rod: &RodResult) -> Option<(f64, f64)> {
    let f = extreme(rod.force_n.iter().map(magnitude))?.0;
    let m = extreme(rod.moment_nm.iter().map(magnitude))?.0;
    Some((f, m))
}

/// Per run and hose: peak `|f|` and where, extreme `f_t`, peak `f_s`, peak `|m|` and
/// where, peak `m_b`, extreme `m_t`.
pub(crate) fn push_peaks(html: &mut String, runs: &[ReportRun]) {
    let mut rows = Vec::new();
    for run in runs {
        for rod in &run.doc.rods {
            let origin = runs
                .first()
                .map_or(ArcOrigin::Start, |r| report_origin(r.doc, &rod.name));
            let at = |peak: Option<(f64, usize)>| {
                (
                    Cell::opt(peak.map(|p| p.0)),
                    Cell::opt(peak.map(|p| 1e3 * arc_at(rod, origin, p.1))),
                )
            };
            let (f, f_s_at) = at(extreme(rod.force_n.iter().map(magnitude)));
            let (m, m_s_at) = at(extreme(rod.moment_nm.iter().map(magnitude)));
            let value = |values: &[f64]| Cell::opt(extreme(values.iter().copied()).map(|p| p.0));
            rows.push((
                keys(run.label, Some(&rod.name)),
                vec![
                    Cell::text(run.label),
                    Cell::text(&rod.name),
                    f,
                    f_s_at,
                    value(&rod.tangential_force_n),
                    value(&rod.shear_force_n),
                    m,
                    m_s_at,
                    value(&rod.bending_moment_nm),
                    value(&rod.torsion_nm),
                ],
            ));
        }
    }
    push_table(
        html,
        "peaks",
        &[
            "result",
            "hose",
            "peak |f| [N]",
            "s of peak |f| [mm]",
            "extreme f_t [N]",
            "peak f_s [N]",
            "peak |m| [N·m]",
            "s of peak |m| [mm]",
            "peak m_b [N·m]",
            "extreme m_t [N·m]",
        ],
        &rows,
    );
    html.push_str("<p class=\"note\">Peak: the largest value along the hose; extreme: the value of largest magnitude, with its sign (f_t &gt; 0 is tension). Arc length s as in the plots.</p>\n");
}

/// Per result after the first and per hose in both: peaks against the reference and
/// the largest displacement of a vertex.
pub(crate) fn push_differences(html: &mut String, runs: &[ReportRun]) {
    let Some((reference, others)) = runs.split_first() else {
        return;
    };
    if others.is_empty() {
        html.push_str("<p class=\"note\">Only one result: nothing to compare.</p>\n");
        return;
    }
    let change = |value: f64, base: f64| {
        (base != 0.0 && base.is_finite() && value.is_finite())
            .then(|| 100.0 * (value - base) / base)
    };
    let mut rows = Vec::new();
    for run in others {
        for rod in &run.doc.rods {
            let Some(base) = reference.doc.rods.iter().find(|r| r.name == rod.name) else {
                continue;
            };
            let (Some((f0, m0)), Some((f1, m1))) = (peak_magnitudes(base), peak_magnitudes(rod))
            else {
                continue;
            };
            let moved = (base.position_m.len() == rod.position_m.len()).then(|| {
                base.position_m
                    .iter()
                    .zip(&rod.position_m)
                    .map(|(a, b)| 1e3 * magnitude(&[b[0] - a[0], b[1] - a[1], b[2] - a[2]]))
                    .fold(0.0, f64::max)
            });
            rows.push((
                keys(run.label, Some(&rod.name)),
                vec![
                    Cell::text(run.label),
                    Cell::text(&rod.name),
                    Cell::Num(f0),
                    Cell::Num(f1),
                    Cell::opt(change(f1, f0)),
                    Cell::Num(m0),
                    Cell::Num(m1),
                    Cell::opt(change(m1, m0)),
                    Cell::opt(moved),
                ],
            ));
        }
    }
    push_table(
        html,
        "differences",
        &[
            "result",
            "hose",
            "reference peak |f| [N]",
            "peak |f| [N]",
            "change |f| [%]",
            "reference peak |m| [N·m]",
            "peak |m| [N·m]",
            "change |m| [%]",
            "largest vertex displacement [mm]",
        ],
        &rows,
    );
    html.push_str("<p class=\"note\">Displacement: the largest distance between the same vertex in the two results (– when the hoses have different numbers of vertices).</p>\n");
}
