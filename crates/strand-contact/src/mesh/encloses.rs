//! Inside a closed part: the winding number of a closed mesh about a point, by signed
//! ray crossings.
//!
//! A ray from the point crosses the surface of a closed, consistently wound mesh a net
//! number of times equal to the winding number about the point (±1 inside one shell,
//! 0 outside, whatever the winding orientation). A ray through an edge or a vertex of
//! the mesh, or grazing a face, would count wrongly; such a ray is discarded and the
//! next of a fixed list of directions is tried. An open mesh has no inside.

use nalgebra::{Point3, Vector3};

use super::ObstacleMesh;
use super::flat_bvh::NodeBox;

/// Ray directions tried in turn (unit after normalisation; none parallel to a
/// coordinate plane, so axis-aligned CAD faces are never grazed).
const DIRECTIONS: [[f64; 3]; 6] = [
    [0.5773, 0.6109, 0.5419],
    [-0.6271, 0.3339, 0.7037],
    [0.2843, -0.8121, 0.5097],
    [-0.4177, -0.5567, -0.7181],
    [0.8313, 0.1709, -0.5289],
    [-0.1931, 0.9127, -0.3601],
];

/// A crossing this close (in barycentric coordinates) to a triangle's edge, or a ray
/// this close to parallel with a face (cosine), makes the ray ambiguous.
const AMBIGUOUS: f64 = 1e-9;

impl ObstacleMesh {
    /// Whether `point` (m) lies inside the mesh: only for a closed, consistently wound
    /// mesh ([`super::MeshDiagnostics::closed`]); an open mesh has no inside and gives
    /// `false`. A point on the surface counts as outside.
    pub fn encloses(&self, point: &Point3<f64>) -> bool {
        if !self.diagnostics.closed {
            return false;
        }
        let point = &self.to_local(point);
        let [min, max] = self.bounding_box;
        if (0..3).any(|k| point[k] < min[k] || point[k] > max[k]) {
            return false;
        }
        DIRECTIONS
            .iter()
            .find_map(|d| self.winding_along(point, &Vector3::from(*d).normalize()))
            .is_some_and(|winding| winding != 0)
    }

    /// The net signed number of crossings of the ray `point + t d`, `t > 0`, with the
    /// mesh; `None` when the ray passes (nearly) through an edge or a vertex or grazes a
    /// face.
    pub(super) fn winding_along(&self, point: &Point3<f64>, d: &Vector3<f64>) -> Option<i64> {
        let mut winding = 0i64;
        // Read by the node test while the leaves set it.
        let ambiguous = std::cell::Cell::new(false);
        self.tree.bvh.depth_first(
            |_, node| !ambiguous.get() && ray_hits_box(point, d, node),
            |leaf| {
                for &t in self.tree.cluster(leaf) {
                    let [a, b, c] = self.local_triangle(t as usize);
                    match crossing(point, d, &a, &b, &c) {
                        Crossing::Miss => {}
                        Crossing::Hit(sign) => winding += sign,
                        Crossing::Ambiguous => ambiguous.set(true),
                    }
                }
            },
        );
        (!ambiguous.get()).then_some(winding)
    }

    /// [`ObstacleMesh::winding_along`] over every triangle, without the BVH (the
    /// reference of the BVH search in the tests).
    #[cfg(test)]
    pub(super) fn winding_by_scan(&self, point: &Point3<f64>, d: &Vector3<f64>) -> Option<i64> {
        let mut winding = 0i64;
        for t in 0..self.triangle_count() {
            let [a, b, c] = self.local_triangle(t);
            match crossing(point, d, &a, &b, &c) {
                Crossing::Miss => {}
                Crossing::Hit(sign) => winding += sign,
                Crossing::Ambiguous => return None,
            }
        }
        Some(winding)
    }
}

/// How a ray meets a triangle.
enum Crossing {
    Miss,
    /// Crosses the interior: +1 along the normal `(b − a) × (c − a)`, −1 against it.
    Hit(i64),
    Ambiguous,
}

/// Möller–Trumbore with a margin on the barycentric coordinates.
fn crossing(
    origin: &Point3<f64>,
    d: &Vector3<f64>,
    a: &Point3<f64>,
    b: &Point3<f64>,
    c: &Point3<f64>,
) -> Crossing {
    let (e1, e2) = (b - a, c - a);
    let normal = e1.cross(&e2);
    let p = d.cross(&e2);
    let det = e1.dot(&p);
    let scale = e1.norm() * e2.norm();
    if det.abs() <= AMBIGUOUS * scale {
        // Parallel: ambiguous only when the ray lies in the triangle's plane near it.
        let offset = (origin - a).dot(&normal).abs();
        return if offset <= AMBIGUOUS * scale * (1.0 + (origin - a).norm()) {
            Crossing::Ambiguous
        } else {
            Crossing::Miss
        };
    }
    let to_origin = origin - a;
    let u = to_origin.dot(&p) / det;
    let q = to_origin.cross(&e1);
    let v = d.dot(&q) / det;
    let t = e2.dot(&q) / det;
    let w = 1.0 - u - v;
    if t <= 0.0 || u < -AMBIGUOUS || v < -AMBIGUOUS || w < -AMBIGUOUS {
        return Crossing::Miss;
    }
    if u <= AMBIGUOUS || v <= AMBIGUOUS || w <= AMBIGUOUS {
        return Crossing::Ambiguous;
    }
    Crossing::Hit(if normal.dot(d) > 0.0 { 1 } else { -1 })
}

/// Slab test of the ray `origin + t d`, `t ≥ 0`, against a BVH node's box (touching
/// counts).
fn ray_hits_box(origin: &Point3<f64>, d: &Vector3<f64>, node: &NodeBox) -> bool {
    let (min, max) = (&node[..3], &node[3..]);
    let (mut enter, mut exit) = (0.0f64, f64::INFINITY);
    for k in 0..3 {
        let (lo, hi) = (min[k] - origin[k], max[k] - origin[k]);
        if d[k] == 0.0 {
            if lo > 0.0 || hi < 0.0 {
                return false;
            }
            continue;
        }
        let (t0, t1) = (lo / d[k], hi / d[k]);
        enter = enter.max(t0.min(t1));
        exit = exit.min(t0.max(t1));
    }
    enter <= exit * (1.0 + 1e-12) + 1e-15
}
