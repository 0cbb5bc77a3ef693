//! `strand._strand._Solved`: one solve's result document (the exact text of
//! `result.json`'s numbers, as `serde_json` writes them) and its solved state, kept for
//! warm starts and pickling.

use std::sync::{Arc, OnceLock};

use pyo3::prelude::*;
use strand_case::BuiltCase;
use strand_cli::library::{self, Failure};
use strand_report::ResultDoc;
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

/// The numbers of a solve for pickling: the case, the segments, the result document
/// (JSON), the state, and converged / iterations / residual (N).
type SolvedState = (CaseState, Option<usize>, String, StateData, bool, usize, f64);

/// A solved case (see `strand.Result`).
#[pyclass(name = "_Solved", module = "strand._strand", frozen)]
pub struct Solved {
    /// The case solved.
    pub case: Arc<CaseSpec>,
    /// `segments` it was built with.
    segments: Option<usize>,
    /// `result.json` (compact).
    json: String,
    /// The solved state.
    pub state: SystemState,
    /// Whether the solve converged.
    pub converged: bool,
    /// Newton iterations.
    pub iterations: usize,
    /// Final residual, N.
    pub residual_n: f64,
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
        doc: &ResultDoc,
        state: SystemState,
        built: BuiltCase,
    ) -> Self {
        Self {
            case,
            segments,
            json: serde_json::to_string(doc).expect("a result document serialises"),
            state,
            converged: doc.converged,
            iterations: doc.iterations,
            residual_n: doc.residual_n,
            not_converged: library::not_converged(&built.origin, doc.variant.as_deref(), doc),
            built: OnceLock::from(Arc::new(built)),
        }
    }

    /// The built case whose state this is (a warm start carries it onto another).
    pub fn built(&self) -> Result<Arc<BuiltCase>, Failure> {
        if let Some(built) = self.built.get() {
            return Ok(Arc::clone(built));
        }
        let built = Arc::new(self.case.build(self.segments)?);
        Ok(Arc::clone(self.built.get_or_init(|| built)))
    }
}

#[pymethods]
impl Solved {
    /// `result.json` as compact JSON text.
    fn json(&self) -> &str {
        &self.json
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
            self.json.clone(),
            to_data(&self.state),
            self.converged,
            self.iterations,
            self.residual_n,
        )
    }

    /// The solve of `state` (see `state`); its case is read again.
    #[staticmethod]
    fn from_state(state: SolvedState) -> PyResult<Solved> {
        let (case, segments, json, data, converged, iterations, residual_n) = state;
        let case = CaseSpec::from_state(&case).map_err(|f| to_py(f, Stage::Solve))?;
        let state = from_data(&data).ok_or_else(|| {
            crate::errors::raise("StrandError", "a pickled result's state is damaged".into())
        })?;
        // The message's numbers are rounded: a re-parsed document gives the same text.
        let not_converged = serde_json::from_str::<ResultDoc>(&json)
            .ok()
            .and_then(|doc| library::not_converged(&case.base_origin(), doc.variant.as_deref(), &doc));
        Ok(Solved {
            not_converged,
            case: Arc::new(case),
            segments,
            json,
            state,
            converged,
            iterations,
            residual_n,
            built: OnceLock::new(),
        })
    }
}
