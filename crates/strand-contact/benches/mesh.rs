//! Mesh benchmarks (issue 11): building the BVH of generated, seeded surfaces of 1k and
//! 1M triangles, loading 1M- and 4M-triangle OBJ files cold (read, parse, build) and
//! through the on-disk mesh cache (hash the OBJ, read the cache file), and nearest
//! point queries of segments against 1k and 1M triangles.
//!
//! `cargo bench -p strand-contact --bench mesh` (prints the memory per triangle too;
//! `taskset -c 0` for one core). The OBJ files (36 MB and 150 MB) are written to a
//! temporary folder.

// criterion's macros generate undocumented functions.
#![allow(missing_docs)]

use std::hint::black_box;
use std::path::Path;

#[path = "../tests/support/wavy_surface.rs"]
mod wavy_surface;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use nalgebra::{Isometry3, Point3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use strand_contact::{MeshCacheSettings, MeshCacheUse, ObstacleMesh};
use wavy_surface::wavy_surface;

/// A wavy 1 m square of about `triangles` triangles, every vertex jittered by a seeded
/// ±0.1 mm (so no two rows are alike).
fn surface(triangles: usize) -> (Vec<Point3<f64>>, Vec<[u32; 3]>) {
    let (mut vertices, faces) = wavy_surface(triangles, 1.0, 0.02);
    let mut rng = ChaCha8Rng::seed_from_u64(triangles as u64);
    for p in &mut vertices {
        p.z += rng.random_range(-1e-4..1e-4);
    }
    (vertices, faces)
}

/// The surface as an OBJ file in mm.
fn write_obj(path: &Path, vertices: &[Point3<f64>], faces: &[[u32; 3]]) {
    use std::io::Write;
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    for p in vertices {
        writeln!(out, "v {} {} {}", p.x * 1e3, p.y * 1e3, p.z * 1e3).unwrap();
    }
    for f in faces {
        writeln!(out, "f {} {} {}", f[0] + 1, f[1] + 1, f[2] + 1).unwrap();
    }
}

/// 1000 horizontal 20 mm segments 5–25 mm above the surface, spread by a seeded rng.
fn segments() -> Vec<(Point3<f64>, Point3<f64>)> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    (0..1000)
        .map(|_| {
            let p = Point3::new(
                rng.random_range(0.05..0.95),
                rng.random_range(0.05..0.95),
                rng.random_range(0.025..0.045),
            );
            let angle: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            (p, p + 0.02 * Vector3::new(angle.cos(), angle.sin(), 0.0))
        })
        .collect()
}

fn build_and_query(c: &mut Criterion) {
    let mut group = c.benchmark_group("mesh");
    group.sample_size(10);
    let queries = segments();
    for (label, triangles) in [("1k", 1_000), ("1M", 1_000_000)] {
        let (vertices, faces) = surface(triangles);
        group.bench_function(BenchmarkId::new("build", label), |b| {
            b.iter(|| {
                ObstacleMesh::try_from_triangles("surface", black_box(vertices.clone()), &faces)
                    .unwrap()
            })
        });
        let mesh = ObstacleMesh::try_from_triangles("surface", vertices, &faces).unwrap();
        eprintln!(
            "{label}: {} triangles, {:.1} bytes per triangle",
            mesh.triangle_count(),
            mesh.memory_bytes() as f64 / mesh.triangle_count() as f64
        );
        group.bench_function(BenchmarkId::new("1000 segment queries", label), |b| {
            b.iter(|| {
                queries
                    .iter()
                    .filter(|(p0, p1)| mesh.segment_proximity(p0, p1, 0.03).is_some())
                    .count()
            })
        });
    }
    group.finish();
}

fn load(c: &mut Criterion) {
    for (label, triangles) in [("1M", 1_000_000), ("4M", 4_000_000)] {
        let dir = tempfile::tempdir().unwrap();
        let obj = dir.path().join(format!("surface_{label}.obj"));
        let (vertices, faces) = surface(triangles);
        write_obj(&obj, &vertices, &faces);
        drop((vertices, faces));
        let pose = Isometry3::identity();
        let cache = MeshCacheSettings::in_directory(dir.path().join("cache"), 0);
        let mut group = c.benchmark_group(format!("mesh load {label}"));
        group.sample_size(10);
        group.bench_function("cold (read, parse, build)", |b| {
            b.iter(|| ObstacleMesh::load(&obj, 1e-3, &pose).unwrap())
        });
        let written = ObstacleMesh::load_cached(&obj, 1e-3, &pose, &cache).unwrap();
        assert!(matches!(written.cache_use(), MeshCacheUse::Written { .. }));
        drop(written);
        group.bench_function(
            "cached (read the OBJ for its hash, read the cache file)",
            |b| {
                b.iter(|| {
                    let mesh = ObstacleMesh::load_cached(&obj, 1e-3, &pose, &cache).unwrap();
                    assert!(mesh.cache_use().is_hit());
                    mesh
                })
            },
        );
        group.finish();
    }
}

criterion_group!(benches, build_and_query, load);
criterion_main!(benches);
