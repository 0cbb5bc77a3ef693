//! A bounded, seeded fuzzer over OBJ loading ([`ObstacleMesh::load_obj`]), run with the
//! normal test suite: generated OBJ text (hostile numbers, out-of-range, zero,
//! negative and huge face indices, odd arities, junk lines) and byte mutations of the
//! bundled box. Every input must load or fail with an error — never panic — and a
//! loaded mesh must hold only finite vertices. The fixed seed and case count keep the
//! run reproducible and short; `FUZZ_CASES=N` runs longer locally. Inputs it once
//! broke on are kept in `tests/fuzz-corpus/obj/` and replayed first.

use std::path::{Path, PathBuf};

use nalgebra::Isometry3;
use proptest::prelude::*;
use proptest::test_runner::{Config, FileFailurePersistence, RngSeed, TestRunner};
use strand_contact::ObstacleMesh;

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-corpus/obj")
}

/// Loads `bytes` as an OBJ file: `Ok(triangles)` or the error's message. Panics (a
/// bug) only through `load_obj` itself.
fn load(bytes: &[u8]) -> Result<usize, String> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("fuzz.obj");
    std::fs::write(&path, bytes).unwrap();
    match ObstacleMesh::load_obj(&path, 0.001, &Isometry3::identity()) {
        Ok(mesh) => {
            let finite = (0..mesh.triangle_count())
                .flat_map(|t| mesh.triangle(t))
                .chain(mesh.bounding_box())
                .all(|v| v.coords.iter().all(|x| x.is_finite()));
            assert!(finite, "a loaded mesh with a non-finite vertex");
            Ok(mesh.triangle_count())
        }
        Err(e) => {
            let text = e.to_string();
            assert!(
                text.contains("fuzz.obj"),
                "the error does not name the file: {text}"
            );
            Err(text)
        }
    }
}

fn runner(cases: u32) -> TestRunner {
    let cases = std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(cases);
    TestRunner::new(Config {
        cases,
        rng_seed: RngSeed::Fixed(0x05ee_d0b1),
        failure_persistence: Some(Box::new(FileFailurePersistence::Off)),
        ..Config::default()
    })
}

fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        (-10.0..10.0f64).prop_map(|x| x.to_string()),
        Just("NaN".to_string()),
        Just("inf".to_string()),
        Just("-inf".to_string()),
        Just("1e308".to_string()),
        Just("-1e308".to_string()),
        Just("1e-320".to_string()),
        Just("-0".to_string()),
        Just("x".to_string()),
        Just(String::new()),
    ]
}

fn index() -> impl Strategy<Value = String> {
    prop_oneof![
        (1..12i64).prop_map(|i| i.to_string()),
        (-12..0i64).prop_map(|i| i.to_string()),
        Just("0".to_string()),
        Just("4294967296".to_string()),
        Just("18446744073709551617".to_string()),
        (1..12i64).prop_map(|i| format!("{i}/{i}/{i}")),
        (1..12i64).prop_map(|i| format!("{i}//")),
    ]
}

fn line() -> impl Strategy<Value = String> {
    prop_oneof![
        4 => proptest::collection::vec(number(), 0..5).prop_map(|n| format!("v {}", n.join(" "))),
        4 => proptest::collection::vec(index(), 0..7).prop_map(|i| format!("f {}", i.join(" "))),
        1 => Just("o part".to_string()),
        1 => Just("g".to_string()),
        1 => Just("vn 0 0 1".to_string()),
        1 => Just("vt 0.5".to_string()),
        1 => Just("l 1 2".to_string()),
        1 => Just("mtllib nowhere.mtl".to_string()),
        1 => "[ -~]{0,20}",
    ]
}

#[test]
fn the_regression_corpus_loads_or_fails_cleanly() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(corpus())
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(files.len() >= 10);
    for file in files {
        let bytes = std::fs::read(&file).unwrap();
        let outcome = std::panic::catch_unwind(|| load(&bytes));
        assert!(outcome.is_ok(), "{} panicked", file.display());
    }
    // The clear cases: what must be an error is one.
    for name in ["empty.obj", "nan_vertex.obj", "face_index_out_of_range.obj"] {
        let bytes = std::fs::read(corpus().join(name)).unwrap();
        assert!(load(&bytes).is_err(), "{name} loaded");
    }
}

#[test]
fn generated_obj_text_loads_or_fails_cleanly() {
    runner(400)
        .run(&proptest::collection::vec(line(), 0..24), |lines| {
            let _ = load(lines.join("\n").as_bytes());
            Ok(())
        })
        .unwrap();
}

#[test]
fn mutated_bundled_meshes_load_or_fail_cleanly() {
    let base =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/parts/box.obj"))
            .unwrap();
    let n = base.len();
    let mutation = proptest::collection::vec((0..n, any::<u8>(), 0..3u8), 1..8);
    runner(200)
        .run(&mutation, |edits| {
            let mut bytes = base.clone();
            for (at, byte, kind) in edits {
                let at = at.min(bytes.len().saturating_sub(1));
                match kind {
                    0 if !bytes.is_empty() => bytes[at] = byte,
                    1 => bytes.insert(at, byte),
                    _ if !bytes.is_empty() => {
                        bytes.truncate(at);
                    }
                    _ => {}
                }
            }
            let _ = load(&bytes);
            Ok(())
        })
        .unwrap();
}
