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
use strand_study::solve::{check_start, cold_start_warning, result_doc, solve_cold, solve_warm};

use crate::errors::{Stage, case_error, to_py};
use crate::solved::{Outcome, Solved};

/// How a case is written down: enough to make it again anywhere (pickling).
pub type CaseState = (String, String, String, Option<String>, Vec<String>);

/// A case and what was applied to it.
pub struct CaseSpec {
    /// The RON text as read.
    text: String,
    /// The case as read (its `name` possibly set by the caller).
    base: Case,
    /// The named variant applied, if any.
    variant: Option<String>,
    /// The case with the variant applied (`base` when none).
    start: Case,
    /// The changes applied on top, as written (`hose2.length=+30mm`) and parsed.
    changes: Vec<(String, VariantChange)>,
    /// The case with everything applied: what a batch varies and what changes are
    /// parsed against.
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
            changes: Vec::new(),
        })
    }

    /// The label of the changes alone (`a=1, b=2`).
    fn changes_label(&self) -> String {
        let texts: Vec<&str> = self.changes.iter().map(|(t, _)| t.as_str()).collect();
        texts.join(", ")
    }

    /// What `result.json` calls this case's variant: the named variant and the
    /// changes, or `None` for the case as read.
    pub fn label(&self) -> Option<String> {
        let mut parts: Vec<String> = self.variant.iter().cloned().collect();
        if !self.changes.is_empty() {
            parts.push(self.changes_label());
        }
        (!parts.is_empty()).then(|| parts.join(", "))
    }

    fn with_variant(&self, name: &str) -> Result<Self, StudyError> {
        if self.variant.is_some() || !self.changes.is_empty() {
            return Err(StudyError::Input(format!(
                "{}: variant '{name}': apply a named variant to the case as read, before any other variant or change",
                self.base.origin
            )));
        }
        let file = self.base.variant_file(name)?;
        let start = Case {
            file,
            ..self.base.clone()
        };
        Ok(Self {
            text: self.text.clone(),
            base: self.base.clone(),
            variant: Some(name.to_string()),
            current: start.clone(),
            start,
            changes: Vec::new(),
        })
    }

    /// Parses every change against the case as changed so far (so that a second
    /// change of one item starts from the first) and applies it.
    fn with_changes(&self, texts: &[String]) -> Result<Self, StudyError> {
        let mut changes = self.changes.clone();
        let mut current = self.current.clone();
        for text in texts {
            let change = parse_change(&current, text)?;
            current = current.with_changes(text, std::slice::from_ref(&change))?;
            changes.push((text.clone(), change));
        }
        Ok(Self {
            text: self.text.clone(),
            base: self.base.clone(),
            variant: self.variant.clone(),
            start: self.start.clone(),
            changes,
            current,
        })
    }

    /// Validates and builds the model, as `strand solve` (`--variant`) and `strand
    /// batch` do: errors name the variant or the changes.
    pub fn build(&self, segments: Option<usize>) -> Result<BuiltCase, StudyError> {
        Ok(match (&self.variant, self.changes.is_empty()) {
            (None, true) => self.base.build(segments)?,
            (Some(name), true) => self.base.build_variant(name, segments)?,
            (_, false) => {
                let all: Vec<VariantChange> = self.changes.iter().map(|(_, c)| c.clone()).collect();
                self.start
                    .build_with_changes(&self.changes_label(), &all, segments)?
            }
        })
    }

    /// The case written down.
    pub fn state(&self) -> CaseState {
        (
            self.text.clone(),
            self.base.origin.clone(),
            self.base.name.clone(),
            self.variant.clone(),
            self.changes.iter().map(|(t, _)| t.clone()).collect(),
        )
    }

    /// The case of `state`, read and changed again.
    pub fn from_state(state: &CaseState) -> Result<Self, StudyError> {
        let (text, origin, name, variant, changes) = state;
        let base = Case::from_str(text, origin)?;
        let mut spec = Self::new(text.clone(), base, Some(name.clone()))?;
        if let Some(variant) = variant {
            spec = spec.with_variant(variant)?;
        }
        if !changes.is_empty() {
            spec = spec.with_changes(changes)?;
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
