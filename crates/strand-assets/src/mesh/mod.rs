//! The triangle mesh and its operations (one file per operation).

pub(crate) mod distance;
pub(crate) mod edges;
pub(crate) mod measure;
pub(crate) mod merge;
pub(crate) mod transform;

use nalgebra::Point3;

/// A triangle soup with shared vertices: positions in m (or whatever unit the caller
/// uses consistently) and triangles as vertex indices, counter-clockwise seen from
/// outside (the right-hand normal `(b − a) × (c − a)` points out of a closed solid).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub vertices: Vec<Point3<f64>>,
    /// Triangles as indices into [`TriangleMesh::vertices`].
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// An empty mesh.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends a vertex and returns its index.
    ///
    /// # Panics
    /// If the mesh already holds `u32::MAX` vertices.
    pub fn push_vertex(&mut self, p: Point3<f64>) -> u32 {
        let index = u32::try_from(self.vertices.len()).expect("more than u32::MAX vertices");
        self.vertices.push(p);
        index
    }

    /// Appends the triangle `(a, b, c)` (counter-clockwise seen from outside).
    pub fn push_triangle(&mut self, a: u32, b: u32, c: u32) {
        self.triangles.push([a, b, c]);
    }

    /// Appends the quad `a b c d` (counter-clockwise seen from outside) as two
    /// triangles `(a, b, c)` and `(a, c, d)`.
    pub fn push_quad(&mut self, a: u32, b: u32, c: u32, d: u32) {
        self.triangles.push([a, b, c]);
        self.triangles.push([a, c, d]);
    }

    /// The three corners of triangle `t`.
    pub fn triangle_points(&self, t: usize) -> [Point3<f64>; 3] {
        let [a, b, c] = self.triangles[t];
        [
            self.vertices[a as usize],
            self.vertices[b as usize],
            self.vertices[c as usize],
        ]
    }
}
