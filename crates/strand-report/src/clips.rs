//! The `clips` section of `result.json`: each clip's joint coordinate and reaction.

use serde::{Deserialize, Serialize};
use strand_solve::Solution;
use strand_system::{Joint, Model, Reaction, ReactionKind};

/// A clip at the solution: where it holds its rod, its joint coordinate, and the
/// force and moment it exerts on the rod.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ClipResult {
    /// Clip name.
    pub name: String,
    /// Name of the rod held.
    pub rod: String,
    /// The vertex held.
    pub vertex: usize,
    /// Reference arc length of the held vertex, m.
    pub s_m: f64,
    /// Position of the held vertex (the clip's output origin), m.
    pub position_m: [f64; 3],
    /// `"fixed"`, `"revolute"`, `"prismatic"` or `"spherical"`.
    pub joint: String,
    /// Joint axis in the world frame (revolute, prismatic), unit.
    pub axis_world: Option<[f64; 3]>,
    /// Joint angle in rad (revolute) or distance in m (prismatic); `null` otherwise.
    pub value: Option<f64>,
    /// Rotation of a spherical joint from its base frame, `[w, x, y, z]` (base
    /// coordinates); `null` otherwise.
    pub rotation_wxyz: Option<[f64; 4]>,
    /// Limits `[lower, upper]` in rad or m, if any.
    pub limits: Option<[f64; 2]>,
    /// Whether the joint sits at one of its limits (the stop then carries load along
    /// or about the axis).
    pub at_limit: bool,
    /// Force on the rod, N.
    #[serde(rename = "force_N")]
    pub force_n: [f64; 3],
    /// Moment on the rod about `position_m`, N·m.
    #[serde(rename = "moment_Nm")]
    pub moment_nm: [f64; 3],
}

/// Relative distance from a limit below which a joint counts as at it.
pub const AT_LIMIT_TOLERANCE: f64 = 1e-9;

fn arr(v: &nalgebra::Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// The clips of `model` at `solution`; `reactions` are `model.reactions(&solution.state)`
/// (clip reactions come in the order of the system's clips).
pub fn collect_clips(
    model: &Model,
    solution: &Solution,
    reactions: &[Reaction],
) -> Vec<ClipResult> {
    let system = model.system();
    let mut clip_reactions = reactions.iter().filter(|r| r.kind == ReactionKind::Clip);
    system
        .clips
        .iter()
        .zip(&solution.state.clips)
        .enumerate()
        .map(|(c, (clip, state))| {
            let reaction = clip_reactions.next().filter(|r| r.name == clip.name);
            let (joint, axis, value, rotation) = match clip.joint {
                Joint::Fixed => ("fixed", None, None, None),
                Joint::Revolute { axis } => ("revolute", Some(axis), Some(state.value), None),
                Joint::Prismatic { axis } => ("prismatic", Some(axis), Some(state.value), None),
                Joint::Spherical => {
                    let q = state.rotation;
                    ("spherical", None, None, Some([q.w, q.i, q.j, q.k]))
                }
            };
            let at_limit = match (clip.limits, value) {
                (Some((lower, upper)), Some(v)) => {
                    let tolerance = AT_LIMIT_TOLERANCE * (upper - lower).max(1.0);
                    (v - lower).abs() <= tolerance || (v - upper).abs() <= tolerance
                }
                _ => false,
            };
            let rod = &system.rods[clip.rod.0];
            let position = solution.state.rods[clip.rod.0].positions[clip.vertex];
            ClipResult {
                name: clip.name.clone(),
                rod: rod.name.clone(),
                vertex: clip.vertex,
                s_m: rod.rod.arc_lengths()[clip.vertex],
                position_m: arr(&position),
                joint: joint.to_string(),
                axis_world: axis.map(|a| {
                    arr(&(system
                        .clip_base(c, &solution.state.clips, &solution.state.bodies)
                        .orientation
                        * a))
                }),
                value,
                rotation_wxyz: rotation,
                limits: clip.limits.map(|(l, u)| [l, u]),
                at_limit,
                force_n: reaction.map_or([f64::NAN; 3], |r| arr(&r.force)),
                moment_nm: reaction.map_or([f64::NAN; 3], |r| arr(&r.moment)),
            }
        })
        .collect()
}
