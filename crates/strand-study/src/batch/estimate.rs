//! Resource limits of `strand batch`, checked before anything is written: worker
//! threads capped at the available cores, and the disk space the variants will take
//! (from the size of the solved case's own files), refused above a threshold unless
//! confirmed with `--yes`.

use super::Keep;

/// Most worker threads, even with `--force-jobs` (thread creation alone takes
/// minutes at 100 000).
pub const MAX_JOBS: usize = 1024;

/// Largest estimated output, bytes (10 GB), written without `--yes`.
pub const MAX_UNCONFIRMED_BYTES: u64 = 10_000_000_000;

/// Most variants run without `--yes`.
pub const MAX_UNCONFIRMED_VARIANTS: usize = 100_000;

/// Why a batch does not start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LimitError {
    /// `--jobs 0`.
    #[error("--jobs 0: give 1 or more worker threads (hint: leave --jobs out to use every core)")]
    NoJobs,
    /// More threads than [`MAX_JOBS`] with `--force-jobs`.
    #[error(
        "--jobs {0} --force-jobs: at most {MAX_JOBS} worker threads (hint: leave --jobs out to use every core)"
    )]
    TooManyJobs(usize),
    /// The estimate is above a threshold and `--yes` was not given.
    #[error(
        "the batch would write about {} to {out} ({variants} variant(s) × {} with --keep {keep}); above the {} / {MAX_UNCONFIRMED_VARIANTS}-variant limit for an unconfirmed batch (hint: pass --yes to go ahead{}, or vary fewer values)",
        human(*total),
        human(*per_variant),
        human(MAX_UNCONFIRMED_BYTES),
        hint_thin.map(|b| format!(", or --keep summary for about {} per variant", human(b))).unwrap_or_default()
    )]
    TooLarge {
        /// The output directory.
        out: String,
        /// Variants this run writes.
        variants: usize,
        /// Estimated bytes per variant.
        per_variant: u64,
        /// Estimated total, bytes.
        total: u64,
        /// The `--keep` in effect.
        keep: String,
        /// Bytes per variant with `--keep summary`, if that is not already in effect.
        hint_thin: Option<u64>,
    },
}

/// `bytes` for people: `330 KB`, `12.5 GB`.
pub fn human(bytes: u64) -> String {
    let b = bytes as f64;
    match bytes {
        0..1_000 => format!("{bytes} B"),
        1_000..1_000_000 => format!("{:.0} KB", b / 1e3),
        1_000_000..1_000_000_000 => format!("{:.1} MB", b / 1e6),
        _ => format!("{:.1} GB", b / 1e9),
    }
}

/// The worker threads to use: `requested` (default: `available`), capped at
/// `available` unless `force`. Returns the count and whether it was capped.
pub(crate) fn jobs(
    requested: Option<usize>,
    available: usize,
    force: bool,
) -> Result<(usize, bool), LimitError> {
    match requested {
        None => Ok((available.clamp(1, MAX_JOBS), false)),
        Some(0) => Err(LimitError::NoJobs),
        Some(n) if n > available && !force => Ok((available.clamp(1, MAX_JOBS), true)),
        Some(n) if n > MAX_JOBS => Err(LimitError::TooManyJobs(n)),
        Some(n) => Ok((n, false)),
    }
}

/// The disk estimate of `variants` variants of `per_variant` bytes; an error above the
/// thresholds unless `confirmed`.
pub(crate) fn check_size(
    out: &str,
    variants: usize,
    per_variant: u64,
    thin_per_variant: u64,
    keep: Keep,
    confirmed: bool,
) -> Result<u64, LimitError> {
    let total = per_variant.saturating_mul(variants as u64);
    if !confirmed && (total > MAX_UNCONFIRMED_BYTES || variants > MAX_UNCONFIRMED_VARIANTS) {
        return Err(LimitError::TooLarge {
            out: out.to_string(),
            variants,
            per_variant,
            total,
            keep: keep.name().to_string(),
            hint_thin: (keep != Keep::Summary).then_some(thin_per_variant),
        });
    }
    Ok(total)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jobs_are_capped_unless_forced_and_bounded_always() {
        assert_eq!(jobs(None, 8, false), Ok((8, false)));
        assert_eq!(jobs(Some(4), 8, false), Ok((4, false)));
        assert_eq!(jobs(Some(100), 8, false), Ok((8, true)));
        assert_eq!(jobs(Some(100), 8, true), Ok((100, false)));
        assert_eq!(jobs(Some(0), 8, true), Err(LimitError::NoJobs));
        assert_eq!(jobs(Some(100_000), 8, false), Ok((8, true)));
        assert_eq!(
            jobs(Some(100_000), 8, true),
            Err(LimitError::TooManyJobs(100_000))
        );
    }

    #[test]
    fn large_batches_need_confirmation() {
        let big = check_size("out", 1_000_000, 330_000, 9_000, Keep::All, false).unwrap_err();
        let text = big.to_string();
        assert!(text.contains("about 330.0 GB"), "{text}");
        assert!(text.contains("--keep summary for about 9 KB"), "{text}");
        assert_eq!(
            check_size("out", 1_000_000, 330_000, 9_000, Keep::All, true),
            Ok(330_000_000_000)
        );
        assert_eq!(
            check_size("out", 100, 330_000, 9_000, Keep::All, false),
            Ok(33_000_000)
        );
        assert_eq!(human(999), "999 B");
        assert_eq!(human(1_500_000), "1.5 MB");
    }
}
