//! Batches: every combination of varied parameters, solved in parallel and
//! warm-started along each parameter, resumable, shardable, merged and summarised —
//! the engine of `strand batch` and `strand merge`.
//!
//! ```text
//! strand batch CASE --vary hose2.length=+0mm..+100mm:10mm [--vary …] --out DIR
//!              [--jobs N] [--shard I/N] [--segments N] [--retry-failed]
//!              [--keep all|results|summary] [--yes] [--force-jobs]
//! strand merge DIR… [--out DIR]
//! ```
//!
//! Layout of `DIR`: `batch.json` (the plan, [`Manifest`]), `variants/<id>/` with
//! `result.json`, one CSV per rod and `state.json` (exact solved state) of a solved
//! variant or `failed.json` ([`FailedVariant`]) of a failed one, and — for a whole
//! batch or after [`merge()`] — `summary.csv` ([`summary_csv`]) and `summary.svg`.
//!
//! - [`spec`]: parsing `--vary` (items, ranges, units, offsets vs values);
//! - [`bounds`]: parsing the `--vary ITEM=LO..HI` bounds of `strand optimize`;
//! - [`plan`]: grid, ids, warm-start tree, shards;
//! - `run`: parallel execution, progress, resume;
//! - [`merge()`]: combining shard directories.
//!
//! A batch runs in three steps, so that a front end can print between them:
//! [`Batch::plan`] (reads, checks and solves the case; writes nothing),
//! [`Batch::open`] (locks `DIR`, writes `batch.json`, removes the temporaries of an
//! interrupted run) and [`OpenBatch::run`] (solves the variants, writes the summary).
//! [`Batch::run`] does the last two at once.
//!
//! ```
//! use strand_study::batch::{Batch, BatchSpec, Outcome};
//! let dir = tempfile::tempdir()?;
//! let spec = BatchSpec {
//!     vary: vec!["rod.length=+0mm..+20mm:10mm".into()],
//!     segments: Some(6),
//!     jobs: Some(1),
//!     ..BatchSpec::new(
//!         concat!(env!("CARGO_MANIFEST_DIR"), "/../../cases/elastica_fig2.ron"),
//!         dir.path(),
//!     )
//! };
//! let batch = Batch::plan(spec)?;
//! assert_eq!(batch.grid().variants.len(), 3);
//! let report = batch.run(&|_progress| {})?;
//! assert_eq!((report.counts.computed, report.counts.failed), (3, 0));
//! // The results, read back from the directory: one converged ResultDoc per variant.
//! let results = strand_study::batch::read_batch(dir.path())?;
//! for (entry, outcome) in results.manifest.variants.iter().zip(&results.outcomes) {
//!     let Outcome::Solved(doc) = outcome else { panic!("{} failed", entry.id) };
//!     assert!(doc.converged && doc.residual_n <= doc.tolerance_n);
//! }
//! assert!(std::fs::read_to_string(dir.path().join("summary.csv"))?.starts_with("id,rod.length [mm],status"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod bounds;
mod checksum;
mod cleanup;
pub mod estimate;
mod integrity;
mod keep;
pub mod lock;
mod manifest;
mod merge;
pub mod plan;
mod plot;
mod predict;
mod run;
pub mod spec;
mod state;
mod summary;
mod variant;

use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::time::Instant;

use strand_case::{BuiltCase, Case};
use strand_report::write_atomic;
use strand_solve::Solution;

use crate::error::{Result, StudyError};
use lock::{DirLock, Role};
pub use manifest::{Entry, Manifest, Parameter};
pub use merge::{MergeReport, merge};
use plan::Plan;
pub use run::Counts;
use run::{Runner, Start};
use spec::{Vary, parse_shard};
pub use state::FailedVariant;
pub use summary::{Outcome, read_outcome, summary_csv};

/// Longest path a batch writes, bytes (Linux allows 4096).
const MAX_PATH_BYTES: usize = 4000;

/// `--keep`: which files a solved variant keeps.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Keep {
    /// `state.json` and a `result.json` thinned to what `summary.csv` reads.
    Summary,
    /// `result.json` and `state.json` (the default: the exports would triple the
    /// files a variant creates, and creating files is most of a batch's time).
    #[default]
    Results,
    /// Every file: also one CSV per rod, `rods.vtp`, `tubes.obj` and `tubes.stl`.
    All,
}

impl Keep {
    /// The option value as written.
    pub fn name(self) -> &'static str {
        match self {
            Keep::Summary => "summary",
            Keep::Results => "results",
            Keep::All => "all",
        }
    }
}

/// What to run: the options of `strand batch`.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BatchSpec {
    /// The case file.
    pub case: PathBuf,
    /// The varied parameters, `ITEM=VALUES` each ([`spec`]), at least one.
    pub vary: Vec<String>,
    /// Output directory.
    pub out: PathBuf,
    /// Worker threads (default: the available cores).
    pub jobs: Option<usize>,
    /// Use `jobs` even above the available cores.
    pub force_jobs: bool,
    /// Go ahead above the size thresholds ([`estimate`]).
    pub yes: bool,
    /// Files kept per solved variant.
    pub keep: Keep,
    /// `I/N`: run the I-th of N shards only.
    pub shard: Option<String>,
    /// Segments of every rod (default: the case's).
    pub segments: Option<usize>,
    /// Solve variants with a `failed.json` again.
    pub retry_failed: bool,
    /// Length unit of each variant's exported geometry (with [`Keep::All`]; default:
    /// the case's), for the variants solved in this run.
    pub export_unit: Option<strand_report::ExportUnit>,
    /// `NAME=VALUE`: solve every variant with the parts of motion `NAME` moved to
    /// pose `VALUE` (the motion's unit), as `strand solve --motion` does; none: the
    /// case's own pose.
    pub motion: Option<String>,
}

impl BatchSpec {
    /// A batch of `case` into `out` with every option at its default (no `vary` yet).
    pub fn new(case: impl Into<PathBuf>, out: impl Into<PathBuf>) -> Self {
        Self {
            case: case.into(),
            vary: Vec::new(),
            out: out.into(),
            jobs: None,
            force_jobs: false,
            yes: false,
            keep: Keep::default(),
            shard: None,
            segments: None,
            retry_failed: false,
            export_unit: None,
            motion: None,
        }
    }
}

/// One more variant of this run's share is finished (solved, failed, or found
/// finished before), with the counts so far: the argument of the progress callback
/// of [`OpenBatch::run`], called from the worker threads.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Progress {
    /// The variant just finished.
    pub id: String,
    /// Whether it failed (now or in an earlier run).
    pub failed_now: bool,
    /// Variants of this run's share finished so far.
    pub done: usize,
    /// Variants of this run's share.
    pub total: usize,
    /// Variants of this run's share that failed so far.
    pub failed: usize,
}

/// A planned batch: the case read, checked and solved, the `--vary` options parsed,
/// the grid, warm-start tree and shard laid out, the resources checked. Nothing has
/// been written yet.
pub struct Batch {
    spec: BatchSpec,
    case: Case,
    plan: Plan,
    shard: Option<(usize, usize)>,
    jobs: usize,
    capped: Option<usize>,
    available: usize,
    owned: Vec<bool>,
    manifest: Manifest,
    base: BuiltCase,
    base_solution: Solution,
    bytes_per_variant: u64,
    bytes_total: u64,
}

/// A batch whose directory is locked and holds its `batch.json`: ready to run.
pub struct OpenBatch {
    batch: Batch,
    held: DirLock,
    cleaned: usize,
}

/// What a run of a batch did.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BatchReport {
    /// The counts of the run.
    #[serde(flatten)]
    pub counts: Counts,
    /// Temporary files of an interrupted run removed before the run.
    pub cleaned: usize,
    /// The failed variants of this run's share, in grid order.
    pub failures: Vec<FailedVariant>,
    /// `summary.csv` and `summary.svg` (a whole batch; `None` for a shard).
    pub summary: Option<[PathBuf; 2]>,
    /// `DIR/variants`.
    pub variants_dir: PathBuf,
    /// Wall-clock time of [`OpenBatch::run`], s.
    pub elapsed_s: f64,
}

/// A batch directory read back: its plan and the outcome of every variant, in grid
/// order.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct BatchResults {
    /// `batch.json`.
    pub manifest: Manifest,
    /// What each variant's directory holds (same order as `manifest.variants`).
    pub outcomes: Vec<Outcome>,
}

/// Reads the batch in `dir` (`batch.json` and every variant's files).
pub fn read_batch(dir: impl AsRef<Path>) -> Result<BatchResults> {
    let dir = dir.as_ref();
    let manifest = Manifest::read(dir)
        .map_err(StudyError::Input)?
        .ok_or_else(|| {
            StudyError::Input(format!(
                "{} has no batch.json: it is not a `strand batch` output directory",
                dir.display()
            ))
        })?;
    let outcomes = read_outcomes(dir, &manifest)?;
    Ok(BatchResults { manifest, outcomes })
}

/// The outcomes of every variant of `manifest` in `dir/variants`.
fn read_outcomes(dir: &Path, manifest: &Manifest) -> Result<Vec<Outcome>> {
    let variants = dir.join("variants");
    manifest
        .variants
        .iter()
        .map(|v| read_outcome(&variants.join(&v.id)).map_err(StudyError::Io))
        .collect()
}

/// Writes `dir/summary.csv` and `dir/summary.svg` from the files in `dir`; returns the
/// outcomes and the two paths. `written[n]`, where given, is what variant `n`'s files
/// hold (written by this run, thinned: [`run::Runner::take_written`]), taken instead
/// of reading them back; the other variants are read and thinned (the summary reads
/// only what a thin result keeps, so the outcomes of a large batch fit in memory).
fn write_summary(
    dir: &Path,
    manifest: &Manifest,
    written: Vec<Option<Outcome>>,
) -> Result<(Vec<Outcome>, [PathBuf; 2])> {
    let variants = dir.join("variants");
    let outcomes = manifest
        .variants
        .iter()
        .zip(written.into_iter().chain(std::iter::repeat(None)))
        .map(|(v, known)| match known {
            Some(outcome) => Ok(outcome),
            None => match read_outcome(&variants.join(&v.id)).map_err(StudyError::Io)? {
                Outcome::Solved(doc) => Ok(Outcome::Solved(Box::new(keep::thin(*doc)))),
                other => Ok(other),
            },
        })
        .collect::<Result<Vec<_>>>()?;
    let csv_path = dir.join("summary.csv");
    let svg_path = dir.join("summary.svg");
    let not_written =
        |e: strand_report::ReportError| StudyError::Io(format!("summary not written: {e}"));
    write_atomic(&csv_path, summary_csv(manifest, &outcomes).as_bytes()).map_err(not_written)?;
    write_atomic(&svg_path, plot::summary_svg(manifest, &outcomes).as_bytes())
        .map_err(not_written)?;
    Ok((outcomes, [csv_path, svg_path]))
}

/// The failed variants among `outcomes` (those with `show[n]`), in grid order.
fn failures(outcomes: &[Outcome], show: &[bool]) -> Vec<FailedVariant> {
    outcomes
        .iter()
        .zip(show)
        .filter_map(|(outcome, shown)| match (outcome, *shown) {
            (Outcome::Failed(f), true) => Some(f.clone()),
            _ => None,
        })
        .collect()
}

impl Batch {
    /// Plans the batch of `spec`: reads and checks the case, parses the `--vary`
    /// options, lays out the grid, the warm-start tree and the shard, checks the
    /// threads, path lengths and disk estimate, and solves the case itself (the
    /// start of every chain). Writes nothing.
    pub fn plan(spec: BatchSpec) -> Result<Self> {
        let case = Case::from_path(&spec.case)?;
        crate::limits::check_case(&case)?;
        Self::plan_case(case, spec)
    }

    /// [`Batch::plan`] of `case`, already read and checked against the limits
    /// (`spec.case` is not read again): a case changed in memory, by a variant or
    /// [`Case::with_changes`], or read from a string. `batch.json` records
    /// `case.origin` and the fingerprint of the changed file.
    pub fn plan_case(case: Case, spec: BatchSpec) -> Result<Self> {
        let case = match spec.motion.as_deref() {
            Some(pose) => {
                let (name, value, _) = crate::motion::parse_pose(&case, pose)?;
                case.at_pose(&name, value)?
            }
            None => case,
        };
        if spec.vary.is_empty() {
            return Err(StudyError::Input(
                "strand batch needs at least one --vary, e.g. --vary hose2.length=+0mm..+100mm:10mm"
                    .into(),
            ));
        }
        let varies = spec
            .vary
            .iter()
            .map(|text| Vary::parse(text, &case.file))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|source| StudyError::Vary {
                origin: case.origin.clone(),
                source,
            })?;
        let plan =
            Plan::new(varies).map_err(|e| StudyError::Input(format!("{}: {e}", case.origin)))?;
        let shard = spec
            .shard
            .as_deref()
            .map(parse_shard)
            .transpose()
            .map_err(StudyError::Input)?;
        let available = std::thread::available_parallelism().map_or(1, |n| n.get());
        let (jobs, capped) = estimate::jobs(spec.jobs, available, spec.force_jobs)?;
        // The longest path a variant writes (a temporary file in its folder) must fit.
        if let Some(longest) = plan.variants.iter().map(|v| v.id.len()).max() {
            let path_bytes = spec.out.as_os_str().len() + "/variants//".len() + longest + 20;
            if path_bytes > MAX_PATH_BYTES {
                return Err(StudyError::Input(format!(
                    "--out {}: the variant folders' paths would be {path_bytes} bytes long; at most {MAX_PATH_BYTES} (hint: use a shorter --out)",
                    crate::limits::shown(&spec.out.display().to_string())
                )));
            }
        }
        let base = case.build(spec.segments)?;
        let manifest = Manifest::new(&case, &plan, spec.segments);
        let base_solution = crate::solve::solve_cold(&base)?;
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
            [spec.keep, Keep::Summary].map(|keep| {
                keep::variant_bytes(
                    &doc,
                    state_bytes,
                    keep,
                    &crate::solve::export_unit(&base, spec.export_unit.as_ref()),
                )
            })
        };
        let bytes_total = estimate::check_size(
            &spec.out.display().to_string(),
            owned_count,
            sizes[0],
            sizes[1],
            spec.keep,
            spec.yes,
        )?;
        Ok(Self {
            capped: capped.then_some(spec.jobs.unwrap_or(0)),
            spec,
            case,
            plan,
            shard,
            jobs,
            available,
            owned,
            manifest,
            base,
            base_solution,
            bytes_per_variant: sizes[0],
            bytes_total,
        })
    }

    /// The options it was planned from.
    pub fn spec(&self) -> &BatchSpec {
        &self.spec
    }

    /// The case.
    pub fn case(&self) -> &Case {
        &self.case
    }

    /// The grid and its warm-start tree.
    pub fn grid(&self) -> &Plan {
        &self.plan
    }

    /// `batch.json` as it is (or will be) written.
    pub fn manifest(&self) -> &Manifest {
        &self.manifest
    }

    /// The shard `(I, N)` this run owns, if sharded.
    pub fn shard(&self) -> Option<(usize, usize)> {
        self.shard
    }

    /// Variants this run owns (all, unless sharded).
    pub fn owned_count(&self) -> usize {
        self.owned.iter().filter(|o| **o).count()
    }

    /// Worker threads the run uses.
    pub fn jobs(&self) -> usize {
        self.jobs
    }

    /// The `--jobs` asked for when it was capped at [`Batch::available_cores`].
    pub fn jobs_capped(&self) -> Option<usize> {
        self.capped
    }

    /// The cores available to the process.
    pub fn available_cores(&self) -> usize {
        self.available
    }

    /// Estimated bytes on disk per variant (with the batch's `keep`).
    pub fn bytes_per_variant(&self) -> u64 {
        self.bytes_per_variant
    }

    /// Estimated bytes on disk of this run's variants.
    pub fn bytes_total(&self) -> u64 {
        self.bytes_total
    }

    /// The solution of the case itself (the start of every chain when it converged).
    pub fn base_solution(&self) -> &Solution {
        &self.base_solution
    }

    /// Locks the output directory for this run, writes `batch.json` (or checks that
    /// the one there is this batch's) and removes the temporary files an interrupted
    /// run left in this run's variants.
    pub fn open(self) -> Result<OpenBatch> {
        let out = &self.spec.out;
        let role = match self.shard {
            Some((i, n)) => Role::Shard(i, n),
            None => Role::Whole,
        };
        let mut held = lock::acquire(out, role, &self.manifest.identity())?;
        match Manifest::read(out).map_err(StudyError::Input)? {
            Some(existing) if !existing.same_batch(&self.manifest) => {
                let by: Vec<String> = lock::recorded_holders(out)
                    .iter()
                    .filter(|h| h.batch == existing.identity())
                    .map(ToString::to_string)
                    .collect();
                return Err(StudyError::Input(format!(
                    "{} holds another batch ({}{}); use another --out, or delete it to start over",
                    out.display(),
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
                let json = serde_json::to_vec_pretty(&self.manifest)
                    .map_err(|e| StudyError::Io(e.to_string()))?;
                write_atomic(&out.join("batch.json"), &json)
                    .map_err(|e| StudyError::Io(format!("batch plan not written: {e}")))?;
            }
        }
        std::fs::create_dir_all(out.join("variants")).map_err(|e| {
            StudyError::Io(format!(
                "cannot create {}: {e}",
                out.join("variants").display()
            ))
        })?;
        let owned_ids: Option<HashSet<&str>> = self.shard.map(|_| {
            self.plan
                .variants
                .iter()
                .zip(&self.owned)
                .filter(|(_, o)| **o)
                .map(|(v, _)| v.id.as_str())
                .collect()
        });
        let cleaned =
            cleanup::remove_stale_temporaries(out, owned_ids.as_ref()).map_err(StudyError::Io)?;
        held.release_plan();
        Ok(OpenBatch {
            batch: self,
            held,
            cleaned,
        })
    }

    /// [`Batch::open`] and [`OpenBatch::run`].
    pub fn run(self, progress: &(dyn Fn(Progress) + Sync)) -> Result<BatchReport> {
        self.open()?.run(progress)
    }
}

impl OpenBatch {
    /// The planned batch.
    pub fn batch(&self) -> &Batch {
        &self.batch
    }

    /// Temporary files of an interrupted run removed by [`Batch::open`].
    pub fn cleaned(&self) -> usize {
        self.cleaned
    }

    /// Solves this run's variants (skipping those finished before, repairing damaged
    /// ones) on the batch's worker threads, calling `progress` from them as each one
    /// finishes, and writes `summary.csv` and `summary.svg` for a whole batch. A
    /// variant that fails is recorded in its `failed.json`, not an error; the error is
    /// the first result that could not be written.
    pub fn run(self, progress: &(dyn Fn(Progress) + Sync)) -> Result<BatchReport> {
        let OpenBatch {
            batch,
            held,
            cleaned,
        } = self;
        let Batch {
            spec,
            case,
            plan,
            shard,
            jobs,
            owned,
            manifest,
            base,
            base_solution,
            ..
        } = batch;
        let started = Instant::now();
        let out = &spec.out;
        let start = base_solution
            .report
            .converged
            .then(|| Start::base(base, base_solution.state));
        let runner = Runner::new(
            &case,
            &plan,
            spec.segments,
            out,
            owned.clone(),
            spec.retry_failed,
            spec.keep,
            spec.export_unit.clone(),
            progress,
        )
        .map_err(StudyError::Io)?;
        let counts = runner.run(start, jobs).map_err(StudyError::Io)?;
        let (outcomes, summary) = if shard.is_none() {
            let (outcomes, paths) = write_summary(out, &manifest, runner.take_written())?;
            (outcomes, Some(paths))
        } else {
            // Other shards' variants are only counted when listing this shard's
            // failures: a damaged one of theirs is their shard's to repair, not an
            // error here.
            let variants = out.join("variants");
            let outcomes = manifest
                .variants
                .iter()
                .zip(&owned)
                .map(|(v, mine)| match read_outcome(&variants.join(&v.id)) {
                    Ok(outcome) => Ok(outcome),
                    Err(_) if !mine => Ok(Outcome::Missing),
                    Err(e) => Err(StudyError::Io(e)),
                })
                .collect::<Result<Vec<_>, _>>()?;
            (outcomes, None)
        };
        drop(held);
        Ok(BatchReport {
            counts,
            cleaned,
            failures: failures(&outcomes, &owned),
            summary,
            variants_dir: out.join("variants"),
            elapsed_s: started.elapsed().as_secs_f64(),
        })
    }
}

#[cfg(test)]
mod tests;
