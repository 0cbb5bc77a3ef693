//! One design point of the optimisation: the case built at the variables' offsets,
//! its equilibrium solved warm from the last point (moved along the first-order path
//! of the last point's sensitivities), and every output with its exact gradient.

use strand_case::{Case, CaseDesign, DesignParameter, DesignedCase};
use strand_solve::sensitivity::{Design, SensitivitySettings};
use strand_solve::{Solution, SolveError, SolverSettings};

use super::OptimizeError;
use crate::error::StudyError;
use crate::sensitivity::{EnergyOutput, OutputEvaluation, OutputTable, output_table_with};

/// A solved design point with its outputs and their gradients.
pub struct Evaluation {
    /// Offsets of the variables from the case's values (item units).
    pub offsets: Vec<f64>,
    /// The built design.
    pub built: DesignedCase,
    /// Its equilibrium (converged).
    pub solution: Solution,
    /// Every output and its derivatives per variable.
    pub table: OutputTable,
}

/// Solves design points, counting the equilibrium solves.
pub struct Evaluator<'c> {
    case: &'c Case,
    parameters: Vec<DesignParameter>,
    sensitivity: SensitivitySettings,
    /// Whether the tables have the energy (only an `energy` objective reads it).
    energy: EnergyOutput,
    /// Equilibrium solves so far (every attempt, warm or cold, counts).
    pub solves: usize,
    /// Newton iterations of those solves.
    pub iterations: usize,
    /// The last point's design, whose analysis (the probes of its parameters) the
    /// next point takes over where it still holds ([`CaseDesign::recentred`]).
    last: Option<CaseDesign<'c>>,
}

/// Why a design point has no evaluation (the optimiser rejects the step there).
pub type Unsolved = String;

impl<'c> Evaluator<'c> {
    /// An evaluator of `case` over `parameters`, whose tables have the energy where
    /// `energy` includes it.
    pub fn new(
        case: &'c Case,
        parameters: Vec<DesignParameter>,
        sensitivity: SensitivitySettings,
        energy: EnergyOutput,
    ) -> Self {
        Self {
            case,
            parameters,
            sensitivity,
            energy,
            solves: 0,
            iterations: 0,
            last: None,
        }
    }

    /// The design centred at `offsets`.
    pub fn design(&self, offsets: &[f64]) -> CaseDesign<'c> {
        CaseDesign::centred_at(self.case, self.parameters.clone(), offsets.to_vec())
    }

    /// Solves the design at `offsets`: warm from `from` (its state moved by its state
    /// derivatives times the change of the offsets; from its plain state when that
    /// starts inside an obstacle) or, without `from`, cold from the case's initial
    /// guess. `Ok(Err(why))` when the equilibrium did not converge or cannot be
    /// differentiated (an unstable state): the point is unusable, not the run.
    pub fn evaluate(
        &mut self,
        offsets: &[f64],
        from: Option<&Evaluation>,
    ) -> Result<Result<Evaluation, Unsolved>, OptimizeError> {
        // A trial point's parameters can make the case invalid (a rod shorter than
        // its ends' distance): the point is unusable, not the run. At the start (no
        // `from`) that is the caller's error.
        let built = match &self.last {
            Some(last) => last.recentred(offsets.to_vec()),
            None => Ok(self.design(offsets)),
        }
        .and_then(|design| {
            let built = design.build(&vec![0.0; offsets.len()])?;
            Ok((design, built))
        });
        let (design, built) = match built {
            Ok(pair) => pair,
            Err(e) if from.is_some() => {
                return Ok(Err(format!("the design cannot be built: {}", e.summary())));
            }
            Err(e) => return Err(e.into()),
        };
        let solved = match from {
            None => {
                let b = &built.built;
                // The sensitivities reuse the solver's Hessian at the equilibrium.
                let settings = SolverSettings {
                    keep_hessian: true,
                    ..b.settings.clone()
                };
                self.solve(&built, b.initial.clone(), &settings)
            }
            Some(from) => {
                let model = &built.built.model;
                let mut start = from.solution.state.clone();
                model.enforce_supports(&mut start);
                let mut delta = vec![0.0; model.dofs().len()];
                for (j, p) in from.table.sensitivities.parameters.iter().enumerate() {
                    let dx = offsets[j] - from.offsets[j];
                    for (d, v) in delta.iter_mut().zip(&p.state) {
                        *d += v * dx;
                    }
                }
                let predicted = model.retract(&start, &delta);
                let settings = SolverSettings {
                    nested_iteration: false,
                    keep_hessian: true,
                    ..built.built.settings.clone()
                };
                match self.solve(&built, predicted, &settings) {
                    Err(SolveError::StartsInside(_)) => self.solve(&built, start, &settings),
                    Ok(s) if !s.report.converged => self.solve(&built, start, &settings),
                    other => other,
                }
            }
        };
        let solution = match solved {
            Ok(s) if s.report.converged => s,
            Ok(s) => {
                return Ok(Err(format!(
                    "the equilibrium did not converge (residual {:.3e} N)",
                    s.report.residual.combined_n
                )));
            }
            Err(e) => return Ok(Err(format!("the equilibrium could not be solved: {e}"))),
        };
        let table = match output_table_with(
            &design,
            &solution,
            &self.sensitivity,
            OutputEvaluation::Local,
            self.energy,
        ) {
            Ok(t) => {
                self.last = Some(design);
                t
            }
            Err(StudyError::Sensitivity { source, .. }) => {
                return Ok(Err(format!(
                    "the equilibrium cannot be differentiated: {source}"
                )));
            }
            Err(e) => return Err(e.into()),
        };
        Ok(Ok(Evaluation {
            offsets: offsets.to_vec(),
            built,
            solution,
            table,
        }))
    }

    fn solve(
        &mut self,
        built: &DesignedCase,
        start: strand_system::SystemState,
        settings: &SolverSettings,
    ) -> Result<Solution, SolveError> {
        self.solves += 1;
        let result = built.built.solve_from(start, settings);
        if let Ok(s) = &result {
            self.iterations += s.report.iterations;
        }
        result
    }
}
