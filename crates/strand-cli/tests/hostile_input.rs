//! Hostile input through the real executable: everything that becomes a file name, a
//! path or a loop bound is checked before anything is written — exit 2, the item
//! named, a hint, and no output folder.

use std::path::{Path, PathBuf};
use std::process::Command;

fn cooler_text() -> String {
    std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases/cooler_hose.ron"),
    )
    .unwrap()
}

fn strand(args: &[&str]) -> (Option<i32>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_strand"))
        .args(args)
        .env_remove("RUST_BACKTRACE")
        .output()
        .unwrap();
    (out.status.code(), String::from_utf8(out.stderr).unwrap())
}

/// Writes `text` as a case file in `dir`.
fn case(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

fn refused(args: &[&str], out: &Path, needles: &[&str]) {
    let (code, err) = strand(args);
    assert_eq!(code, Some(2), "{args:?}: {err}");
    for needle in needles {
        assert!(err.contains(needle), "{args:?}: no '{needle}' in {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out.exists(), "{args:?} wrote {}", out.display());
}

#[test]
fn hostile_names_values_and_bounds_are_refused_before_anything_is_written() {
    let tmp = tempfile::tempdir().unwrap();
    let out: PathBuf = tmp.path().join("out");
    let o = out.to_str().unwrap();
    let text = cooler_text();

    let long_rod = case(
        tmp.path(),
        "long_rod.ron",
        &text.replace(
            "name: \"hose2\"",
            &format!("name: \"{}\"", "h".repeat(10_000)),
        ),
    );
    refused(
        &["solve", &long_rod, "--out", o],
        &out,
        &["rod 'hhhh", "10000 bytes; at most 200", "hint: "],
    );
    let long_variant = case(
        tmp.path(),
        "long_variant.ron",
        &text.replace("\"hose2_plus50\":", &format!("\"{}\":", "v".repeat(300))),
    );
    refused(
        &["study", &long_variant, "--out", o],
        &out,
        &["variant 'vvvv", "300 bytes", "hint: "],
    );
    let far = case(
        tmp.path(),
        "far.ron",
        &text.replacen("length: 190", "length: 1e300", 1),
    );
    refused(
        &["solve", &far, "--out", o],
        &out,
        &["rods.hose2.length: 1e300 mm is beyond", "hint: "],
    );
    let cooler = case(tmp.path(), "cooler.ron", &text);
    for (vary, needle) in [
        ("hose2.length=1e308mm", "is too large"),
        ("hose2.length=+0mm,+1e308m", "overflows"),
        ("hose2.segments=1000000", "at most 100000 per rod"),
    ] {
        refused(
            &["batch", &cooler, "--vary", vary, "--out", o],
            &out,
            &[&format!("--vary {vary}: "), needle, "hint: "],
        );
    }
    let deep = tmp.path().join("d".repeat(200)).join("e".repeat(200));
    let deep_out = (0..20).fold(deep, |p, k| p.join(format!("{k}{}", "x".repeat(190))));
    refused(
        &[
            "batch",
            &cooler,
            "--vary",
            "hose2.length=+0mm,+10mm",
            "--out",
            deep_out.to_str().unwrap(),
        ],
        &tmp.path().join("d".repeat(200)),
        &["bytes long; at most 4000", "hint: use a shorter --out"],
    );
    refused(
        &["check", &cooler, "--segments", "10000000"],
        &out,
        &["--segments", "1..=100000"],
    );
    refused(
        &["bench", "--repeats", "0"],
        &out,
        &["--repeats", "1..=10000"],
    );
    let slow = case(
        tmp.path(),
        "slow.ron",
        &text.replacen(
            "units: (",
            "solver: (max_line_search_steps: 1000000000),\n    units: (",
            1,
        ),
    );
    refused(
        &["solve", &slow, "--out", o],
        &out,
        &["max_line_search_steps"],
    );
}
