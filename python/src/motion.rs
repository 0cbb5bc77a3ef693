//! `strand motion` from Python: a case followed over a range of one of its motions
//! ([`strand_study::motion::follow_motion`], the engine of the command line), every
//! pose kept as a `_Solved` (its result document and solved state).

use std::sync::Arc;

use strand_case::BuiltCase;
use strand_study::StudyError;
use strand_study::motion::{follow_motion, parse_predictor};
use strand_system::SystemState;

use crate::case::CaseSpec;
use crate::solved::Solved;

/// One solved pose: its folder name under `steps/` (`000`, …), the motion's value
/// (the motion's unit), the solves and Newton iterations it took, and its solve.
pub type Pose = (String, f64, usize, usize, Solved);

/// A direction that ended early: the value that could not be solved, the last value
/// solved (the motion's unit), and why.
pub type Failed = (f64, f64, String);

/// A followed motion: the motion's name and unit, the poses in order of the value,
/// the events (`events.csv`'s records as JSON), the directions that ended early,
/// `motion.csv`, whether the whole range was solved and converged, and the wall time
/// of the path following (s).
pub type FollowedMotion = (
    String,
    String,
    Vec<Pose>,
    String,
    Vec<Failed>,
    String,
    bool,
    f64,
);

/// Follows `spec`'s case (its variant and changes applied) over `range`
/// (`FROM..TO:STEP` in the motion's unit) of motion `motion` from the case's own pose
/// in both directions, as `strand motion` does, with `predictor` (`tangent`,
/// `secant`, `last`) and rods of `segments` segments (default: the case's).
pub fn follow(
    spec: &Arc<CaseSpec>,
    motion: &str,
    range: &str,
    segments: Option<usize>,
    predictor: &str,
) -> Result<FollowedMotion, StudyError> {
    let predictor = parse_predictor(predictor)?;
    let case = &spec.current;
    if spec.posed() {
        return Err(StudyError::Input(format!(
            "{}: motion '{motion}': the case is already at a motion pose (hint: follow the motion from the case without a pose)",
            case.origin
        )));
    }
    let mut states: Vec<(f64, BuiltCase, SystemState)> = Vec::new();
    let run = follow_motion(case, motion, range, segments, predictor, &mut |step, _| {
        states.push((step.value, step.built.clone(), step.solution.state.clone()));
        Ok(())
    })?;
    let mut poses = Vec::with_capacity(run.solved.len());
    for pose in &run.solved {
        let k = states
            .iter()
            .position(|(value, _, _)| *value == pose.value)
            .ok_or_else(|| StudyError::Io(format!("{}: pose {} lost", case.origin, pose.value)))?;
        let (_, built, state) = states.swap_remove(k);
        let at = Arc::new(spec.with_pose(&format!("{motion}={}", pose.value))?);
        let solved = Solved::new(at, segments, pose.doc.clone(), state, built);
        poses.push((
            pose.id.clone(),
            pose.value,
            pose.solves,
            pose.iterations,
            solved,
        ));
    }
    let events = serde_json::to_string(&run.events)
        .map_err(|e| StudyError::Io(format!("{}: events: {e}", case.origin)))?;
    let failed = run
        .failed
        .iter()
        .map(|f| (f.value, f.reached, f.reason.clone()))
        .collect();
    Ok((
        run.motion.clone(),
        run.unit.clone(),
        poses,
        events,
        failed,
        run.csv(),
        run.complete(),
        run.following_s,
    ))
}
