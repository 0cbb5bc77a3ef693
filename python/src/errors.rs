//! `strand-study` errors as the Python exceptions of `strand._errors`: the error's
//! kind (the exit status of `strand`) chooses the class, the message is the one
//! `strand` prints after `error: `.

use pyo3::prelude::*;
use strand_case::CaseError;
use strand_study::{ErrorKind, StudyError};

/// Which exception an I/O-kind error (exit status 1) means where it happens.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// A solve: status 1 means the solver could not start (`SolveError`).
    Solve,
    /// A batch: status 1 means its directory could not be written or read (`StrandError`).
    Files,
}

/// The Python exception of `error`.
pub fn to_py(error: StudyError, stage: Stage) -> PyErr {
    let class = match (error.kind(), stage) {
        (ErrorKind::Input, _) => "InputError",
        (ErrorKind::NotConverged, _) => "NotConvergedError",
        (ErrorKind::Io, Stage::Solve) => "SolveError",
        (ErrorKind::Io, Stage::Files) => "StrandError",
    };
    raise(class, error.to_string())
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
