//! `strand sensitivity CASE --param NAME … --out DIR`: the derivative of every output
//! of the case's equilibrium with respect to each parameter
//! ([`strand_solve::sensitivity`]), written to `DIR/sensitivity.json` and
//! `DIR/sensitivity.csv`; the terminal shows the largest ones.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use strand_case::{Case, CaseDesign, DesignParameter, LengthUnit};
use strand_report::{SensitivityDoc, SensitivityOutput, SensitivityParameter};
use strand_solve::Solution;
use strand_solve::sensitivity::SensitivitySettings;
use strand_study::optimize::{ENERGY, output_table};

use crate::Exit;
use crate::batch::spec::{Quantity, resolve};
use crate::commands::Failure;
use crate::summary::significant;

/// Largest derivatives shown on the terminal.
const SHOWN: usize = 12;

fn invalid(message: String) -> Failure {
    Failure {
        exit: Exit::InvalidInput,
        message,
    }
}

/// The typical size of a parameter of `quantity` in its unit in `case` (the
/// difference steps are a small fraction of it; [`DesignParameter::scale`]) and that
/// unit; `None` for a count.
pub(crate) fn parameter_scale(quantity: Quantity, case: &Case) -> Option<(f64, String)> {
    let unit = LengthUnit::parse(&case.file.units.length);
    Some(match quantity {
        Quantity::Length => (
            1.0 / unit.map_or(1.0, |u| u.metres()),
            case.file.units.length.clone(),
        ),
        // Loads enter the gradient linearly: large steps are exact and keep the
        // round-off of the stiff forces small.
        Quantity::Mass => (100.0, "kg".to_string()),
        Quantity::Force => (100.0, "N".to_string()),
        Quantity::Acceleration => (10.0, "m/s2".to_string()),
        Quantity::Count => return None,
    })
}

/// The design parameters named on the command line, with their units.
fn parameters(case: &Case, names: &[String]) -> Result<Vec<(DesignParameter, String)>, Failure> {
    let mut out: Vec<(DesignParameter, String)> = Vec::new();
    for name in names {
        let (item, quantity, component) = resolve(name, name, &case.file)
            .map_err(|e| invalid(format!("--param {name}: {} (hint: {})", e.message, e.hint)))?;
        let Some((scale, unit_name)) = parameter_scale(quantity, case) else {
            return Err(invalid(format!(
                "--param {name}: a number of segments is not a continuous parameter (hint: differentiate with respect to lengths, positions, masses, forces or gravity)"
            )));
        };
        if out
            .iter()
            .any(|(p, _)| p.item == item && p.component == component)
        {
            return Err(invalid(format!(
                "--param {name}: named twice (hint: give each parameter once)"
            )));
        }
        out.push((
            DesignParameter {
                item,
                component,
                scale,
            },
            unit_name,
        ));
    }
    Ok(out)
}

/// The sensitivities of `case`'s solved equilibrium `solution` with respect to
/// `names`.
pub(crate) fn sensitivities(
    case: &Case,
    names: &[String],
    solution: &Solution,
) -> Result<SensitivityDoc, Failure> {
    let params = parameters(case, names)?;
    let design = CaseDesign::new(case, params.iter().map(|(p, _)| p.clone()).collect());
    let table =
        output_table(&design, solution, &SensitivitySettings::default()).map_err(|e| Failure {
            exit: if e.is_input() {
                Exit::InvalidInput
            } else {
                Exit::Failure
            },
            message: format!("{}: sensitivities: {e}", case.origin),
        })?;
    let outputs = table
        .outputs
        .iter()
        .enumerate()
        .filter(|(_, o)| o.name != ENERGY)
        .map(|(k, o)| SensitivityOutput {
            name: o.name.clone(),
            value: o.value,
            d: names
                .iter()
                .zip(&table.derivatives[k])
                .filter(|(_, d)| d.is_finite())
                .map(|(n, d)| (n.clone(), *d))
                .collect(),
            // A peak whose arg differs from the base's on one side jumps here.
            one_sided: names
                .iter()
                .zip(&table.one_sided[k])
                .filter(|(_, one)| **one)
                .map(|(n, _)| n.clone())
                .collect(),
        })
        .collect();
    Ok(SensitivityDoc {
        case: case.name.clone(),
        converged: solution.report.converged,
        residual_n: solution.report.residual.combined_n,
        parameters: names
            .iter()
            .zip(&params)
            .map(|(n, (_, unit))| SensitivityParameter {
                name: n.clone(),
                unit: unit.clone(),
            })
            .collect(),
        outputs,
        near_switch: table
            .sensitivities
            .flagged
            .iter()
            .map(|f| {
                format!(
                    "{:?}: {:?} (value {:.3e}, multiplier {:.3e})",
                    f.key, f.flag, f.value, f.multiplier
                )
            })
            .collect(),
    })
}

/// `strand sensitivity`.
pub(crate) fn run(
    path: &Path,
    names: &[String],
    dir: &Path,
    out: &mut dyn Write,
) -> Result<Exit, Failure> {
    let started = Instant::now();
    let case = Case::from_path(path)?;
    crate::limits::check_case(&case)?;
    parameters(&case, names)?;
    let built = case.build(None)?;
    let solution = crate::study::solve_cold(&built)?;
    if !solution.report.converged {
        return Err(Failure {
            exit: Exit::NotConverged,
            message: format!(
                "{}: the case did not converge (residual {} N): there is no equilibrium to differentiate",
                case.origin,
                significant(solution.report.residual.combined_n, 3)
            ),
        });
    }
    let solve_s = started.elapsed().as_secs_f64();
    let doc = sensitivities(&case, names, &solution)?;
    let json = serde_json::to_string_pretty(&doc).expect("serialisable");
    crate::commands::write_files(
        dir,
        &[
            ("sensitivity.json", json.as_bytes()),
            ("sensitivity.csv", doc.csv().as_bytes()),
        ],
    )?;
    // The base solve's results next to them: the folder is a result for `strand report`.
    let result = crate::commands::result_doc(&built, &solution, strand_report::Timing::default())?;
    crate::commands::write_result_files(&built, &result, dir)?;
    let _ = write!(
        out,
        "{}",
        summary(&doc, solve_s, started.elapsed().as_secs_f64(), dir)
    );
    Ok(Exit::Success)
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
    let weight = |(o, _, d): &(&SensitivityOutput, &SensitivityParameter, f64)| {
        (d / o.value.abs().max(1e-12)).abs()
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
        let unit = o
            .name
            .rsplit('.')
            .find(|part| part.contains('_'))
            .map_or("", |part| part.rsplit('_').next().unwrap_or(""));
        s.push_str(&format!(
            "  {:<40} {:>12} {unit:<3}  d/d{}: {:>12} {unit}/{}{}\n",
            o.name,
            significant(o.value, 4),
            p.name,
            significant(*d, 4),
            p.unit,
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
