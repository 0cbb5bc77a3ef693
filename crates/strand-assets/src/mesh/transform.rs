//! Rigid placement and scaling of a mesh.

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};

use super::TriangleMesh;

impl TriangleMesh {
    /// Moves every vertex by the rigid motion `iso` (rotation about the origin, then
    /// translation). Orientation (outward normals) is preserved.
    pub fn transform(&mut self, iso: &Isometry3<f64>) {
        for v in &mut self.vertices {
            *v = iso * *v;
        }
    }

    /// A copy moved by the rigid motion `iso`.
    pub fn transformed(&self, iso: &Isometry3<f64>) -> Self {
        let mut out = self.clone();
        out.transform(iso);
        out
    }

    /// A copy shifted by `offset`.
    pub fn translated(&self, offset: &Vector3<f64>) -> Self {
        self.transformed(&Isometry3::from_parts(
            Translation3::from(*offset),
            UnitQuaternion::identity(),
        ))
    }

    /// A copy rotated by `angle` (rad, right-hand rule) about `axis` through the
    /// origin. A zero axis leaves the mesh unchanged.
    pub fn rotated(&self, axis: &Vector3<f64>, angle: f64) -> Self {
        match Unit::try_new(*axis, 1e-300) {
            Some(axis) => self.transformed(&Isometry3::from_parts(
                Translation3::identity(),
                UnitQuaternion::from_axis_angle(&axis, angle),
            )),
            None => self.clone(),
        }
    }

    /// A copy with every coordinate multiplied by `factor` (e.g. 1000 for m → mm).
    /// A negative factor would turn the mesh inside out and is the caller's choice.
    pub fn scaled(&self, factor: f64) -> Self {
        let mut out = self.clone();
        for v in &mut out.vertices {
            v.coords *= factor;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Point3, Vector3};

    use crate::axis_box;

    #[test]
    fn rotation_and_translation_keep_volume_and_move_the_centre() {
        let b = axis_box(Point3::new(-1.0, -0.5, -0.25), Point3::new(1.0, 0.5, 0.25));
        let moved = b
            .rotated(&Vector3::new(0.0, 0.0, 1.0), std::f64::consts::FRAC_PI_2)
            .translated(&Vector3::new(3.0, 0.0, 0.0));
        assert!((moved.signed_volume() - b.signed_volume()).abs() < 1e-12);
        let (lo, hi) = moved.aabb().unwrap();
        // A quarter turn about z swaps the x and y extents.
        assert!((lo - Point3::new(2.5, -1.0, -0.25)).norm() < 1e-12);
        assert!((hi - Point3::new(3.5, 1.0, 0.25)).norm() < 1e-12);
        let scaled = b.scaled(1000.0);
        assert!((scaled.signed_volume() - 1e9 * b.signed_volume()).abs() < 1e-3);
    }
}
