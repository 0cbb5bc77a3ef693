//! A mesh moved rigidly without rebuilding it: the triangles and the BVH stay in the
//! mesh's own frame, and each query is moved into that frame and its answer back.
//!
//! A part riding on a motion (an engine rolling on its mounts) is the same mesh at
//! every pose; rebuilding its BVH per pose costs `O(n log n)` for `n` triangles,
//! placing it costs one pass over its vertices (for the world bounding box).

use nalgebra::{Isometry3, Point3};

use super::ObstacleMesh;
use super::segment_proximity::Proximity;

impl ObstacleMesh {
    /// The mesh moved rigidly by `pose` (world coordinates, m: a world point `x` of
    /// this mesh becomes `pose · x`), sharing this mesh's triangles and BVH. Queries
    /// of the placed mesh agree with those of a mesh built from the moved triangles
    /// up to rounding of the coordinates.
    ///
    /// ```
    /// use nalgebra::{Isometry3, Point3, Vector3};
    /// use strand_contact::ObstacleMesh;
    /// let floor = ObstacleMesh::try_from_triangles(
    ///     "floor",
    ///     vec![Point3::new(-1.0, -1.0, 0.0), Point3::new(1.0, -1.0, 0.0), Point3::new(0.0, 1.0, 0.0)],
    ///     &[[0, 1, 2]],
    /// ).unwrap();
    /// // Lifted by 0.1 m and turned upside down about x.
    /// let pose = Isometry3::new(Vector3::new(0.0, 0.0, 0.1), Vector3::new(std::f64::consts::PI, 0.0, 0.0));
    /// let lifted = floor.placed(&pose);
    /// let near = lifted.point_proximity(&Point3::new(0.0, 0.0, 0.5), 1.0).unwrap();
    /// assert!((near.distance - 0.4).abs() < 1e-12);
    /// assert!((lifted.bounding_box()[0].z - 0.1).abs() < 1e-12);
    /// ```
    pub fn placed(&self, pose: &Isometry3<f64>) -> ObstacleMesh {
        let placement = match &self.placement {
            Some(own) => pose * own,
            None => *pose,
        };
        let mut min = Point3::from([f64::INFINITY; 3]);
        let mut max = Point3::from([f64::NEG_INFINITY; 3]);
        let vertices = &self.tree.vertices;
        for indices in &self.tree.indices {
            for &i in indices {
                let p = placement * Point3::from(vertices[i as usize]);
                min = min.inf(&p);
                max = max.sup(&p);
            }
        }
        let mut placed = self.clone();
        placed.placement = Some(placement);
        placed.diagnostics.bounding_box_m = [min, max];
        placed
    }

    /// The map from the mesh's own frame (where its triangles are stored) to the
    /// world; `None` for a mesh built where it is.
    pub fn placement(&self) -> Option<&Isometry3<f64>> {
        self.placement.as_ref()
    }

    /// A world point in the mesh's own frame.
    pub(crate) fn to_local(&self, point: &Point3<f64>) -> Point3<f64> {
        match &self.placement {
            None => *point,
            Some(pose) => pose.inverse_transform_point(point),
        }
    }

    /// A proximity found in the mesh's own frame for the world segment `[p0, p1]`,
    /// in world coordinates: the segment point from the world segment itself, the mesh
    /// point and the normal moved.
    pub(crate) fn to_world(
        &self,
        mut found: Proximity,
        p0: &Point3<f64>,
        p1: &Point3<f64>,
    ) -> Proximity {
        if let Some(pose) = &self.placement {
            found.point_on_segment = p0 + (p1 - p0) * found.s;
            found.point_on_mesh = pose * found.point_on_mesh;
            found.normal = found.normal.map(|n| pose.rotation * n);
        }
        found
    }
}
