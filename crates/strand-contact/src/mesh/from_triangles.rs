//! Building a mesh from vertices and triangles, with validation.

use nalgebra::{Point3, Vector3};
use rayon::prelude::*;

use super::topology::{Shape, analyse, shape};
use super::triangle_tree::TriangleTree;
use super::{MAX_COORDINATE_M, MeshError, ObstacleMesh};

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
        let vertices = vertices.iter().map(|p| [p.x, p.y, p.z]).collect();
        build(name, vertices, triangles.to_vec())
    }
}

/// Builds the mesh from finite vertices (m) and 0-based triangles.
pub(crate) fn build(
    name: String,
    vertices: Vec<[f64; 3]>,
    mut triangles: Vec<[u32; 3]>,
) -> Result<ObstacleMesh, MeshError> {
    let count = vertices.len();
    if let Some((k, p)) = vertices
        .iter()
        .enumerate()
        .find(|(_, p)| p.iter().any(|x| x.abs() > MAX_COORDINATE_M))
    {
        return Err(MeshError::VertexTooFar {
            mesh: name,
            vertex: k + 1,
            x: p[0],
            y: p[1],
            z: p[2],
            limit: MAX_COORDINATE_M,
        });
    }
    let in_range = |i: &u32| (*i as usize) < count;
    if !triangles.iter().flatten().all(in_range) {
        let (triangle, index) = triangles
            .iter()
            .enumerate()
            .find_map(|(t, indices)| indices.iter().find(|i| !in_range(i)).map(|&i| (t, i)))
            .expect("an index out of range");
        return Err(MeshError::IndexOutOfRange {
            mesh: name,
            triangle,
            index,
            count,
        });
    }
    // Each triangle's shape (in parallel), then the degenerate ones dropped in place
    // (the kept ones in their order, with their normals) and the bounding box grown
    // over the kept ones' corners in turn.
    let given = triangles.len();
    let (mut normals, kinds): (Vec<Vector3<f64>>, Vec<Kind>) = triangles
        .par_iter()
        .map(|indices| {
            let [a, b, c] = indices.map(|i| Point3::from(vertices[i as usize]));
            match shape(&a, &b, &c) {
                Shape::Degenerate => (Vector3::zeros(), Kind::Degenerate),
                Shape::Kept { normal, sliver } => {
                    (normal, if sliver { Kind::Sliver } else { Kind::Kept })
                }
            }
        })
        .unzip();
    let mut min = Point3::from([f64::INFINITY; 3]);
    let mut max = Point3::from([f64::NEG_INFINITY; 3]);
    let mut kinds_in_turn = kinds.iter();
    triangles.retain(|indices| {
        if *kinds_in_turn.next().expect("a kind per triangle") == Kind::Degenerate {
            return false;
        }
        for i in indices {
            let p = Point3::from(vertices[*i as usize]);
            min = min.inf(&p);
            max = max.sup(&p);
        }
        true
    });
    if triangles.len() < given {
        let mut kinds_in_turn = kinds.iter();
        normals.retain(|_| *kinds_in_turn.next().expect("a kind per triangle") != Kind::Degenerate);
    }
    let slivers = kinds.iter().filter(|&&k| k == Kind::Sliver).count();
    drop(kinds);
    let kept = triangles;
    let skipped_degenerate = given - kept.len();
    if kept.is_empty() {
        let detail = if given == 0 {
            String::new()
        } else {
            format!(" of positive area (all {given} are degenerate)")
        };
        return Err(MeshError::NoTriangles { mesh: name, detail });
    }
    // The topology analysis and the BVH are independent: one core each.
    let (topology, (order, bvh)) = rayon::join(
        || {
            analyse(
                &vertices,
                &kept,
                &normals,
                slivers,
                skipped_degenerate,
                [min, max],
            )
        },
        || TriangleTree::order_and_bvh(&vertices, &kept, [min, max]),
    );
    let tree = TriangleTree {
        vertices,
        indices: kept,
        order,
        bvh,
    };
    Ok(ObstacleMesh {
        name,
        tree: std::sync::Arc::new(tree),
        bounding_box: [min, max],
        patch: topology.patch.into(),
        node_patches: Default::default(),
        node_frames: Default::default(),
        diagnostics: topology.diagnostics,
        placement: None,
        cache_use: crate::mesh_cache::MeshCacheUse::Off,
    })
}

/// What a triangle is, for the build.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// Skipped.
    Degenerate,
    /// Kept, not a sliver.
    Kept,
    /// Kept, a sliver.
    Sliver,
}
