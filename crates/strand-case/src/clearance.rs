//! Whether a segment keeps a clearance from the environment's meshes: what the
//! generated starts ([`crate::drape`], [`crate::detour`]) test their steps with.

use std::sync::Arc;

use nalgebra::{Point3, Vector3};
use strand_contact::ObstacleMesh;

/// Clearance a generated start keeps beyond a hose's radius, as a fraction of the
/// radius (a drape's steps, a detour's way, a moved junction's ports).
pub(crate) const RADIUS_SLACK: f64 = 0.05;

/// The clearance (m) a segment from `a` keeps: `clearance`, or, where `a` itself is
/// closer to a mesh, no less than `a` is.
pub(crate) fn needed_from(
    environment: &[Arc<ObstacleMesh>],
    a: &Vector3<f64>,
    clearance: f64,
) -> f64 {
    let a = Point3::from(*a);
    let here = environment
        .iter()
        .filter_map(|mesh| mesh.segment_distance(&a, &a, clearance))
        .fold(clearance, f64::min);
    clearance.min(here * (1.0 - 1e-9))
}

/// Whether segment `[a, b]` keeps at least `needed` (m) from every mesh.
pub(crate) fn clear(
    environment: &[Arc<ObstacleMesh>],
    a: &Vector3<f64>,
    b: &Vector3<f64>,
    needed: f64,
) -> bool {
    let (a, b) = (Point3::from(*a), Point3::from(*b));
    environment
        .iter()
        .all(|mesh| mesh.segment_distance(&a, &b, needed).is_none())
}
