//! The real `strand` executable on a pseudo-terminal, as in an ordinary shell or tmux.
//!
//! Output to a terminal takes paths that pipes never take: the batch progress bar
//! draws (only when stderr is a terminal), from the rayon worker threads. When `main`
//! held the stderr lock for the whole run, the first draw from a worker waited for
//! that lock forever and every `strand batch` hung at `0/N variants` in a terminal,
//! while every piped test passed (issue 12). Each test here runs the binary with
//! stdin, stdout and stderr on the slave side of a fresh pseudo-terminal, under a
//! deadline: a hang is killed and reported as a failure, never waited for.
//!
//! The pseudo-terminal comes from `rustix` (pure Rust, already in the dependency graph
//! through `tempfile`), not from an external tool such as util-linux `script`: no
//! shell quoting, and the same code on Linux, macOS and the BSDs.

#![cfg(unix)]

use std::ffi::OsStr;
use std::fs::{File, OpenOptions};
use std::io::{ErrorKind, Read};
use std::os::unix::ffi::OsStrExt;
use std::os::unix::fs::OpenOptionsExt;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use rustix::pty::{OpenptFlags, grantpt, openpt, ptsname, unlockpt};
use rustix::termios::{Winsize, tcsetwinsize};

/// How long a command may take. The cases below finish in well under a second in a
/// release build; the margin is for loaded CI machines.
const DEADLINE: Duration = Duration::from_secs(120);

/// A finished run on a pseudo-terminal.
struct Run {
    /// The command line, for messages.
    command: String,
    status: ExitStatus,
    /// Everything the terminal received (stdout and stderr, with escape sequences).
    screen: String,
}

impl Run {
    fn assert_success(&self) {
        assert!(
            self.status.success(),
            "`{}` on a terminal: {}; terminal output:\n{}",
            self.command,
            self.status,
            self.screen
        );
        assert!(
            !self.screen.contains("error:") && !self.screen.contains("panicked"),
            "`{}` on a terminal reported an error:\n{}",
            self.command,
            self.screen
        );
    }

    fn assert_shows(&self, text: &str) {
        assert!(
            self.screen.contains(text),
            "`{}`: the terminal does not show {text:?}; terminal output:\n{}",
            self.command,
            self.screen.escape_debug()
        );
    }
}

/// A case file of the repository.
fn case(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../cases")
        .join(name)
}

/// Runs `strand ARGS` with stdin, stdout and stderr on a new 80×24 pseudo-terminal;
/// kills it and fails the test if it has not exited after [`DEADLINE`].
fn on_terminal(args: &[&OsStr]) -> Run {
    on_terminal_with(args, &[])
}

/// [`on_terminal`] with extra environment variables for the child.
fn on_terminal_with(args: &[&OsStr], env: &[(&str, &str)]) -> Run {
    let command = format!(
        "strand {}",
        args.iter()
            .map(|a| a.to_string_lossy())
            .collect::<Vec<_>>()
            .join(" ")
    );
    let master = openpt(OpenptFlags::RDWR | OpenptFlags::NOCTTY | OpenptFlags::CLOEXEC)
        .expect("cannot open a pseudo-terminal (/dev/ptmx)");
    grantpt(&master).expect("grantpt");
    unlockpt(&master).expect("unlockpt");
    let size = Winsize {
        ws_row: 24,
        ws_col: 80,
        ws_xpixel: 0,
        ws_ypixel: 0,
    };
    tcsetwinsize(&master, size).expect("cannot set the terminal size");
    let name = ptsname(&master, Vec::new()).expect("ptsname");
    let slave = OpenOptions::new()
        .read(true)
        .write(true)
        .custom_flags(rustix::fs::OFlags::NOCTTY.bits() as i32)
        .open(OsStr::from_bytes(name.as_bytes()))
        .expect("cannot open the terminal side of the pseudo-terminal");
    let stdio = || slave.try_clone().expect("cannot duplicate the terminal");
    let mut child = Command::new(env!("CARGO_BIN_EXE_strand"))
        .args(args)
        .env_remove("RUST_BACKTRACE")
        .env("TERM", "xterm-256color")
        .envs(env.iter().copied())
        .stdin(stdio())
        .stdout(stdio())
        .stderr(stdio())
        .spawn()
        .expect("cannot start the strand binary");
    // The `Command` is gone: only the child holds the terminal side now, so reading
    // the master ends (EIO, or 0 on the BSDs) once the child has exited.
    drop(slave);

    // Drain the terminal meanwhile: a full terminal buffer would block the child.
    let (sender, received) = mpsc::channel();
    let mut master = File::from(master);
    std::thread::spawn(move || {
        let mut screen = Vec::new();
        let mut chunk = [0u8; 4096];
        loop {
            match master.read(&mut chunk) {
                Ok(0) => break,
                Ok(n) => screen.extend_from_slice(&chunk[..n]),
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(_) => break,
            }
        }
        let _ = sender.send(screen);
    });

    let started = Instant::now();
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) if started.elapsed() >= DEADLINE => {
                let _ = child.kill();
                let _ = child.wait();
                break None;
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(20)),
            Err(e) => panic!("`{command}`: cannot wait for it: {e}"),
        }
    };
    let screen = received
        .recv_timeout(Duration::from_secs(10))
        .map(|bytes| String::from_utf8_lossy(&bytes).into_owned())
        .unwrap_or_else(|_| "(the terminal output could not be read)".into());
    let Some(status) = status else {
        panic!(
            "`{command}` hangs on a terminal: still running after {} s, killed. A thread \
             writing to the terminal (the batch progress bar, a panic message) probably \
             waits for a stdout/stderr lock that the main thread holds (issue 12). \
             Terminal output:\n{}",
            DEADLINE.as_secs(),
            screen.escape_debug()
        )
    };
    Run {
        command,
        status,
        screen,
    }
}

#[test]
fn batch_on_a_terminal_draws_the_progress_bar_and_finishes() {
    let tmp = tempfile::tempdir().expect("temporary directory");
    let dir = tmp.path().join("batch");
    let cooler = case("cooler_hose.ron");
    let run = on_terminal(&[
        OsStr::new("batch"),
        cooler.as_os_str(),
        OsStr::new("--vary"),
        OsStr::new("hose2.length=+0mm..+20mm:10mm"),
        OsStr::new("--jobs"),
        OsStr::new("2"),
        OsStr::new("--out"),
        dir.as_os_str(),
    ]);
    run.assert_success();
    // The bar was drawn and finished: its final state is left on the terminal.
    run.assert_shows("3/3 variants");
    run.assert_shows("computed 3, skipped 0 (finished before), failed 0");
    // The summary starts a line of its own, not at the end of the bar's.
    run.assert_shows("\nbatch       cooler_hose");
    assert!(dir.join("summary.csv").is_file(), "no summary.csv");
    let solved = std::fs::read_dir(dir.join("variants"))
        .expect("no variants directory")
        .filter_map(Result::ok)
        .filter(|entry| entry.path().join("result.json").is_file())
        .count();
    assert_eq!(solved, 3, "variants with a result.json");
}

#[test]
fn study_on_a_terminal_finishes() {
    let tmp = tempfile::tempdir().expect("temporary directory");
    let dir = tmp.path().join("study");
    let demo = case("study_demo.ron");
    let run = on_terminal(&[
        OsStr::new("study"),
        demo.as_os_str(),
        OsStr::new("--variants"),
        OsStr::new("base,plus50"),
        OsStr::new("--out"),
        dir.as_os_str(),
    ]);
    run.assert_success();
    run.assert_shows("written");
    assert!(dir.join("study.csv").is_file(), "no study.csv");
    for variant in ["base", "plus50"] {
        assert!(
            dir.join(variant).join("result.json").is_file(),
            "no {variant}/result.json"
        );
    }
}

#[test]
fn solve_on_a_terminal_finishes() {
    let tmp = tempfile::tempdir().expect("temporary directory");
    let dir = tmp.path().join("solve");
    let cooler = case("cooler_hose.ron");
    let run = on_terminal(&[
        OsStr::new("solve"),
        cooler.as_os_str(),
        OsStr::new("--out"),
        dir.as_os_str(),
    ]);
    run.assert_success();
    run.assert_shows("written");
    assert!(dir.join("result.json").is_file(), "no result.json");
}

#[test]
fn a_solve_on_a_terminal_shows_its_progress_and_clears_it() {
    // The line appears after a second; at once with STRAND_PROGRESS_DELAY_MS=0.
    let tmp = tempfile::tempdir().expect("temporary directory");
    let dir = tmp.path().join("solve");
    let hanging = case("hanging_cable.ron");
    let run = on_terminal_with(
        &[
            OsStr::new("solve"),
            hanging.as_os_str(),
            OsStr::new("--out"),
            dir.as_os_str(),
        ],
        &[("STRAND_PROGRESS_DELAY_MS", "0")],
    );
    run.assert_success();
    run.assert_shows("solving ");
    // Cleared before the summary: the erase sequence follows the last progress line.
    let last = run.screen.rfind("solving ").expect("progress line");
    let cleared = run.screen[last..]
        .find("\r\x1b[2K")
        .expect("line not cleared");
    let summary = run.screen.rfind("converged").expect("summary");
    assert!(last + cleared < summary, "{}", run.screen.escape_debug());
}
