//! Carrying a hose along with a moving mesh that pushes it: the parts of the last
//! equilibrium near a mesh riding on the motion are moved rigidly with the mesh (fading
//! out with the distance from it), so that the next pose's solve does not start inside
//! the moved mesh.
//!
//! A mesh that moves onto a hose (an engine rolling into a hose resting on it) leaves
//! the last state inside the moved mesh, and a solve refuses to start there. The hose
//! near the mesh is instead taken along: vertices within `radius + D` of the mesh at the
//! last pose (the tube's outer radius, and `D` the largest displacement of the mesh's
//! bounding box between the poses) move with it, those beyond twice that distance
//! stay, and the weight falls linearly in between; edge frames turn by the same
//! weight of the mesh's rotation. The solve then settles the hose against the moved
//! mesh.

use nalgebra::{Isometry3, Point3, UnitQuaternion};
use strand_contact::ObstacleMesh;
use strand_rod::RodState;
use strand_system::SystemState;

use crate::units::LengthUnit;
use crate::{BuiltCase, Case};

/// The rigid map (world, m) from pose `from` to pose `to` of `motion`.
fn map_between(case: &Case, motion: &str, from: f64, to: f64) -> Option<Isometry3<f64>> {
    let pose = case.motion(motion).ok()?;
    let map = pose.map_at(to)? * pose.map_at(from)?.inverse();
    let metres = LengthUnit::parse(&case.file.units.length)?.metres();
    Some(Isometry3::from_parts(
        (map.translation.vector * metres).into(),
        map.rotation,
    ))
}

/// Largest displacement under `map` of a point of the box `[min, max]` (a rigid
/// motion's displacement is convex in the point, so a corner attains it), m.
fn largest_displacement(map: &Isometry3<f64>, [min, max]: [Point3<f64>; 2]) -> f64 {
    (0..8)
        .map(|i| {
            let corner = Point3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            );
            (map * corner - corner).norm()
        })
        .fold(0.0, f64::max)
}

/// `state`, an equilibrium at pose `from`, with the hose parts near the meshes riding
/// on `motion` carried with them to pose `to` (`built` is the case at `to`); `None`
/// when no vertex is near a moving mesh (nothing to carry).
pub fn carry(
    case: &Case,
    motion: &str,
    built: &BuiltCase,
    state: &SystemState,
    from: f64,
    to: f64,
) -> Option<SystemState> {
    let map = map_between(case, motion, from, to)?;
    let back = map.inverse();
    let moving: Vec<ObstacleMesh> = case
        .file
        .environment
        .iter()
        .filter(|e| e.moves_with.as_deref() == Some(motion))
        .filter_map(|e| built.environment.iter().find(|m| m.name() == e.name))
        .map(|m| m.placed(&back))
        .collect();
    let mut carried = false;
    let mut out = state.clone();
    for (r, rod) in out.rods.iter_mut().enumerate() {
        let radius = built.model.system().rods[r].rod.section().outer_radius;
        let weights: Vec<f64> = rod
            .positions
            .iter()
            .map(|p| {
                let p = Point3::from(*p);
                moving
                    .iter()
                    .map(|mesh| {
                        let near = radius + largest_displacement(&map, mesh.bounding_box());
                        mesh.point_proximity(&p, 2.0 * near).map_or(0.0, |found| {
                            ((2.0 * near - found.distance) / near).clamp(0.0, 1.0)
                        })
                    })
                    .fold(0.0, f64::max)
            })
            .collect();
        if weights.iter().all(|w| *w == 0.0) {
            continue;
        }
        carried = true;
        let positions = rod
            .positions
            .iter()
            .zip(&weights)
            .map(|(p, w)| p + (map * Point3::from(*p) - Point3::from(*p)) * *w)
            .collect();
        let frames = rod
            .frames
            .iter()
            .enumerate()
            .map(|(e, q)| {
                let w = 0.5 * (weights[e] + weights[e + 1]);
                UnitQuaternion::identity().slerp(&map.rotation, w) * q
            })
            .collect();
        *rod = RodState::new(positions, frames);
    }
    carried.then_some(out)
}
