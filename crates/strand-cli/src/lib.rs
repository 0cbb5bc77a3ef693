//! # strand-cli
//!
//! The `strand` command line, as a library so that tests drive exactly the code path
//! of the binary: `main` only calls [`run`] with the process's arguments, stdout and
//! stderr and exits with the returned [`Exit`] code. It is a thin front end: argument
//! parsing, progress display, printing and exit codes; the engines of `study`,
//! `batch`, `merge` and `sensitivity` are in [`strand_study`].
//!
//! ```text
//! strand solve CASE [--out DIR] [--segments N]   solve, write DIR/result.json + DIR/<rod>.csv
//! strand solve CASE --variant NAME [...]         solve a variant, warm-started from the case's solution
//! strand solve CASE --motion NAME=VALUE [...]   solve the case with a motion's parts at one pose (cold)
//! strand motion CASE --motion NAME --range FROM..TO:STEP [--out DIR] [--segments N]
//!                                                follow a motion both ways from the case's pose,
//!                                                warm-started; DIR/motion.csv, events.csv,
//!                                                motion.svg, envelope.obj, steps/<k>/
//! strand study CASE [--variants base,a,b] [--out DIR] [--segments N]
//!                                                solve variants; DIR/study.svg, DIR/study.csv,
//!                                                DIR/<variant>/result.json
//! strand batch CASE --vary ITEM=A..B:STEP [--vary …] --out DIR [--jobs N] [--shard I/N]
//!              [--keep results|all|summary] [--yes] [--force-jobs] [--retry-failed]
//!                                                every combination, parallel, warm-started,
//!                                                resumable; DIR/summary.csv, DIR/summary.svg
//! strand optimize CASE --vary ITEM=LO..HI [--vary …] [--minimize peak_force]
//!              [--subject-to "clearance>=10mm" …] --out DIR
//!                                                best design within bounds (exact gradients);
//!                                                DIR/optimum.json, history.csv, history.svg,
//!                                                DIR/<case>_optimum.ron
//! strand merge DIR… [--out DIR]                  combine the shards of a batch
//! strand report RESULT_DIR… [--out report.html] [--labels a,b] [--title T]
//!                                                HTML design review of results (first = reference)
//! strand check CASE [--segments N]               validate the case only
//! strand bench [CASE] [--segments 19,99,999] [--repeats 20]   timing table
//! strand bench --grid [--cases 200]              convergence map (issue 9): iterations and
//!                                                time per case, medians against the targets
//! ```
//!
//! | exit code | meaning |
//! |-----------|---------|
//! | 0 | success: solved and converged / case is valid |
//! | 1 | internal error, or the results could not be written (I/O) |
//! | 2 | invalid input: case file missing or unreadable, bad RON, validation error, bad command line |
//! | 3 | solved but not converged: results are written, with `"converged": false` (`motion`: a step failed; the poses before it are written) |
//!
//! Errors go to stderr as `error: <message>`; the message names the case file (and
//! `line:column` for syntax errors). Bad input never panics.

mod args;
mod batch;
pub mod bench;
mod commands;
mod motion;
mod optimize;
mod progress;
mod report;
mod sensitivity;
mod study;
pub mod summary;

use std::ffi::OsString;
use std::io::Write;

use clap::Parser;

pub use args::{Cli, Command};
/// The boundary checks of a case, from the library ([`strand_study::limits`]).
pub use strand_study::limits;

/// Exit status of a `strand` run (see the table in the crate docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exit {
    /// 0: solved and converged, or the case is valid.
    Success,
    /// 1: internal error or the results could not be written.
    Failure,
    /// 2: invalid input (case file or command line).
    InvalidInput,
    /// 3: solved but not converged; results are written with `converged: false`.
    NotConverged,
}

impl Exit {
    /// The process exit code.
    pub fn code(self) -> u8 {
        match self {
            Exit::Success => 0,
            Exit::Failure => 1,
            Exit::InvalidInput => 2,
            Exit::NotConverged => 3,
        }
    }
}

impl From<Exit> for std::process::ExitCode {
    fn from(exit: Exit) -> Self {
        std::process::ExitCode::from(exit.code())
    }
}

/// Runs `strand` with `args` (including the program name, as `std::env::args_os`),
/// printing the summary to `out` and messages to `err`.
pub fn run<I, T>(args: I, out: &mut dyn Write, err: &mut dyn Write) -> Exit
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            use clap::error::ErrorKind;
            let text = e.render().to_string();
            return match e.kind() {
                ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
                    let _ = write!(out, "{text}");
                    Exit::Success
                }
                _ => {
                    let _ = write!(err, "{text}");
                    Exit::InvalidInput
                }
            };
        }
    };
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        commands::execute(&cli.command, out, err)
    }));
    match outcome {
        Ok(Ok(exit)) => exit,
        Ok(Err(e)) => {
            let _ = writeln!(err, "error: {}", e.message);
            e.exit
        }
        Err(_) => {
            let _ = writeln!(
                err,
                "error: internal error (a bug in strand; please report it with the case file)"
            );
            Exit::Failure
        }
    }
}

#[cfg(test)]
mod findings_tests;
#[cfg(test)]
mod tests;
