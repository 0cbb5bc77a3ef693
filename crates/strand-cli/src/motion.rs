//! `strand motion CASE --motion NAME --range FROM..TO:STEP --out DIR`: the case over a
//! motion of its parts, followed quasi-statically from the case's own pose in both
//! directions ([`strand_case::motion::follow`]); and the pose of
//! `strand solve CASE --motion NAME=VALUE`.
//!
//! Writes `DIR/steps/<k>/` (the results of each pose, `k` in order of the parameter),
//! `DIR/motion.csv`, `DIR/events.csv`, `DIR/motion.svg` and `DIR/envelope.obj`
//! (see [`strand_report::motion`]), each atomically. A direction that fails even at
//! the smallest step ends there: the poses solved so far are written, the reason is
//! printed, and the exit status is 3.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use strand_case::Case;
use strand_case::motion::{MotionStep, Predictor};
use strand_report::motion::{WorstKind, envelope_obj, events_csv, motion_svg, worst_poses};
use strand_report::{ResultDoc, Timing, write_atomic, write_results_in};
use strand_study::StudyError;
use strand_study::motion::{SolvedPose as Solved, build_pose, follow_motion};

use crate::Exit;
use crate::commands::Failure;
use crate::summary::number;

/// The I/O error of writing results of `origin` (exit 1).
fn write_failure(origin: &str, e: impl std::fmt::Display) -> StudyError {
    StudyError::Io(format!("{origin}: results not written: {e}"))
}

/// `strand solve CASE --motion NAME=VALUE`: the case at one pose, solved cold.
pub(crate) fn solve_pose(
    path: &Path,
    pose: &str,
    dir: Option<&Path>,
    segments: Option<usize>,
    export_unit: Option<strand_report::ExportUnit>,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<Exit, Failure> {
    let started = Instant::now();
    let (built, label) = build_pose(path, pose, segments)?;
    let build = started.elapsed().as_secs_f64();
    let solution = crate::commands::solve_cold(&built)?;
    let timing = Timing {
        build,
        solve: solution.report.solve_seconds,
        total: started.elapsed().as_secs_f64(),
        ..Timing::default()
    };
    let solved = crate::commands::Solved {
        built: &built,
        solution: &solution,
        timing,
        variant: Some(&label),
        base_iterations: None,
        export_unit,
    };
    crate::commands::write_solved(&solved, dir, out, err)
}

/// `strand motion`.
pub(crate) fn run(
    path: &Path,
    motion: &str,
    range: &str,
    dir: Option<&Path>,
    segments: Option<usize>,
    predictor: Predictor,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<Exit, Failure> {
    let started = Instant::now();
    let case = Case::from_path(path)?;
    strand_study::limits::check_case(&case)?;
    let dir = dir
        .map(Path::to_path_buf)
        .unwrap_or_else(|| Path::new("out").join(format!("{}-{motion}", case.name)));
    let parameter_unit = case.motion(motion)?.unit;
    let mut writing_s = 0.0;
    let run = follow_motion(
        &case,
        motion,
        range,
        segments,
        predictor,
        &mut |step: &MotionStep, pose: &Solved| {
            let writing = Instant::now();
            let _count = WriteTime(&mut writing_s, writing);
            let unit = strand_study::solve::export_unit(&step.built, None);
            write_results_in(&dir.join("steps").join(&pose.id), &pose.doc, &unit)
                .map_err(|e| write_failure(&step.built.origin, e))?;
            let _ = writeln!(
                out,
                "{:>10} {}  {}  {} iteration(s) in {} solve(s){}",
                number(step.value),
                parameter_unit,
                if pose.doc.converged {
                    "ok"
                } else {
                    "not converged"
                },
                step.iterations,
                step.solves,
                if pose.doc.stable { "" } else { "  UNSTABLE" }
            );
            Ok(())
        },
    )?;
    let following_s = run.following_s - writing_s;
    let (metres, symbol) = (run.length_unit.metres(), run.length_unit.symbol());
    let (solved, events, unit) = (&run.solved, &run.events, &run.unit);
    let rows = run.rows();
    let csv = run.csv();
    let docs: Vec<&ResultDoc> = solved.iter().map(|s| &s.doc).collect();
    let radii: Vec<(String, f64)> = docs
        .first()
        .map(|d| {
            d.rods
                .iter()
                .map(|r| (r.name.clone(), strand_report::tube_radius(r).0))
                .collect()
        })
        .unwrap_or_default();
    let (obj, envelopes) = envelope_obj(&docs, &radii, metres, symbol);
    let title = format!("{}: motion '{motion}'", case.name);
    let svg = motion_svg(&title, motion, unit, &rows, events, metres, symbol);
    let io = |e: &dyn std::fmt::Display| Failure::from(write_failure(&case.origin, e));
    std::fs::create_dir_all(&dir).map_err(|e| io(&e))?;
    for (name, content) in [
        ("motion.csv", csv.as_bytes()),
        ("events.csv", events_csv(events, unit).as_bytes()),
        ("motion.svg", svg.as_bytes()),
        ("envelope.obj", obj.as_bytes()),
    ] {
        write_atomic(&dir.join(name), content).map_err(|e| io(&e))?;
    }
    let total_iterations: usize = solved.iter().map(|s| s.iterations).sum();
    let warm: Vec<&Solved> = solved.iter().filter(|s| s.doc.warm_start).collect();
    let mut per_step: Vec<usize> = warm.iter().map(|s| s.iterations).collect();
    per_step.sort_unstable();
    let _ = writeln!(
        out,
        "{} pose(s) solved in {:.3} s (path following {following_s:.3} s, the rest reading, writing and the envelope); {total_iterations} Newton iterations in all; warm-started poses: median {} iteration(s), at most {}",
        solved.len(),
        started.elapsed().as_secs_f64(),
        per_step.get(per_step.len() / 2).copied().unwrap_or(0),
        per_step.last().copied().unwrap_or(0)
    );
    for e in events {
        let _ = writeln!(
            out,
            "event {} {} at {} {} (between {} and {}){}",
            e.kind,
            e.what,
            number(e.at),
            unit,
            number(e.between[0]),
            number(e.between[1]),
            if e.detail.is_empty() {
                String::new()
            } else {
                format!(": {}", e.detail)
            }
        );
    }
    worst_lines(out, solved, unit, metres, symbol);
    for env in &envelopes {
        let _ = writeln!(
            out,
            "envelope {}: {} triangles, voxel pitch {} {symbol}",
            env.rod,
            env.triangles.len(),
            number(env.pitch_m / metres)
        );
    }
    let _ = writeln!(
        out,
        "written: {}/motion.csv, events.csv, motion.svg, envelope.obj, steps/",
        dir.display()
    );
    if run.complete() {
        Ok(Exit::Success)
    } else {
        for f in &run.failed {
            let _ = writeln!(
                err,
                "error: {}: motion '{motion}' ended at {} {} (last solved: {} {}): {}",
                case.origin,
                number(f.value),
                unit,
                number(f.reached),
                unit,
                f.reason
            );
        }
        Ok(Exit::NotConverged)
    }
}

/// Adds the time from its start to `total` (s) when dropped.
struct WriteTime<'a>(&'a mut f64, Instant);

impl Drop for WriteTime<'_> {
    fn drop(&mut self) {
        *self.0 += self.1.elapsed().as_secs_f64();
    }
}

/// The worst pose of each quantity ([`strand_report::motion::worst_poses`]).
fn worst_lines(out: &mut dyn Write, solved: &[Solved], unit: &str, metres: f64, symbol: &str) {
    let poses: Vec<(f64, &ResultDoc)> = solved.iter().map(|s| (s.value, &s.doc)).collect();
    let worst = worst_poses(&poses);
    let rods: Vec<&str> = solved
        .first()
        .map(|s| s.doc.rods.iter().map(|r| r.name.as_str()).collect())
        .unwrap_or_default();
    let find = |kind: WorstKind, item: &str| {
        worst
            .iter()
            .find(|w| w.kind == kind && w.item == item)
            .map_or((f64::NAN, f64::NAN), |w| (w.value, w.at))
    };
    for rod in rods {
        let (f, vf) = find(WorstKind::PeakForce, rod);
        let (m, vm) = find(WorstKind::PeakMoment, rod);
        let (b, vb) = find(WorstKind::MinBendRadius, rod);
        let _ = writeln!(
            out,
            "worst {rod}: peak |f| {} N at {} {unit}; peak |m| {} N·m at {} {unit}; min bend radius {} {symbol} at {} {unit}",
            number(f),
            number(vf),
            number(m),
            number(vm),
            number(b / metres),
            number(vb)
        );
    }
    for w in worst.iter().filter(|w| w.kind == WorstKind::MinClearance) {
        let _ = writeln!(
            out,
            "worst clearance to {}: {} {symbol} at {} {unit}",
            w.item,
            number(w.value / metres),
            number(w.at)
        );
    }
}
