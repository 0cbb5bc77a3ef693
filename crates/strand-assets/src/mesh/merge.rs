//! Concatenation of meshes.

use super::TriangleMesh;

impl TriangleMesh {
    /// Appends `other`'s vertices and triangles (indices shifted).
    ///
    /// # Panics
    /// If the result would hold more than `u32::MAX` vertices.
    pub fn append(&mut self, other: &TriangleMesh) {
        let offset = u32::try_from(self.vertices.len()).expect("more than u32::MAX vertices");
        u32::try_from(self.vertices.len() + other.vertices.len())
            .expect("more than u32::MAX vertices");
        self.vertices.extend_from_slice(&other.vertices);
        self.triangles.extend(
            other
                .triangles
                .iter()
                .map(|t| [t[0] + offset, t[1] + offset, t[2] + offset]),
        );
    }
}

/// One mesh holding all of `meshes` (vertices are not welded: each part keeps its own).
pub fn merge(meshes: &[TriangleMesh]) -> TriangleMesh {
    let mut out = TriangleMesh {
        vertices: Vec::with_capacity(meshes.iter().map(|m| m.vertices.len()).sum()),
        triangles: Vec::with_capacity(meshes.iter().map(|m| m.triangles.len()).sum()),
    };
    for m in meshes {
        out.append(m);
    }
    out
}

#[cfg(test)]
mod tests {
    use nalgebra::{Point3, Vector3};

    use super::merge;
    use crate::{axis_box, cylinder};

    #[test]
    fn merged_closed_parts_stay_closed_and_volumes_add() {
        let a = axis_box(Point3::origin(), Point3::new(1.0, 1.0, 1.0));
        let c = cylinder(0.2, 1.0, 24, true).translated(&Vector3::new(5.0, 0.0, 0.0));
        let m = merge(&[a.clone(), c.clone()]);
        assert_eq!(m.vertices.len(), a.vertices.len() + c.vertices.len());
        assert_eq!(m.triangles.len(), a.triangles.len() + c.triangles.len());
        assert!(m.edge_report().is_closed_and_oriented());
        let expected = a.signed_volume() + c.signed_volume();
        assert!((m.signed_volume() - expected).abs() < 1e-12);
    }
}
