//! `strand batch` and `strand merge` on the command line: the engine is
//! [`strand_study::batch`]; here the plan line, the progress bar, the counts, the
//! failures and the warnings are printed.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use strand_study::StudyError;
use strand_study::batch::estimate::human;
use strand_study::batch::{Batch, BatchSpec, FailedVariant};

use crate::Exit;
use crate::commands::Failure;

/// The progress bar: done/total, failures and ETA on stderr, hidden unless stderr
/// is a terminal. It draws from the worker threads, straight to the process's
/// stderr (not to the `err` writer of [`crate::run`]): nothing may hold the `Stderr`
/// lock while the pool runs, or the first draw from a worker waits for it forever
/// (issue 12; `main` passes `std::io::stderr()`, which locks per write). The bar
/// takes the width the text leaves, so that the line does not wrap on 80 columns.
fn progress_bar(total: usize) -> ProgressBar {
    let target = if std::io::stderr().is_terminal() {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    };
    let bar = ProgressBar::with_draw_target(Some(total as u64), target);
    if let Ok(style) = ProgressStyle::with_template(
        "{wide_bar:.cyan/blue} {pos}/{len} variants  {msg}  {elapsed_precise} elapsed, ETA {eta_precise}",
    ) {
        bar.set_style(style);
    }
    bar.set_message("0 failed");
    bar
}

/// Prints the `failures` to `out`, one line each.
fn list_failures(failures: &[FailedVariant], out: &mut dyn Write) {
    for f in failures {
        let _ = writeln!(out, "failed      {} ({}): {}", f.id, f.stage, f.reason);
    }
}

/// `strand batch`.
pub(crate) fn run(
    spec: BatchSpec,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<Exit, Failure> {
    let started = Instant::now();
    let batch = Batch::plan(spec)?;
    if let Some(requested) = batch.jobs_capped() {
        let _ = writeln!(
            err,
            "note: --jobs {requested} capped at the {} available core(s) (--force-jobs to use more threads)",
            batch.available_cores()
        );
    }
    let jobs = batch.jobs();
    let owned_count = batch.owned_count();
    let shard = batch.shard();
    let _ = writeln!(
        out,
        "plan        {} variant(s){}, about {} on disk ({} per variant, --keep {}), {jobs} thread(s)",
        batch.grid().variants.len(),
        shard
            .map(|(i, n)| format!(" (shard {i}/{n}: {owned_count} of them)"))
            .unwrap_or_default(),
        human(batch.bytes_total()),
        human(batch.bytes_per_variant()),
        batch.spec().keep.name()
    );
    // Nothing is written before this point: bad input leaves no trace.
    let open = batch.open()?;
    if open.cleaned() > 0 {
        let _ = writeln!(
            out,
            "cleaned     {} temporary file(s) left by an interrupted run",
            open.cleaned()
        );
    }
    let (name, origin, count) = {
        let batch = open.batch();
        if !batch.base_solution().report.converged {
            let _ = writeln!(
                err,
                "warning: {}: the case itself did not converge; the first variant of each chain starts cold",
                batch.case().origin
            );
        }
        (
            batch.case().name.clone(),
            batch.case().origin.clone(),
            batch.grid().variants.len(),
        )
    };
    let out_dir = open.batch().spec().out.clone();
    let bar = progress_bar(owned_count);
    let report = open.run(&|p| {
        if p.failed_now {
            bar.set_message(format!("{} failed", p.failed));
        }
        bar.inc(1);
    });
    // Forced final draw, left on the terminal: the last increments may have been
    // skipped by the refresh-rate limit, and "N/N variants … elapsed" is the record
    // of the run.
    bar.finish();
    // The bar leaves the cursor at the end of its line: the summary starts a new one.
    if !bar.is_hidden() {
        eprintln!();
    }
    let report = report?;
    let _ = writeln!(
        out,
        "batch       {name} ({origin}): {count} variant(s){}",
        shard
            .map(|(i, n)| format!(", shard {i}/{n}: {owned_count} of them"))
            .unwrap_or_default()
    );
    let _ = writeln!(
        out,
        "variants    computed {}, skipped {} (finished before), failed {}{}",
        report.counts.computed,
        report.counts.skipped,
        report.counts.failed,
        if report.counts.helpers > 0 {
            format!(
                "; {} other shards' variants solved as warm starts only",
                report.counts.helpers
            )
        } else {
            String::new()
        }
    );
    let _ = writeln!(
        out,
        "solver      {} Newton iterations in this run, {:.3} s in total on {jobs} thread(s)",
        report.counts.iterations,
        started.elapsed().as_secs_f64()
    );
    for (id, damage) in &report.counts.repaired {
        let _ = writeln!(out, "repaired    {id} ({damage}): solved again");
    }
    for (id, damage) in &report.counts.foreign_damaged {
        let _ = writeln!(
            err,
            "warning: variant '{id}' of another shard is damaged ({damage}); solved here as a warm start only — run its shard again to repair it"
        );
    }
    list_failures(&report.failures, out);
    match &report.summary {
        Some([csv, svg]) => {
            let _ = writeln!(
                out,
                "written     {}, {}, {}",
                csv.display(),
                svg.display(),
                report.variants_dir.display()
            );
        }
        None => {
            let _ = writeln!(
                out,
                "written     {} (combine the shards with `strand merge {}`)",
                report.variants_dir.display(),
                out_dir.display()
            );
        }
    }
    if report.failures.is_empty() {
        Ok(Exit::Success)
    } else {
        let _ = writeln!(
            err,
            "warning: {origin}: {} variant(s) failed (see failed.json in their directories); the others are complete",
            report.failures.len()
        );
        Ok(Exit::NotConverged)
    }
}

/// Prints the warning about damaged copies that a merge did not take.
fn damaged_warning(damaged: &[String], err: &mut dyn Write) {
    if !damaged.is_empty() {
        let _ = writeln!(
            err,
            "warning: damaged variant files, not merged: {}; run their shard again (it repairs them)",
            damaged.join(", ")
        );
    }
}

/// `strand merge`.
pub(crate) fn merge(
    dirs: &[PathBuf],
    out_dir: Option<&Path>,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<Exit, Failure> {
    let report = match strand_study::batch::merge(dirs, out_dir) {
        Ok(report) => report,
        Err(e) => {
            if let StudyError::MergeIncomplete { damaged, .. } = &e {
                damaged_warning(damaged, err);
            }
            return Err(e.into());
        }
    };
    damaged_warning(&report.damaged, err);
    let _ = writeln!(
        out,
        "merge       {} director{} of {}: {} variant(s) copied into {}",
        dirs.len(),
        if dirs.len() == 1 { "y" } else { "ies" },
        report.batch,
        report.copied,
        report.target.display()
    );
    list_failures(&report.failures, out);
    let [csv, svg] = &report.summary;
    let _ = writeln!(out, "written     {}, {}", csv.display(), svg.display());
    if report.failures.is_empty() {
        Ok(Exit::Success)
    } else {
        let _ = writeln!(
            err,
            "warning: {} variant(s) failed (see failed.json in their directories)",
            report.failures.len()
        );
        Ok(Exit::NotConverged)
    }
}
