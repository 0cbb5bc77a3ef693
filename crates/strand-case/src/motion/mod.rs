//! Motions: named rigid motions of groups of parts as functions of one parameter, for
//! checking a hose between a part that moves and one that does not (an engine rolling
//! on its mounts, a door on its hinge) over the whole motion.
//!
//! ```ron
//! motions: {
//!     // The engine rolls about the fore–aft axis through its mount line.
//!     "engine_roll": (unit: "deg", moves: [Rotate(axis: (1, 0, 0), point: (0, 180, -60))]),
//!     // Roll and a fore–aft shift of 0.5 mm per degree, driven together.
//!     "roll_shift": (unit: "deg", moves: [
//!         Rotate(axis: (1, 0, 0), point: (0, 180, -60)),
//!         Translate(direction: (1, 0, 0), per: 0.5),
//!     ]),
//!     // Keyframe poses (translation in the case's unit, rotation about `center`),
//!     // interpolated on SE(3) by screw motion.
//!     "lift": (unit: "mm", moves: [Keyframes(center: (0, 0, 0), frames: [
//!         (at: 0, translation: (0, 0, 0)),
//!         (at: 20, translation: (0, 0, 20), rotation: (axis: (1, 0, 0), angle_deg: 5)),
//!     ])]),
//! },
//! connectors: {
//!     "engine_stub": (position: (80, 265, 60), direction: (0, 0, -1), normal: (1, 0, 0),
//!                     moves_with: "engine_roll"),
//! },
//! ```
//!
//! Parts that ride on a motion (`moves_with`): connectors, fixed junctions, clip bases
//! held in the world, environment meshes. They are where the file writes them at the
//! parameter value 0, and at value `p` the motion's rigid map `x ↦ R x + t` (case's
//! length unit) is applied to their positions and axes.
//!
//! The parameter's `unit` is `"deg"` or a length unit (`"mm"`, `"m"`). Moves:
//! - `Rotate(axis, point, per)`: the rotation by `per · p` degrees about `axis` through
//!   `point` (default `per: 1`, degrees per parameter unit);
//! - `Translate(direction, per)`: the shift by `per · p` case length units along
//!   `direction` (default `per`: 1 for a parameter in degrees, else the parameter's
//!   length unit in case units);
//! - `Keyframes(center, frames)`: poses at parameter values `at` (increasing, at
//!   least two, covering 0), each a rotation about `center` (default origin) followed
//!   by a `translation`, screw-interpolated between neighbouring frames
//!   ([`screw::interpolate`]); the part's written pose is the pose at 0, and a value
//!   outside the frames is an error.
//!
//! Several moves are driven together by the one parameter, in order: the motion's
//! map is `M_n(p) ∘ … ∘ M_1(p)`.

pub mod carry;
mod case;
mod follow;
mod place;
mod pose;
mod range;
pub mod screw;
pub mod tangent;

use serde::{Deserialize, Serialize};

use crate::environment::AxisAngleDef;
use crate::schema::Vec3;

pub use follow::{
    FollowEnd, FollowSettings, MotionEvent, MotionStep, PhaseTimes, Predictor, StepOutcome, follow,
    jump_m,
};
pub use pose::MotionPose;
pub use range::{MotionRange, RangeError, parse_value};

/// Checks every motion of `file` and every part's `moves_with`.
pub(crate) fn check(
    report: &crate::error::Reporter,
    unit: crate::units::LengthUnit,
    file: &crate::schema::CaseFile,
) -> Result<(), crate::error::CaseError> {
    place::motions(report, unit, file)?;
    place::check_parts(report, file)
}

/// A named motion: its parameter's unit and the moves it drives.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionDef {
    /// Unit of the parameter: `"deg"`, `"mm"` or `"m"`.
    pub unit: String,
    /// The moves driven together by the parameter, applied in order (at least one).
    pub moves: Vec<MoveDef>,
}

/// One rigid move of a [`MotionDef`] as a function of its parameter `p`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum MoveDef {
    /// Rotation by `per · p` degrees (right-hand rule) about `axis` through `point`.
    Rotate {
        /// Rotation axis (any non-zero length).
        axis: Vec3,
        /// A point on the axis, in the case's length unit.
        point: Vec3,
        /// Degrees per parameter unit (default 1).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        per: Option<f64>,
    },
    /// Translation by `per · p` case length units along `direction`.
    Translate {
        /// Direction (any non-zero length).
        direction: Vec3,
        /// Case length units per parameter unit (default: 1 for a parameter in
        /// degrees, the parameter's length unit in case units otherwise).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        per: Option<f64>,
    },
    /// Keyframe poses, screw-interpolated on SE(3).
    Keyframes {
        /// Centre of the keyframes' rotations, in the case's length unit (default the
        /// origin).
        #[serde(default)]
        center: Vec3,
        /// The keyframes, in increasing `at` (at least two; the first `at ≤ 0 ≤` the
        /// last `at`).
        frames: Vec<KeyframeDef>,
    },
}

/// A keyframe: at parameter `at`, the rotation about the move's `center`, then the
/// `translation`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyframeDef {
    /// Parameter value, in the motion's unit.
    pub at: f64,
    /// Translation in the case's length unit (default none).
    #[serde(default)]
    pub translation: Vec3,
    /// Rotation about the move's `center` (default none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<AxisAngleDef>,
}
