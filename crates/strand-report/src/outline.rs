//! Outlines of the environment meshes near the hoses, for drawings (the HTML report's
//! projections and 3D view): the mesh's boundary edges (open rims) and feature edges
//! (where the surface turns by more than [`FEATURE_ANGLE_RAD`]), clipped to a box
//! around the hoses, as line segments in metres (`result.json`:
//! `environment[*].segments_m`).
//!
//! Only triangles whose bounding box meets the box are examined, so the cost follows
//! the triangles near the hoses, not the size of the mesh. An edge whose other triangle
//! was not examined looks like a rim, but such an edge lies entirely outside the box
//! (its other triangle contains it, so that triangle's bounding box would have met the
//! box too), so clipping removes it.

use std::collections::HashMap;
use std::sync::Arc;

use nalgebra::{Point3, Vector3};
use strand_contact::{ObstacleMesh, SMOOTH_PATCH_ANGLE_RAD};

use crate::{EnvironmentOutline, ResultDoc};

/// Smallest turn of the surface normal across an edge that makes it a feature edge,
/// rad (30°, as the contact's smooth patches: the faces of a box are outlined, a finely
/// faceted cylinder is not).
pub const FEATURE_ANGLE_RAD: f64 = SMOOTH_PATCH_ANGLE_RAD;

/// How far (m) beyond the bounding box of the hoses (and their supports) the outlines
/// reach.
pub const OUTLINE_MARGIN_M: f64 = 0.1;

/// Most segments kept per mesh; beyond it the longest are kept (and the outline is
/// marked `truncated`), so that `result.json` and the report stay small.
pub const MAX_OUTLINE_SEGMENTS: usize = 5000;

/// An axis-aligned box `[min, max]`, m.
pub type Aabb = [[f64; 3]; 2];

/// The outline of `mesh` inside `region`: boundary, non-manifold and feature edges,
/// each clipped to the box, m; and whether [`MAX_OUTLINE_SEGMENTS`] cut it short.
pub fn mesh_outline(mesh: &ObstacleMesh, region: &Aabb) -> (Vec<[[f64; 3]; 2]>, bool) {
    // Triangles near the region, their welded corners and normals.
    let mut ids: HashMap<[u64; 3], u32> = HashMap::new();
    let mut corners: Vec<[f64; 3]> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut normals: Vec<Vector3<f64>> = Vec::new();
    for t in 0..mesh.triangle_count() {
        let points = mesh.triangle(t);
        if !meets(&points, region) {
            continue;
        }
        let indices = points.map(|p| {
            let key = [p.x, p.y, p.z].map(|v| (v + 0.0).to_bits());
            *ids.entry(key).or_insert_with(|| {
                corners.push([p.x, p.y, p.z]);
                (corners.len() - 1) as u32
            })
        });
        let [a, b, c] = points;
        normals.push((b - a).cross(&(c - a)).normalize());
        triangles.push(indices);
    }
    // Edge uses: (low, high, triangle, forward), sorted by edge.
    let mut uses: Vec<(u32, u32, u32, bool)> = Vec::with_capacity(3 * triangles.len());
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            if a != b {
                uses.push((a.min(b), a.max(b), t as u32, a < b));
            }
        }
    }
    uses.sort_unstable();
    let sharp = FEATURE_ANGLE_RAD.cos();
    let mut segments = Vec::new();
    for group in uses.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
        let feature = match group {
            [(_, _, t1, f1), (_, _, t2, f2)] => {
                // Consistent winding traverses a shared edge in opposite directions;
                // compare the normals as if it did.
                let sign = if f1 == f2 { -1.0 } else { 1.0 };
                let cos = sign * normals[*t1 as usize].dot(&normals[*t2 as usize]);
                // NaN (a sliver's normal) compares false: not a feature.
                cos < sharp
            }
            _ => true, // rim (one use) or non-manifold (three or more)
        };
        if feature {
            let (a, b) = (corners[group[0].0 as usize], corners[group[0].1 as usize]);
            if let Some(clipped) = clip(a, b, region) {
                segments.push(clipped);
            }
        }
    }
    let truncated = segments.len() > MAX_OUTLINE_SEGMENTS;
    if truncated {
        let length = |s: &[[f64; 3]; 2]| (Point3::from(s[1]) - Point3::from(s[0])).norm();
        segments.sort_by(|x, y| length(y).total_cmp(&length(x)));
        segments.truncate(MAX_OUTLINE_SEGMENTS);
    }
    (segments, truncated)
}

/// Whether the bounding box of `points` meets `region`.
fn meets(points: &[Point3<f64>; 3], region: &Aabb) -> bool {
    (0..3).all(|i| {
        let lo = points.iter().map(|p| p[i]).fold(f64::INFINITY, f64::min);
        let hi = points
            .iter()
            .map(|p| p[i])
            .fold(f64::NEG_INFINITY, f64::max);
        lo <= region[1][i] && hi >= region[0][i]
    })
}

/// The part of segment `a`–`b` inside `region` (Liang–Barsky), if any.
pub(crate) fn clip(a: [f64; 3], b: [f64; 3], region: &Aabb) -> Option<[[f64; 3]; 2]> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for i in 0..3 {
        let d = b[i] - a[i];
        for (p, q) in [(-d, a[i] - region[0][i]), (d, region[1][i] - a[i])] {
            if p == 0.0 {
                if q < 0.0 {
                    return None;
                }
            } else {
                let r = q / p;
                if p < 0.0 {
                    t0 = t0.max(r);
                } else {
                    t1 = t1.min(r);
                }
            }
        }
    }
    if t0
        .partial_cmp(&t1)
        .is_none_or(|o| o == std::cmp::Ordering::Greater)
    {
        return None;
    }
    let at = |t: f64| [0, 1, 2].map(|i| a[i] + t * (b[i] - a[i]));
    Some([at(t0), at(t1)])
}

/// The box around the hoses, their supports, bodies and clips in `doc`, grown by
/// `margin` (m) on every side; `None` if `doc` has no finite point.
pub fn region_around(doc: &ResultDoc, margin: f64) -> Option<Aabb> {
    let points = doc
        .rods
        .iter()
        .flat_map(|r| r.position_m.iter().copied())
        .chain(doc.reactions.iter().map(|r| r.position_m))
        .chain(doc.bodies.iter().map(|b| b.position_m))
        .chain(doc.clips.iter().map(|c| c.position_m))
        .filter(|p| p.iter().all(|v| v.is_finite()));
    let mut region: Option<Aabb> = None;
    for p in points {
        let r = region.get_or_insert([p, p]);
        for i in 0..3 {
            r[0][i] = r[0][i].min(p[i]);
            r[1][i] = r[1][i].max(p[i]);
        }
    }
    region.map(|[lo, hi]| [lo.map(|v| v - margin), hi.map(|v| v + margin)])
}

/// Puts the outline and the surface ([`crate::mesh_surface`]) of every mesh within
/// [`OUTLINE_MARGIN_M`] of the hoses into `doc.environment` (one entry per mesh by
/// name; an existing entry keeps its diagnostics). Call after the rods are in `doc`.
pub fn collect_outlines(doc: &mut ResultDoc, meshes: &[Arc<ObstacleMesh>]) {
    let Some(region) = region_around(doc, OUTLINE_MARGIN_M) else {
        return;
    };
    for mesh in meshes {
        let (segments, truncated) = mesh_outline(mesh, &region);
        let (surface, cell) = crate::surface::mesh_surface(mesh, &region);
        match doc.environment.iter_mut().find(|e| e.name == mesh.name()) {
            Some(entry) => {
                entry.segments_m = segments;
                entry.truncated = truncated;
                entry.surface_m = surface;
                entry.surface_cell_m = cell;
            }
            None => doc.environment.push(EnvironmentOutline {
                name: mesh.name().to_string(),
                segments_m: segments,
                truncated,
                surface_m: surface,
                surface_cell_m: cell,
                diagnostics: None,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed unit box [0, 1]³ scaled by `size` (m), 12 triangles.
    fn cube(size: [f64; 3], offset: [f64; 3]) -> ObstacleMesh {
        let v = |i: usize| {
            Point3::new(
                offset[0] + size[0] * (i & 1) as f64,
                offset[1] + size[1] * ((i >> 1) & 1) as f64,
                offset[2] + size[2] * ((i >> 2) & 1) as f64,
            )
        };
        // Outward-wound quads (a, b, c, d) of the six faces.
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let mut triangles = Vec::new();
        for [a, b, c, d] in quads {
            triangles.push([v(a), v(b), v(c)]);
            triangles.push([v(a), v(c), v(d)]);
        }
        let vertices: Vec<Point3<f64>> = triangles.iter().flatten().copied().collect();
        let indices: Vec<[u32; 3]> = (0..triangles.len() as u32)
            .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
            .collect();
        ObstacleMesh::try_from_triangles("box", vertices, &indices).expect("a box")
    }

    const EVERYWHERE: Aabb = [[-10.0; 3], [10.0; 3]];

    #[test]
    fn a_box_is_outlined_by_its_twelve_edges() {
        let mesh = cube([0.2, 0.1, 0.05], [1.0, 2.0, 3.0]);
        let (segments, truncated) = mesh_outline(&mesh, &EVERYWHERE);
        assert!(!truncated);
        assert_eq!(segments.len(), 12, "{segments:?}");
        // Every edge is axis-aligned, joins two corners and has one of the three sizes.
        for [a, b] in &segments {
            let d: Vec<f64> = (0..3).map(|i| (b[i] - a[i]).abs()).collect();
            let along: Vec<usize> = (0..3).filter(|&i| d[i] > 1e-12).collect();
            assert_eq!(along.len(), 1, "{a:?} {b:?}");
            let size = [0.2, 0.1, 0.05][along[0]];
            assert!((d[along[0]] - size).abs() < 1e-12);
        }
    }

    #[test]
    fn a_flat_tessellated_sheet_shows_only_its_rim() {
        // A 2 × 2 grid of squares in z = 0 (8 triangles): rim of 8 edges, the 8 inner
        // (flat) edges are no features.
        let p = |i: usize, j: usize| Point3::new(i as f64, j as f64, 0.0);
        let mut vertices = Vec::new();
        for i in 0..2 {
            for j in 0..2 {
                vertices.extend([p(i, j), p(i + 1, j), p(i + 1, j + 1)]);
                vertices.extend([p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
            }
        }
        let indices: Vec<[u32; 3]> = (0..8u32).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
        let mesh = ObstacleMesh::try_from_triangles("sheet", vertices, &indices).unwrap();
        let (segments, _) = mesh_outline(&mesh, &EVERYWHERE);
        assert_eq!(segments.len(), 8);
        for [a, b] in &segments {
            let on_rim = |q: &[f64; 3]| q[0] == 0.0 || q[0] == 2.0 || q[1] == 0.0 || q[1] == 2.0;
            assert!(on_rim(a) && on_rim(b), "{a:?} {b:?}");
        }
    }

    #[test]
    fn the_outline_is_clipped_to_the_region_without_false_rims() {
        // A long box x in [0, 1]; the region covers x in [0.25, 0.5] only: the four
        // long edges remain, cut to the region; no end face shows.
        let mesh = cube([1.0, 0.1, 0.1], [0.0; 3]);
        let region = [[0.25, -1.0, -1.0], [0.5, 1.0, 1.0]];
        let (segments, _) = mesh_outline(&mesh, &region);
        assert_eq!(segments.len(), 4, "{segments:?}");
        for [a, b] in &segments {
            let (lo, hi) = (a[0].min(b[0]), a[0].max(b[0]));
            assert!((lo - 0.25).abs() < 1e-12 && (hi - 0.5).abs() < 1e-12);
        }
        // Nothing at all from a region away from the box.
        let away = [[5.0; 3], [6.0; 3]];
        assert!(mesh_outline(&mesh, &away).0.is_empty());
    }

    #[test]
    fn clipping_keeps_inside_and_cuts_crossing_segments() {
        let region = [[0.0; 3], [1.0; 3]];
        assert_eq!(
            clip([0.2, 0.2, 0.2], [0.8, 0.5, 0.5], &region),
            Some([[0.2, 0.2, 0.2], [0.8, 0.5, 0.5]])
        );
        assert_eq!(
            clip([-1.0, 0.5, 0.5], [3.0, 0.5, 0.5], &region),
            Some([[0.0, 0.5, 0.5], [1.0, 0.5, 0.5]])
        );
        assert_eq!(clip([2.0, 0.5, 0.5], [3.0, 0.5, 0.5], &region), None);
        assert_eq!(clip([-1.0, 2.0, 0.5], [2.0, 2.0, 0.5], &region), None);
    }
}
