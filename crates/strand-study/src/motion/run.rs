//! `strand motion`'s engine: the case followed over a range of a motion's parameter
//! ([`follow_motion`]), each pose as its result document, the poses in order of the
//! parameter, the events along the path and the table of `motion.csv`
//! ([`MotionRun::csv`]). The front ends (the CLI, Python) write or keep each pose as
//! it is solved.

use strand_case::motion::{
    FollowSettings, MotionEvent, MotionRange, MotionStep, Predictor, StepOutcome, follow,
};
use strand_case::{Case, LengthUnit};
use strand_report::motion::{MotionEventRecord, MotionRow, motion_csv};

use super::{SolvedPose, events_of, step_doc};
use crate::error::{Result, StudyError};

/// A followed motion.
#[derive(Clone, Debug)]
pub struct MotionRun {
    /// The motion's name.
    pub motion: String,
    /// The unit of its parameter (`deg`, `mm`, …).
    pub unit: String,
    /// The case's length unit (the table's lengths).
    pub length_unit: LengthUnit,
    /// The solved poses, in order of the parameter.
    pub solved: Vec<SolvedPose>,
    /// The events along the path (snap-throughs, stability, contacts, findings), in
    /// order of the parameter.
    pub events: Vec<MotionEventRecord>,
    /// The directions that ended early, where and why (empty: the whole range).
    pub failed: Vec<StepOutcome>,
    /// Wall time of the path following, s (the callback's time included).
    pub following_s: f64,
}

impl MotionRun {
    /// The rows of `motion.csv`: the solved poses and the failed ones, in order.
    pub fn rows(&self) -> Vec<MotionRow<'_>> {
        let mut rows: Vec<MotionRow> = self
            .solved
            .iter()
            .map(|s| MotionRow {
                id: s.id.clone(),
                value: s.value,
                doc: Some(&s.doc),
                solves: s.solves,
                iterations: s.iterations,
            })
            .collect();
        rows.extend(self.failed.iter().map(|f| MotionRow {
            id: String::new(),
            value: f.value,
            doc: None,
            solves: 0,
            iterations: 0,
        }));
        rows.sort_by(|a, b| a.value.total_cmp(&b.value));
        rows
    }

    /// `motion.csv` ([`strand_report::motion::motion_csv`]), lengths in the case's unit.
    pub fn csv(&self) -> String {
        let unit = &self.length_unit;
        motion_csv(
            &self.motion,
            &self.unit,
            &self.rows(),
            unit.metres(),
            unit.symbol(),
        )
    }

    /// Whether every pose of the range was solved and converged.
    pub fn complete(&self) -> bool {
        self.failed.is_empty() && self.solved.iter().all(|s| s.doc.converged)
    }
}

/// The folder name of pose `k` of `count` under `steps/` (`000`, `001`, …).
pub fn step_id(k: usize, count: usize) -> String {
    let width = count.saturating_sub(1).to_string().len().max(3);
    format!("{k:0width$}")
}

/// Follows `case` over `range` (`FROM..TO:STEP` in the motion's unit, the grammar of
/// `strand motion --range`) of motion `motion` from the case's own pose in both
/// directions ([`strand_case::motion::follow`]) with `predictor`, rods of `segments`
/// segments (default: the case's). `on_step` gets every solved pose as it is solved
/// (with its step: the built case and the solution); its error ends the run. Errors:
/// an unknown motion or a bad range (input), a case that cannot be built or solved
/// at its own pose.
pub fn follow_motion(
    case: &Case,
    motion: &str,
    range: &str,
    segments: Option<usize>,
    predictor: Predictor,
    on_step: &mut dyn FnMut(&MotionStep, &SolvedPose) -> Result<()>,
) -> Result<MotionRun> {
    let started = std::time::Instant::now();
    let pose = case.motion(motion)?;
    let range = MotionRange::parse(range, motion, &pose.unit)
        .map_err(|e| StudyError::Input(format!("{}: --range: {e}", case.origin)))?;
    for v in [range.from, range.to] {
        if !pose.contains(v) {
            return Err(StudyError::Input(format!(
                "{}: --range: {v} {} is outside motion '{motion}''s keyframes ({}..{} {})\n  hint: choose a range within the keyframes, or add keyframes that cover it",
                case.origin, pose.unit, pose.domain.0, pose.domain.1, pose.unit
            )));
        }
    }
    let values = range.values();
    let id_of = |v: f64| {
        values
            .iter()
            .position(|x| *x == v)
            .map(|k| step_id(k, values.len()))
            .unwrap_or_default()
    };
    let mut solved: Vec<SolvedPose> = Vec::new();
    let mut path_events: Vec<(f64, MotionEvent)> = Vec::new();
    let mut failure: Option<StudyError> = None;
    let end = follow(
        case,
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
            let label = format!("{motion}={}{}", step.value, pose.unit);
            let done = step_doc(&step, &label).and_then(|doc| {
                let pose = SolvedPose {
                    id: id_of(step.value),
                    value: step.value,
                    doc,
                    solves: step.solves,
                    iterations: step.iterations,
                };
                on_step(&step, &pose)?;
                path_events.extend(step.events.iter().map(|e| (step.value, e.clone())));
                solved.push(pose);
                Ok(())
            });
            if let Err(e) = done {
                failure = Some(e);
            }
        },
    )?;
    if let Some(e) = failure {
        return Err(e);
    }
    let following_s = started.elapsed().as_secs_f64();
    let length_unit = case.build_motion(motion, 0.0, segments)?.length_unit;
    let mut events = events_of(&solved, &path_events);
    events.sort_by(|a, b| a.at.total_cmp(&b.at));
    solved.sort_by(|a, b| a.value.total_cmp(&b.value));
    Ok(MotionRun {
        motion: motion.to_string(),
        unit: pose.unit,
        length_unit,
        solved,
        events,
        failed: end.failed,
        following_s,
    })
}
