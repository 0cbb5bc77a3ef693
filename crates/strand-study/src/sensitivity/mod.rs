//! The engine of `strand sensitivity CASE --param NAME … --out DIR`: the derivative of
//! every output of the case's equilibrium with respect to each parameter
//! ([`strand_solve::sensitivity`]), written to `DIR/sensitivity.json` and
//! `DIR/sensitivity.csv`.

pub mod local;
pub mod table;

use std::path::Path;

use strand_case::{
    Case, CaseDesign, DesignParameter, ItemQuantity as Quantity, LengthUnit, VariantItem,
};
use strand_report::{SensitivityDoc, SensitivityOutput, SensitivityParameter};
use strand_solve::Solution;
use strand_solve::sensitivity::SensitivitySettings;

pub use local::{ExactDerivatives, LocalOutputs, LocalPath, LocalTangents};
pub use table::{
    ENERGY, EnergyOutput, OutputEvaluation, OutputTable, output_table, output_table_with,
    outputs_at,
};

use crate::batch::spec::{base_unit, resolve};
use crate::error::{Result, StudyError};
use crate::format::significant;

fn invalid(message: String) -> StudyError {
    StudyError::Input(message)
}

/// The typical size of parameter `item` in its unit in `case` (the difference steps
/// are a small fraction of it, [`DesignParameter::scale`]) and that unit (the case's
/// length unit, kg, N, m/s2, deg, N·m², Pa); `None` for a count.
pub fn parameter_scale(item: VariantItem, case: &Case) -> Option<(f64, String)> {
    let unit = LengthUnit::parse(&case.file.units.length);
    let quantity = item.quantity();
    if let VariantItem::Section { .. } = item {
        // A stiffness enters the gradient linearly (the energy is linear in it at a
        // fixed state), so the differences are exact at any step: a hundred times its
        // own value makes the steps 1 % of it and keeps the round-off of the stiff
        // forces out of the derivatives (as for masses and loads).
        let value = item.case_value(&case.file).map_or(1.0, f64::abs);
        let scale = if value > 0.0 && value.is_finite() {
            100.0 * value
        } else {
            100.0
        };
        return Some((scale, base_unit(quantity).to_string()));
    }
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
        // Ten radians, in degrees: the steps turn a frame by 1e-3 rad, small for the
        // truncation of the extrapolated differences (O(h⁴)) and large against the
        // round-off of reactions summed from stiff forces.
        Quantity::Angle => (1800.0 / std::f64::consts::PI, "deg".to_string()),
        Quantity::BendingStiffness | Quantity::Modulus => (1.0, base_unit(quantity).to_string()),
        Quantity::Count => return None,
    })
}

/// The design parameters `names` (variant items in short or full form, a vector's
/// component by `.x`, `.y`, `.z`), with their units: the error names a parameter that
/// is not a continuous item of the case or is named twice.
pub fn parameters(case: &Case, names: &[String]) -> Result<Vec<(DesignParameter, String)>> {
    let mut out: Vec<(DesignParameter, String)> = Vec::new();
    for name in names {
        let (item, target, component) = resolve(name, name, &case.file)
            .map_err(|e| invalid(format!("--param {name}: {} (hint: {})", e.message, e.hint)))?;
        let Some((scale, unit_name)) = parameter_scale(target, case) else {
            return Err(invalid(format!(
                "--param {name}: a number of segments is not a continuous parameter (hint: differentiate with respect to lengths, positions, directions, masses, forces, stiffnesses or gravity)"
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
/// `names` ([`parameters`]): every output's value and its derivative per parameter
/// (per unit of the parameter: the case's length unit, kg, N, m/s², deg, N·m², Pa), from
/// [`output_table`] (without the energy, [`ENERGY`]: [`EnergyOutput::Omitted`]).
pub fn sensitivities(case: &Case, names: &[String], solution: &Solution) -> Result<SensitivityDoc> {
    let params = parameters(case, names)?;
    if !solution.report.converged {
        return Err(StudyError::NotConverged(format!(
            "{}: the case did not converge (residual {} N): there is no equilibrium to differentiate",
            case.origin,
            significant(solution.report.residual.combined_n, 3)
        )));
    }
    // The steps start from the equilibrium: no guess of the case is computed for them.
    let design = CaseDesign::new(case, params.iter().map(|(p, _)| p.clone()).collect())
        .starting_from(&solution.state);
    let table = output_table(&design, solution, &SensitivitySettings::default())?;
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
    let json = serde_json::to_string_pretty(doc)
        .map_err(|e| StudyError::Io(format!("{}: {e}", dir.display())))?;
    crate::solve::write_files(
        dir,
        &[
            ("sensitivity.json", json.as_bytes()),
            ("sensitivity.csv", doc.csv().as_bytes()),
        ],
    )
}
