//! The named outputs of a solved design and their exact derivatives with respect to
//! every parameter ([`strand_solve::sensitivity`] and the chain rule along the
//! first-order path): what `strand sensitivity` writes ([`super::sensitivities`])
//! and what the optimiser's gradients are ([`crate::optimize`]).

use strand_case::{CaseDesign, DesignedCase};
use strand_report::{ContactOutputs, OutputValue, design_outputs, sensitivity_doc_from};
use strand_solve::Solution;
use strand_solve::sensitivity::{
    Design, PathRows, Sample, Sensitivities, SensitivityError, SensitivitySettings,
};

use super::local::{LocalOutputs, LocalPath, LocalTangents};
use crate::error::{Result, StudyError};

/// Every output of a solved design with its derivative per parameter.
#[derive(Clone, Debug)]
pub struct OutputTable {
    /// The outputs at the design (names and units as in `sensitivity.json`).
    pub outputs: Vec<OutputValue>,
    /// `derivatives[k][j]`: d output `k` / d parameter `j`, output unit per parameter
    /// unit (NaN where the output is not defined along the path).
    pub derivatives: Vec<Vec<f64>>,
    /// `one_sided[k][j]`: the arg-max/arg-min of output `k` moves within the
    /// difference steps of parameter `j` (the derivative holds on one side only).
    pub one_sided: Vec<Vec<bool>>,
    /// The sensitivities of the equilibrium (state and multiplier derivatives).
    pub sensitivities: Sensitivities,
    /// Vertices whose sectional quantities were evaluated at the outermost points of
    /// the parameters' paths to find where the peaks are there, summed over the
    /// parameters read locally (both sides counted): every vertex of every rod along
    /// a path ([`OutputEvaluation::LocalDifferences`]), the candidates a first-order
    /// bound leaves with exact derivatives ([`OutputEvaluation::Local`]).
    pub outer_vertices: usize,
}

impl OutputTable {
    /// The index of output `name`.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.outputs.iter().position(|o| o.name == name)
    }
}

/// The named outputs of `built` at `solution` (peaks read at the pinned args when
/// `pins` are given, see [`design_outputs`]), the energy ([`ENERGY`]) last.
pub fn outputs_at(
    built: &DesignedCase,
    solution: &Solution,
    pins: Option<&[OutputValue]>,
) -> Result<Vec<OutputValue>> {
    let contacts = contact_outputs(built, solution)?;
    outputs_with(
        built,
        solution,
        pins,
        EnergyOutput::Included,
        contacts.as_ref(),
    )
}

/// The contacts and least clearances of `built` at `solution` (`None` without
/// contact).
fn contact_outputs(built: &DesignedCase, solution: &Solution) -> Result<Option<ContactOutputs>> {
    let b = &built.built;
    built
        .contact
        .as_ref()
        .map(|c| ContactOutputs::of(&b.model, solution, c))
        .transpose()
        .map_err(|e| StudyError::Io(format!("{}: contacts: {e}", b.origin)))
}

/// [`outputs_at`] with the energy only where `energy` includes it, and the contacts
/// and least clearances `contacts` (those of `built` at `solution`).
fn outputs_with(
    built: &DesignedCase,
    solution: &Solution,
    pins: Option<&[OutputValue]>,
    energy: EnergyOutput,
    contacts: Option<&ContactOutputs>,
) -> Result<Vec<OutputValue>> {
    let b = &built.built;
    let doc = sensitivity_doc_from(&b.name, &b.model, solution, contacts, &b.connector_names);
    let mut outputs = design_outputs(&doc, pins);
    if energy == EnergyOutput::Omitted {
        return Ok(outputs);
    }
    // The energy of this state (a point near an equilibrium carries the equilibrium's
    // report, whose energy is the equilibrium's).
    outputs.push(OutputValue {
        name: ENERGY.to_string(),
        value: b.model.energy(&solution.state),
        arg: 0,
    });
    Ok(outputs)
}

/// The name of the total potential energy (J) among the outputs: the optimiser's
/// `energy` objective. Not part of `sensitivity.json`: its derivative matches full
/// solves to 1e-5 on the Elastica, cooler-hose and contact cases, but only to
/// 1.3e-3 relative on the harness with its hinge on the stop (not understood yet).
pub const ENERGY: &str = "energy_J";

/// Whether an [`OutputTable`] has the total potential energy ([`ENERGY`]) among its
/// outputs. It has no local reading: the whole model's energy at every point of the
/// first-order path costs about two Newton iterations of the cooler hose's ten
/// parameters, so a table has it only where it is asked for (the optimiser's
/// `energy` objective).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum EnergyOutput {
    /// Without the energy (the default: `sensitivity.json` does not list it).
    #[default]
    Omitted,
    /// With the energy as the last output.
    Included,
}

/// How [`output_table_with`] evaluates the outputs along the first-order path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum OutputEvaluation {
    /// Each output from the elements it depends on ([`LocalOutputs`]) where the case
    /// has a local plan, else the whole table (the default). Along an affine
    /// parameter the derivatives are exact directional derivatives of the readings
    /// ([`LocalTangents`]: no point of the path is evaluated but the outermost ones,
    /// for the few vertices that could hold a peak there); elsewhere
    /// [`OutputEvaluation::LocalDifferences`].
    #[default]
    Local,
    /// Each output from the elements it depends on where the case has a local plan,
    /// differentiated along the first-order path (extrapolated differences at up to
    /// twelve points, [`LocalPath`] along an affine parameter): the reference the
    /// exact derivatives are tested against.
    LocalDifferences,
    /// The whole table ([`outputs_at`]) at every point: the reference the local
    /// reading is tested against.
    WholeTable,
}

/// The outputs of `design` at its converged `solution` (at zero offsets) and their
/// derivatives with respect to every parameter of `design` (outputs read locally
/// where the case allows, [`OutputEvaluation::Local`]; without the energy,
/// [`EnergyOutput::Omitted`]).
pub fn output_table(
    design: &CaseDesign<'_>,
    solution: &Solution,
    settings: &SensitivitySettings,
) -> Result<OutputTable> {
    output_table_with(
        design,
        solution,
        settings,
        OutputEvaluation::Local,
        EnergyOutput::Omitted,
    )
}

/// [`output_table`] with the outputs along the path evaluated as `evaluation` says,
/// and the energy where `energy` includes it.
pub fn output_table_with(
    design: &CaseDesign<'_>,
    solution: &Solution,
    settings: &SensitivitySettings,
    evaluation: OutputEvaluation,
    energy: EnergyOutput,
) -> Result<OutputTable> {
    let count = design.parameter_count();
    let failed = |e: SensitivityError| StudyError::sensitivity(&design.case().origin, e);
    let base_built = design.build(&vec![0.0; count])?;
    // The base's contacts and least clearances, found once for its outputs and plan.
    let base_contacts = contact_outputs(&base_built, solution)?;
    let outputs = outputs_with(&base_built, solution, None, energy, base_contacts.as_ref())?;
    let plan = match evaluation {
        OutputEvaluation::Local => {
            LocalOutputs::plan_exact(&base_built, solution, &outputs, base_contacts)
        }
        OutputEvaluation::LocalDifferences => LocalOutputs::plan(&base_built, solution, &outputs),
        OutputEvaluation::WholeTable => None,
    };
    // Every rod linearised once for the exact derivatives along affine lines.
    let mut tangents = match (&plan, evaluation) {
        (Some(plan), OutputEvaluation::Local) => {
            LocalTangents::new(plan, &base_built.built.model, &solution.state)
        }
        _ => None,
    };
    let all_vertices: usize = base_built
        .built
        .model
        .system()
        .rods
        .iter()
        .map(|r| r.rod.segments() + 1)
        .sum();
    let mut outer_vertices = 0;
    // Read along the affine parameters' lines, the outputs build no design at the
    // path's points: the designs the state's right-hand sides move need not be kept.
    let local_lines = plan.as_ref().is_some_and(|p| !p.reads_energy());
    let kept = design.keep_moved_designs(!local_lines);
    let sensitivities = Sensitivities::compute(design, solution, settings);
    design.keep_moved_designs(kept);
    let sensitivities = sensitivities.map_err(failed)?;
    let mut derivatives = vec![vec![f64::NAN; count]; outputs.len()];
    let mut one_sided = vec![vec![false; count]; outputs.len()];
    for j in 0..count {
        let mut failure = None;
        // Along an affine parameter the local readings need no design built at the
        // path's points ([`LocalPath`]); the energy has no local reading there.
        let line = match &plan {
            Some(plan) if !plan.reads_energy() => design.affine_line(j)?,
            _ => None,
        };
        // Exact along an affine line (the energy, which has no local reading, along
        // the path with the designs built there).
        let line = match (&plan, &tangents) {
            (Some(plan), Some(_)) if plan.reads_energy() => design.affine_line(j)?,
            _ => line,
        };
        let exact = match (&mut tangents, &line) {
            (Some(tangents), Some(line)) => {
                let p = &sensitivities.parameters[j];
                let multipliers = (sensitivities.active.as_slice(), p.multipliers.as_slice());
                tangents
                    .derivatives(line, &p.state, multipliers, p.output_step)
                    .map_err(|e| {
                        failed(SensitivityError::Design {
                            parameter: j,
                            source: Box::new(e),
                        })
                    })?
            }
            _ => None,
        };
        // A plan with contact readings reads them at the base only: without exact
        // derivatives the whole table is differentiated along the path.
        let along = plan.as_ref().filter(|p| !p.reads_contacts());
        let d = match (along, line) {
            _ if exact.is_some() => {
                let exact = exact.expect("checked");
                outer_vertices += exact.outer_vertices;
                let mut d = exact.outputs;
                if let Some(plan) = plan.as_ref().filter(|p| p.reads_energy()) {
                    outer_vertices += 2 * all_vertices;
                    let along = sensitivities
                        .derivative_at(design, solution, j, PathRows::Active, |built, at, place| {
                            plan.read(&built.built.model, at, place)
                        })
                        .map_err(failed)?;
                    let k = d.len() - 1;
                    d[k] = along[k];
                }
                Ok(d)
            }
            (Some(plan), Some(line)) => {
                outer_vertices += 2 * all_vertices;
                let tangent = &sensitivities.parameters[j].state;
                let mut path = LocalPath::new(plan, line, &solution.state, tangent);
                sensitivities.derivative_along(j, |t, place| {
                    path.read(t, place).map_err(|e| SensitivityError::Design {
                        parameter: j,
                        source: Box::new(e),
                    })
                })
            }
            (Some(plan), None) => {
                outer_vertices += 2 * all_vertices;
                sensitivities.derivative_at(
                    design,
                    solution,
                    j,
                    PathRows::Active,
                    |built, at, place| plan.read(&built.built.model, at, place),
                )
            }
            // The outputs read contact forces by their keys: the active rows suffice.
            (None, _) => {
                sensitivities.derivative(design, solution, j, PathRows::Active, |built, at| {
                    whole_table_samples(built, at, &outputs, energy, &mut failure)
                })
            }
        }
        .map_err(failed)?;
        if let Some(e) = failure {
            return Err(e);
        }
        for (k, d) in d.iter().enumerate() {
            derivatives[k][j] = d.derivative;
            one_sided[k][j] = d.one_sided;
        }
    }
    Ok(OutputTable {
        outputs,
        derivatives,
        one_sided,
        sensitivities,
        outer_vertices,
    })
}

/// The whole table at a point, as samples in the order of the base's `outputs` (NaN
/// where an output is missing there); the first error is kept in `failure`.
fn whole_table_samples(
    built: &DesignedCase,
    at: &Solution,
    outputs: &[OutputValue],
    energy: EnergyOutput,
    failure: &mut Option<StudyError>,
) -> Vec<Sample> {
    let here = contact_outputs(built, at)
        .and_then(|contacts| outputs_with(built, at, Some(outputs), energy, contacts.as_ref()))
        .unwrap_or_else(|e| {
            *failure = Some(e);
            Vec::new()
        });
    outputs
        .iter()
        .enumerate()
        .map(|(k, b)| {
            // The same output is almost always at the same index.
            let same = here.get(k).filter(|o| o.name == b.name);
            same.or_else(|| here.iter().find(|o| o.name == b.name))
                .map_or(
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
}
