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
use strand_case::motion::{
    FollowSettings, MotionEvent, MotionRange, MotionStep, Predictor, follow,
};
use strand_report::motion::{
    MotionRow, WorstKind, envelope_obj, events_csv, motion_csv, motion_svg, worst_poses,
};
use strand_report::{ResultDoc, Timing, write_atomic, write_results_in};
use strand_study::motion::{SolvedPose as Solved, build_pose, events_of, step_doc};

use crate::Exit;
use crate::commands::Failure;
use crate::summary::number;

fn invalid(message: String) -> Failure {
    Failure {
        exit: Exit::InvalidInput,
        message,
    }
}

fn write_failure(origin: &str, e: impl std::fmt::Display) -> Failure {
    Failure {
        exit: Exit::Failure,
        message: format!("{origin}: results not written: {e}"),
    }
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

/// The folder name of pose `k` of `count`.
fn step_id(k: usize, count: usize) -> String {
    let width = count.saturating_sub(1).to_string().len().max(3);
    format!("{k:0width$}")
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
    let pose = case.motion(motion)?;
    let range = MotionRange::parse(range, motion, &pose.unit)
        .map_err(|e| invalid(format!("{}: --range: {e}", case.origin)))?;
    let values = range.values();
    for v in [range.from, range.to] {
        if !pose.contains(v) {
            return Err(invalid(format!(
                "{}: --range: {v} {} is outside motion '{motion}''s keyframes ({}..{} {})\n  hint: choose a range within the keyframes, or add keyframes that cover it",
                case.origin, pose.unit, pose.domain.0, pose.domain.1, pose.unit
            )));
        }
    }
    let dir = dir
        .map(Path::to_path_buf)
        .unwrap_or_else(|| Path::new("out").join(format!("{}-{motion}", case.name)));
    let ids: Vec<(f64, String)> = values
        .iter()
        .enumerate()
        .map(|(k, v)| (*v, step_id(k, values.len())))
        .collect();
    let id_of = |v: f64| {
        ids.iter()
            .find(|(x, _)| *x == v)
            .map(|(_, id)| id.clone())
            .unwrap_or_default()
    };
    let label = |v: f64| format!("{motion}={v}{}", pose.unit);
    let mut solved: Vec<Solved> = Vec::new();
    let mut path_events: Vec<(f64, MotionEvent)> = Vec::new();
    let mut failure: Option<Failure> = None;
    let mut writing_s = 0.0;
    let following = Instant::now();
    let end = follow(
        &case,
        motion,
        &values,
        range.step,
        segments,
        &FollowSettings {
            predictor,
            ..FollowSettings::default()
        },
        &mut |step: MotionStep| {
            if failure.is_some() {
                return;
            }
            let id = id_of(step.value);
            let writing = Instant::now();
            let _count = WriteTime(&mut writing_s, writing);
            match step_doc(&step, &label(step.value)) {
                Ok(doc) => {
                    let unit = strand_study::solve::export_unit(&step.built, None);
                    if let Err(e) = write_results_in(&dir.join("steps").join(&id), &doc, &unit) {
                        failure = Some(write_failure(&step.built.origin, e));
                        return;
                    }
                    let _ = writeln!(
                        out,
                        "{:>10} {}  {}  {} iteration(s) in {} solve(s){}",
                        number(step.value),
                        pose.unit,
                        if doc.converged { "ok" } else { "not converged" },
                        step.iterations,
                        step.solves,
                        if doc.stable { "" } else { "  UNSTABLE" }
                    );
                    path_events.extend(step.events.iter().map(|e| (step.value, e.clone())));
                    solved.push(Solved {
                        id,
                        value: step.value,
                        doc,
                        solves: step.solves,
                        iterations: step.iterations,
                    });
                }
                Err(f) => failure = Some(f.into()),
            }
        },
    )?;
    if let Some(f) = failure {
        return Err(f);
    }
    let following_s = following.elapsed().as_secs_f64() - writing_s;
    let unit_case = case.build_motion(motion, 0.0, segments)?.length_unit;
    let (metres, symbol) = (unit_case.metres(), unit_case.symbol());
    let mut events = events_of(&solved, &path_events);
    events.sort_by(|a, b| a.at.total_cmp(&b.at));
    solved.sort_by(|a, b| a.value.total_cmp(&b.value));
    let mut rows: Vec<MotionRow> = solved
        .iter()
        .map(|s| MotionRow {
            id: s.id.clone(),
            value: s.value,
            doc: Some(&s.doc),
            solves: s.solves,
            iterations: s.iterations,
        })
        .collect();
    for f in &end.failed {
        rows.push(MotionRow {
            id: String::new(),
            value: f.value,
            doc: None,
            solves: 0,
            iterations: 0,
        });
    }
    rows.sort_by(|a, b| a.value.total_cmp(&b.value));
    let parameter = motion;
    let csv = motion_csv(parameter, &pose.unit, &rows, metres, symbol);
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
    let svg = motion_svg(
        &title, parameter, &pose.unit, &rows, &events, metres, symbol,
    );
    std::fs::create_dir_all(&dir).map_err(|e| write_failure(&case.origin, e))?;
    for (name, content) in [
        ("motion.csv", csv.as_bytes()),
        ("events.csv", events_csv(&events, &pose.unit).as_bytes()),
        ("motion.svg", svg.as_bytes()),
        ("envelope.obj", obj.as_bytes()),
    ] {
        write_atomic(&dir.join(name), content).map_err(|e| write_failure(&case.origin, e))?;
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
    for e in &events {
        let _ = writeln!(
            out,
            "event {} {} at {} {} (between {} and {}){}",
            e.kind,
            e.what,
            number(e.at),
            pose.unit,
            number(e.between[0]),
            number(e.between[1]),
            if e.detail.is_empty() {
                String::new()
            } else {
                format!(": {}", e.detail)
            }
        );
    }
    worst_lines(out, &solved, &pose.unit, metres, symbol);
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
    if end.failed.is_empty() && solved.iter().all(|s| s.doc.converged) {
        Ok(Exit::Success)
    } else {
        for f in &end.failed {
            let _ = writeln!(
                err,
                "error: {}: motion '{motion}' ended at {} {} (last solved: {} {}): {}",
                case.origin,
                number(f.value),
                pose.unit,
                number(f.reached),
                pose.unit,
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
