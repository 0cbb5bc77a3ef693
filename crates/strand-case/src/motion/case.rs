//! The motions of a [`Case`]: looking one up and building the case at a pose.

use super::MotionPose;
use super::place::moved;
use crate::error::{CaseError, Reporter};
use crate::units::LengthUnit;
use crate::{BuiltCase, Case, build};
use strand_system::SystemState;

impl Case {
    /// The names of the case's motions, in file order.
    pub fn motion_names(&self) -> Vec<&str> {
        self.file.motions.iter().map(|(n, _)| n.as_str()).collect()
    }

    /// Motion `name`, validated; an unknown name is an error listing the defined
    /// motions.
    pub fn motion(&self, name: &str) -> Result<MotionPose, CaseError> {
        let report = Reporter {
            origin: &self.origin,
        };
        let unit = LengthUnit::parse(&self.file.units.length).ok_or_else(|| {
            report.invalid(
                "units.length",
                format!("unknown length unit \"{}\"", self.file.units.length),
                format!("use {}", LengthUnit::ACCEPTED),
            )
        })?;
        let Some((_, def)) = self.file.motions.iter().find(|(n, _)| n == name) else {
            let names = self.motion_names();
            let (message, hint) = if names.is_empty() {
                (
                    format!("no motion named '{name}': the case defines no motions"),
                    "add it under `motions: { \"name\": (unit: \"deg\", moves: [...]) }` (see cases/README.md, Motions)".to_string(),
                )
            } else {
                (
                    format!("no motion named '{name}' (defined: {})", names.join(", ")),
                    "use one of the defined motions".to_string(),
                )
            };
            return Err(report.invalid("motions", message, hint));
        };
        MotionPose::compile(&report, unit, name, def)
    }

    /// Validates the case with the parts riding on motion `name` moved to parameter
    /// `value` (the motion's unit) and builds its model, like [`Case::build`]. A value
    /// outside the motion's keyframes, or a pose the case cannot be built at (a held
    /// end out of the rod's reach), is an error naming the motion and the value.
    pub fn build_motion(
        &self,
        name: &str,
        value: f64,
        segments: Option<usize>,
    ) -> Result<BuiltCase, CaseError> {
        self.build_pose(name, value, segments, None)
    }

    /// [`Case::build_motion`] for a solve warm-started from `warm` (a state of the
    /// case's model at a neighbouring pose, e.g. the previous step of the motion): the
    /// built case's `initial` is `warm`, and no default guess is computed or checked
    /// against the environment, which makes the build much cheaper. The model is the
    /// same as [`Case::build_motion`]'s.
    pub fn build_motion_from(
        &self,
        name: &str,
        value: f64,
        segments: Option<usize>,
        warm: &SystemState,
    ) -> Result<BuiltCase, CaseError> {
        self.build_pose(name, value, segments, Some(warm))
    }

    /// The case with the parts riding on motion `name` moved to parameter `value` (the
    /// motion's unit), as one fixed pose: its file has the moved connectors, junctions,
    /// clip bases and routes, and every build of it (its variants and batches too)
    /// places the moving meshes there. Errors as for [`Case::build_motion`]; a case
    /// already at a pose cannot be moved again.
    pub fn at_pose(&self, name: &str, value: f64) -> Result<Case, CaseError> {
        if !self.placed.is_empty() {
            let report = Reporter {
                origin: &self.origin,
            };
            return Err(report.invalid(
                format!("motions '{name}'"),
                "the case is already at a motion pose".to_string(),
                "give one --motion pose",
            ));
        }
        let (file, meshes, _) = self.moved_at(name, value)?;
        Ok(Case {
            name: self.name.clone(),
            origin: self.origin.clone(),
            file,
            environment: self.environment.clone(),
            placed: meshes,
        })
    }

    /// The case file at pose `value` of motion `name`, the moved meshes and the pose's
    /// label for messages.
    fn moved_at(
        &self,
        name: &str,
        value: f64,
    ) -> Result<(crate::schema::CaseFile, super::place::MovedMeshes, String), CaseError> {
        let motion = self.motion(name)?;
        let at = format!("{name} = {value} {}", motion.unit);
        let report = Reporter {
            origin: &self.origin,
        };
        let Some(map) = motion.map_at(value) else {
            return Err(report.invalid(
                format!("motions '{name}'"),
                format!(
                    "{value} {} is outside the motion's keyframes ({}..{} {})",
                    motion.unit, motion.domain.0, motion.domain.1, motion.unit
                ),
                "choose values within the keyframes, or add keyframes that cover them",
            ));
        };
        // `self.motion` has checked the length unit.
        let unit = LengthUnit::parse(&self.file.units.length).unwrap_or(LengthUnit::Metre);
        let (file, meshes) = moved(&report, unit, &self.file, name, &map)?;
        Ok((file, meshes, at))
    }

    fn build_pose(
        &self,
        name: &str,
        value: f64,
        segments: Option<usize>,
        warm: Option<&SystemState>,
    ) -> Result<BuiltCase, CaseError> {
        let (file, meshes, at) = self.moved_at(name, value)?;
        let extras = build::BuildExtras {
            moved_meshes: &meshes,
            warm,
            clip_vertices: None,
            like: None,
        };
        self.build_file(&file, segments, extras)
            .map_err(|e| at_pose(e, &at))
    }
}

/// `error` of the case built at a pose, with the pose named.
fn at_pose(error: CaseError, at: &str) -> CaseError {
    error.within(
        &format!("at motion pose {at}"),
        "the parts cannot be placed there: shorten the motion's range or check its axis and point",
        |_| false,
    )
}
