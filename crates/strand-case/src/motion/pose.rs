//! A motion compiled from its definition: the rigid map of its parts at a parameter
//! value.

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};

use super::{MotionDef, MoveDef, screw};
use crate::error::{CaseError, Reporter};
use crate::units::LengthUnit;

/// A validated motion: the rigid map of the parts riding on it as a function of its
/// parameter, in the case's length unit.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionPose {
    /// The motion's name.
    pub name: String,
    /// The parameter's unit (`"deg"`, `"mm"` or `"m"`).
    pub unit: String,
    /// The smallest and largest parameter values the motion is defined for (infinite
    /// without keyframes).
    pub domain: (f64, f64),
    moves: Vec<Move>,
}

#[derive(Clone, Debug, PartialEq)]
enum Move {
    /// Rotation by `per · p` degrees about `axis` through `point`.
    Rotate {
        axis: Unit<Vector3<f64>>,
        point: Vector3<f64>,
        per: f64,
    },
    /// Translation by `p · step` (case units).
    Translate { step: Vector3<f64> },
    /// Keyframes `(at, pose)`, increasing in `at`.
    Keyframes { frames: Vec<(f64, Isometry3<f64>)> },
}

/// The parameter units a motion accepts.
pub(crate) const MOTION_UNITS: &str = "\"deg\", \"mm\" or \"m\"";

fn nonzero(report: &Reporter, item: &str, v: &[f64; 3]) -> Result<Unit<Vector3<f64>>, CaseError> {
    let v = report.finite3(item, v, "")?;
    Unit::try_new(v, 0.0).ok_or_else(|| {
        report.invalid(
            item,
            "the direction is zero",
            "give a non-zero vector, e.g. (1, 0, 0)",
        )
    })
}

impl MotionPose {
    /// Validates motion `name` of a case written in `case_unit`.
    pub(crate) fn compile(
        report: &Reporter,
        case_unit: LengthUnit,
        name: &str,
        def: &MotionDef,
    ) -> Result<Self, CaseError> {
        let item = format!("motions '{name}'");
        let length_unit = LengthUnit::parse(&def.unit);
        if def.unit != "deg" && length_unit.is_none() {
            return Err(report.invalid(
                format!("{item}.unit"),
                format!("unknown parameter unit \"{}\"", def.unit),
                format!("use {MOTION_UNITS}"),
            ));
        }
        if def.moves.is_empty() {
            return Err(report.invalid(
                format!("{item}.moves"),
                "the motion has no moves",
                "add e.g. Rotate(axis: (1, 0, 0), point: (0, 0, 0))",
            ));
        }
        let mut domain = (f64::NEG_INFINITY, f64::INFINITY);
        let mut moves = Vec::with_capacity(def.moves.len());
        for (i, m) in def.moves.iter().enumerate() {
            let at = format!("{item}.moves[{i}]");
            moves.push(match m {
                MoveDef::Rotate { axis, point, per } => Move::Rotate {
                    axis: nonzero(report, &format!("{at}.axis"), axis)?,
                    point: report.finite3(&format!("{at}.point"), point, "")?,
                    per: report.finite(&format!("{at}.per"), per.unwrap_or(1.0), "")?,
                },
                MoveDef::Translate { direction, per } => {
                    let default = length_unit.map_or(1.0, |u| u.metres() / case_unit.metres());
                    let per = report.finite(&format!("{at}.per"), per.unwrap_or(default), "")?;
                    Move::Translate {
                        step: nonzero(report, &format!("{at}.direction"), direction)?.into_inner()
                            * per,
                    }
                }
                MoveDef::Keyframes { center, frames } => {
                    let center = report.finite3(&format!("{at}.center"), center, "")?;
                    let frames = keyframes(report, &at, &center, frames)?;
                    domain.0 = domain.0.max(frames[0].0);
                    domain.1 = domain.1.min(frames[frames.len() - 1].0);
                    Move::Keyframes { frames }
                }
            });
        }
        Ok(Self {
            name: name.to_string(),
            unit: def.unit.clone(),
            domain,
            moves,
        })
    }

    /// Whether the motion is defined at parameter `p`.
    pub fn contains(&self, p: f64) -> bool {
        p.is_finite() && self.domain.0 <= p && p <= self.domain.1
    }

    /// The rigid map `x ↦ R x + t` (case's length unit) that carries the parts riding
    /// on the motion from where the file writes them (parameter 0) to where they are
    /// at parameter `p`; `None` outside [`MotionPose::domain`].
    pub fn map_at(&self, p: f64) -> Option<Isometry3<f64>> {
        if !self.contains(p) {
            return None;
        }
        let mut map = Isometry3::identity();
        for m in &self.moves {
            let step = match m {
                Move::Rotate { axis, point, per } => {
                    let r = UnitQuaternion::from_axis_angle(axis, (per * p).to_radians());
                    Isometry3::from_parts(Translation3::from(point - r * point), r)
                }
                Move::Translate { step } => {
                    Isometry3::translation(step.x * p, step.y * p, step.z * p)
                }
                Move::Keyframes { frames } => {
                    keyframe_at(frames, p) * keyframe_at(frames, 0.0).inverse()
                }
            };
            map = step * map;
        }
        Some(map)
    }
}

/// The keyframes of a move as poses, checked.
fn keyframes(
    report: &Reporter,
    at: &str,
    center: &Vector3<f64>,
    frames: &[super::KeyframeDef],
) -> Result<Vec<(f64, Isometry3<f64>)>, CaseError> {
    if frames.len() < 2 {
        return Err(report.invalid(
            format!("{at}.frames"),
            format!(
                "{} keyframe(s): a keyframe motion needs at least two",
                frames.len()
            ),
            "add a keyframe for each end of the motion, e.g. (at: 0) and (at: 90, rotation: ...)",
        ));
    }
    let mut out: Vec<(f64, Isometry3<f64>)> = Vec::with_capacity(frames.len());
    for (k, f) in frames.iter().enumerate() {
        let item = format!("{at}.frames[{k}]");
        let p = report.finite(&format!("{item}.at"), f.at, "")?;
        if let Some((last, _)) = out.last()
            && p <= *last
        {
            return Err(report.invalid(
                format!("{item}.at"),
                format!("at {p} does not follow the previous keyframe's {last}"),
                "list keyframes in strictly increasing `at`",
            ));
        }
        let t = report.finite3(&format!("{item}.translation"), &f.translation, "")?;
        let r = match &f.rotation {
            None => UnitQuaternion::identity(),
            Some(def) => {
                let axis = nonzero(report, &format!("{item}.rotation.axis"), &def.axis)?;
                let deg =
                    report.finite(&format!("{item}.rotation.angle_deg"), def.angle_deg, "°")?;
                UnitQuaternion::from_axis_angle(&axis, deg.to_radians())
            }
        };
        out.push((
            p,
            Isometry3::from_parts(Translation3::from(center - r * center + t), r),
        ));
    }
    let (first, last) = (out[0].0, out[out.len() - 1].0);
    if !(first <= 0.0 && 0.0 <= last) {
        return Err(report.invalid(
            format!("{at}.frames"),
            format!("the keyframes cover {first}..{last}, not the parameter value 0 where the parts are as written"),
            "add a keyframe at 0 (the pose the case file describes)",
        ));
    }
    Ok(out)
}

/// The screw interpolation of the keyframes at `p` (within their range).
fn keyframe_at(frames: &[(f64, Isometry3<f64>)], p: f64) -> Isometry3<f64> {
    let k = frames
        .partition_point(|(at, _)| *at <= p)
        .clamp(1, frames.len() - 1);
    let ((a, pa), (b, pb)) = (&frames[k - 1], &frames[k]);
    screw::interpolate(pa, pb, (p - a) / (b - a))
}
