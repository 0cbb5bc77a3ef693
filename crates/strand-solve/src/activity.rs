//! Process-wide counters of solver activity, for a caller's progress display: another
//! thread reads them while a long solve runs (`strand solve` on a terminal). No I/O
//! here; the counters only ever grow or are overwritten.

use std::sync::atomic::{AtomicU64, Ordering};

static ITERATIONS: AtomicU64 = AtomicU64::new(0);
static RESIDUAL_BITS: AtomicU64 = AtomicU64::new(0);

/// What the solver has done so far in this process.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Activity {
    /// Newton iterations started by every solve of the process (all levels, steps and
    /// threads together).
    pub iterations: u64,
    /// The residual of the latest iterate of any solve, N.
    pub residual_n: f64,
}

/// The solver's activity so far (see [`Activity`]).
///
/// ```
/// let before = strand_solve::activity().iterations;
/// // ... a solve on another thread ...
/// assert!(strand_solve::activity().iterations >= before);
/// ```
pub fn activity() -> Activity {
    Activity {
        iterations: ITERATIONS.load(Ordering::Relaxed),
        residual_n: f64::from_bits(RESIDUAL_BITS.load(Ordering::Relaxed)),
    }
}

/// Records one iteration at residual `residual_n` (N).
pub(crate) fn record(residual_n: f64) {
    ITERATIONS.fetch_add(1, Ordering::Relaxed);
    RESIDUAL_BITS.store(residual_n.to_bits(), Ordering::Relaxed);
}
