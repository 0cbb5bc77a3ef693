//! Which environment meshes can be near a region of space: a BVH over the meshes'
//! bounding boxes, so that each rod asks only the meshes around it. Without it every
//! vertex and edge of every rod is tested against every mesh, which is quadratic in a
//! scene that grows by whole bays (rods and their meshes together).

use parry3d_f64::bounding_volume::Aabb as ParryAabb;
use parry3d_f64::math::Vector as GlamVector;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};

use super::Aabb;
use crate::ObstacleMesh;

/// A bounding-volume hierarchy over the world bounding boxes of a list of meshes.
#[derive(Clone)]
pub struct MeshIndex {
    bvh: Bvh,
    count: usize,
}

impl MeshIndex {
    /// Indexes `meshes` by their world bounding boxes ([`ObstacleMesh::bounding_box`]):
    /// `O(meshes · log meshes)`.
    pub fn new<M: AsRef<ObstacleMesh>>(meshes: &[M]) -> Self {
        let leaves: Vec<ParryAabb> = meshes
            .iter()
            .map(|mesh| {
                let [min, max] = mesh.as_ref().bounding_box();
                ParryAabb::new(glam(&min), glam(&max))
            })
            .collect();
        let bvh = if leaves.is_empty() {
            Bvh::new()
        } else {
            Bvh::from_leaves(BvhBuildStrategy::Binned, &leaves)
        };
        Self {
            bvh,
            count: meshes.len(),
        }
    }

    /// The number of meshes indexed.
    pub fn len(&self) -> usize {
        self.count
    }

    /// Whether no mesh is indexed.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The indices (ascending) of the meshes whose bounding box overlaps `region`
    /// (touching counts): `O(log meshes + found)`. A mesh left out has no point within
    /// `region`, so a query that reaches no farther than `region` cannot find it.
    pub fn overlapping(&self, region: &Aabb) -> Vec<usize> {
        if self.count == 0 {
            return Vec::new();
        }
        let query = ParryAabb::new(glam(&region.min), glam(&region.max));
        let mut found: Vec<usize> = self
            .bvh
            .intersect_aabb(&query)
            .map(|leaf| leaf as usize)
            .collect();
        found.sort_unstable();
        found
    }
}

/// A point as parry's vector type.
fn glam(p: &nalgebra::Point3<f64>) -> GlamVector {
    GlamVector::new(p.x, p.y, p.z)
}

impl Aabb {
    /// The box of `points` grown by `inflation` (m) on every side, or `None` for no
    /// points.
    pub fn of_points<'a>(
        points: impl IntoIterator<Item = &'a nalgebra::Point3<f64>>,
        inflation: f64,
    ) -> Option<Self> {
        let mut points = points.into_iter();
        let first = points.next()?;
        let (min, max) = points.fold((*first, *first), |(min, max), p| (min.inf(p), max.sup(p)));
        let grow = nalgebra::Vector3::repeat(inflation);
        Some(Self {
            min: min - grow,
            max: max + grow,
        })
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Point3;

    use super::{Aabb, MeshIndex};
    use crate::ObstacleMesh;

    /// A unit square (two triangles) in the plane z = 0 with its corner at `(x, 0, 0)`.
    fn square(x: f64) -> ObstacleMesh {
        let vertices = vec![
            Point3::new(x, 0.0, 0.0),
            Point3::new(x + 1.0, 0.0, 0.0),
            Point3::new(x + 1.0, 1.0, 0.0),
            Point3::new(x, 1.0, 0.0),
        ];
        ObstacleMesh::try_from_triangles("square", vertices, &[[0, 1, 2], [0, 2, 3]]).unwrap()
    }

    #[test]
    fn a_region_finds_exactly_the_meshes_whose_boxes_it_overlaps() {
        // Squares at x = 0, 2, 4, …, 38: brute force against every box.
        let meshes: Vec<ObstacleMesh> = (0..20).map(|k| square(2.0 * k as f64)).collect();
        let index = MeshIndex::new(&meshes);
        assert_eq!(index.len(), 20);
        for (from, to, z) in [
            (0.5, 0.6, 0.0),
            (1.0, 2.0, 0.1),
            (1.1, 1.9, 0.0),
            (-3.0, 50.0, -0.1),
        ] {
            let region = Aabb {
                min: Point3::new(from, 0.2, z),
                max: Point3::new(to, 0.3, z + 0.05),
            };
            let brute: Vec<usize> = meshes
                .iter()
                .enumerate()
                .filter(|(_, m)| {
                    let [min, max] = m.bounding_box();
                    region.overlaps(&Aabb { min, max })
                })
                .map(|(k, _)| k)
                .collect();
            assert_eq!(index.overlapping(&region), brute, "{from}..{to} at z {z}");
        }
        assert!(
            MeshIndex::new::<ObstacleMesh>(&[])
                .overlapping(&Aabb {
                    min: Point3::origin(),
                    max: Point3::new(1.0, 1.0, 1.0)
                })
                .is_empty()
        );
    }
}
