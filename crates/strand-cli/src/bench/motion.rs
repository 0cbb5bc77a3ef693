//! `strand bench --motion`: the engine-roll motion of `cases/cooler_hose_engine_roll.ron`
//! (−8° to 8° in 0.5° steps, 33 poses, the hoses in contact with the engine bay)
//! followed with each predictor: Newton iterations per pose and the time of the path
//! following, split into builds, solves and tangents (wall clock), and its CPU time.
//! Results are not written (that is `strand motion`'s job, and its cost is I/O).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use strand_case::Case;
use strand_case::motion::{FollowSettings, MotionRange, PhaseTimes, Predictor, follow};

use crate::Exit;
use crate::commands::Failure;

/// The benchmarked case, relative to the `cases/` folder.
pub const MOTION_CASE: &str = "cooler_hose_engine_roll.ron";
/// Its motion and range.
pub const MOTION: (&str, &str) = ("engine_roll", "-8deg..8deg:0.5deg");

/// One predictor's run (the median-time run of the repeats).
#[derive(Clone, Debug)]
pub struct MotionBenchRow {
    /// The predictor.
    pub predictor: Predictor,
    /// Poses solved, and how many converged.
    pub poses: usize,
    /// Poses that converged.
    pub converged: usize,
    /// Whether both directions reached the end of the range.
    pub complete: bool,
    /// Newton iterations of every solve, the case's own pose (cold) included.
    pub iterations: usize,
    /// Newton iterations per warm-started pose (intermediate steps included), sorted.
    pub per_pose: Vec<usize>,
    /// Solves (accepted and rejected) in all.
    pub solves: usize,
    /// Of those, the solves that started from the tangent prediction.
    pub tangent_starts: usize,
    /// Wall time of the path following, ms.
    pub wall_ms: f64,
    /// CPU time of the path following on this thread, ms (`None` where the platform
    /// does not tell).
    pub cpu_ms: Option<f64>,
    /// Wall time per phase.
    pub phases: PhaseTimes,
}

/// CPU time of the calling thread, s (Linux: `/proc/thread-self/schedstat`, ns).
fn thread_cpu_s() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

/// Follows the engine roll of `cases_dir` with `predictor` once.
fn run_once(
    case: &Case,
    predictor: Predictor,
) -> Result<MotionBenchRow, Box<dyn std::error::Error>> {
    let (motion, range) = MOTION;
    let pose = case.motion(motion)?;
    let range = MotionRange::parse(range, motion, &pose.unit)?;
    let settings = FollowSettings {
        predictor,
        ..FollowSettings::default()
    };
    let (mut poses, mut converged, mut iterations, mut solves) = (0, 0, 0, 0);
    let mut tangent_starts = 0;
    let mut per_pose = Vec::new();
    let cpu = thread_cpu_s();
    let started = Instant::now();
    let end = follow(
        case,
        motion,
        &range.values(),
        range.step,
        None,
        &settings,
        &mut |step| {
            poses += 1;
            converged += usize::from(step.solution.report.converged);
            iterations += step.iterations;
            solves += step.solves;
            tangent_starts += step.tangent_starts;
            if step.warm {
                per_pose.push(step.iterations);
            }
        },
    )?;
    let wall_ms = started.elapsed().as_secs_f64() * 1e3;
    let cpu_ms = cpu.zip(thread_cpu_s()).map(|(a, b)| (b - a) * 1e3);
    per_pose.sort_unstable();
    Ok(MotionBenchRow {
        predictor,
        poses,
        converged,
        complete: end.failed.is_empty(),
        iterations,
        per_pose,
        solves,
        tangent_starts,
        wall_ms,
        cpu_ms,
        phases: end.times,
    })
}

/// Runs the engine roll with each predictor, `repeats` times each; per predictor the
/// run of median wall time.
pub fn run_motion(
    cases_dir: &Path,
    repeats: usize,
) -> Result<(PathBuf, Vec<MotionBenchRow>), Box<dyn std::error::Error>> {
    let path = cases_dir.join(MOTION_CASE);
    let case = Case::from_path(&path)?;
    let mut rows = Vec::new();
    for predictor in [Predictor::Last, Predictor::Secant, Predictor::Tangent] {
        let mut runs = (0..repeats.max(1))
            .map(|_| run_once(&case, predictor))
            .collect::<Result<Vec<_>, _>>()?;
        runs.sort_by(|a, b| a.wall_ms.total_cmp(&b.wall_ms));
        rows.push(runs.swap_remove(runs.len() / 2));
    }
    Ok((path, rows))
}

/// The table of [`run_motion`].
pub fn format_motion_table(rows: &[MotionBenchRow]) -> String {
    let mut out = String::from(
        "predictor  poses  converged  iterations  per pose: median  max  1-3  solves (from tangent)  wall [ms]  cpu [ms]  builds [ms]  solves [ms]  tangents [ms]\n",
    );
    for r in rows {
        let median = r.per_pose.get(r.per_pose.len() / 2).copied().unwrap_or(0);
        let max = r.per_pose.last().copied().unwrap_or(0);
        let easy = r.per_pose.iter().filter(|&&n| (1..=3).contains(&n)).count();
        out.push_str(&format!(
            "{:<9}  {:>5}  {:>9}  {:>10}  {:>16}  {:>3}  {:>3}  {:>6} ({:>3})        {:>9.1}  {:>8}  {:>11.1}  {:>11.1}  {:>13.1}{}\n",
            format!("{:?}", r.predictor).to_lowercase(),
            r.poses,
            r.converged,
            r.iterations,
            median,
            max,
            easy,
            r.solves,
            r.tangent_starts,
            r.wall_ms,
            r.cpu_ms.map_or("-".to_string(), |c| format!("{c:.1}")),
            r.phases.build_s * 1e3,
            r.phases.solve_s * 1e3,
            r.phases.tangent_s * 1e3,
            if r.complete { "" } else { "  INCOMPLETE" },
        ));
    }
    out
}

/// `strand bench --motion`: runs and prints the table.
pub(crate) fn run_and_print(
    cases_dir: &Path,
    repeats: usize,
    out: &mut dyn Write,
) -> Result<Exit, Failure> {
    let (path, rows) = run_motion(cases_dir, repeats).map_err(|e| Failure {
        exit: Exit::InvalidInput,
        message: format!(
            "{e}\n  hint: run `strand bench --motion` from the repository root (it reads cases/)"
        ),
    })?;
    let (motion, range) = MOTION;
    let _ = write!(
        out,
        "{}: motion {motion} {range}, path following without writing results, median of {repeats} run(s)\n{}",
        path.display(),
        format_motion_table(&rows)
    );
    Ok(
        if rows.iter().all(|r| r.complete && r.converged == r.poses) {
            Exit::Success
        } else {
            Exit::NotConverged
        },
    )
}
