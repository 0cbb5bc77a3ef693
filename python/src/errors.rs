//! `strand-cli` failures as the Python exceptions of `strand._errors`: the exit status
//! of the failure chooses the class, the message is the one `strand` prints after
//! `error: `.

use pyo3::prelude::*;
use strand_case::CaseError;
use strand_cli::Exit;
use strand_cli::library::Failure;

/// Which exception an exit status 1 means where it happens.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// A solve: status 1 means the solver could not start (`SolveError`).
    Solve,
    /// A batch: status 1 means its directory could not be written or read (`StrandError`).
    Files,
}

/// The Python exception of `failure`.
pub fn to_py(failure: Failure, stage: Stage) -> PyErr {
    let class = match (failure.exit, stage) {
        (Exit::InvalidInput, _) => "InputError",
        (Exit::NotConverged, _) => "NotConvergedError",
        (Exit::Failure, Stage::Solve) => "SolveError",
        (Exit::Failure, Stage::Files) | (Exit::Success, _) => "StrandError",
    };
    raise(class, failure.message)
}

/// An input error of strand-case (exit status 2).
pub fn case_error(e: CaseError) -> PyErr {
    raise("InputError", e.to_string())
}

/// `strand._errors.<class>(message)`.
pub fn raise(class: &str, message: String) -> PyErr {
    Python::attach(|py| {
        let made = py
            .import("strand._errors")
            .and_then(|m| m.getattr(class))
            .and_then(|c| c.call1((message.clone(),)));
        match made {
            Ok(value) => PyErr::from_value(value),
            Err(e) => e,
        }
    })
}
