//! `strand batch` and `strand merge`: every combination of varied parameters, solved
//! in parallel and warm-started along each parameter, resumable, shardable.
//!
//! ```text
//! strand batch CASE --vary hose2.length=+0mm..+100mm:10mm [--vary …] --out DIR
//!              [--jobs N] [--shard I/N] [--segments N] [--retry-failed]
//!              [--keep all|results|summary] [--yes] [--force-jobs]
//! strand merge DIR… [--out DIR]
//! ```
//!
//! Layout of `DIR`: `batch.json` (the plan, [`manifest`]), `variants/<id>/` with
//! `result.json`, one CSV per rod and `state.json` (exact solved state) of a solved
//! variant or `failed.json` (the reason) of a failed one, and — for a whole batch or
//! after `strand merge` — `summary.csv` ([`summary`]) and `summary.svg` ([`plot`]).
//!
//! - [`spec`]: parsing `--vary` (items, ranges, units, offsets vs values);
//! - [`plan`]: grid, ids, warm-start tree, shards;
//! - [`run`]: parallel execution, progress bar, resume;
//! - [`merge`]: combining shard directories.

pub(crate) mod bounds;
mod checksum;
mod cleanup;
pub(crate) mod estimate;
mod integrity;
mod keep;
mod lock;
mod manifest;
pub(crate) mod merge;
mod plan;
mod plot;
mod predict;
mod run;
pub(crate) mod spec;
mod state;
mod summary;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use strand_case::Case;
use strand_report::write_atomic;

use crate::Exit;
use crate::commands::Failure;
use lock::Role;
use manifest::Manifest;
use plan::Plan;
use run::{Runner, Start};
use spec::{Vary, parse_shard};
use summary::{Outcome, read_outcome, summary_csv};

/// Longest path a batch writes, bytes (Linux allows 4096).
const MAX_PATH_BYTES: usize = 4000;

/// The options of `strand batch`.
pub(crate) struct BatchOptions<'a> {
    /// The case file.
    pub case: &'a Path,
    /// The `--vary` options.
    pub vary: &'a [String],
    /// Output directory.
    pub out: &'a Path,
    /// Worker threads (default: the available cores).
    pub jobs: Option<usize>,
    /// Use `jobs` even above the available cores.
    pub force_jobs: bool,
    /// Go ahead above the size thresholds ([`estimate`]).
    pub yes: bool,
    /// Files kept per solved variant.
    pub keep: crate::args::Keep,
    /// `--shard I/N`.
    pub shard: Option<&'a str>,
    /// `--segments N`.
    pub segments: Option<usize>,
    /// Solve variants with a `failed.json` again.
    pub retry_failed: bool,
}

pub(crate) fn invalid(message: impl Into<String>) -> Failure {
    Failure {
        exit: Exit::InvalidInput,
        message: message.into(),
    }
}

/// A directory that cannot be locked: exit 2 when another run holds it, else 1.
pub(crate) fn lock_failure(e: lock::LockError) -> Failure {
    match e {
        lock::LockError::Busy { .. } => invalid(e.to_string()),
        lock::LockError::Io { .. } => io_failure(e.to_string()),
    }
}

pub(crate) fn io_failure(message: impl Into<String>) -> Failure {
    Failure {
        exit: Exit::Failure,
        message: message.into(),
    }
}

/// The outcomes of every variant of `manifest` in `dir/variants`.
pub(crate) fn read_outcomes(dir: &Path, manifest: &Manifest) -> Result<Vec<Outcome>, Failure> {
    let variants = dir.join("variants");
    manifest
        .variants
        .iter()
        .map(|v| read_outcome(&variants.join(&v.id)).map_err(io_failure))
        .collect()
}

/// Writes `dir/summary.csv` and `dir/summary.svg` from the files in `dir`; returns the
/// outcomes and the two paths.
pub(crate) fn write_summary(
    dir: &Path,
    manifest: &Manifest,
) -> Result<(Vec<Outcome>, [PathBuf; 2]), Failure> {
    let outcomes = read_outcomes(dir, manifest)?;
    let csv_path = dir.join("summary.csv");
    let svg_path = dir.join("summary.svg");
    let not_written =
        |e: strand_report::ReportError| io_failure(format!("summary not written: {e}"));
    write_atomic(&csv_path, summary_csv(manifest, &outcomes).as_bytes()).map_err(not_written)?;
    write_atomic(&svg_path, plot::summary_svg(manifest, &outcomes).as_bytes())
        .map_err(not_written)?;
    Ok((outcomes, [csv_path, svg_path]))
}

/// Prints the failed variants among `outcomes` (those with `show[n]`) to `out`;
/// returns how many there are.
pub(crate) fn list_failures(
    manifest: &Manifest,
    outcomes: &[Outcome],
    show: &[bool],
    out: &mut dyn Write,
) -> usize {
    let mut count = 0;
    for ((entry, outcome), shown) in manifest.variants.iter().zip(outcomes).zip(show) {
        if let (Outcome::Failed(f), true) = (outcome, *shown) {
            count += 1;
            let _ = writeln!(out, "failed      {} ({}): {}", entry.id, f.stage, f.reason);
        }
    }
    count
}

/// `strand batch`.
pub(crate) fn run(
    options: &BatchOptions,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<Exit, Failure> {
    let started = Instant::now();
    let case = Case::from_path(options.case)?;
    crate::limits::check_case(&case)?;
    if options.vary.is_empty() {
        return Err(invalid(
            "strand batch needs at least one --vary, e.g. --vary hose2.length=+0mm..+100mm:10mm",
        ));
    }
    let varies = options
        .vary
        .iter()
        .map(|text| Vary::parse(text, &case.file))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| invalid(format!("{}: {e}", case.origin)))?;
    let plan = Plan::new(varies).map_err(|e| invalid(format!("{}: {e}", case.origin)))?;
    let shard = options
        .shard
        .map(parse_shard)
        .transpose()
        .map_err(invalid)?;
    let available = std::thread::available_parallelism().map_or(1, |n| n.get());
    let (jobs, capped) = estimate::jobs(options.jobs, available, options.force_jobs)
        .map_err(|e| invalid(e.to_string()))?;
    if capped {
        let _ = writeln!(
            err,
            "note: --jobs {} capped at the {available} available core(s) (--force-jobs to use more threads)",
            options.jobs.unwrap_or(0)
        );
    }
    // The longest path a variant writes (a temporary file in its folder) must fit.
    if let Some(longest) = plan.variants.iter().map(|v| v.id.len()).max() {
        let path_bytes = options.out.as_os_str().len() + "/variants//".len() + longest + 20;
        if path_bytes > MAX_PATH_BYTES {
            return Err(invalid(format!(
                "--out {}: the variant folders' paths would be {path_bytes} bytes long; at most {MAX_PATH_BYTES} (hint: use a shorter --out)",
                crate::limits::shown(&options.out.display().to_string())
            )));
        }
    }
    let base = case.build(options.segments)?;
    let manifest = Manifest::new(&case, &plan, options.segments);

    let base_solution = base
        .solve_from(base.initial.clone(), &base.settings)
        .map_err(|e| crate::commands::solver_failure(&base.origin, e))?;

    let owned = plan.owned(shard);
    let owned_count = owned.iter().filter(|o| **o).count();
    let sizes = {
        let doc = run::result_doc("estimate", &base, &base_solution, false, Default::default());
        let full_json = serde_json::to_vec_pretty(&doc).map_or(0, |v| v.len());
        let state_bytes = serde_json::to_vec(&state::StoredState::from_state(
            &base_solution.state,
            &vec![0; full_json],
        ))
        .map_or(0, |v| v.len());
        [options.keep, crate::args::Keep::Summary].map(|keep| {
            keep::variant_bytes(
                &doc,
                state_bytes,
                keep,
                &crate::commands::export_unit(&base),
            )
        })
    };
    let total = estimate::check_size(
        &options.out.display().to_string(),
        owned_count,
        sizes[0],
        sizes[1],
        options.keep,
        options.yes,
    )
    .map_err(|e| invalid(e.to_string()))?;
    let _ = writeln!(
        out,
        "plan        {} variant(s){}, about {} on disk ({} per variant, --keep {}), {jobs} thread(s)",
        plan.variants.len(),
        shard
            .map(|(i, n)| format!(" (shard {i}/{n}: {owned_count} of them)"))
            .unwrap_or_default(),
        estimate::human(total),
        estimate::human(sizes[0]),
        options.keep.name()
    );

    // Nothing is written before this point: bad input leaves no trace.
    let role = match shard {
        Some((i, n)) => Role::Shard(i, n),
        None => Role::Whole,
    };
    let mut held = lock::acquire(options.out, role, &manifest.identity()).map_err(lock_failure)?;
    match Manifest::read(options.out).map_err(invalid)? {
        Some(existing) if !existing.same_batch(&manifest) => {
            let by: Vec<String> = lock::recorded_holders(options.out)
                .iter()
                .filter(|h| h.batch == existing.identity())
                .map(ToString::to_string)
                .collect();
            return Err(invalid(format!(
                "{} holds another batch ({}{}); use another --out, or delete it to start over",
                options.out.display(),
                existing.describe(),
                if by.is_empty() {
                    String::new()
                } else {
                    format!("; last run by {}", by.join(", "))
                }
            )));
        }
        Some(_) => {}
        None => {
            let json =
                serde_json::to_vec_pretty(&manifest).map_err(|e| io_failure(e.to_string()))?;
            write_atomic(&options.out.join("batch.json"), &json)
                .map_err(|e| io_failure(format!("batch plan not written: {e}")))?;
        }
    }
    std::fs::create_dir_all(options.out.join("variants")).map_err(|e| {
        io_failure(format!(
            "cannot create {}: {e}",
            options.out.join("variants").display()
        ))
    })?;
    let owned_ids: Option<std::collections::HashSet<&str>> = shard.map(|_| {
        plan.variants
            .iter()
            .zip(&owned)
            .filter(|(_, o)| **o)
            .map(|(v, _)| v.id.as_str())
            .collect()
    });
    let cleaned =
        cleanup::remove_stale_temporaries(options.out, owned_ids.as_ref()).map_err(io_failure)?;
    held.release_plan();
    if cleaned > 0 {
        let _ = writeln!(
            out,
            "cleaned     {cleaned} temporary file(s) left by an interrupted run"
        );
    }

    let start = if base_solution.report.converged {
        Some(Start::base(base, base_solution.state))
    } else {
        let _ = writeln!(
            err,
            "warning: {}: the case itself did not converge; the first variant of each chain starts cold",
            case.origin
        );
        None
    };
    let runner = Runner::new(
        &case,
        &plan,
        options.segments,
        options.out,
        owned.clone(),
        options.retry_failed,
        options.keep,
    )
    .map_err(io_failure)?;
    let counts = runner.run(start, jobs).map_err(io_failure)?;

    let (outcomes, written) = if shard.is_none() {
        let (outcomes, paths) = write_summary(options.out, &manifest)?;
        (outcomes, Some(paths))
    } else {
        // Other shards' variants are only counted when listing this shard's failures:
        // a damaged one of theirs is their shard's to repair, not an error here.
        let variants = options.out.join("variants");
        let outcomes = manifest
            .variants
            .iter()
            .zip(&owned)
            .map(|(v, mine)| match read_outcome(&variants.join(&v.id)) {
                Ok(outcome) => Ok(outcome),
                Err(_) if !mine => Ok(Outcome::Missing),
                Err(e) => Err(io_failure(e)),
            })
            .collect::<Result<Vec<_>, _>>()?;
        (outcomes, None)
    };
    let _ = writeln!(
        out,
        "batch       {} ({}): {} variant(s){}",
        case.name,
        case.origin,
        plan.variants.len(),
        shard
            .map(|(i, n)| format!(", shard {i}/{n}: {owned_count} of them"))
            .unwrap_or_default()
    );
    let _ = writeln!(
        out,
        "variants    computed {}, skipped {} (finished before), failed {}{}",
        counts.computed,
        counts.skipped,
        counts.failed,
        if counts.helpers > 0 {
            format!(
                "; {} other shards' variants solved as warm starts only",
                counts.helpers
            )
        } else {
            String::new()
        }
    );
    let _ = writeln!(
        out,
        "solver      {} Newton iterations in this run, {:.3} s in total on {jobs} thread(s)",
        counts.iterations,
        started.elapsed().as_secs_f64()
    );
    for (id, damage) in &counts.repaired {
        let _ = writeln!(out, "repaired    {id} ({damage}): solved again");
    }
    for (id, damage) in &counts.foreign_damaged {
        let _ = writeln!(
            err,
            "warning: variant '{id}' of another shard is damaged ({damage}); solved here as a warm start only — run its shard again to repair it"
        );
    }
    let failed = list_failures(&manifest, &outcomes, &owned, out);
    match written {
        Some([csv, svg]) => {
            let _ = writeln!(
                out,
                "written     {}, {}, {}",
                csv.display(),
                svg.display(),
                options.out.join("variants").display()
            );
        }
        None => {
            let _ = writeln!(
                out,
                "written     {} (combine the shards with `strand merge {}`)",
                options.out.join("variants").display(),
                options.out.display()
            );
        }
    }
    if failed > 0 {
        let _ = writeln!(
            err,
            "warning: {}: {failed} variant(s) failed (see failed.json in their directories); the others are complete",
            case.origin
        );
        Ok(Exit::NotConverged)
    } else {
        Ok(Exit::Success)
    }
}

#[cfg(test)]
mod tests;
