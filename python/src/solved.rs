//! `strand._strand._Solved`: one solve's result document (the exact text of
//! `result.json`'s numbers, as `serde_json` writes them) and its solved state, kept for
//! warm starts and pickling.

use std::sync::{Arc, OnceLock};

use pyo3::prelude::*;
use strand_case::BuiltCase;
use strand_report::ResultDoc;
use strand_study::StudyError;
use strand_study::solve::not_converged;
use strand_system::SystemState;

use crate::case::{CaseSpec, CaseState};
use crate::errors::{Stage, to_py};
use crate::state::{StateData, from_data, to_data};

/// A solve and the warning of a cold start instead of a warm one, if any.
pub struct Outcome {
    /// The solve.
    pub solved: Solved,
    /// `strand solve --variant`'s warning when the warm start had not converged.
    pub warning: Option<String>,
}

/// The convergence report of a solve: converged, stable, iterations, residual (N),
/// tolerance (N), energy (J), termination, warm-started, variant.
pub type Report = (
    bool,
    bool,
    usize,
    f64,
    f64,
    f64,
    String,
    bool,
    Option<String>,
);

/// The numbers of a solve for pickling: the case, the segments, the result document
/// (JSON), the state, the report and the not-converged warning.
type SolvedState = (
    CaseState,
    Option<usize>,
    String,
    StateData,
    Report,
    Option<String>,
);

/// A solved case (see `strand.Result`).
#[pyclass(name = "_Solved", module = "strand._strand", frozen)]
pub struct Solved {
    /// The case solved.
    pub case: Arc<CaseSpec>,
    /// `segments` it was built with.
    segments: Option<usize>,
    /// The result document until it is written as JSON (`None` after unpickling).
    doc: Option<Box<ResultDoc>>,
    /// `result.json` (compact), written on first use.
    json: OnceLock<String>,
    /// The solved state.
    pub state: SystemState,
    /// The convergence report.
    report: Report,
    /// What `strand solve` warns about a solve that did not converge.
    not_converged: Option<String>,
    /// The built case, made again on first use after unpickling.
    built: OnceLock<Arc<BuiltCase>>,
}

impl Solved {
    /// The solve of `case` (built with `segments` into `built`): `doc` and `state`.
    pub fn new(
        case: Arc<CaseSpec>,
        segments: Option<usize>,
        doc: ResultDoc,
        state: SystemState,
        built: BuiltCase,
    ) -> Self {
        let report = (
            doc.converged,
            doc.stable,
            doc.iterations,
            doc.residual_n,
            doc.tolerance_n,
            doc.energy_j,
            doc.termination.clone(),
            doc.warm_start,
            doc.variant.clone(),
        );
        Self {
            case,
            segments,
            not_converged: not_converged(&built.origin, doc.variant.as_deref(), &doc),
            doc: Some(Box::new(doc)),
            json: OnceLock::new(),
            state,
            report,
            built: OnceLock::from(Arc::new(built)),
        }
    }

    /// Whether the solve converged.
    pub fn converged(&self) -> bool {
        self.report.0
    }

    /// Newton iterations.
    pub fn iterations(&self) -> usize {
        self.report.2
    }

    /// Final residual, N.
    pub fn residual_n(&self) -> f64 {
        self.report.3
    }

    /// The built case whose state this is (a warm start carries it onto another).
    pub fn built(&self) -> Result<Arc<BuiltCase>, StudyError> {
        if let Some(built) = self.built.get() {
            return Ok(Arc::clone(built));
        }
        let built = Arc::new(self.case.build(self.segments)?);
        Ok(Arc::clone(self.built.get_or_init(|| built)))
    }

    fn json_text(&self) -> &str {
        self.json.get_or_init(|| {
            let doc = self.doc.as_ref().expect("a document or its JSON");
            serde_json::to_string(doc).expect("a result document serialises")
        })
    }
}

#[pymethods]
impl Solved {
    /// `result.json` as compact JSON text (written on the first call).
    fn json(&self) -> &str {
        self.json_text()
    }

    /// The convergence report (see [`Report`]).
    fn report(&self) -> Report {
        self.report.clone()
    }

    /// `strand solve`'s warning about a solve that did not converge (`None`: converged).
    fn not_converged(&self) -> Option<String> {
        self.not_converged.clone()
    }

    /// The solve written down (for pickling).
    fn state(&self) -> SolvedState {
        (
            self.case.state(),
            self.segments,
            self.json_text().to_string(),
            to_data(&self.state),
            self.report.clone(),
            self.not_converged.clone(),
        )
    }

    /// The solve of `state` (see `state`); its case is read again.
    #[staticmethod]
    fn from_state(state: SolvedState) -> PyResult<Solved> {
        let (case, segments, json, data, report, not_converged) = state;
        let case = CaseSpec::from_state(&case).map_err(|f| to_py(f, Stage::Solve))?;
        let state = from_data(&data).ok_or_else(|| {
            crate::errors::raise("StrandError", "a pickled result's state is damaged".into())
        })?;
        Ok(Solved {
            case: Arc::new(case),
            segments,
            doc: None,
            json: OnceLock::from(json),
            state,
            report,
            not_converged,
            built: OnceLock::new(),
        })
    }
}
