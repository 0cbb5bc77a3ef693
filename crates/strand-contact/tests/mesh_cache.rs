//! The on-disk mesh cache (issue 11): a cached mesh answers every query exactly as a
//! fresh build does; a changed file, a corrupt or truncated cache file and concurrent
//! builders are handled; a cache folder that cannot be written never fails a load.

#[path = "support/wavy_surface.rs"]
mod wavy_surface;

use std::io::Write;
use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Point3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use strand_contact::{MeshCacheSettings, MeshCacheUse, ObstacleMesh};
use wavy_surface::wavy_surface;

/// An OBJ (mm) of a wavy surface, a closed box floating above it, a degenerate
/// triangle, a duplicate vertex and a non-manifold fin: every diagnostic is non-zero.
fn write_obj(path: &Path, wave: f64) {
    let (vertices, faces) = wavy_surface(2_000, 1.0, wave);
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    for p in &vertices {
        writeln!(out, "v {} {} {}", p.x * 1e3, p.y * 1e3, p.z * 1e3).unwrap();
    }
    for f in &faces {
        writeln!(out, "f {} {} {}", f[0] + 1, f[1] + 1, f[2] + 1).unwrap();
    }
    let base = vertices.len() + 1;
    // A closed 100 mm cube at (400..500, 400..500, 100..200).
    for z in [100, 200] {
        for (x, y) in [(400, 400), (500, 400), (500, 500), (400, 500)] {
            writeln!(out, "v {x} {y} {z}").unwrap();
        }
    }
    for [a, b, c] in CUBE {
        writeln!(out, "f {} {} {}", base + a, base + b, base + c).unwrap();
    }
    // A fin on the diagonal of the surface's first cell (non-manifold: the cell's two
    // triangles share it), a degenerate triangle and a duplicate of the first vertex.
    let n = ((2_000f64 / 2.0).sqrt().ceil()) as usize;
    let fin = base + 8;
    writeln!(out, "v 0 0 50\nv 1 1 1\nv 2 2 2\nv 3 3 3").unwrap();
    writeln!(out, "f 1 {} {fin}", n + 3).unwrap();
    writeln!(out, "f {} {} {}", fin + 1, fin + 2, fin + 3).unwrap();
    let first = vertices[0];
    writeln!(
        out,
        "v {} {} {}",
        first.x * 1e3,
        first.y * 1e3,
        first.z * 1e3
    )
    .unwrap();
    writeln!(out, "f {} 2 {}", fin + 4, base + 2).unwrap();
}

/// A closed 100 mm cube (mm), 12 triangles.
fn write_cube(path: &Path) {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    for z in [0, 100] {
        for (x, y) in [(0, 0), (100, 0), (100, 100), (0, 100)] {
            writeln!(out, "v {x} {y} {z}").unwrap();
        }
    }
    for [a, b, c] in CUBE {
        writeln!(out, "f {} {} {}", a + 1, b + 1, c + 1).unwrap();
    }
}

/// The faces of a cube with corners 0..4 below and 4..8 above, outward winding.
const CUBE: [[usize; 3]; 12] = [
    [0, 2, 1],
    [0, 3, 2],
    [4, 5, 6],
    [4, 6, 7],
    [0, 1, 5],
    [0, 5, 4],
    [1, 2, 6],
    [1, 6, 5],
    [2, 3, 7],
    [2, 7, 6],
    [3, 0, 4],
    [3, 4, 7],
];

fn pose() -> Isometry3<f64> {
    Isometry3::new(Vector3::new(0.1, -0.2, 0.05), Vector3::new(0.0, 0.0, 0.3))
}

fn settings(dir: &Path) -> MeshCacheSettings {
    MeshCacheSettings::in_directory(dir, 0)
}

fn cached(obj: &Path, dir: &Path) -> ObstacleMesh {
    ObstacleMesh::load_cached(obj, 1e-3, &pose(), &settings(dir)).unwrap()
}

fn cache_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files
}

/// Every triangle, patch, diagnostic, nearest point, local contact and inside test of
/// `a` and `b` agree exactly.
fn assert_same_mesh(a: &ObstacleMesh, b: &ObstacleMesh) {
    assert_eq!(a.name(), b.name());
    assert_eq!(a.diagnostics(), b.diagnostics());
    assert_eq!(a.triangle_count(), b.triangle_count());
    assert_eq!(a.vertex_count(), b.vertex_count());
    for t in 0..a.triangle_count() {
        assert_eq!(a.triangle(t), b.triangle(t), "triangle {t}");
        assert_eq!(a.patch_of(t), b.patch_of(t), "patch of {t}");
    }
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let [min, max] = a.bounding_box();
    let mut found = 0;
    for _ in 0..300 {
        let p = Point3::from(
            min.coords
                + Vector3::from_fn(|k, _| rng.random_range(0.0..1.0) * (max[k] - min[k]))
                + Vector3::new(0.0, 0.0, 0.02),
        );
        let q = p + Vector3::from_fn(|_, _| rng.random_range(-0.03..0.03));
        let near = a.segment_proximity(&p, &q, 0.05);
        assert_eq!(near, b.segment_proximity(&p, &q, 0.05));
        found += usize::from(near.is_some());
        assert_eq!(
            a.local_contacts(&p, &q, 0.05),
            b.local_contacts(&p, &q, 0.05)
        );
        assert_eq!(a.encloses(&p), b.encloses(&p));
    }
    assert!(found > 60, "only {found} queries found the mesh");
}

#[test]
fn a_cached_mesh_is_exactly_the_freshly_built_one() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("part.obj");
    write_obj(&obj, 0.05);
    let cache = dir.path().join("cache");
    let fresh = ObstacleMesh::load(&obj, 1e-3, &pose()).unwrap();
    assert_eq!(fresh.cache_use(), &MeshCacheUse::Off);
    let d = fresh.diagnostics();
    assert!(d.degenerate_skipped == 1 && d.duplicate_vertices == 1 && d.non_manifold_edges == 1);

    let written = cached(&obj, &cache);
    let files = cache_files(&cache);
    assert_eq!(files.len(), 1);
    assert_eq!(
        written.cache_use(),
        &MeshCacheUse::Written {
            file: files[0].clone()
        }
    );
    let hit = cached(&obj, &cache);
    assert_eq!(
        hit.cache_use(),
        &MeshCacheUse::Hit {
            file: files[0].clone()
        }
    );
    assert_same_mesh(&fresh, &written);
    assert_same_mesh(&fresh, &hit);
}

#[test]
fn a_cached_closed_part_has_the_same_inside() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("cube.obj");
    write_cube(&obj);
    let cache = dir.path().join("cache");
    cached(&obj, &cache);
    let hit = cached(&obj, &cache);
    assert!(hit.cache_use().is_hit() && hit.diagnostics().closed);
    assert!(hit.encloses(&(pose() * Point3::new(0.05, 0.05, 0.05))));
    assert!(!hit.encloses(&(pose() * Point3::new(0.05, 0.05, 0.15))));
    assert_same_mesh(&ObstacleMesh::load(&obj, 1e-3, &pose()).unwrap(), &hit);
}

#[test]
fn a_changed_file_or_placement_is_a_new_cache_entry() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("part.obj");
    let cache = dir.path().join("cache");
    write_obj(&obj, 0.05);
    let before = cached(&obj, &cache);
    write_obj(&obj, 0.06);
    let after = cached(&obj, &cache);
    assert!(matches!(after.cache_use(), MeshCacheUse::Written { .. }));
    assert_same_mesh(&after, &ObstacleMesh::load(&obj, 1e-3, &pose()).unwrap());
    assert_ne!(before.bounding_box(), after.bounding_box());
    // Another scale is another mesh.
    let scaled = ObstacleMesh::load_cached(&obj, 2e-3, &pose(), &settings(&cache)).unwrap();
    assert!(matches!(scaled.cache_use(), MeshCacheUse::Written { .. }));
    assert_eq!(cache_files(&cache).len(), 3);
}

/// A way to damage a cache file's bytes.
type Damage = fn(&mut Vec<u8>);

#[test]
fn a_corrupt_or_truncated_cache_file_is_detected_and_rebuilt() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("part.obj");
    let cache = dir.path().join("cache");
    write_obj(&obj, 0.05);
    let fresh = ObstacleMesh::load(&obj, 1e-3, &pose()).unwrap();
    cached(&obj, &cache);
    let file = cache_files(&cache).remove(0);
    let good = std::fs::read(&file).unwrap();

    let damages: [(&str, Damage); 4] = [
        ("checksum", |b| {
            let middle = b.len() / 2;
            b[middle] ^= 0x10;
        }),
        ("truncated", |b| b.truncate(b.len() - 100)),
        ("not a Strand mesh cache file", |b| b[0] = b'X'),
        ("too short", |b| b.truncate(10)),
    ];
    for (expected, damage) in damages {
        let mut bytes = good.clone();
        damage(&mut bytes);
        std::fs::write(&file, &bytes).unwrap();
        let rebuilt = cached(&obj, &cache);
        match rebuilt.cache_use() {
            MeshCacheUse::Replaced { file: f, reason } => {
                assert_eq!(f, &file);
                assert!(reason.contains(expected), "{expected}: {reason}");
            }
            other => panic!("{expected}: {other:?}"),
        }
        assert_same_mesh(&fresh, &rebuilt);
        assert_eq!(std::fs::read(&file).unwrap(), good, "{expected}: rewritten");
        assert!(cached(&obj, &cache).cache_use().is_hit());
    }
}

#[test]
fn two_concurrent_builders_of_the_same_mesh_both_succeed() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("part.obj");
    let cache = dir.path().join("cache");
    write_obj(&obj, 0.05);
    let fresh = ObstacleMesh::load(&obj, 1e-3, &pose()).unwrap();
    for _ in 0..3 {
        let _ = std::fs::remove_dir_all(&cache);
        let barrier = std::sync::Barrier::new(2);
        let meshes: Vec<ObstacleMesh> = std::thread::scope(|s| {
            let workers: Vec<_> = (0..2)
                .map(|_| {
                    s.spawn(|| {
                        barrier.wait();
                        cached(&obj, &cache)
                    })
                })
                .collect();
            workers.into_iter().map(|w| w.join().unwrap()).collect()
        });
        for mesh in &meshes {
            assert!(matches!(
                mesh.cache_use(),
                MeshCacheUse::Written { .. } | MeshCacheUse::Hit { .. }
            ));
            assert_same_mesh(&fresh, mesh);
        }
        // One cache file, no temporary left over, and it is whole.
        assert_eq!(cache_files(&cache).len(), 1);
        assert!(cached(&obj, &cache).cache_use().is_hit());
    }
}

#[test]
fn an_unwritable_cache_or_a_small_file_never_fails_a_load() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("part.obj");
    write_obj(&obj, 0.05);
    // The cache "folder" is a regular file: it cannot be created.
    let blocked = dir.path().join("blocked");
    std::fs::write(&blocked, b"not a folder").unwrap();
    let mesh = cached(&obj, &blocked);
    assert!(matches!(mesh.cache_use(), MeshCacheUse::NotWritten { .. }));
    assert_same_mesh(&ObstacleMesh::load(&obj, 1e-3, &pose()).unwrap(), &mesh);
    // Below the size threshold, and with the cache off, nothing is written.
    let cache = dir.path().join("cache");
    let big = MeshCacheSettings::in_directory(&cache, 1 << 40);
    let small = ObstacleMesh::load_cached(&obj, 1e-3, &pose(), &big).unwrap();
    assert_eq!(small.cache_use(), &MeshCacheUse::Off);
    let off = ObstacleMesh::load_cached(&obj, 1e-3, &pose(), &MeshCacheSettings::off()).unwrap();
    assert_eq!(off.cache_use(), &MeshCacheUse::Off);
    assert!(!cache.exists());
    // Load errors are those of a load without the cache.
    let missing = dir.path().join("missing.obj");
    let error = ObstacleMesh::load_cached(&missing, 1e-3, &pose(), &settings(&cache));
    assert!(error.unwrap_err().to_string().contains("missing.obj"));
}

/// The cache folder stays within its size limit: writing a new entry removes the least
/// recently used ones, and a hit counts as a use.
#[test]
fn a_full_cache_folder_forgets_the_least_recently_used_meshes() {
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let objs: Vec<PathBuf> = (0..3)
        .map(|i| {
            let obj = dir.path().join(format!("part{i}.obj"));
            write_obj(&obj, 0.05 + 0.01 * i as f64);
            obj
        })
        .collect();
    let load = |obj: &Path, limit: u64| {
        let settings = settings(&cache).with_max_bytes(limit);
        ObstacleMesh::load_cached(obj, 1e-3, &pose(), &settings).unwrap()
    };
    let file_of = |mesh: &ObstacleMesh| match mesh.cache_use() {
        MeshCacheUse::Written { file } | MeshCacheUse::Hit { file } => file.clone(),
        other => panic!("not cached: {other:?}"),
    };
    let unlimited = u64::MAX;
    let first = file_of(&load(&objs[0], unlimited));
    let one = std::fs::metadata(&first).unwrap().len();
    std::thread::sleep(std::time::Duration::from_millis(20));
    let second = file_of(&load(&objs[1], unlimited));
    std::thread::sleep(std::time::Duration::from_millis(20));
    // A hit on the first makes the second the least recently used.
    let hit = load(&objs[0], unlimited);
    assert!(matches!(hit.cache_use(), MeshCacheUse::Hit { .. }));
    std::thread::sleep(std::time::Duration::from_millis(20));
    // Room for two files (they are about the same size): the third evicts the second.
    let third = file_of(&load(&objs[2], 2 * one + one / 2));
    assert_eq!(cache_files(&cache), {
        let mut kept = vec![first.clone(), third.clone()];
        kept.sort();
        kept
    });
    assert!(!second.exists());
    // The evicted mesh is simply built again, and the limit holds.
    let again = load(&objs[1], 2 * one + one / 2);
    assert!(matches!(again.cache_use(), MeshCacheUse::Written { .. }));
    assert_same_mesh(
        &again,
        &ObstacleMesh::load(&objs[1], 1e-3, &pose()).unwrap(),
    );
    assert_eq!(cache_files(&cache).len(), 2);
}
