//! Topology of the kept triangles: welded vertices, edge use, smooth patches and the
//! [`MeshDiagnostics`].

use nalgebra::{Point3, Vector3};

use super::DEGENERATE_RELATIVE_AREA;
use super::diagnostics::{MeshDiagnostics, SLIVER_RELATIVE_AREA};
use super::edge_uses::{EdgeUses, weld};

/// Largest turn of the normal across a shared edge inside one smooth patch, rad (30°):
/// a tessellated plane or a finely faceted cylinder is one patch, the two flanks of a
/// groove (90° or sharper) or the faces of a box are separate patches.
pub const SMOOTH_PATCH_ANGLE_RAD: f64 = std::f64::consts::PI / 6.0;

/// The patch of every kept triangle (the smallest triangle index of its patch) and the
/// diagnostics.
pub(crate) struct Topology {
    /// `patch[t]`: the patch of triangle `t`, named by its smallest triangle index.
    pub patch: Vec<u32>,
    /// What the user should know.
    pub diagnostics: MeshDiagnostics,
}

/// The shape of one triangle: degenerate (skipped), or kept with its unit normal and
/// whether it is a sliver.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Shape {
    /// Zero area up to rounding (see [`DEGENERATE_RELATIVE_AREA`]).
    Degenerate,
    /// A kept triangle.
    Kept {
        /// Its unit normal (by its winding).
        normal: Vector3<f64>,
        /// Twice its area is below [`SLIVER_RELATIVE_AREA`] times its longest edge
        /// squared.
        sliver: bool,
    },
}

/// The [`Shape`] of triangle `(a, b, c)` (m).
pub(crate) fn shape(a: &Point3<f64>, b: &Point3<f64>, c: &Point3<f64>) -> Shape {
    let (ab, ac, bc) = (b - a, c - a, c - b);
    let cross = ab.cross(&ac);
    let area2 = cross.norm();
    let longest2 = ab
        .norm_squared()
        .max(ac.norm_squared())
        .max(bc.norm_squared());
    if area2.is_nan() || area2 <= DEGENERATE_RELATIVE_AREA * longest2 {
        return Shape::Degenerate;
    }
    Shape::Kept {
        normal: cross.normalize(),
        sliver: area2 < SLIVER_RELATIVE_AREA * longest2,
    }
}

/// Analyses `triangles` (kept, 0-based into `vertices`, m) whose unit normals are
/// `normals` and of which `slivers` are slivers.
pub(crate) fn analyse(
    vertices: &[[f64; 3]],
    triangles: &[[u32; 3]],
    normals: &[Vector3<f64>],
    slivers: usize,
    degenerate_skipped: usize,
    bounding_box_m: [Point3<f64>; 2],
) -> Topology {
    let (welded, distinct) = weld(vertices);
    let duplicate_vertices = vertices.len() - distinct;
    let edges = EdgeUses::new(&welded, triangles);
    drop(welded);

    let mut parent: Vec<u32> = (0..triangles.len() as u32).collect();
    let (mut boundary_edges, mut non_manifold_edges, mut misoriented_edges) = (0, 0, 0);
    let smooth = SMOOTH_PATCH_ANGLE_RAD.cos();
    for users in edges.groups() {
        match users {
            [_] => boundary_edges += 1,
            [first, second] => {
                let ((t1, f1), (t2, f2)) = (first.user(), second.user());
                // Consistent winding traverses the edge in opposite directions; compare
                // the normals as if it did.
                let sign = if f1 == f2 {
                    misoriented_edges += 1;
                    -1.0
                } else {
                    1.0
                };
                if sign * normals[t1 as usize].dot(&normals[t2 as usize]) >= smooth {
                    union(&mut parent, t1, t2);
                }
            }
            _ => non_manifold_edges += 1,
        }
    }
    drop(edges);
    // Name each patch by its smallest triangle, which is its root: a union makes the
    // smaller root the parent, so every parent is smaller than its child. In
    // increasing order, a triangle's parent already names its patch.
    let mut patches = 0;
    for t in 0..parent.len() {
        let up = parent[t] as usize;
        if up == t {
            patches += 1;
        } else {
            parent[t] = parent[up];
        }
    }
    let patch = parent;
    let closed = !triangles.is_empty()
        && boundary_edges == 0
        && non_manifold_edges == 0
        && misoriented_edges == 0;
    Topology {
        patch,
        diagnostics: MeshDiagnostics {
            triangles: triangles.len(),
            degenerate_skipped,
            slivers,
            vertices: vertices.len(),
            duplicate_vertices,
            boundary_edges,
            non_manifold_edges,
            misoriented_edges,
            closed,
            patches,
            bounding_box_m,
        },
    }
}

/// Root of `x` with path halving.
fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let up = parent[parent[x as usize] as usize];
        parent[x as usize] = up;
        x = up;
    }
    x
}

/// Joins the sets of `a` and `b`.
fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb) as usize] = ra.min(rb);
    }
}
