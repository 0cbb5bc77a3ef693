//! Errors of reading and building a case. Every message names the file; syntax and type
//! errors add `line:column`, semantic errors the item path (e.g. `rods[0] 'hose'`), and
//! each carries a hint how to fix it.

use strand_solve::SettingsError;
use strand_system::SystemError;

/// Why a case could not be read, parsed, validated or built.
#[derive(Debug, thiserror::Error)]
pub enum CaseError {
    /// The case file could not be read (missing, unreadable, not UTF-8).
    #[error("{origin}: cannot read the case file: {source}\n  hint: {hint}")]
    Read {
        /// The file as named by the user.
        origin: String,
        /// The I/O error.
        #[source]
        source: std::io::Error,
        /// How to fix it.
        hint: String,
    },
    /// RON syntax error, or a value of the wrong type, a missing or an unknown field.
    #[error("{origin}:{line}:{column}: {message}\n  hint: {hint}")]
    Syntax {
        /// The file as named by the user.
        origin: String,
        /// 1-based line of the error.
        line: usize,
        /// 1-based column of the error.
        column: usize,
        /// What the parser found.
        message: String,
        /// How to fix it.
        hint: String,
    },
    /// A value that parses but makes no sense (non-positive length, unknown section, …).
    #[error("{origin}: {item}: {message}\n  hint: {hint}")]
    Invalid {
        /// The file as named by the user.
        origin: String,
        /// Path of the offending item, e.g. `rods[0] 'hose'.length` or `sections 'steel'`.
        item: String,
        /// What is wrong.
        message: String,
        /// How to fix it.
        hint: String,
    },
    /// The solver settings are invalid.
    #[error(
        "{origin}: {source}\n  hint: correct the value in `solver: (...)` or remove it to use the default"
    )]
    Settings {
        /// The file as named by the user.
        origin: String,
        /// The settings error.
        #[source]
        source: SettingsError,
    },
    /// The assembled system is not solvable as given (e.g. a held end out of reach).
    #[error("{origin}: {source}")]
    System {
        /// The file as named by the user.
        origin: String,
        /// The system's own validation error.
        #[source]
        source: SystemError,
    },
}

impl CaseError {
    /// What is wrong, on one line, without the file and the hint (e.g. a rejected
    /// trial's note in an optimisation's history).
    pub fn summary(&self) -> String {
        match self {
            CaseError::Read { source, .. } => format!("cannot read the case file: {source}"),
            CaseError::Syntax {
                line,
                column,
                message,
                ..
            } => format!("{line}:{column}: {message}"),
            CaseError::Invalid { item, message, .. } => format!("{item}: {message}"),
            CaseError::Settings { source, .. } => source.to_string(),
            CaseError::System { source, .. } => source.to_string(),
        }
    }

    /// The file the error is about, as named by the user.
    pub fn origin(&self) -> &str {
        match self {
            CaseError::Read { origin, .. }
            | CaseError::Syntax { origin, .. }
            | CaseError::Invalid { origin, .. }
            | CaseError::Settings { origin, .. }
            | CaseError::System { origin, .. } => origin,
        }
    }

    /// A syntax or type error from the RON parser.
    pub(crate) fn from_ron(origin: &str, error: &ron::error::SpannedError) -> Self {
        use ron::Error as E;
        let hint = match &error.code {
            E::MissingStructField { field, .. } => {
                format!("add the field `{field}` (see cases/README.md)")
            }
            E::NoSuchStructField { .. } => {
                "remove or correct the field; the allowed fields are listed above".to_string()
            }
            E::NoSuchEnumVariant { .. } => "use one of the variants listed above".to_string(),
            E::DuplicateStructField { field, .. } => format!("write the field `{field}` only once"),
            E::Eof => "the file ends early: check for an unclosed `(`, `[` or `{`".to_string(),
            E::InvalidValueForType { .. } => {
                "check the value's type (numbers, \"strings\", (x, y, z) vectors)".to_string()
            }
            E::ExpectedString => "write text in double quotes, e.g. \"mm\"".to_string(),
            E::ExpectedStructLike => {
                "write struct-like values with parentheses, e.g. `Free()` for an unloaded free end"
                    .to_string()
            }
            E::IntegerOutOfBounds => {
                "whole-number fields (segments, iteration limits) must be ≥ 0 and not too large"
                    .to_string()
            }
            _ => "check the RON syntax near this position (see cases/README.md for the format)"
                .to_string(),
        };
        CaseError::Syntax {
            origin: origin.to_string(),
            line: error.span.start.line,
            column: error.span.start.col,
            message: error.code.to_string(),
            hint,
        }
    }
}

/// Builds [`CaseError::Invalid`] for one file.
#[derive(Clone, Debug)]
pub(crate) struct Reporter<'a> {
    pub origin: &'a str,
}

impl Reporter<'_> {
    /// An invalid item.
    pub fn invalid(
        &self,
        item: impl Into<String>,
        message: impl Into<String>,
        hint: impl Into<String>,
    ) -> CaseError {
        CaseError::Invalid {
            origin: self.origin.to_string(),
            item: item.into(),
            message: message.into(),
            hint: hint.into(),
        }
    }

    /// `value` must be finite.
    pub fn finite(&self, item: &str, value: f64, unit: &str) -> Result<f64, CaseError> {
        if value.is_finite() {
            Ok(value)
        } else {
            Err(self.invalid(
                item,
                format!("must be a finite number (got {value}{unit})"),
                "replace NaN/inf by a number",
            ))
        }
    }

    /// `value` must be finite and > 0.
    pub fn positive(&self, item: &str, value: f64, unit: &str) -> Result<f64, CaseError> {
        self.finite(item, value, unit)?;
        if value > 0.0 {
            Ok(value)
        } else {
            Err(self.invalid(
                item,
                format!("must be a finite number > 0 (got {value}{unit})"),
                "give a positive value",
            ))
        }
    }

    /// `value` must be finite and ≥ 0.
    pub fn non_negative(&self, item: &str, value: f64, unit: &str) -> Result<f64, CaseError> {
        self.finite(item, value, unit)?;
        if value >= 0.0 {
            Ok(value)
        } else {
            Err(self.invalid(
                item,
                format!("must be a finite number ≥ 0 (got {value}{unit})"),
                "give a value ≥ 0",
            ))
        }
    }

    /// Every component of `v` must be finite.
    pub fn finite3(
        &self,
        item: &str,
        v: &[f64; 3],
        unit: &str,
    ) -> Result<nalgebra::Vector3<f64>, CaseError> {
        if v.iter().all(|x| x.is_finite()) {
            Ok(nalgebra::Vector3::from(*v))
        } else {
            Err(self.invalid(
                item,
                format!(
                    "must have finite components (got ({}, {}, {}){unit})",
                    v[0], v[1], v[2]
                ),
                "replace NaN/inf by a number",
            ))
        }
    }
}

impl CaseError {
    /// This error, found while building the case in `context` (a variant, a motion
    /// pose), with the context named: an invalid item becomes "`context`: item"
    /// unless `keep_item` says its name is already complete; a system that could not
    /// be built becomes an invalid `context` with `hint`.
    pub(crate) fn within(
        self,
        context: &str,
        hint: &str,
        keep_item: impl Fn(&str) -> bool,
    ) -> CaseError {
        match self {
            CaseError::Invalid {
                origin,
                item,
                message,
                hint: item_hint,
            } if !keep_item(&item) => CaseError::Invalid {
                origin,
                item: format!("{context}: {item}"),
                message,
                hint: item_hint,
            },
            CaseError::System { origin, source } => CaseError::Invalid {
                origin,
                item: context.to_string(),
                message: source.to_string(),
                hint: hint.to_string(),
            },
            other => other,
        }
    }
}
