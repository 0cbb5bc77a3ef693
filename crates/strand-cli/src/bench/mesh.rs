//! `strand bench --mesh FILE`: the load of an environment mesh file (OBJ or STL) cold
//! (read, parse, topology, BVH) and through a fresh on-disk mesh cache (hash the file,
//! read the cache file), medians of repeated loads, against the issue-11 targets for a
//! 1M-triangle mesh (cold ≤ 0.4 s, cached ≤ 50 ms).

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use nalgebra::Isometry3;
use strand_contact::{MeshCacheSettings, MeshError, ObstacleMesh};

use crate::Exit;
use crate::commands::Failure;

/// Issue-11 target for a cold load of 1M triangles, s.
pub const COLD_TARGET_S: f64 = 0.4;
/// Issue-11 target for a cached load of 1M triangles, s.
pub const CACHED_TARGET_S: f64 = 0.05;

/// What `strand bench --mesh` measured.
#[derive(Clone, Debug)]
pub struct MeshBench {
    /// Triangles kept.
    pub triangles: usize,
    /// Memory held by the mesh per triangle, bytes.
    pub bytes_per_triangle: f64,
    /// Median wall time of a cold load, s.
    pub cold_s: f64,
    /// Wall time of the first cached load (build and write the cache file), s.
    pub write_s: f64,
    /// Median wall time of a cached load (a hit), s.
    pub cached_s: f64,
    /// Worker threads available to the load.
    pub threads: usize,
}

/// Loads `path` (file units to metres `scale`) `repeats` times cold and through a
/// cache in a fresh folder of the system's temporary folder (removed afterwards).
pub fn run_mesh(path: &Path, scale: f64, repeats: usize) -> Result<MeshBench, MeshError> {
    let pose = Isometry3::identity();
    let timed = |load: &dyn Fn() -> Result<ObstacleMesh, MeshError>| {
        let start = Instant::now();
        load().map(|mesh| (start.elapsed().as_secs_f64(), mesh))
    };
    let mut cold = Vec::with_capacity(repeats);
    let mut mesh = None;
    for _ in 0..repeats {
        let (seconds, loaded) = timed(&|| ObstacleMesh::load(path, scale, &pose))?;
        cold.push(seconds);
        mesh = Some(loaded);
    }
    let mesh = mesh.expect("at least one repeat");
    let folder = std::env::temp_dir().join(format!("strand-bench-mesh-{}", std::process::id()));
    let cache = MeshCacheSettings::in_directory(&folder, 0);
    let cached_loads = || -> Result<(f64, Vec<f64>), MeshError> {
        let (write_s, _) = timed(&|| ObstacleMesh::load_cached(path, scale, &pose, &cache))?;
        let mut cached = Vec::with_capacity(repeats);
        for _ in 0..repeats {
            let (seconds, hit) = timed(&|| ObstacleMesh::load_cached(path, scale, &pose, &cache))?;
            debug_assert!(hit.cache_use().is_hit());
            cached.push(seconds);
        }
        Ok((write_s, cached))
    };
    let measured = cached_loads();
    let _ = std::fs::remove_dir_all(&folder);
    let (write_s, cached) = measured?;
    Ok(MeshBench {
        triangles: mesh.triangle_count(),
        bytes_per_triangle: mesh.memory_bytes() as f64 / mesh.triangle_count() as f64,
        cold_s: super::median(cold),
        write_s,
        cached_s: super::median(cached),
        threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
    })
}

/// The report of [`run_mesh`], with the targets scaled to the mesh's size.
pub fn format_mesh(path: &Path, repeats: usize, b: &MeshBench) -> String {
    let per_million = 1e6 / b.triangles as f64;
    let verdict = |seconds: f64, target: f64| {
        if seconds * per_million <= target {
            "met"
        } else {
            "NOT MET"
        }
    };
    // See `fresh_memory`: the binary runs this benchmark with glibc's mmap threshold
    // fixed, so every load faults its pages in as a new process does.
    let memory = if std::env::var("GLIBC_TUNABLES").is_ok_and(|t| t.contains("mmap_threshold")) {
        "each load in fresh memory"
    } else {
        "memory reused between repeats"
    };
    format!(
        "{}: mesh load, median of {repeats}, {} thread(s), {memory}\n\
         triangles  bytes/triangle  cold [ms]  build+write cache [ms]  cached [ms]  cold/cached\n\
         {:>9}  {:>14.1}  {:>9.1}  {:>22.1}  {:>11.1}  {:>10.1}x\n\
         targets per 1M triangles: cold <= {:.0} ms ({}), cached <= {:.0} ms ({})\n",
        path.display(),
        b.threads,
        b.triangles,
        b.bytes_per_triangle,
        b.cold_s * 1e3,
        b.write_s * 1e3,
        b.cached_s * 1e3,
        b.cold_s / b.cached_s,
        COLD_TARGET_S * 1e3,
        verdict(b.cold_s, COLD_TARGET_S),
        CACHED_TARGET_S * 1e3,
        verdict(b.cached_s, CACHED_TARGET_S),
    )
}

/// `strand bench --mesh FILE`: runs and prints the table.
pub(crate) fn run_and_print(
    path: &Path,
    scale: f64,
    repeats: usize,
    out: &mut dyn Write,
) -> Result<Exit, Failure> {
    let bench = run_mesh(path, scale, repeats).map_err(|e| Failure {
        exit: Exit::InvalidInput,
        message: e.to_string(),
    })?;
    let _ = write!(out, "{}", format_mesh(path, repeats, &bench));
    Ok(Exit::Success)
}
