//! `strand bench --mesh` in memory the process has not used before.
//!
//! A mesh load writes its arrays into freshly allocated memory: in a new process (one
//! `strand solve`) every page is faulted in on first touch. Repeated loads in one
//! process would not all pay that: glibc serves allocations below its mmap threshold
//! (dynamic, up to 32 MB) from memory a dropped mesh left mapped, and maps the larger
//! ones afresh. A 1M-triangle mesh's arrays sit below the threshold and a 4M one's
//! above it, so the medians of repeated loads would compare a faulting 4M load with a
//! non-faulting 1M one (measured: 4M / 1M 6.6× cached, 7.5× the page faults for 4× the
//! triangles; a new process: 3.3×). The binary therefore runs the mesh benchmark again
//! with glibc's mmap threshold fixed at [`FRESH_MMAP_THRESHOLD_BYTES`]: every large
//! array is then mapped when allocated and unmapped when dropped, and each repeat pays
//! its page faults as a new process does.

use std::ffi::OsString;
use std::process::{Command, ExitCode};

/// The fixed glibc mmap threshold of the benchmark's run, bytes (1 MiB: every mesh
/// array of interest is larger).
pub const FRESH_MMAP_THRESHOLD_BYTES: usize = 1 << 20;

/// The environment variable glibc reads its tunables from.
const TUNABLES: &str = "GLIBC_TUNABLES";

/// When `args` (the binary's arguments, program name first) ask for `strand bench
/// --mesh` and glibc's mmap threshold is not set yet, runs the same command again with
/// the threshold fixed and returns its exit code; otherwise (another command, the
/// threshold already set, or no way to run the binary again) `None`: run in this
/// process.
pub fn rerun_mesh_bench(args: &[OsString]) -> Option<ExitCode> {
    let bench_mesh = args.get(1).is_some_and(|a| a == "bench")
        && args
            .iter()
            .skip(2)
            .any(|a| a == "--mesh" || a.to_str().is_some_and(|a| a.starts_with("--mesh=")));
    let tunables = std::env::var(TUNABLES).unwrap_or_default();
    if !bench_mesh || !cfg!(target_os = "linux") || tunables.contains("mmap_threshold") {
        return None;
    }
    let threshold = format!("glibc.malloc.mmap_threshold={FRESH_MMAP_THRESHOLD_BYTES}");
    let tunables = if tunables.is_empty() {
        threshold
    } else {
        format!("{tunables}:{threshold}")
    };
    let status = Command::new(std::env::current_exe().ok()?)
        .args(&args[1..])
        .env(TUNABLES, tunables)
        .status()
        .ok()?;
    // A run ended by a signal has no code: report it as an internal failure.
    Some(ExitCode::from(status.code().map_or(1, |c| c as u8)))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(list: &[&str]) -> Vec<OsString> {
        list.iter().map(OsString::from).collect()
    }

    #[test]
    fn only_the_mesh_benchmark_runs_again() {
        // Other commands, and the other benchmarks, run in this process.
        assert!(rerun_mesh_bench(&args(&["strand", "solve", "case.ron"])).is_none());
        assert!(rerun_mesh_bench(&args(&["strand", "bench", "--grid"])).is_none());
        assert!(rerun_mesh_bench(&args(&["strand", "solve", "--mesh", "x"])).is_none());
    }
}
