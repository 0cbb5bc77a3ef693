//! The errors of a study, a batch or a merge: each one's `Display` is the message the
//! `strand` command line prints after `error: `, and [`StudyError::kind`] says which
//! exit status it maps to.

use strand_case::CaseError;
use strand_solve::SolveError;
use strand_solve::sensitivity::SensitivityError;

use crate::batch::estimate::LimitError;
use crate::batch::lock::LockError;
use crate::batch::spec::SpecError;

/// What kind of failure an error is (the `strand` exit status it maps to).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ErrorKind {
    /// Invalid input: the case file, an option, a directory held by another run
    /// (exit 2).
    Input,
    /// Files that could not be written or read, or an internal failure (exit 1).
    Io,
    /// The case did not converge where an equilibrium is needed (exit 3).
    NotConverged,
}

/// A study, batch or merge that cannot go on: the message names the file, the
/// option or the directory, and the fix.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The case file is missing, unreadable, malformed or invalid.
    #[error(transparent)]
    Case(#[from] CaseError),
    /// A `--vary` that cannot be used (`origin` names the case file).
    #[error("{origin}: {source}")]
    Vary {
        /// The case file, as messages name it.
        origin: String,
        /// What is wrong with the option.
        source: SpecError,
    },
    /// A resource limit of a batch (worker threads, disk space without confirmation).
    #[error(transparent)]
    Limit(#[from] LimitError),
    /// A batch directory that cannot be locked (busy, or the lock file fails).
    #[error(transparent)]
    Lock(#[from] LockError),
    /// A solve that could not start (`origin` names the case or variant).
    #[error("{}", solver_message(origin, source))]
    Solver {
        /// The case (or variant) file, as messages name it.
        origin: String,
        /// Why the solver could not start.
        source: Box<SolveError>,
    },
    /// The sensitivities of an equilibrium could not be computed (`origin` names the
    /// case).
    #[error("{origin}: sensitivities: {source}")]
    Sensitivity {
        /// The case file, as messages name it.
        origin: String,
        /// Why the derivatives failed.
        source: Box<SensitivityError>,
    },
    /// A merge that found variants in none of the directories (nothing written).
    #[error(
        "{} of {total} variants are in none of the directories ({}{}); run the shards that own them (strand batch … --shard I/N) and merge again",
        missing.len(),
        missing.iter().take(5).cloned().collect::<Vec<_>>().join(", "),
        if missing.len() > 5 { ", …" } else { "" }
    )]
    MergeIncomplete {
        /// The ids of the missing variants, in grid order.
        missing: Vec<String>,
        /// Variants of the batch.
        total: usize,
        /// Damaged copies that were not taken: the variant directory and what was
        /// wrong.
        damaged: Vec<String>,
    },
    /// Other invalid input: an option, a name, a directory that holds another batch.
    #[error("{0}")]
    Input(String),
    /// Results that could not be written or read, or an internal failure.
    #[error("{0}")]
    Io(String),
    /// The case did not converge where an equilibrium is needed.
    #[error("{0}")]
    NotConverged(String),
}

/// The message of a solve of `origin` that could not start.
fn solver_message(origin: &str, e: &SolveError) -> String {
    match e {
        SolveError::StartsInside(_) => format!("{origin}: {e}"),
        SolveError::Settings(_) => format!("{origin}: solver: {e}"),
        _ => format!("{origin}: the solver could not start: {e}"),
    }
}

impl StudyError {
    /// The kind of the failure (the exit status of `strand`).
    pub fn kind(&self) -> ErrorKind {
        match self {
            StudyError::Case(_)
            | StudyError::Vary { .. }
            | StudyError::Limit(_)
            | StudyError::Input(_)
            | StudyError::Lock(LockError::Busy { .. }) => ErrorKind::Input,
            StudyError::Solver { source, .. } => match source.as_ref() {
                SolveError::StartsInside(_) | SolveError::Settings(_) => ErrorKind::Input,
                _ => ErrorKind::Io,
            },
            StudyError::Lock(LockError::Io { .. })
            | StudyError::Io(_)
            | StudyError::Sensitivity { .. }
            | StudyError::MergeIncomplete { .. } => ErrorKind::Io,
            StudyError::NotConverged(_) => ErrorKind::NotConverged,
        }
    }

    /// The error of the sensitivities of a solution of `origin`.
    pub fn sensitivity(origin: &str, source: SensitivityError) -> Self {
        StudyError::Sensitivity {
            origin: origin.to_string(),
            source: Box::new(source),
        }
    }

    /// The error of a solve of `origin` that could not start.
    pub fn solver(origin: &str, source: SolveError) -> Self {
        StudyError::Solver {
            origin: origin.to_string(),
            source: Box::new(source),
        }
    }
}

/// A result of the library.
pub type Result<T, E = StudyError> = std::result::Result<T, E>;
