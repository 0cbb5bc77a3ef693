//! `strand._strand._Case`: a case as read (its RON text and origin), optionally with a
//! named variant and `--vary`-style changes applied, and its solve.
//!
//! The text is kept so that a pickled case is parsed again by the same RON parser
//! (bit-identical numbers), and the changes as written so that they are parsed again
//! by the same grammar.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use pyo3::prelude::*;
use strand_case::schema::VariantChange;
use strand_case::{BuiltCase, Case};
use strand_report::Timing;
use strand_study::StudyError;
use strand_study::change::parse_change;
use strand_study::limits::check_case;
use strand_study::motion::parse_pose;
use strand_study::solve::{check_start, cold_start_warning, result_doc, solve_cold, solve_warm};

use crate::errors::{Stage, case_error, to_py};
use crate::solved::{Outcome, Solved};

/// How a case is written down: enough to make it again anywhere (pickling). The
/// steps are `("change", "ITEM=VALUE")` or `("pose", "NAME=VALUE")`, in order.
pub type CaseState = (
    String,
    String,
    String,
    Option<String>,
    Vec<(String, String)>,
);

/// One thing applied to the case after its named variant.
#[derive(Clone)]
enum Step {
    /// A change as written (`hose2.length=+30mm`) and parsed.
    Change(String, VariantChange),
    /// A pose of a motion: the motion, its parameter value (the motion's unit) and
    /// the pose as `strand solve --motion` labels it (`engine_roll=4deg`).
    Pose {
        motion: String,
        value: f64,
        label: String,
    },
}

impl Step {
    fn label(&self) -> &str {
        match self {
            Step::Change(text, _) => text,
            Step::Pose { label, .. } => label,
        }
    }
}

/// The label of `steps` (changes only) and their changes.
fn changes_of(steps: &[Step]) -> (String, Vec<VariantChange>) {
    let label: Vec<&str> = steps.iter().map(Step::label).collect();
    let changes = steps
        .iter()
        .filter_map(|s| match s {
            Step::Change(_, c) => Some(c.clone()),
            Step::Pose { .. } => None,
        })
        .collect();
    (label.join(", "), changes)
}

/// A case and what was applied to it.
#[derive(Clone)]
pub struct CaseSpec {
    /// The RON text as read.
    text: String,
    /// The case as read (its `name` possibly set by the caller).
    base: Case,
    /// The named variant applied, if any.
    variant: Option<String>,
    /// The case with the variant applied (`base` when none).
    start: Case,
    /// The changes and the motion pose (at most one) applied on top, in order.
    steps: Vec<Step>,
    /// The case with everything applied: what a batch varies, what changes are
    /// parsed against and what a motion follows.
    pub current: Case,
}

impl CaseSpec {
    fn new(text: String, mut base: Case, name: Option<String>) -> Result<Self, StudyError> {
        if let Some(name) = name {
            base.name = name;
        }
        check_case(&base)?;
        Ok(Self {
            text,
            start: base.clone(),
            current: base.clone(),
            base,
            variant: None,
            steps: Vec::new(),
        })
    }

    /// The case of RON `text`, named in messages `origin` (mesh paths relative to its
    /// folder), its name `name` (default: the file stem of `origin`).
    pub fn from_text(text: String, origin: &str, name: Option<String>) -> Result<Self, StudyError> {
        let case = Case::from_str(&text, origin)?;
        Self::new(text, case, name)
    }

    /// What `result.json` calls this case's variant: the named variant, the changes
    /// and the pose, or `None` for the case as read.
    pub fn label(&self) -> Option<String> {
        let mut parts: Vec<&str> = self.variant.iter().map(String::as_str).collect();
        parts.extend(self.steps.iter().map(Step::label));
        (!parts.is_empty()).then(|| parts.join(", "))
    }

    /// This case with `step` applied on top (the case so applied: `current`).
    fn with_step(&self, step: Step, current: Case) -> Self {
        let mut spec = self.clone();
        spec.steps.push(step);
        spec.current = current;
        spec
    }

    fn with_variant(&self, name: &str) -> Result<Self, StudyError> {
        if self.variant.is_some() || !self.steps.is_empty() {
            return Err(StudyError::Input(format!(
                "{}: variant '{name}': apply a named variant to the case as read, before any other variant, change or motion pose",
                self.base.origin
            )));
        }
        let start = self.base.with_variant(name)?;
        Ok(Self {
            text: self.text.clone(),
            base: self.base.clone(),
            variant: Some(name.to_string()),
            current: start.clone(),
            start,
            steps: Vec::new(),
        })
    }

    /// Parses every change against the case as changed so far (so that a second
    /// change of one item starts from the first) and applies it.
    fn with_changes(&self, texts: &[String]) -> Result<Self, StudyError> {
        let mut spec = self.clone();
        for text in texts {
            let change = parse_change(&spec.current, text)?;
            let current = spec
                .current
                .with_changes(text, std::slice::from_ref(&change))?;
            spec = spec.with_step(Step::Change(text.clone(), change), current);
        }
        Ok(spec)
    }

    /// The case at pose `NAME=VALUE` of one of its motions, as `strand solve
    /// --motion` and `strand batch --motion` take it (`engine_roll=4deg`; the value in
    /// the motion's unit, the unit optional): the moving parts moved, for this case's
    /// solves, batches and later changes. Errors as the command line's.
    pub fn with_pose(&self, pose: &str) -> Result<Self, StudyError> {
        let (motion, value, unit) = parse_pose(&self.current, pose)?;
        let current = self.current.at_pose(&motion, value)?;
        let label = format!("{motion}={value}{unit}");
        Ok(self.with_step(
            Step::Pose {
                motion,
                value,
                label,
            },
            current,
        ))
    }

    /// Whether a motion pose is applied.
    pub fn posed(&self) -> bool {
        self.steps.iter().any(|s| matches!(s, Step::Pose { .. }))
    }

    /// Validates and builds the model, as `strand solve` (`--variant`, `--motion`)
    /// and `strand batch` do: errors name the variant, the changes or the pose.
    pub fn build(&self, segments: Option<usize>) -> Result<BuiltCase, StudyError> {
        let pose = self
            .steps
            .iter()
            .position(|s| matches!(s, Step::Pose { .. }));
        Ok(match (pose, &self.variant, self.steps.is_empty()) {
            (_, None, true) => self.base.build(segments)?,
            (_, Some(name), true) => self.base.build_variant(name, segments)?,
            (None, _, false) => {
                let (label, changes) = changes_of(&self.steps);
                self.start.build_with_changes(&label, &changes, segments)?
            }
            (Some(k), _, false) => {
                let Step::Pose { motion, value, .. } = &self.steps[k] else {
                    unreachable!("a pose step")
                };
                let (before, after) = (&self.steps[..k], &self.steps[k + 1..]);
                let unposed = if before.is_empty() {
                    self.start.clone()
                } else {
                    let (label, changes) = changes_of(before);
                    self.start.with_changes(&label, &changes)?
                };
                if after.is_empty() {
                    // `strand solve --motion`'s build.
                    unposed.build_motion(motion, *value, segments)?
                } else {
                    let (label, changes) = changes_of(after);
                    unposed
                        .at_pose(motion, *value)?
                        .build_with_changes(&label, &changes, segments)?
                }
            }
        })
    }

    /// The case written down.
    pub fn state(&self) -> CaseState {
        let steps = self
            .steps
            .iter()
            .map(|s| match s {
                Step::Change(text, _) => ("change".to_string(), text.clone()),
                Step::Pose { label, .. } => ("pose".to_string(), label.clone()),
            })
            .collect();
        (
            self.text.clone(),
            self.base.origin.clone(),
            self.base.name.clone(),
            self.variant.clone(),
            steps,
        )
    }

    /// The case of `state`, read and changed again.
    pub fn from_state(state: &CaseState) -> Result<Self, StudyError> {
        let (text, origin, name, variant, steps) = state;
        let base = Case::from_str(text, origin)?;
        let mut spec = Self::new(text.clone(), base, Some(name.clone()))?;
        if let Some(variant) = variant {
            spec = spec.with_variant(variant)?;
        }
        for (kind, text) in steps {
            spec = match kind.as_str() {
                "pose" => spec.with_pose(text)?,
                _ => spec.with_changes(std::slice::from_ref(text))?,
            };
        }
        Ok(spec)
    }

    /// Builds and solves, cold or warm-started from `warm` (when that converged), and
    /// makes the result document, timed like `strand solve` (`read` is 0: the case was
    /// read before).
    pub fn solve(
        self: &Arc<Self>,
        warm: Option<&Solved>,
        segments: Option<usize>,
    ) -> Result<Outcome, StudyError> {
        let started = Instant::now();
        let built = self.build(segments)?;
        let build_s = started.elapsed().as_secs_f64();
        let label = self.label();
        let mut warning = None;
        let (solution, base_iterations) = match warm {
            Some(base) if base.converged() => {
                let base_built = base.built()?;
                fits(&base_built, &built)?;
                let solution = solve_warm(&base_built, &base.state, &built)?;
                (solution, Some(base.iterations()))
            }
            Some(base) => {
                warning = Some(cold_start_warning(
                    &base.case.base.origin,
                    label.as_deref().unwrap_or(&self.base.name),
                    base.residual_n(),
                    base.iterations(),
                ));
                (solve_cold(&built)?, None)
            }
            None => (solve_cold(&built)?, None),
        };
        let timing = Timing {
            read: 0.0,
            build: build_s,
            solve: solution.report.solve_seconds,
            post: 0.0,
            total: started.elapsed().as_secs_f64(),
        };
        let mut doc = result_doc(&built, &solution, timing, label.as_deref(), base_iterations)?;
        doc.timing_s.total = started.elapsed().as_secs_f64();
        Ok(Outcome {
            solved: Solved::new(Arc::clone(self), segments, doc, solution.state, built),
            warning,
        })
    }
}

/// A warm start carries rods over by name and everything else (junction poses, clip
/// joints) as it is: `base` must have the junctions and clips of `built`.
fn fits(base: &BuiltCase, built: &BuiltCase) -> Result<(), StudyError> {
    let (from, to) = (base.model.system(), built.model.system());
    if from.bodies.len() == to.bodies.len() && from.clips.len() == to.clips.len() {
        return Ok(());
    }
    Err(StudyError::Input(format!(
        "{}: warm_start: the result is of {} with {} junction(s) and {} clip(s), this case has {} and {} (hint: warm-start from a result of this case or of a variant of it)",
        built.origin,
        base.origin,
        from.bodies.len(),
        from.clips.len(),
        to.bodies.len(),
        to.clips.len()
    )))
}

/// A case (see `strand.Case`).
#[pyclass(name = "_Case", module = "strand._strand", frozen)]
pub struct PyCase {
    pub spec: Arc<CaseSpec>,
}

fn solve_error(f: StudyError) -> PyErr {
    to_py(f, Stage::Solve)
}

/// `spec` as a Python case, or its error as the exception.
fn wrap(spec: Result<CaseSpec, StudyError>) -> PyResult<PyCase> {
    Ok(PyCase {
        spec: Arc::new(spec.map_err(solve_error)?),
    })
}

#[pymethods]
impl PyCase {
    /// Reads and checks the case file `path`.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<PyCase> {
        // An unreadable file: the error of `strand solve`, with its hint.
        let text = std::fs::read_to_string(&path).map_err(|e| match Case::from_path(&path) {
            Err(error) => case_error(error),
            Ok(_) => crate::errors::raise("InputError", format!("{}: {e}", path.display())),
        })?;
        let case = Case::from_str(&text, &path.display().to_string()).map_err(case_error)?;
        wrap(CaseSpec::new(text, case, None))
    }

    /// Parses case text; mesh paths are relative to `base_dir` (default: the current
    /// directory); messages name the text `<base_dir>/<string>`.
    #[staticmethod]
    #[pyo3(signature = (text, base_dir=None, name=None))]
    fn from_str(text: String, base_dir: Option<PathBuf>, name: Option<String>) -> PyResult<PyCase> {
        let origin = base_dir
            .map(|d| d.join("<string>"))
            .unwrap_or_else(|| PathBuf::from("<string>"));
        let case = Case::from_str(&text, &origin.display().to_string()).map_err(case_error)?;
        wrap(CaseSpec::new(
            text,
            case,
            Some(name.unwrap_or_else(|| "case".into())),
        ))
    }

    /// The case name.
    #[getter]
    fn name(&self) -> String {
        self.spec.base.name.clone()
    }

    /// The file as named (messages use it).
    #[getter]
    fn origin(&self) -> String {
        self.spec.base.origin.clone()
    }

    /// The applied variant and changes, or `None`.
    #[getter]
    fn label(&self) -> Option<String> {
        self.spec.label()
    }

    /// The case's named variants.
    #[getter]
    fn variant_names(&self) -> Vec<String> {
        self.spec
            .base
            .variant_names()
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    /// The case with named variant `name` applied.
    fn variant(&self, name: &str) -> PyResult<PyCase> {
        wrap(self.spec.with_variant(name))
    }

    /// The case with changes `ITEM=VALUE` (the `--vary` grammar) applied.
    fn with_changes(&self, changes: Vec<String>) -> PyResult<PyCase> {
        wrap(self.spec.with_changes(&changes))
    }

    /// Validates the case (with its variant and changes) as `strand check` does:
    /// builds it and checks that no hose starts inside a part.
    #[pyo3(signature = (segments=None))]
    fn check(&self, py: Python<'_>, segments: Option<usize>) -> PyResult<()> {
        let spec = &self.spec;
        py.detach(|| check_start(&spec.build(segments)?))
            .map_err(solve_error)
    }

    /// Solves (GIL released): a `_Solved` and the warning of a cold start, if any.
    #[pyo3(signature = (warm_start=None, segments=None))]
    fn solve(
        &self,
        py: Python<'_>,
        warm_start: Option<Bound<'_, Solved>>,
        segments: Option<usize>,
    ) -> PyResult<(Solved, Option<String>)> {
        let warm = warm_start.as_ref().map(|w| w.get());
        let spec = &self.spec;
        let outcome = py
            .detach(|| spec.solve(warm, segments))
            .map_err(solve_error)?;
        Ok((outcome.solved, outcome.warning))
    }

    /// `sensitivity.json` of `strand sensitivity` for `params` (GIL released).
    fn sensitivity(&self, py: Python<'_>, params: Vec<String>) -> PyResult<String> {
        let case = &self.spec.current;
        let doc = py
            .detach(|| strand_study::sensitivity::solve_and_differentiate(case, &params))
            .map_err(solve_error)?;
        serde_json::to_string(&doc).map_err(|e| crate::errors::raise("StrandError", e.to_string()))
    }

    /// The case at pose `NAME=VALUE` of one of its motions (`strand solve --motion`).
    fn at_pose(&self, pose: &str) -> PyResult<PyCase> {
        wrap(self.spec.with_pose(pose))
    }

    /// `strand motion` over `range` of motion `motion` (GIL released): see
    /// [`crate::motion::FollowedMotion`].
    #[pyo3(signature = (motion, range, segments=None, predictor="secant"))]
    fn motion(
        &self,
        py: Python<'_>,
        motion: &str,
        range: &str,
        segments: Option<usize>,
        predictor: &str,
    ) -> PyResult<crate::motion::FollowedMotion> {
        let spec = &self.spec;
        py.detach(|| crate::motion::follow(spec, motion, range, segments, predictor))
            .map_err(solve_error)
    }

    /// `strand optimize` (GIL released): see [`crate::optimize::OptimizeOutput`].
    fn optimize(
        &self,
        py: Python<'_>,
        vary: Vec<String>,
        minimize: &str,
        subject_to: Vec<String>,
    ) -> PyResult<crate::optimize::OptimizeOutput> {
        let spec = &self.spec;
        py.detach(|| crate::optimize::optimize(spec, &vary, minimize, &subject_to))
            .map_err(solve_error)
    }

    /// The case written down (for pickling).
    fn state(&self) -> CaseState {
        self.spec.state()
    }

    /// The case of `state` (see `state`).
    #[staticmethod]
    fn from_state(state: CaseState) -> PyResult<PyCase> {
        wrap(CaseSpec::from_state(&state))
    }
}
