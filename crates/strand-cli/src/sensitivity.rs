//! `strand sensitivity CASE --param NAME … --out DIR`: the derivative of every output
//! of the case's equilibrium with respect to each parameter
//! ([`strand_solve::sensitivity`]), written to `DIR/sensitivity.json` and
//! `DIR/sensitivity.csv`; the terminal shows the largest ones.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use strand_case::{Case, CaseDesign, DesignParameter, DesignedCase, LengthUnit};
use strand_report::{
    OutputValue, SensitivityDoc, SensitivityOutput, SensitivityParameter, design_outputs,
    sensitivity_doc, write_atomic,
};
use strand_solve::Solution;
use strand_solve::sensitivity::{Sample, Sensitivities, SensitivitySettings};

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

/// The design parameters named on the command line, with their units.
pub(crate) fn parameters(
    case: &Case,
    names: &[String],
) -> Result<Vec<(DesignParameter, String)>, Failure> {
    let unit = LengthUnit::parse(&case.file.units.length);
    let mut out: Vec<(DesignParameter, String)> = Vec::new();
    for name in names {
        let (item, quantity, component) = resolve(name, name, &case.file)
            .map_err(|e| invalid(format!("--param {name}: {} (hint: {})", e.message, e.hint)))?;
        let (scale, unit_name) = match quantity {
            Quantity::Length => (
                1.0 / unit.map_or(1.0, |u| u.metres()),
                case.file.units.length.clone(),
            ),
            // Loads enter the gradient linearly: large steps are exact and keep the
            // round-off of the stiff forces small.
            Quantity::Mass => (100.0, "kg".to_string()),
            Quantity::Force => (100.0, "N".to_string()),
            Quantity::Acceleration => (10.0, "m/s2".to_string()),
            Quantity::Count => {
                return Err(invalid(format!(
                    "--param {name}: a number of segments is not a continuous parameter (hint: differentiate with respect to lengths, positions, masses, forces or gravity)"
                )));
            }
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

/// The named outputs of a design at a solution.
fn outputs_at(
    built: &DesignedCase,
    solution: &Solution,
    pins: Option<&[OutputValue]>,
) -> Result<Vec<OutputValue>, Failure> {
    let b = &built.built;
    let doc = sensitivity_doc(
        &b.name,
        &b.model,
        solution,
        built.contact.as_ref(),
        &b.connector_names,
    )
    .map_err(|e| Failure {
        exit: Exit::Failure,
        message: format!("{}: contacts: {e}", b.origin),
    })?;
    Ok(design_outputs(&doc, pins))
}

/// The sensitivities of `case`'s solved equilibrium `solution` with respect to
/// `names`; an error (exit 3) when `solution` did not converge.
pub(crate) fn sensitivities(
    case: &Case,
    names: &[String],
    solution: &Solution,
) -> Result<SensitivityDoc, Failure> {
    let params = parameters(case, names)?;
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
    let design = CaseDesign::new(case, params.iter().map(|(p, _)| p.clone()).collect());
    let fail = |e: strand_solve::sensitivity::SensitivityError| Failure {
        exit: Exit::Failure,
        message: format!("{}: sensitivities: {e}", case.origin),
    };
    let s =
        Sensitivities::compute(&design, solution, &SensitivitySettings::default()).map_err(fail)?;
    let base_built = strand_solve::sensitivity::Design::build(&design, &vec![0.0; names.len()])?;
    let base = outputs_at(&base_built, solution, None)?;
    let mut outputs: Vec<SensitivityOutput> = base
        .iter()
        .map(|o| SensitivityOutput {
            name: o.name.clone(),
            value: o.value,
            d: Default::default(),
            one_sided: Vec::new(),
        })
        .collect();
    for (j, name) in names.iter().enumerate() {
        let mut failure = None;
        let derivatives = s
            .derivative(&design, solution, j, |built, at| {
                let here = outputs_at(built, at, Some(&base)).unwrap_or_else(|e| {
                    failure = Some(e);
                    Vec::new()
                });
                base.iter()
                    .map(|b| {
                        here.iter().find(|o| o.name == b.name).map_or(
                            Sample {
                                value: f64::NAN,
                                arg: usize::MAX,
                            },
                            |o| Sample {
                                value: o.value,
                                arg: o.arg,
                            },
                        )
                    })
                    .collect()
            })
            .map_err(fail)?;
        if let Some(e) = failure {
            return Err(e);
        }
        for (o, d) in outputs.iter_mut().zip(&derivatives) {
            if d.derivative.is_finite() {
                o.d.insert(name.clone(), d.derivative);
            }
            // A peak whose arg differs from the base's on one side jumps here.
            if d.one_sided {
                o.one_sided.push(name.clone());
            }
        }
    }
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
        near_switch: s
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
    let solve_s = started.elapsed().as_secs_f64();
    let doc = sensitivities(&case, names, &solution)?;
    let not_written = |e: strand_report::ReportError| Failure {
        exit: Exit::Failure,
        message: format!("{}: {e}", dir.display()),
    };
    std::fs::create_dir_all(dir).map_err(|e| Failure {
        exit: Exit::Failure,
        message: format!("{}: cannot create the output directory: {e}", dir.display()),
    })?;
    let json = serde_json::to_string_pretty(&doc).expect("serialisable");
    write_atomic(&dir.join("sensitivity.json"), json.as_bytes()).map_err(not_written)?;
    write_atomic(&dir.join("sensitivity.csv"), doc.csv().as_bytes()).map_err(not_written)?;
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
        "written: {}, {}\n",
        dir.join("sensitivity.json").display(),
        dir.join("sensitivity.csv").display()
    ));
    s
}
