//! The `direction` items (`connectors.<c>.direction`, `junctions.<j>.ports.<p>.
//! direction`, `clips.<c>.base.direction`): a change `Add((rx, ry, rz))` turns the
//! written frame (its `direction` and `normal` together) by the rotation vector
//! `(rx, ry, rz)` in degrees — by `|r|` degrees about the axis `r / |r|`, right-handed,
//! in the axes the frame is written in — so `Add((0, 0, 15))` turns a nozzle by 15°
//! about z. One component alone is a turn about that axis.

use nalgebra::{Rotation3, Vector3};

use crate::error::{CaseError, Reporter};
use crate::schema::{Amount, Change, Vec3};

/// The rotation of a `direction` change; a `Set` or a number is an error naming the
/// item and the fix.
pub(crate) fn rotation(
    report: &Reporter,
    at: &str,
    item: &str,
    change: &Change,
) -> Result<Rotation3<f64>, CaseError> {
    match change {
        Change::Add(Amount::Vector(r)) => {
            let radians = Vector3::from(*r) * std::f64::consts::PI / 180.0;
            Ok(Rotation3::new(radians))
        }
        Change::Add(Amount::Number(_)) => Err(report.invalid(
            at,
            format!("{item} takes a rotation vector (x, y, z) in degrees, not a number"),
            format!("write e.g. `(item: \"{item}\", change: Add((0, 0, 15)))` to turn it by 15° about z"),
        )),
        Change::Set(_) => Err(report.invalid(
            at,
            format!("{item} can only be turned (Add a rotation vector in degrees), not Set"),
            format!(
                "write e.g. `(item: \"{item}\", change: Add((0, 0, 15)))`, or change `direction` and `normal` in the case itself"
            ),
        )),
    }
}

/// Turns the frame written as `direction` and `normal` by `turn`.
pub(crate) fn frame(turn: &Rotation3<f64>, direction: &mut Vec3, normal: &mut Vec3) {
    let apply = |v: &mut Vec3| {
        let w = turn * Vector3::from(*v);
        *v = [w.x, w.y, w.z];
    };
    apply(direction);
    apply(normal);
}
