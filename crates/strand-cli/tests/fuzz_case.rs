//! A bounded, seeded fuzzer over the case pipeline `strand` runs before it writes
//! anything: RON text → [`Case`] → the boundary limits
//! ([`strand_cli::limits::case_problem`]) → the model ([`Case::build`], and every
//! variant). Inputs are shipped cases with hostile numbers swapped in for their
//! numbers (NaN, ±inf, 1e308, 0, −1, segment counts at the limit), random byte edits
//! and truncations. Every input must build or fail with an error — never panic, never
//! hang (the limits bound every loop) — in the normal test suite, with a fixed seed
//! and case count (`FUZZ_CASES=N` runs longer locally). Inputs that once broke it are
//! kept in `tests/fuzz-corpus/case/` and replayed first.

use std::path::{Path, PathBuf};

use proptest::prelude::*;
use proptest::test_runner::{Config, FileFailurePersistence, RngSeed, TestRunner};
use strand_case::Case;

/// Cases the mutations start from (small, without meshes, and one with a mesh).
const SEEDS: [&str; 5] = [
    "elastica_fig2.ron",
    "cooler_hose.ron",
    "hanging_cable.ron",
    "harness_clips.ron",
    "cable_over_box.ron",
];

fn cases_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases")
}

/// Runs the pipeline on `text` as if it were `cases/<name>` (so that its meshes are
/// found): `Ok(())` if the case and its variants build, else the first error.
fn pipeline(text: &str, name: &str) -> Result<(), String> {
    let origin = cases_dir().join(name);
    let case = Case::from_str(text, origin.to_str().unwrap()).map_err(|e| e.to_string())?;
    if let Some(problem) = strand_cli::limits::case_problem(&case) {
        return Err(problem);
    }
    case.build(None).map_err(|e| e.to_string())?;
    for variant in case.variant_names() {
        case.build_variant(variant, None)
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn runner(cases: u32) -> TestRunner {
    let cases = std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(cases);
    TestRunner::new(Config {
        cases,
        rng_seed: RngSeed::Fixed(0xca5e_f022),
        failure_persistence: Some(Box::new(FileFailurePersistence::Off)),
        ..Config::default()
    })
}

/// Byte ranges of the numbers in `text`.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut spans = Vec::new();
    let mut k = 0;
    while k < bytes.len() {
        let starts = bytes[k].is_ascii_digit()
            && (k == 0 || !(bytes[k - 1].is_ascii_alphanumeric() || bytes[k - 1] == b'_'));
        if starts {
            let from = k;
            while k < bytes.len()
                && (bytes[k].is_ascii_alphanumeric() || b".+-".contains(&bytes[k]))
            {
                k += 1;
            }
            spans.push((from, k));
        } else {
            k += 1;
        }
    }
    spans
}

/// A seed case: its file name, its text and the byte ranges of its numbers.
type Seed = (String, String, Vec<(usize, usize)>);

const HOSTILE: [&str; 14] = [
    "0",
    "-1",
    "-0",
    "1e308",
    "-1e308",
    "1e-308",
    "NaN",
    "inf",
    "-inf",
    "1e300",
    "100000",
    "100001",
    "3.5",
    "4294967296",
];

#[test]
fn the_regression_corpus_is_refused_or_built_cleanly() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-corpus/case");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(files.len() >= 10);
    for file in &files {
        let text = String::from_utf8_lossy(&std::fs::read(file).unwrap()).to_string();
        let outcome = std::panic::catch_unwind(|| pipeline(&text, "cooler_hose.ron"));
        let Ok(result) = outcome else {
            panic!("{} panicked", file.display());
        };
        // Each of these was accepted once and then failed late (or hung): now an
        // input error up front.
        let name = file.file_name().unwrap().to_string_lossy();
        if name != "unicode_name.ron" {
            assert!(result.is_err(), "{name} was accepted");
        }
    }
}

#[test]
fn cases_with_hostile_numbers_are_refused_or_built_cleanly() {
    let seeds: Vec<Seed> = SEEDS
        .iter()
        .map(|name| {
            let text = std::fs::read_to_string(cases_dir().join(name)).unwrap();
            let spans = numbers(&text);
            (name.to_string(), text, spans)
        })
        .collect();
    let edit = (
        0..SEEDS.len(),
        proptest::collection::vec((any::<usize>(), 0..HOSTILE.len()), 1..4),
    );
    runner(48)
        .run(&edit, |(seed, swaps)| {
            let (name, text, spans) = &seeds[seed];
            let mut chosen: Vec<(usize, usize, &str)> = swaps
                .iter()
                .map(|(at, h)| {
                    let (a, b) = spans[at % spans.len()];
                    (a, b, HOSTILE[*h])
                })
                .collect();
            chosen.sort();
            chosen.dedup_by_key(|c| c.0);
            let mut mutated = text.clone();
            for (a, b, value) in chosen.iter().rev() {
                mutated.replace_range(*a..*b, value);
            }
            let _ = pipeline(&mutated, name);
            Ok(())
        })
        .unwrap();
}

#[test]
fn cases_with_random_edits_are_refused_or_built_cleanly() {
    let seeds: Vec<(String, Vec<u8>)> = SEEDS
        .iter()
        .map(|name| {
            (
                name.to_string(),
                std::fs::read(cases_dir().join(name)).unwrap(),
            )
        })
        .collect();
    let edit = (
        0..SEEDS.len(),
        proptest::collection::vec((any::<usize>(), 0x20..0x7fu8, 0..3u8), 1..6),
    );
    runner(64)
        .run(&edit, |(seed, edits)| {
            let (name, base) = &seeds[seed];
            let mut bytes = base.clone();
            for (at, byte, kind) in edits {
                let at = at % bytes.len().max(1);
                match kind {
                    0 if !bytes.is_empty() => bytes[at] = byte,
                    1 => bytes.insert(at, byte),
                    _ => bytes.truncate(at.max(bytes.len() / 2)),
                }
            }
            let _ = pipeline(&String::from_utf8_lossy(&bytes), name);
            Ok(())
        })
        .unwrap();
}
