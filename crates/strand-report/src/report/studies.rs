//! The report's design-study sections: the sensitivity table of a result folder that
//! holds `sensitivity.json` ("hose2.length +1 mm: hose2 peak |f| −0.2253 N, tee drops
//! 0.7904 mm, …", then every output's derivative per parameter), and the optimisation
//! of one that holds `optimum.json` (the optimum, its active constraints and the
//! history, as a table and the SVG).

use std::fmt::Write;

use super::format::{Cell, Row, push_table, sig};
use crate::optimum::OptimumDoc;
use crate::optimum_svg;
use crate::plot::escape;
use crate::sensitivity::SensitivityDoc;

/// How many changes the sentence of one parameter names.
const NAMED: usize = 6;

/// An output's change as words and a number in display units: `(what, change, unit)`,
/// e.g. `("tee drops", 0.79, "mm")`; `None` for outputs the sentence leaves out.
fn phrase(name: &str, d: f64) -> Option<(String, f64, &'static str)> {
    let (stem, what) = name.split_once('.')?;
    Some(match what {
        "peak_force_N" => (format!("{stem} peak |f|"), d, "N"),
        "peak_moment_Nm" => (format!("{stem} peak |m|"), d, "N·m"),
        "min_bend_radius_m" => (format!("{stem} tightest bend radius"), 1e3 * d, "mm"),
        "min_clearance_m" => (format!("{stem} clearance"), 1e3 * d, "mm"),
        "position_m.z" => (
            format!("{stem} {}", if d < 0.0 { "drops" } else { "rises" }),
            1e3 * d.abs(),
            "mm",
        ),
        "position_m.x" | "position_m.y" => (
            format!("{stem} moves {}", &what[what.len() - 1..]),
            1e3 * d,
            "mm",
        ),
        _ => return None,
    })
}

/// A signed number with an explicit `+` (and a true minus sign).
fn signed(x: f64) -> String {
    let s = sig(x);
    if x > 0.0 {
        format!("+{s}")
    } else {
        s.replacen('-', "−", 1)
    }
}

/// The sensitivity section of `label`'s `doc`.
pub(crate) fn push_sensitivity(html: &mut String, label: &str, doc: &SensitivityDoc) {
    let _ = writeln!(
        html,
        "<section class=\"sensitivity\" data-result=\"{}\"><h3>{}: sensitivities</h3>",
        escape(label),
        escape(label)
    );
    let _ = writeln!(
        html,
        "<p class=\"note\">Exact derivatives of the equilibrium ({}; residual {} N): the change of each output per unit increase of each parameter, to first order. Where a peak's location or a contact would switch within the step, the derivative holds on one side only (marked ⚠).</p>\n<ul class=\"sentences\">",
        if doc.converged {
            "converged"
        } else {
            "NOT converged"
        },
        sig(doc.residual_n)
    );
    for p in &doc.parameters {
        let mut changes: Vec<(String, f64, &str, f64)> = doc
            .outputs
            .iter()
            .filter_map(|o| {
                let d = *o.d.get(&p.name)?;
                let (what, shown, unit) = phrase(&o.name, d)?;
                let weight = (d / o.value.abs().max(1e-12)).abs();
                Some((what, shown, unit, weight))
            })
            .collect();
        changes.sort_by(|a, b| b.3.total_cmp(&a.3));
        let words: Vec<String> = changes
            .iter()
            .take(NAMED)
            .map(|(what, shown, unit, _)| {
                if what.ends_with("drops") || what.ends_with("rises") {
                    format!("{what} {} {unit}", sig(*shown))
                } else {
                    format!("{what} {} {unit}", signed(*shown))
                }
            })
            .collect();
        let _ = writeln!(
            html,
            "<li data-parameter=\"{}\"><b>{} +1 {}:</b> {}</li>",
            escape(&p.name),
            escape(&p.name),
            escape(&p.unit),
            escape(&if words.is_empty() {
                "no peak, bend, clearance or pose output changes".to_string()
            } else {
                words.join(", ")
            })
        );
    }
    html.push_str("</ul>\n");
    let mut headers: Vec<String> = vec!["output".into(), "value".into()];
    headers.extend(
        doc.parameters
            .iter()
            .map(|p| format!("d/d {} [per {}]", p.name, p.unit)),
    );
    let rows: Vec<Row> = doc
        .outputs
        .iter()
        .map(|o| {
            let mut cells = vec![Cell::text(o.name.clone()), Cell::Num(o.value)];
            for p in &doc.parameters {
                cells.push(match o.d.get(&p.name) {
                    Some(d) if o.one_sided.contains(&p.name) => {
                        Cell::text(format!("{} ⚠", sig(*d)))
                    }
                    Some(d) => Cell::Num(*d),
                    None => Cell::None,
                });
            }
            (vec![("output", o.name.clone())], cells)
        })
        .collect();
    let headers: Vec<&str> = headers.iter().map(String::as_str).collect();
    html.push_str("<details><summary>Every output and its derivatives</summary>\n");
    push_table(html, "sensitivity-table", &headers, &rows);
    html.push_str("</details>\n");
    if !doc.near_switch.is_empty() {
        let _ = writeln!(
            html,
            "<p class=\"note\">Near a switch (derivatives one-sided): {}</p>",
            escape(&doc.near_switch.join("; "))
        );
    }
    html.push_str("</section>\n");
}

/// The optimisation section of `label`'s `doc`.
pub(crate) fn push_optimum(html: &mut String, label: &str, doc: &OptimumDoc) {
    let _ = writeln!(
        html,
        "<section class=\"optimum\" data-result=\"{}\" data-converged=\"{}\"><h3>{}: optimisation</h3>",
        escape(label),
        doc.converged,
        escape(label)
    );
    let values: Vec<String> = doc
        .variables
        .iter()
        .filter_map(|v| doc.parameters.get(v).map(|p| (v, p)))
        .map(|(v, p)| {
            format!(
                "{v} = {} {} (bounds {}..{})",
                sig(p.value),
                p.unit,
                sig(p.lower),
                sig(p.upper)
            )
        })
        .collect();
    let _ = writeln!(
        html,
        "<p><b>{}</b>: {}. Minimise {} = <b>{} {}</b> (attained by {}); {} equilibrium solves, {} trial points.</p>",
        escape(if doc.converged {
            "Converged"
        } else {
            "NOT converged"
        }),
        escape(&values.join(", ")),
        escape(&doc.objective.name),
        sig(doc.objective.value),
        escape(&doc.objective.unit),
        escape(&doc.objective.attained_by.join(", ")),
        doc.solves,
        doc.iterations
    );
    let _ = writeln!(html, "<p class=\"note\">{}</p>", escape(&doc.message));
    let rows: Vec<Row> = doc
        .constraints
        .iter()
        .map(|c| {
            (
                vec![("constraint", c.name.clone())],
                vec![
                    Cell::text(c.name.clone()),
                    Cell::text(c.output.clone()),
                    Cell::Num(c.value),
                    Cell::Num(c.bound),
                    Cell::Check(c.satisfied, "yes", "NO"),
                    Cell::text(if c.active { "active" } else { "" }),
                    Cell::Num(c.d_objective_d_bound),
                    Cell::text(c.multiplier_unit.clone()),
                ],
            )
        })
        .collect();
    if !rows.is_empty() {
        push_table(
            html,
            "optimum-constraints",
            &[
                "constraint",
                "output",
                "value",
                "bound",
                "satisfied",
                "",
                "d objective / d bound",
                "unit",
            ],
            &rows,
        );
    }
    let _ = writeln!(html, "<figure>{}</figure>", optimum_svg(doc));
    let mut headers: Vec<String> = vec!["trial".into(), "solves".into()];
    headers.extend(doc.variables.iter().map(|v| {
        let unit = doc.parameters.get(v).map_or("", |p| p.unit.as_str());
        format!("{v} [{unit}]")
    }));
    headers.extend([
        format!("{} [{}]", doc.objective.name, doc.objective.unit),
        "violation".into(),
        "note".into(),
    ]);
    let rows: Vec<Row> = doc
        .history
        .iter()
        .map(|h| {
            let mut cells = vec![Cell::Int(h.iteration), Cell::Int(h.solves)];
            cells.extend(h.values.iter().map(|v| Cell::Num(*v)));
            cells.push(Cell::opt(h.objective));
            cells.push(Cell::opt(h.violation));
            cells.push(Cell::text(h.note.clone()));
            (vec![("accepted", h.accepted.to_string())], cells)
        })
        .collect();
    let headers: Vec<&str> = headers.iter().map(String::as_str).collect();
    push_table(html, "optimum-history", &headers, &rows);
    if !doc.non_smooth.is_empty() {
        let _ = writeln!(
            html,
            "<p class=\"note\">Non-smooth: {}</p>",
            escape(&doc.non_smooth.join("; "))
        );
    }
    html.push_str("</section>\n");
}
