//! Motions: the case at one pose of a motion of its parts (`strand solve CASE --motion
//! NAME=VALUE`), the result document of each pose a motion is followed through
//! ([`strand_case::motion::follow`]), and the events along a followed motion — the
//! engine of `strand motion`, whose front end writes and prints each pose.

pub mod run;

use std::path::Path;

use strand_case::motion::{MotionEvent, MotionStep, Predictor, parse_value};
use strand_case::{BuiltCase, Case};
use strand_report::motion::{MotionEventRecord, doc_events};
use strand_report::{ResultDoc, Timing, collect, name_connectors};

use crate::error::{Result, StudyError};
use crate::solve::add_contacts;

pub use run::{MotionRun, follow_motion, step_id};

fn invalid(message: String) -> StudyError {
    StudyError::Input(message)
}

/// `NAME=VALUE` of `--motion`, split and checked against the case: the motion's
/// name, the value (in the motion's unit) and the unit.
pub fn parse_pose(case: &Case, text: &str) -> Result<(String, f64, String)> {
    let (name, value) = text.split_once('=').ok_or_else(|| {
        invalid(format!(
            "--motion '{text}': write NAME=VALUE, e.g. --motion engine_roll=4deg (motions: {})",
            names(case)
        ))
    })?;
    let motion = case.motion(name.trim())?;
    let value = parse_value(value, &motion.name, &motion.unit)
        .map_err(|e| invalid(format!("{}: --motion: {e}", case.origin)))?;
    Ok((motion.name, value, motion.unit))
}

/// The predictor named `text` (`tangent`, `secant` or `last`, as `strand motion
/// --predictor` takes them).
pub fn parse_predictor(text: &str) -> Result<Predictor> {
    match text.trim() {
        "tangent" => Ok(Predictor::Tangent),
        "secant" => Ok(Predictor::Secant),
        "last" => Ok(Predictor::Last),
        other => Err(invalid(format!(
            "--predictor '{other}': not a predictor (hint: use tangent, secant or last)"
        ))),
    }
}

/// The motions of `case`, for messages.
fn names(case: &Case) -> String {
    let n = case.motion_names();
    if n.is_empty() {
        "none".into()
    } else {
        n.join(", ")
    }
}

/// The case built at the pose `NAME=VALUE` (for `strand solve --motion`), with the
/// label of the pose (`engine_roll=4deg`).
pub fn build_pose(path: &Path, pose: &str, segments: Option<usize>) -> Result<(BuiltCase, String)> {
    let case = Case::from_path(path)?;
    crate::limits::check_case(&case)?;
    let (name, value, unit) = parse_pose(&case, pose)?;
    let built = case.build_motion(&name, value, segments)?;
    Ok((built, format!("{name}={value}{unit}")))
}

/// One solved pose of a followed motion, kept for the tables.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SolvedPose {
    /// Its folder name under `steps/`.
    pub id: String,
    /// The motion's value, in the motion's unit.
    pub value: f64,
    /// Its result.
    pub doc: ResultDoc,
    /// Solves it took (more than one: the step was refined).
    pub solves: usize,
    /// Newton iterations in all.
    pub iterations: usize,
}

/// The result document of one pose of a followed motion, labelled `label`
/// (`engine_roll=4deg`).
pub fn step_doc(step: &MotionStep, label: &str) -> Result<ResultDoc> {
    let timing = Timing {
        solve: step.solution.report.solve_seconds,
        ..Timing::default()
    };
    let mut doc = collect(&step.built.name, &step.built.model, &step.solution, timing);
    add_contacts(&mut doc, &step.built, &step.solution)?;
    name_connectors(&mut doc, &step.built.connector_names);
    doc.variant = Some(label.to_string());
    doc.warm_start = step.warm;
    Ok(doc)
}

/// The events of the motion: those of the path following, and those found between
/// neighbouring poses along each direction from the case's pose.
pub fn events_of(solved: &[SolvedPose], path: &[(f64, MotionEvent)]) -> Vec<MotionEventRecord> {
    let mut out = Vec::new();
    for direction in [1.0, -1.0] {
        let mut chain: Vec<&SolvedPose> = solved
            .iter()
            .filter(|s| s.value * direction > 0.0 || s.value == 0.0)
            .collect();
        chain.sort_by(|a, b| (a.value * direction).total_cmp(&(b.value * direction)));
        for k in 1..chain.len() {
            let earlier = (k >= 2).then(|| (chain[k - 2].value, &chain[k - 2].doc));
            out.extend(doc_events(
                earlier,
                (chain[k - 1].value, &chain[k - 1].doc),
                (chain[k].value, &chain[k].doc),
            ));
        }
    }
    for (at, e) in path {
        out.push(match e {
            MotionEvent::SnapThrough { from, to, jump_m } => MotionEventRecord {
                kind: "snap_through".into(),
                what: "state".into(),
                between: [*from, *to],
                at: *to,
                detail: format!("the hoses jumped by up to {jump_m:.4e} m within the smallest step (reached at pose {at})"),
            },
            MotionEvent::StabilityLost { at: v, negative_directions } => MotionEventRecord {
                kind: "stability_lost".into(),
                what: "state".into(),
                between: [*v, *v],
                at: *v,
                detail: format!("{negative_directions} direction(s) of negative curvature"),
            },
            MotionEvent::StabilityRegained { at: v } => MotionEventRecord {
                kind: "stability_regained".into(),
                what: "state".into(),
                between: [*v, *v],
                at: *v,
                detail: String::new(),
            },
        });
    }
    out
}
