//! Executing a plan: the warm-start tree walked in parallel (rayon), each variant
//! built, solved, written to `DIR/variants/<id>/` and reported to the progress callback.
//!
//! A variant is **finished** when its directory holds `result.json` (written last,
//! atomically, after `state.json` and the rod CSVs) or `failed.json`, and they pass
//! their checks ([`super::integrity`]). A re-run skips finished variants and
//! warm-starts their children from the stored `state.json` (bit-exact), so resuming
//! gives the same numbers as an uninterrupted run. A damaged variant of this run's
//! share is solved again (and reported as repaired), and so are its dependants'
//! starts.
//! `failed.json` variants are finished too (their failure is deterministic); pass
//! `--retry-failed` to solve them again.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use strand_case::{BuiltCase, Case};
use strand_report::{
    ExportUnit, ResultDoc, Timing, collect, name_connectors, write_atomic, write_result_files,
};
use strand_solve::Solution;
use strand_system::SystemState;

use super::integrity::{Damage, Stored, clear, inspect};
use super::keep::{kept_doc, thin};
use super::plan::Plan;
use super::predict::{Solved, predicted_start};
use super::state::{FailedVariant, StoredState};
use super::summary::Outcome;
use super::variant::{WarmStart, build_and_solve};
use super::{Keep, Progress};

/// What the children of a variant start from: the nearest solved variant on the way
/// to the case and the solved ones before it (nearest first, at most
/// [`PREDICTOR_POINTS`] in all), for the continuation predictor.
#[derive(Clone)]
pub(crate) struct Start {
    solved: Arc<Solved>,
    history: Vec<Arc<Solved>>,
}

/// Solved neighbours a variant's start is extrapolated from (3: quadratic).
pub(crate) const PREDICTOR_POINTS: usize = 4;

impl Start {
    /// The start from the solved case itself.
    pub(crate) fn base(built: BuiltCase, state: SystemState) -> Self {
        Self {
            solved: Arc::new(Solved {
                n: None,
                built,
                state,
            }),
            history: Vec::new(),
        }
    }

    /// The start of the children of variant `n`, solved from `from`.
    fn after(n: usize, built: BuiltCase, state: SystemState, from: Option<&Start>) -> Self {
        let history = from
            .map(|f| {
                std::iter::once(f.solved.clone())
                    .chain(f.history.iter().cloned())
                    .take(PREDICTOR_POINTS - 1)
                    .collect()
            })
            .unwrap_or_default();
        Self {
            solved: Arc::new(Solved {
                n: Some(n),
                built,
                state,
            }),
            history,
        }
    }
}

/// Counts of one run of a batch.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Counts {
    /// Variants of this run's share solved (or built and failed) in this run.
    pub computed: usize,
    /// Variants of this run's share found finished and skipped.
    pub skipped: usize,
    /// Variants of this run's share that failed (this run or before).
    pub failed: usize,
    /// Other shards' variants solved here only as warm starts (not written).
    pub helpers: usize,
    /// Newton iterations of the variants computed in this run.
    pub iterations: usize,
    /// Variants of this run's share whose stored files were damaged and that were solved again,
    /// in grid order: the id and what was wrong.
    pub repaired: Vec<(String, String)>,
    /// Other shards' variants with damaged files (not touched here; their own
    /// shard repairs them): the id and what was wrong.
    pub foreign_damaged: Vec<(String, String)>,
}

/// What a run needs to know, shared by the parallel tasks.
pub(crate) struct Runner<'a> {
    pub case: &'a Case,
    pub plan: &'a Plan,
    pub segments: Option<usize>,
    /// `DIR/variants`.
    pub variants_dir: PathBuf,
    pub owned: Vec<bool>,
    pub needed: Vec<bool>,
    /// Whether a variant or one of its descendants has to be solved in this run.
    pending: Vec<bool>,
    /// What the directory of each needed variant held when the run started (damaged
    /// owned variants cleared and `Missing`).
    stored: Vec<Stored>,
    /// Damaged variants: owned ones (repaired) and other shards' ones, by variant.
    damage: Mutex<Vec<(usize, Damage)>>,
    pub retry_failed: bool,
    /// Which files a solved variant keeps.
    keep: Keep,
    /// The unit of the exported geometry (`None`: the case's).
    export_unit: Option<ExportUnit>,
    /// Called as each owned variant is finished.
    progress: &'a (dyn Fn(Progress) + Sync),
    /// Owned variants.
    total: usize,
    /// Owned variants finished so far.
    done: AtomicUsize,
    computed: AtomicUsize,
    skipped: AtomicUsize,
    failed: AtomicUsize,
    helpers: AtomicUsize,
    iterations: AtomicUsize,
    /// The first I/O error (results that could not be written).
    io_error: Mutex<Option<String>>,
    /// What each owned variant finished in this run left in its directory, by
    /// variant (`None`: not finished here, or not written): a solved one's result
    /// thinned as by `--keep summary` (all that `summary.csv` and `summary.svg` read,
    /// bit for bit the numbers of its `result.json`), so that the summary does not
    /// read back the files just written.
    written: Mutex<Vec<Option<Outcome>>>,
    /// Length of the last `result.json` serialised, bytes (its successor's buffer).
    json_len: AtomicUsize,
}

/// The directory of variant `id`.
pub(crate) fn variant_dir(variants_dir: &Path, id: &str) -> PathBuf {
    variants_dir.join(id)
}

impl<'a> Runner<'a> {
    /// A runner for the variants `owned` (and their ancestors). Checks the stored
    /// files of every needed variant and removes those of damaged owned variants
    /// (the error names a file that cannot be removed).
    pub(crate) fn new(
        case: &'a Case,
        plan: &'a Plan,
        segments: Option<usize>,
        dir: &Path,
        owned: Vec<bool>,
        retry_failed: bool,
        keep: Keep,
        export_unit: Option<ExportUnit>,
        progress: &'a (dyn Fn(Progress) + Sync),
    ) -> Result<Self, String> {
        let needed = plan.needed(&owned);
        let total = owned.iter().filter(|o| **o).count();
        let variants_dir = dir.join("variants");
        let mut stored = vec![Stored::Missing; owned.len()];
        let mut damage = Vec::new();
        for (n, variant) in plan.variants.iter().enumerate() {
            if !needed[n] {
                continue;
            }
            let here = variant_dir(&variants_dir, &variant.id);
            match inspect(&here, &variant.id) {
                Stored::Damaged(d) => {
                    if owned[n] {
                        clear(&here)?;
                    }
                    damage.push((n, d));
                }
                other => stored[n] = other,
            }
        }
        // Children after their parents in `order`: walk it backwards.
        let mut pending = vec![false; owned.len()];
        for &n in plan.order.iter().rev() {
            let finished =
                stored[n] == Stored::Solved || (stored[n] == Stored::Failed && !retry_failed);
            pending[n] = needed[n] && (!finished || plan.children[n].iter().any(|&c| pending[c]));
        }
        Ok(Self {
            case,
            plan,
            segments,
            variants_dir,
            owned,
            needed,
            pending,
            stored,
            damage: Mutex::new(damage),
            retry_failed,
            keep,
            export_unit,
            progress,
            total,
            done: AtomicUsize::new(0),
            computed: AtomicUsize::new(0),
            skipped: AtomicUsize::new(0),
            failed: AtomicUsize::new(0),
            helpers: AtomicUsize::new(0),
            iterations: AtomicUsize::new(0),
            io_error: Mutex::new(None),
            written: Mutex::new(vec![None; plan.variants.len()]),
            json_len: AtomicUsize::new(0),
        })
    }

    /// What the owned variants finished in this run wrote (see the field's docs),
    /// by variant; taken, so that a second call gives `None`s.
    pub(crate) fn take_written(&self) -> Vec<Option<Outcome>> {
        self.written
            .lock()
            .map(|mut w| {
                let none = vec![None; w.len()];
                std::mem::replace(&mut *w, none)
            })
            .unwrap_or_default()
    }

    /// Records what variant `n` left in its directory.
    fn remember(&self, n: usize, outcome: Outcome) {
        if let Ok(mut written) = self.written.lock()
            && let Some(slot) = written.get_mut(n)
        {
            *slot = Some(outcome);
        }
    }

    /// Walks the tree from its roots (started from `base`, the solved case, or cold
    /// when `None`) on `jobs` threads. Returns the counts, or the first I/O error.
    pub(crate) fn run(&self, base: Option<Start>, jobs: usize) -> Result<Counts, String> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(jobs)
            .build()
            .map_err(|e| format!("cannot start {jobs} worker threads: {e}"))?;
        pool.install(|| {
            rayon::scope(|s| {
                for &root in &self.plan.roots {
                    let base = base.clone();
                    s.spawn(move |s| self.visit(s, root, base));
                }
            })
        });
        if let Some(e) = self.io_error.lock().map(|e| e.clone()).unwrap_or(None) {
            return Err(e);
        }
        let mut damage = self.damage.lock().map(|d| d.clone()).unwrap_or_default();
        damage.sort_by_key(|(n, _)| *n);
        let named = |(n, d): &(usize, Damage)| (self.plan.variants[*n].id.clone(), d.to_string());
        Ok(Counts {
            computed: self.computed.load(Ordering::Relaxed),
            skipped: self.skipped.load(Ordering::Relaxed),
            failed: self.failed.load(Ordering::Relaxed),
            helpers: self.helpers.load(Ordering::Relaxed),
            iterations: self.iterations.load(Ordering::Relaxed),
            repaired: damage
                .iter()
                .filter(|(n, _)| self.owned[*n])
                .map(named)
                .collect(),
            foreign_damaged: damage
                .iter()
                .filter(|(n, _)| !self.owned[*n])
                .map(named)
                .collect(),
        })
    }

    fn record_io(&self, message: String) {
        if let Ok(mut slot) = self.io_error.lock() {
            slot.get_or_insert(message);
        }
    }

    /// Owned variant `id` is finished (`failed`: without a result).
    fn tick(&self, id: &str, failed: bool) {
        let failed_so_far = if failed {
            self.failed.fetch_add(1, Ordering::Relaxed) + 1
        } else {
            self.failed.load(Ordering::Relaxed)
        };
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        (self.progress)(Progress {
            id: id.to_string(),
            failed_now: failed,
            done,
            total: self.total,
            failed: failed_so_far,
        });
    }

    /// Solves variant `n` (or takes it from disk) and then its children in parallel.
    fn visit<'s>(&'s self, s: &rayon::Scope<'s>, n: usize, start: Option<Start>) {
        if !self.needed[n] {
            return;
        }
        let next = self.settle(s, n, start.as_ref()).or(start);
        for &child in &self.plan.children[n] {
            let next = next.clone();
            s.spawn(move |s| self.visit(s, child, next));
        }
    }

    /// Variant `n`: what its children start from (`None`: the same as `n` itself did).
    /// The results of a solved variant are written by a task of their own, so that
    /// the chain goes on solving meanwhile.
    fn settle<'s>(
        &'s self,
        s: &rayon::Scope<'s>,
        n: usize,
        start: Option<&Start>,
    ) -> Option<Start> {
        let id = &self.plan.variants[n].id;
        let dir = variant_dir(&self.variants_dir, id);
        let owned = self.owned[n];
        let finished = self.stored[n] == Stored::Solved;
        let failed_before = self.stored[n] == Stored::Failed && !self.retry_failed;
        let wanted = self.plan.children[n].iter().any(|&c| self.pending[c]);
        // A finished variant whose state cannot start its children (it does not fit
        // the model) is solved again like a damaged one.
        let loaded = if finished && wanted {
            let loaded = self.load(n, &dir, start);
            if loaded.is_none()
                && let Ok(mut damage) = self.damage.lock()
            {
                damage.push((
                    n,
                    Damage {
                        file: "state.json",
                        reason: "does not fit the variant's model".into(),
                    },
                ));
            }
            loaded
        } else {
            None
        };
        if (finished && (!wanted || loaded.is_some())) || failed_before {
            if owned {
                self.skipped.fetch_add(1, Ordering::Relaxed);
                self.tick(id, !finished);
            }
            return loaded;
        }
        let started = Instant::now();
        let changes = self.plan.changes(n);
        let warm = start.map(|st| WarmStart {
            neighbour: &st.solved,
            predict: move |built: &BuiltCase| self.predict(n, st, built),
        });
        let outcome = build_and_solve(self.case, id, &changes, self.segments, warm);
        if owned {
            self.computed.fetch_add(1, Ordering::Relaxed);
        } else {
            self.helpers.fetch_add(1, Ordering::Relaxed);
        }
        match outcome {
            Ok((built, solution, warm)) => {
                self.iterations
                    .fetch_add(solution.report.iterations, Ordering::Relaxed);
                let next = Start::after(n, built, solution.state.clone(), start);
                if owned {
                    let time = started.elapsed().as_secs_f64();
                    let (solved, id) = (next.solved.clone(), id.clone());
                    s.spawn(move |_| {
                        self.write(n, &id, &solved.built, &dir, &solution, warm, time);
                        self.tick(&id, false);
                    });
                }
                Some(next)
            }
            Err(mut failure) => {
                failure.time_s = started.elapsed().as_secs_f64();
                if let Some(iterations) = failure.iterations {
                    self.iterations.fetch_add(iterations, Ordering::Relaxed);
                }
                if owned {
                    self.write_failure(n, &dir, &failure);
                    self.tick(id, true);
                }
                None
            }
        }
    }

    /// A finished variant's stored state as a start (`None` if it cannot be read).
    fn load(&self, n: usize, dir: &Path, from: Option<&Start>) -> Option<Start> {
        let text = std::fs::read_to_string(dir.join("state.json")).ok()?;
        let stored: StoredState = serde_json::from_str(&text).ok()?;
        let changes = self.plan.changes(n);
        let built = self
            .case
            .build_with_changes(&self.plan.variants[n].id, &changes, self.segments)
            .ok()?;
        let state = stored.to_state(&built.initial)?;
        Some(Start::after(n, built, state, from))
    }

    /// The initial state of variant `n` (built as `built`) from `start`: extrapolated
    /// from the solved variants before it on its parameter line when `start` holds
    /// them, else `start`'s state carried over.
    fn predict(&self, n: usize, start: &Start, built: &BuiltCase) -> SystemState {
        let (line, x) = self.plan.line_samples(n, PREDICTOR_POINTS);
        let held = std::iter::once(&start.solved).chain(&start.history);
        let mut samples: Vec<&Solved> = Vec::new();
        let mut xs = Vec::new();
        for ((want, value), have) in line.iter().zip(held) {
            if have.n != Some(*want) {
                break;
            }
            samples.push(have);
            xs.push(*value);
        }
        if samples.is_empty() {
            samples.push(&start.solved);
        }
        predicted_start(&samples, &xs, x, &built.model)
    }

    /// Writes the files of solved variant `n` (`id`) under `self.keep`.
    fn write(
        &self,
        n: usize,
        id: &str,
        built: &BuiltCase,
        dir: &Path,
        solution: &Solution,
        warm: bool,
        time: f64,
    ) {
        let timing = Timing {
            solve: solution.report.solve_seconds,
            total: time,
            ..Timing::default()
        };
        let doc = kept_doc(result_doc(id, built, solution, warm, timing), self.keep);
        let written = std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))
            // `result.json` is exactly these bytes, serialised once: `state.json`
            // records their checksum before they are written.
            .and_then(|()| {
                // `to_vec_pretty`'s bytes, into a buffer the size of the last
                // variant's (the results of neighbouring variants are about as
                // long), not grown from 128 bytes by copying.
                let mut json = Vec::with_capacity(self.json_len.load(Ordering::Relaxed) + 4096);
                serde_json::to_writer_pretty(&mut json, &doc).map_err(|e| e.to_string())?;
                self.json_len.store(json.len(), Ordering::Relaxed);
                Ok(json)
            })
            .and_then(|result_json| {
                let stored = StoredState::from_state(&solution.state, &result_json);
                serde_json::to_vec(&stored)
                    .map_err(|e| e.to_string())
                    .and_then(|json| {
                        write_atomic(&dir.join("state.json"), &json).map_err(|e| e.to_string())
                    })
                    .map(|()| result_json)
            })
            .and_then(|result_json| match self.keep {
                Keep::All => write_result_files(
                    dir,
                    &doc,
                    &result_json,
                    &crate::solve::export_unit(built, self.export_unit.as_ref()),
                )
                .map(|_| ())
                .map_err(|e| e.to_string()),
                Keep::Results | Keep::Summary => {
                    write_atomic(&dir.join("result.json"), &result_json).map_err(|e| e.to_string())
                }
            });
        match written {
            Ok(()) => self.remember(n, Outcome::Solved(Box::new(thin(doc)))),
            Err(e) => self.record_io(format!("variant '{id}': results not written: {e}")),
        }
    }

    /// Writes `failed.json` of variant `n`.
    fn write_failure(&self, n: usize, dir: &Path, failure: &FailedVariant) {
        let written = std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))
            .and_then(|()| serde_json::to_vec_pretty(failure).map_err(|e| e.to_string()))
            .and_then(|json| {
                write_atomic(&dir.join("failed.json"), &json).map_err(|e| e.to_string())
            });
        match written {
            Ok(()) => self.remember(n, Outcome::Failed(failure.clone())),
            Err(e) => self.record_io(format!(
                "variant '{}': failure not written: {e}",
                failure.id
            )),
        }
    }
}

/// The result document of a solved variant, with the allowed bend radii filled in.
pub(crate) fn result_doc(
    id: &str,
    built: &BuiltCase,
    solution: &Solution,
    warm: bool,
    timing: Timing,
) -> ResultDoc {
    let mut doc = collect(&built.name, &built.model, solution, timing);
    // A contact set that cannot be evaluated at a converged state leaves the lists
    // empty rather than failing the variant.
    let _ = crate::solve::add_contacts(&mut doc, built, solution);
    name_connectors(&mut doc, &built.connector_names);
    for (rod, allowed) in doc.rods.iter_mut().zip(&built.min_bend_radius) {
        rod.min_bend_radius_m = *allowed;
    }
    doc.variant = Some(id.to_string());
    doc.warm_start = warm;
    doc
}
