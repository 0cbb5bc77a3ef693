//! Rod ends of a case file → [`strand_system::End`] in SI units.

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use strand_system::{End, EndLoad, Support};

use crate::error::{CaseError, Reporter};
use crate::schema::EndDef;
use crate::units::LengthUnit;

/// Why a clamp frame cannot be built from a tangent and a normal.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FrameError {
    /// The tangent has zero (or non-finite) length.
    #[error("the tangent must be a non-zero direction")]
    ZeroTangent,
    /// The normal is zero or parallel to the tangent.
    #[error("the normal must not be zero or parallel to the tangent")]
    DegenerateNormal,
}

/// The frame with `a3` along `tangent` and `a1` along `normal` orthogonalised against
/// the tangent (`a2 = a3 × a1`). Neither direction needs unit length.
pub fn frame_from_tangent_normal(
    tangent: &Vector3<f64>,
    normal: &Vector3<f64>,
) -> Result<UnitQuaternion<f64>, FrameError> {
    let length = tangent.norm();
    if !(length.is_finite() && length > 0.0) {
        return Err(FrameError::ZeroTangent);
    }
    let a3 = tangent / length;
    let in_plane = normal - a3 * a3.dot(normal);
    let scale = normal.norm();
    if !(scale.is_finite() && scale > 0.0) || in_plane.norm() <= 1e-9 * scale {
        return Err(FrameError::DegenerateNormal);
    }
    let a1 = in_plane.normalize();
    let a2 = a3.cross(&a1);
    let rotation = Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[a1, a2, a3]));
    Ok(UnitQuaternion::from_rotation_matrix(&rotation))
}

/// Converts one end; `item` is e.g. `rods[0] 'hose'.start`. The moment reference is
/// left at the identity (set later from the initial state). `nominal` is the rod's
/// nominal position and frame at this end, if it has a nominal shape (`NominalClamp`).
pub(crate) fn build_end(
    report: &Reporter,
    item: &str,
    unit: LengthUnit,
    def: &EndDef,
    nominal: Option<(Vector3<f64>, UnitQuaternion<f64>)>,
) -> Result<End, CaseError> {
    let u = format!(" {unit}");
    let (support, force, moment) = match def {
        EndDef::Clamp {
            position,
            tangent,
            normal,
            force,
            moment,
        } => {
            let position =
                report.finite3(&format!("{item}.position"), position, &u)? * unit.metres();
            let t = report.finite3(&format!("{item}.tangent"), tangent, "")?;
            let n = report.finite3(&format!("{item}.normal"), normal, "")?;
            let frame = frame_from_tangent_normal(&t, &n).map_err(|e| {
                report.invalid(
                    item,
                    e.to_string(),
                    "tangent points along the rod, normal is any direction across it (e.g. tangent (1, 0, 0), normal (0, 1, 0))",
                )
            })?;
            (Support::Clamped { position, frame }, force, moment)
        }
        EndDef::Pin {
            position,
            force,
            moment,
        } => {
            let position =
                report.finite3(&format!("{item}.position"), position, &u)? * unit.metres();
            (Support::Pinned { position }, force, moment)
        }
        EndDef::NominalClamp { force, moment } => {
            let (position, frame) = nominal.ok_or_else(|| {
                report.invalid(
                    item,
                    "NominalClamp needs the rod's `nominal` shape, and the rod has none",
                    "add `nominal: (points: [...])` to the rod, or use \
                     Clamp(position: ..., tangent: ..., normal: ...)",
                )
            })?;
            (Support::Clamped { position, frame }, force, moment)
        }
        EndDef::Free { force, moment } => (Support::Free, force, moment),
        EndDef::Connector(_) | EndDef::ConnectorPin(_) | EndDef::Port(..) | EndDef::PortPin(..) => {
            // Resolved against the case's connectors and junctions (crate::attach).
            return Err(report.invalid(
                item,
                "a connector or port end cannot be built without the case's connectors and junctions",
                "this is a bug in strand: please report it",
            ));
        }
    };
    let force = report.finite3(&format!("{item}.force"), force, " N")?;
    let moment = report.finite3(&format!("{item}.moment"), moment, " N·m")?;
    Ok(End {
        support,
        load: EndLoad {
            force,
            moment,
            moment_reference: UnitQuaternion::identity(),
        },
        twist_turns: 0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_has_requested_directors() {
        let q =
            frame_from_tangent_normal(&Vector3::new(2.0, 0.0, 0.0), &Vector3::new(0.3, 5.0, 0.0))
                .unwrap();
        assert!((q * Vector3::z() - Vector3::x()).norm() < 1e-15);
        assert!((q * Vector3::x() - Vector3::y()).norm() < 1e-15);
        assert!((q * Vector3::y() - Vector3::z()).norm() < 1e-15);
    }

    #[test]
    fn degenerate_directions_are_rejected() {
        let x = Vector3::x();
        assert_eq!(
            frame_from_tangent_normal(&Vector3::zeros(), &x),
            Err(FrameError::ZeroTangent)
        );
        assert_eq!(
            frame_from_tangent_normal(&x, &(3.0 * x)),
            Err(FrameError::DegenerateNormal)
        );
        assert_eq!(
            frame_from_tangent_normal(&x, &Vector3::zeros()),
            Err(FrameError::DegenerateNormal)
        );
    }
}
