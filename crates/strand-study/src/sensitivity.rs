//! The engine of `strand sensitivity CASE --param NAME … --out DIR`: the derivative of
//! every output of the case's equilibrium with respect to each parameter
//! ([`strand_solve::sensitivity`]), written to `DIR/sensitivity.json` and
//! `DIR/sensitivity.csv`.

use std::path::Path;

use strand_case::{Case, CaseDesign, DesignParameter, DesignedCase, LengthUnit};
use strand_report::{
    OutputValue, SensitivityDoc, SensitivityOutput, SensitivityParameter, design_outputs,
    sensitivity_doc, write_atomic,
};
use strand_solve::Solution;
use strand_solve::sensitivity::{Sample, Sensitivities, SensitivitySettings};

use strand_case::ItemQuantity as Quantity;

use crate::batch::spec::resolve;
use crate::error::{Result, StudyError};
use crate::format::significant;

fn invalid(message: String) -> StudyError {
    StudyError::Input(message)
}

/// The design parameters `names` (variant items in short or full form, a vector's
/// component by `.x`, `.y`, `.z`), with their units: the error names a parameter that
/// is not a continuous item of the case or is named twice.
pub fn parameters(case: &Case, names: &[String]) -> Result<Vec<(DesignParameter, String)>> {
    let unit = LengthUnit::parse(&case.file.units.length);
    let mut out: Vec<(DesignParameter, String)> = Vec::new();
    for name in names {
        let (item, target, component) = resolve(name, name, &case.file)
            .map_err(|e| invalid(format!("--param {name}: {} (hint: {})", e.message, e.hint)))?;
        let (scale, unit_name) = match target.quantity() {
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
) -> Result<Vec<OutputValue>> {
    let b = &built.built;
    let doc = sensitivity_doc(
        &b.name,
        &b.model,
        solution,
        built.contact.as_ref(),
        &b.connector_names,
    )
    .map_err(|e| StudyError::Io(format!("{}: contacts: {e}", b.origin)))?;
    Ok(design_outputs(&doc, pins))
}

/// The sensitivities of `case`'s solved equilibrium `solution` with respect to
/// `names` ([`parameters`]): every output's value and its derivative per parameter
/// (per unit of the parameter: the case's length unit, kg, N, m/s²). A `solution`
/// that did not converge is [`StudyError::NotConverged`]: there is no equilibrium to
/// differentiate.
pub fn sensitivities(case: &Case, names: &[String], solution: &Solution) -> Result<SensitivityDoc> {
    let params = parameters(case, names)?;
    if !solution.report.converged {
        return Err(StudyError::NotConverged(format!(
            "{}: the case did not converge (residual {} N): there is no equilibrium to differentiate",
            case.origin,
            significant(solution.report.residual.combined_n, 3)
        )));
    }
    let design = CaseDesign::new(case, params.iter().map(|(p, _)| p.clone()).collect());
    let fail = |e: strand_solve::sensitivity::SensitivityError| {
        StudyError::Io(format!("{}: sensitivities: {e}", case.origin))
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

/// `strand sensitivity`'s document for `case` (checked against the limits): its
/// parameters `names` checked, the case built with its own segments and solved cold,
/// then [`sensitivities`] (a case that does not converge is
/// [`StudyError::NotConverged`]).
pub fn solve_and_differentiate(case: &Case, names: &[String]) -> Result<SensitivityDoc> {
    parameters(case, names)?;
    let built = case.build(None)?;
    let solution = crate::solve::solve_cold(&built)?;
    sensitivities(case, names, &solution)
}

/// Writes `doc` to `dir/sensitivity.json` and `dir/sensitivity.csv` (each atomically,
/// `dir` created).
pub fn write_sensitivities(dir: &Path, doc: &SensitivityDoc) -> Result<()> {
    let not_written =
        |e: strand_report::ReportError| StudyError::Io(format!("{}: {e}", dir.display()));
    std::fs::create_dir_all(dir).map_err(|e| {
        StudyError::Io(format!(
            "{}: cannot create the output directory: {e}",
            dir.display()
        ))
    })?;
    let json = serde_json::to_string_pretty(doc)
        .map_err(|e| StudyError::Io(format!("{}: {e}", dir.display())))?;
    write_atomic(&dir.join("sensitivity.json"), json.as_bytes()).map_err(not_written)?;
    write_atomic(&dir.join("sensitivity.csv"), doc.csv().as_bytes()).map_err(not_written)?;
    Ok(())
}
