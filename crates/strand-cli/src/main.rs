//! `strand`: static equilibria of cables and hoses.
//!
//! ```text
//! strand solve CASE [--out DIR] [--segments N]   solve; write DIR/result.json + DIR/<rod>.csv
//!                                                (DIR defaults to out/<case name>)
//! strand check CASE [--segments N]               validate the case only
//! ```
//!
//! | exit code | meaning |
//! |-----------|---------|
//! | 0 | success: solved and converged / case is valid |
//! | 1 | internal error, or the results could not be written (I/O) |
//! | 2 | invalid input: case file missing or unreadable, bad RON, validation error, bad command line |
//! | 3 | solved but not converged: results are written, with `"converged": false` |
//!
//! Errors go to stderr as `error: <message>`. All logic lives in [`strand_cli::run`].

use std::process::ExitCode;

fn main() -> ExitCode {
    // A panic is a bug, never bad input: report it in one line, without a backtrace
    // unless RUST_BACKTRACE asks for one.
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if std::env::var_os("RUST_BACKTRACE").is_some() {
            default_hook(info);
        } else {
            eprintln!("error: internal error: {info}");
        }
    }));
    let stdout = std::io::stdout();
    let stderr = std::io::stderr();
    strand_cli::run(std::env::args_os(), &mut stdout.lock(), &mut stderr.lock()).into()
}
