//! The subcommands `solve`, `check` and `bench`.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use strand_case::{BuiltCase, Case, CaseError};
use strand_report::{Timing, collect, write_results};
use strand_solve::{SolveError, solve};

use crate::Exit;
use crate::args::Command;
use crate::summary::{number, summary};

/// A failure with the exit status it maps to.
#[derive(Debug)]
pub(crate) struct Failure {
    pub exit: Exit,
    pub message: String,
}

impl From<CaseError> for Failure {
    fn from(e: CaseError) -> Self {
        Failure {
            exit: Exit::InvalidInput,
            message: e.to_string(),
        }
    }
}

pub(crate) fn execute(
    command: &Command,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<Exit, Failure> {
    match command {
        Command::Solve {
            case,
            out: dir,
            segments,
        } => solve_case(case, dir.as_deref(), segments.map(|n| n as usize), out, err),
        Command::Check { case, segments } => check_case(case, segments.map(|n| n as usize), out),
        Command::Bench {
            case,
            segments,
            repeats,
        } => {
            if segments.contains(&0) {
                return Err(Failure {
                    exit: Exit::InvalidInput,
                    message: "--segments: every entry must be ≥ 1".into(),
                });
            }
            let rows = crate::bench::run(case, segments, *repeats).map_err(|e| Failure {
                exit: Exit::InvalidInput,
                message: e.to_string(),
            })?;
            let _ = write!(
                out,
                "{}: bench, median of {} solves each\n{}",
                case.display(),
                repeats,
                crate::bench::format_table(&rows)
            );
            Ok(if rows.iter().all(|r| r.converged) {
                Exit::Success
            } else {
                Exit::NotConverged
            })
        }
    }
}

fn load(path: &Path, segments: Option<usize>) -> Result<(BuiltCase, Timing), Failure> {
    let started = Instant::now();
    let case = Case::from_path(path)?;
    let read = started.elapsed().as_secs_f64();
    let built = case.build(segments)?;
    let total = started.elapsed().as_secs_f64();
    Ok((
        built,
        Timing {
            read,
            build: total - read,
            total,
            ..Timing::default()
        },
    ))
}

fn check_case(path: &Path, segments: Option<usize>, out: &mut dyn Write) -> Result<Exit, Failure> {
    let (built, _) = load(path, segments)?;
    let system = built.model.system();
    let segments: usize = system.rods.iter().map(|r| r.rod.segments()).sum();
    let _ = writeln!(
        out,
        "ok: {} is valid ({} rod(s), {segments} segments, {} unknowns)",
        built.origin,
        system.rods.len(),
        built.model.dofs().len()
    );
    Ok(Exit::Success)
}

fn solve_case(
    path: &Path,
    dir: Option<&Path>,
    segments: Option<usize>,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<Exit, Failure> {
    let started = Instant::now();
    let (built, mut timing) = load(path, segments)?;
    let solution =
        solve(&built.model, built.initial.clone(), &built.settings).map_err(|e| match e {
            SolveError::Settings(_) => Failure {
                exit: Exit::InvalidInput,
                message: format!("{}: solver: {e}", built.origin),
            },
            _ => Failure {
                exit: Exit::Failure,
                message: format!("{}: the solver could not start: {e}", built.origin),
            },
        })?;
    timing.solve = solution.report.solve_seconds;
    timing.total = started.elapsed().as_secs_f64();
    let doc = collect(&built.name, &built.model, &solution, timing);
    let dir: PathBuf = dir
        .map(Path::to_path_buf)
        .unwrap_or_else(|| Path::new("out").join(&built.name));
    let written = write_results(&dir, &doc).map_err(|e| Failure {
        exit: Exit::Failure,
        message: format!("{}: results not written: {e}", built.origin),
    })?;
    let _ = write!(out, "{}", summary(&built, &doc, &written));
    if doc.converged {
        Ok(Exit::Success)
    } else {
        let _ = writeln!(
            err,
            "warning: {}: not converged ({}; residual {} N > tolerance {} N after {} iterations); \
             results written with \"converged\": false",
            built.origin,
            doc.termination,
            number(doc.residual_n),
            number(doc.tolerance_n),
            doc.iterations
        );
        Ok(Exit::NotConverged)
    }
}
