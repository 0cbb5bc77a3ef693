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

use std::io::{IsTerminal, Write};
use std::panic::PanicHookInfo;
use std::process::ExitCode;

fn main() -> ExitCode {
    // A panic is a bug, never bad input: report it in one line, without a backtrace
    // unless RUST_BACKTRACE asks for one. (The default hook writes to the raw stderr
    // without taking the `Stderr` lock, and so does `report_panic`.)
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if std::env::var_os("RUST_BACKTRACE").is_some() {
            default_hook(info);
        } else {
            report_panic(info);
        }
    }));
    // The handles themselves, not `stdout().lock()`/`stderr().lock()`: they lock per
    // write. Holding a lock for the whole run deadlocks as soon as another thread
    // writes to the same stream while the main thread waits for it — the batch
    // progress bar draws to stderr from the rayon workers (only when stderr is a
    // terminal), and so does the panic message of a worker (issue 12).
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    if let Some(code) = strand_cli::bench::fresh_memory::rerun_mesh_bench(&args) {
        return code;
    }
    strand_cli::run(args, &mut std::io::stdout(), &mut std::io::stderr()).into()
}

/// Prints `error: internal error: <info>` on stderr without taking the `Stderr` lock,
/// so that a panicking thread never waits for another one that holds it. On a
/// terminal the line is cleared first, so that the message does not run on from a
/// progress bar.
fn report_panic(info: &PanicHookInfo<'_>) {
    let clear = if std::io::stderr().is_terminal() {
        "\r\x1b[2K"
    } else {
        ""
    };
    let message = format!("{clear}error: internal error: {info}\n");
    if write_unlocked(message.as_bytes()).is_err() {
        // No duplicate of the stderr descriptor: fall back to the locked stream.
        eprint!("{message}");
    }
}

/// Writes `bytes` to a duplicate of the stderr descriptor (no `Stderr` lock).
#[cfg(unix)]
fn write_unlocked(bytes: &[u8]) -> std::io::Result<()> {
    use std::os::fd::AsFd;
    let fd = std::io::stderr().as_fd().try_clone_to_owned()?;
    std::fs::File::from(fd).write_all(bytes)
}

/// Writes `bytes` to a duplicate of the stderr handle (no `Stderr` lock).
#[cfg(windows)]
fn write_unlocked(bytes: &[u8]) -> std::io::Result<()> {
    use std::os::windows::io::AsHandle;
    let handle = std::io::stderr().as_handle().try_clone_to_owned()?;
    std::fs::File::from(handle).write_all(bytes)
}

/// Writes `bytes` to stderr (no way to bypass the `Stderr` lock on this platform).
#[cfg(not(any(unix, windows)))]
fn write_unlocked(bytes: &[u8]) -> std::io::Result<()> {
    std::io::stderr().write_all(bytes)
}
