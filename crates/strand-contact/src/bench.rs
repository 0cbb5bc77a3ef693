//! Timing of mesh construction and queries on large generated meshes, for
//! `strand bench`-style reports and the `mesh_bench` example (no files needed).

use std::time::Instant;

use nalgebra::Point3;

use crate::{MeshError, ObstacleMesh};

/// A wavy square surface `z = amplitude · sin(kx) · cos(ky)` over `[0, size]²` (m),
/// tessellated into `2 n²` triangles with `n = ⌈√(triangles / 2)⌉` (so at least
/// `triangles` triangles).
pub fn wavy_surface(
    triangles: usize,
    size: f64,
    amplitude: f64,
) -> (Vec<Point3<f64>>, Vec<[u32; 3]>) {
    let n = ((triangles as f64 / 2.0).sqrt().ceil() as usize).max(1);
    let k = 2.0 * std::f64::consts::PI * 3.0 / size;
    let step = size / n as f64;
    let mut vertices = Vec::with_capacity((n + 1) * (n + 1));
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f64 * step, j as f64 * step);
            vertices.push(Point3::new(x, y, amplitude * (k * x).sin() * (k * y).cos()));
        }
    }
    let index = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut faces = Vec::with_capacity(2 * n * n);
    for j in 0..n {
        for i in 0..n {
            faces.push([index(i, j), index(i + 1, j), index(i + 1, j + 1)]);
            faces.push([index(i, j), index(i + 1, j + 1), index(i, j + 1)]);
        }
    }
    (vertices, faces)
}

/// Timings of one mesh: BVH build and nearest-point queries.
#[derive(Clone, Copy, Debug)]
pub struct MeshTiming {
    /// Triangles in the mesh.
    pub triangles: usize,
    /// Wall time of [`ObstacleMesh::try_from_triangles`]: validate the triangles, skip
    /// degenerate ones, convert and build the `TriMesh` with its BVH, s.
    pub build_seconds: f64,
    /// Wall time of parry's `TriMesh` construction alone (mostly the BVH), s.
    pub bvh_seconds: f64,
    /// Queries run.
    pub queries: usize,
    /// Queries that found the mesh within the query distance.
    pub hits: usize,
    /// Mean wall time of one segment query (fastest of 5 rounds over all queries), s.
    pub seconds_per_query: f64,
}

/// Builds a [`wavy_surface`] of about `triangles` triangles on a 1 m square and times
/// `queries` segment queries (horizontal 20 mm segments in all directions, 5–25 mm
/// above the surface's crests, at spread-out places, query distance 30 mm).
pub fn time_wavy_surface(triangles: usize, queries: usize) -> Result<MeshTiming, MeshError> {
    let (vertices, faces) = wavy_surface(triangles, 1.0, 0.02);
    let glam_vertices = vertices.iter().map(crate::mesh::to_glam).collect();
    let start = Instant::now();
    let trimesh = parry3d_f64::shape::TriMesh::new(glam_vertices, faces.clone());
    let bvh_seconds = start.elapsed().as_secs_f64();
    drop(trimesh);
    let start = Instant::now();
    let mesh = ObstacleMesh::try_from_triangles("wavy", vertices, &faces)?;
    let build_seconds = start.elapsed().as_secs_f64();
    // A deterministic low-discrepancy sequence of query places.
    let golden = 0.618_033_988_749_895_f64;
    let segments: Vec<_> = (0..queries)
        .map(|q| {
            let q = q as f64;
            let (x, y) = (
                0.05 + 0.9 * (q * golden).fract(),
                0.05 + 0.9 * (q * golden * golden).fract(),
            );
            let z = 0.025 + 0.02 * (q * 0.37).fract();
            let angle = std::f64::consts::TAU * (q * 0.137).fract();
            let direction = nalgebra::Vector3::new(angle.cos(), angle.sin(), 0.0) * 0.02;
            (Point3::new(x, y, z), Point3::new(x, y, z) + direction)
        })
        .collect();
    // The fastest of 5 rounds: the least disturbed by other processes.
    let mut hits = 0;
    let mut seconds_per_query = f64::INFINITY;
    for _ in 0..5 {
        let start = Instant::now();
        hits = segments
            .iter()
            .filter(|(a, b)| mesh.segment_proximity(a, b, 0.03).is_some())
            .count();
        let elapsed = start.elapsed().as_secs_f64() / queries.max(1) as f64;
        seconds_per_query = seconds_per_query.min(elapsed);
    }
    Ok(MeshTiming {
        triangles: mesh.triangle_count(),
        build_seconds,
        bvh_seconds,
        queries,
        hits,
        seconds_per_query,
    })
}
