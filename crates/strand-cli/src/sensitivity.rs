//! `strand sensitivity CASE --param NAME … --out DIR`: the derivative of every output
//! of the case's equilibrium with respect to each parameter
//! ([`strand_study::sensitivity`]), written to `DIR/sensitivity.json` and
//! `DIR/sensitivity.csv`, with the base solve's results (`result.json`, per-rod CSV,
//! geometry) so that the folder is an input of `strand report`; the terminal shows
//! the largest ones.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use strand_case::Case;
use strand_report::{ExportUnit, SensitivityDoc, SensitivityOutput, SensitivityParameter, Timing};
use strand_study::sensitivity::{parameters, sensitivities, write_sensitivities};

use crate::Exit;
use crate::commands::Failure;
use crate::summary::significant;

/// Largest derivatives shown on the terminal.
const SHOWN: usize = 12;

/// `strand sensitivity`.
pub(crate) fn run(
    path: &Path,
    names: &[String],
    dir: &Path,
    export_unit: Option<ExportUnit>,
    out: &mut dyn Write,
) -> Result<Exit, Failure> {
    let started = Instant::now();
    let case = Case::from_path(path)?;
    strand_study::limits::check_case(&case)?;
    parameters(&case, names)?;
    let mut built = case.build(None)?;
    // The sensitivities reuse the solver's Hessian at the equilibrium.
    built.settings.keep_hessian = true;
    let solution = crate::commands::solve_cold(&built)?;
    let solve_s = started.elapsed().as_secs_f64();
    let doc = sensitivities(&case, names, &solution)?;
    write_sensitivities(dir, &doc)?;
    let result = strand_study::solve::result_doc(&built, &solution, Timing::default(), None, None)?;
    strand_study::solve::write_result(dir, &result, &built, export_unit.as_ref())?;
    let _ = write!(
        out,
        "{}",
        summary(&doc, solve_s, started.elapsed().as_secs_f64(), dir)
    );
    Ok(Exit::Success)
}

/// The smallest value, as a fraction of the largest of its unit, that the summary's
/// ranking divides a derivative by (see [`summary`]).
const RELATIVE_FLOOR: f64 = 1e-3;

/// The unit of an output from its name (`cable.peak_force_N` → `N`,
/// `ecu.moment_Nm.x` → `Nm`); empty where the name has none.
fn unit_of(name: &str) -> &str {
    name.rsplit('.')
        .find(|part| part.contains('_'))
        .map_or("", |part| part.rsplit('_').next().unwrap_or(""))
}

/// The terminal summary: the largest derivatives (by size relative to the output's
/// value) with units.
fn summary(doc: &SensitivityDoc, solve_s: f64, total_s: f64, dir: &Path) -> String {
    let mut rows: Vec<(&SensitivityOutput, &SensitivityParameter, f64)> = Vec::new();
    for o in &doc.outputs {
        for p in &doc.parameters {
            if let Some(&d) = o.d.get(&p.name) {
                rows.push((o, p, d));
            }
        }
    }
    // Relative to the value, but never to less than 1e-3 of the largest value of the
    // same unit: an output that is zero by statics (a horizontal reaction of a
    // symmetric cable, -3.9e-12 N) would otherwise lead the list with its round-off.
    let mut largest: std::collections::HashMap<&str, f64> = std::collections::HashMap::new();
    for o in &doc.outputs {
        let entry = largest.entry(unit_of(&o.name)).or_insert(0.0);
        *entry = entry.max(o.value.abs());
    }
    let weight = |(o, _, d): &(&SensitivityOutput, &SensitivityParameter, f64)| {
        let scale = RELATIVE_FLOOR * largest.get(unit_of(&o.name)).copied().unwrap_or(0.0);
        (d / o.value.abs().max(scale).max(1e-300)).abs()
    };
    rows.sort_by(|a, b| weight(b).total_cmp(&weight(a)));
    let mut s = format!(
        "{}: converged (residual {} N); sensitivities of {} outputs to {} parameters in {} s (solve {} s)\n",
        doc.case,
        significant(doc.residual_n, 3),
        doc.outputs.len(),
        doc.parameters.len(),
        significant(total_s - solve_s, 3),
        significant(solve_s, 3),
    );
    s.push_str("largest relative changes (output value, derivative per parameter unit):\n");
    for (o, p, d) in rows.iter().take(SHOWN) {
        let unit = unit_of(&o.name);
        s.push_str(&format!(
            "  {:<40} {:>12} {unit:<3}  d/d{}: {:>12} {unit}/{}{}\n",
            o.name,
            significant(o.value, 4),
            p.name,
            significant(*d, 4),
            // A compound unit in parentheses: N/(m/s2), not N/m/s2.
            if p.unit.contains('/') {
                format!("({})", p.unit)
            } else {
                p.unit.clone()
            },
            if o.one_sided.contains(&p.name) {
                "  (one-sided)"
            } else {
                ""
            }
        ));
    }
    if !doc.near_switch.is_empty() {
        s.push_str(&format!(
            "{} constraint rows are near a switch (derivatives one-sided there): see sensitivity.json\n",
            doc.near_switch.len()
        ));
    }
    s.push_str(&format!(
        "written: {}, {} (and the base solve's result.json: `strand report {}` shows the table)\n",
        dir.join("sensitivity.json").display(),
        dir.join("sensitivity.csv").display(),
        dir.display()
    ));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_zero_by_statics_do_not_lead_the_relative_ranking() {
        let output = |name: &str, value: f64, d: f64| SensitivityOutput {
            name: name.into(),
            value,
            d: [("cable.length".to_string(), d)].into_iter().collect(),
            one_sided: Vec::new(),
        };
        let doc = SensitivityDoc {
            case: "hanging_cable".into(),
            converged: true,
            residual_n: 1e-12,
            parameters: vec![SensitivityParameter {
                name: "cable.length".into(),
                unit: "mm".into(),
            }],
            outputs: vec![
                // Zero by statics, its round-off and its derivative's.
                output("ecu.force_N.x", -3.9e-12, 1e-11),
                output("ecu.moment_Nm.x", 6e-18, 1e-17),
                // Real outputs: 1 % and 0.5 % per mm.
                output("ecu.force_N.z", 0.29, 0.0029),
                output("ecu.moment_Nm.y", 0.08, 0.0004),
            ],
            near_switch: Vec::new(),
        };
        let text = summary(&doc, 0.01, 0.02, Path::new("out"));
        let listed: Vec<&str> = text.lines().filter(|l| l.starts_with("  ")).collect();
        assert!(listed[0].contains("ecu.force_N.z"), "{text}");
        assert!(listed[1].contains("ecu.moment_Nm.y"), "{text}");
    }

    #[test]
    fn a_derivative_per_compound_unit_puts_it_in_parentheses() {
        let doc = SensitivityDoc {
            case: "pinned_cable".into(),
            converged: true,
            residual_n: 1e-12,
            parameters: vec![SensitivityParameter {
                name: "gravity.z".into(),
                unit: "m/s2".into(),
            }],
            outputs: vec![SensitivityOutput {
                name: "stud_left.force_N.z".into(),
                value: 0.39,
                d: [("gravity.z".to_string(), -0.04)].into_iter().collect(),
                one_sided: Vec::new(),
            }],
            near_switch: Vec::new(),
        };
        let text = summary(&doc, 0.01, 0.02, Path::new("out"));
        assert!(text.contains("-0.04 N/(m/s2)"), "{text}");
    }
}
