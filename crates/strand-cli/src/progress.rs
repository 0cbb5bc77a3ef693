//! A progress line for long solves on a terminal: after a second, stderr shows
//! `solving: N iterations, residual R N, T s`, refreshed twice a second, and the line
//! is cleared when the solve ends. Nothing is drawn when stderr is not a terminal.
//! `STRAND_PROGRESS_DELAY_MS` sets the delay before the first line (0: at once; the
//! terminal tests use it).

use std::io::{IsTerminal, Write};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Delay before the line first appears: short solves print nothing.
const FIRST_DRAW: Duration = Duration::from_secs(1);
/// Refresh interval of the line.
const REFRESH: Duration = Duration::from_millis(500);
/// How often the drawing thread looks whether the solve has ended.
const POLL: Duration = Duration::from_millis(50);

/// Draws the progress line while alive (see the module docs).
pub(crate) struct Progress {
    done: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Progress {
    /// Starts the line for `what` (e.g. the case file) when stderr is a terminal.
    pub(crate) fn start(what: &str) -> Self {
        let done = Arc::new(AtomicBool::new(false));
        if !std::io::stderr().is_terminal() {
            return Self { done, thread: None };
        }
        let flag = Arc::clone(&done);
        let what = what.to_string();
        let thread = std::thread::spawn(move || {
            let started = Instant::now();
            let before = strand_solve::activity().iterations;
            let mut drawn = false;
            let delay = std::env::var("STRAND_PROGRESS_DELAY_MS")
                .ok()
                .and_then(|v| v.parse().ok())
                .map_or(FIRST_DRAW, Duration::from_millis);
            let mut next = started + delay;
            while !flag.load(Ordering::Relaxed) || (delay.is_zero() && !drawn) {
                if Instant::now() < next {
                    std::thread::sleep(POLL);
                    continue;
                }
                next += REFRESH;
                let activity = strand_solve::activity();
                let iterations = activity.iterations - before;
                let elapsed_s = started.elapsed().as_secs_f64();
                // One write per line, without holding the stderr lock in between.
                let line = line(&what, iterations, activity.residual_n, elapsed_s);
                let _ = std::io::stderr().write_all(line.as_bytes());
                drawn = true;
            }
            if drawn {
                let _ = std::io::stderr().write_all(b"\r\x1b[2K");
            }
        });
        Self {
            done,
            thread: Some(thread),
        }
    }
}

/// The progress line (with the escape that clears the previous one). Before the first
/// iteration there is no residual to show: a fine model's build and coarse levels take
/// seconds, and `residual 0.00e0 N` there read as converged.
fn line(what: &str, iterations: u64, residual_n: f64, elapsed_s: f64) -> String {
    let state = if iterations == 0 {
        "building the model, no iteration yet".to_string()
    } else {
        format!("{iterations} iterations, residual {residual_n:.2e} N")
    };
    format!("\r\x1b[2Ksolving {what}: {state}, {elapsed_s:.0} s")
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.done.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::line;

    #[test]
    fn the_line_shows_a_residual_only_after_an_iteration() {
        let first = line("case.ron", 0, 0.0, 1.2);
        assert_eq!(
            first,
            "\r\x1b[2Ksolving case.ron: building the model, no iteration yet, 1 s"
        );
        let later = line("case.ron", 19, 2.09e-9, 2.0);
        assert!(later.ends_with("case.ron: 19 iterations, residual 2.09e-9 N, 2 s"));
    }
}
