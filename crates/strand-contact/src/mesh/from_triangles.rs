//! Building a mesh from vertices and triangles, with validation.

use nalgebra::Point3;

use super::topology::analyse;
use super::triangle_tree::TriangleTree;
use super::{MeshError, ObstacleMesh};

/// A triangle counts as degenerate (and is skipped) when twice its area is at most
/// this fraction of its longest edge squared, i.e. it is flat to rounding.
pub const DEGENERATE_RELATIVE_AREA: f64 = 1e-12;

impl ObstacleMesh {
    /// Builds a mesh from vertices (m, world frame) and 0-based triangles.
    ///
    /// Checks that every vertex is finite and every index in range; degenerate
    /// (zero-area, see [`DEGENERATE_RELATIVE_AREA`]) triangles are skipped and counted
    /// ([`ObstacleMesh::skipped_degenerate`]); at least one triangle must remain.
    /// Open and non-manifold meshes are accepted; [`ObstacleMesh::diagnostics`] says
    /// what was found.
    pub fn try_from_triangles(
        name: impl Into<String>,
        vertices: Vec<Point3<f64>>,
        triangles: &[[u32; 3]],
    ) -> Result<Self, MeshError> {
        let name = name.into();
        if let Some((k, p)) = vertices
            .iter()
            .enumerate()
            .find(|(_, p)| !p.iter().all(|x| x.is_finite()))
        {
            return Err(MeshError::NonFiniteVertex {
                mesh: name,
                vertex: k + 1,
                at: String::new(),
                x: p.x,
                y: p.y,
                z: p.z,
            });
        }
        build(name, vertices, triangles)
    }
}

/// Builds the mesh from finite vertices.
pub(crate) fn build(
    name: String,
    vertices: Vec<Point3<f64>>,
    triangles: &[[u32; 3]],
) -> Result<ObstacleMesh, MeshError> {
    let count = vertices.len();
    let mut kept = Vec::with_capacity(triangles.len());
    let mut min = Point3::from([f64::INFINITY; 3]);
    let mut max = Point3::from([f64::NEG_INFINITY; 3]);
    for (triangle, indices) in triangles.iter().enumerate() {
        if let Some(&index) = indices.iter().find(|&&i| i as usize >= count) {
            return Err(MeshError::IndexOutOfRange {
                mesh: name,
                triangle,
                index,
                count,
            });
        }
        let [a, b, c] = indices.map(|i| vertices[i as usize]);
        if is_degenerate(&a, &b, &c) {
            continue;
        }
        for p in [a, b, c] {
            min = min.inf(&p);
            max = max.sup(&p);
        }
        kept.push(*indices);
    }
    let skipped_degenerate = triangles.len() - kept.len();
    if kept.is_empty() {
        let detail = if triangles.is_empty() {
            String::new()
        } else {
            format!(" of positive area (all {} are degenerate)", triangles.len())
        };
        return Err(MeshError::NoTriangles { mesh: name, detail });
    }
    // The topology analysis and the BVH are independent: one core each.
    let (topology, tree) = rayon::join(
        || analyse(&vertices, &kept, skipped_degenerate, [min, max]),
        || {
            let raw = vertices.iter().map(|p| [p.x, p.y, p.z]).collect();
            TriangleTree::build(raw, kept.clone(), [min, max])
        },
    );
    Ok(ObstacleMesh {
        name,
        tree: std::sync::Arc::new(tree),
        bounding_box: [min, max],
        patch: topology.patch.into(),
        node_patches: Default::default(),
        diagnostics: topology.diagnostics,
        placement: None,
        cache_use: crate::mesh_cache::MeshCacheUse::Off,
    })
}

/// Whether triangle `(a, b, c)` has zero area up to rounding.
fn is_degenerate(a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>) -> bool {
    let (ab, ac, bc) = (b - a, c - a, c - b);
    let longest2 = ab
        .norm_squared()
        .max(ac.norm_squared())
        .max(bc.norm_squared());
    let area2 = ab.cross(&ac).norm();
    area2.is_nan() || area2 <= DEGENERATE_RELATIVE_AREA * longest2
}
