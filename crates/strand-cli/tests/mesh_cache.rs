//! The on-disk mesh cache through the real executable (issue 11): two `strand solve`
//! processes building the same mesh at once both succeed; later runs read the cache and
//! give exactly the same solution and contacts as a run without it; a corrupt cache
//! file is replaced.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// A wavy 600 x 600 mm floor 80 mm under a cable of 500 mm hung between points 400 mm
/// apart (it rests on the floor), the floor finely meshed so that its OBJ is above the
/// cache's 1 MiB threshold.
fn write_case(dir: &Path) -> PathBuf {
    let n = 140;
    let mut obj = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (
                -100.0 + 600.0 * i as f64 / n as f64,
                -300.0 + 600.0 * j as f64 / n as f64,
            );
            let z = -80.0 + 3.0 * (x / 40.0).sin() * (y / 40.0).cos();
            writeln!(obj, "v {x} {y} {z}").unwrap();
        }
    }
    let index = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (
                index(i, j),
                index(i + 1, j),
                index(i + 1, j + 1),
                index(i, j + 1),
            );
            writeln!(obj, "f {a} {b} {c}\nf {a} {c} {d}").unwrap();
        }
    }
    assert!(obj.len() > 1 << 20, "{} bytes", obj.len());
    std::fs::write(dir.join("floor.obj"), obj).unwrap();
    let case = dir.join("case.ron");
    std::fs::write(
        &case,
        r#"(
    units: (length: "mm"),
    sections: {
        "cable6": Explicit(ea: 20e3, ga: 5e3, ei: 5e-3, gj: 3.8e-3, mass_per_length: 0.1,
                           outer_radius: 3),
    },
    connectors: {
        "a": (position: (0, 0, 0), direction: (1, 0, 0), normal: (0, 0, 1)),
        "b": (position: (400, 0, 0), direction: (-1, 0, 0), normal: (0, 0, 1)),
    },
    rods: [
        (name: "cable", section: "cable6", length: 500, segments: 50,
         start: Connector("a"), end: Connector("b")),
    ],
    environment: [(name: "floor", obj: "floor.obj", unit: "mm")],
    gravity: (0, 0, -9.81),
)
"#,
    )
    .unwrap();
    case
}

fn solve(case: &Path, out: &Path, cache: &Path, extra_env: &[(&str, &str)]) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_strand"));
    cmd.arg("solve")
        .arg(case)
        .arg("--out")
        .arg(out)
        .env("STRAND_CACHE_DIR", cache)
        .env_remove("STRAND_MESH_CACHE")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    for (name, value) in extra_env {
        cmd.env(name, value);
    }
    cmd
}

/// The run's solution (the rod CSV), its contact lines, its cache state in result.json
/// and its terminal output.
struct Run {
    csv: Vec<u8>,
    contacts: Vec<String>,
    cache: String,
    stdout: String,
}

fn finish(output: Output, out: &Path) -> Run {
    let stdout = String::from_utf8(output.stdout).unwrap();
    assert_eq!(
        output.status.code(),
        Some(0),
        "{stdout}\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let result: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("result.json")).unwrap()).unwrap();
    let floor = &result["environment"][0]["diagnostics"];
    Run {
        csv: std::fs::read(out.join("cable.csv")).unwrap(),
        contacts: stdout
            .lines()
            .filter(|l| l.starts_with("  cable at s ="))
            .map(str::to_string)
            .collect(),
        cache: floor["cache"].as_str().unwrap().to_string(),
        stdout,
    }
}

#[test]
fn concurrent_solves_share_the_mesh_cache_and_agree_with_a_solve_without_it() {
    let dir = tempfile::tempdir().unwrap();
    let case = write_case(dir.path());
    let cache = dir.path().join("cache");
    let out = |name: &str| dir.path().join(name);

    let reference = finish(
        solve(&case, &out("off"), &cache, &[("STRAND_MESH_CACHE", "off")])
            .output()
            .unwrap(),
        &out("off"),
    );
    assert_eq!(reference.cache, "off");
    assert!(!cache.exists(), "the cache was off");
    assert!(!reference.contacts.is_empty(), "{}", reference.stdout);

    // Two processes building the same mesh at once.
    let first = solve(&case, &out("a"), &cache, &[]).spawn().unwrap();
    let second = solve(&case, &out("b"), &cache, &[]).spawn().unwrap();
    let runs = [
        finish(first.wait_with_output().unwrap(), &out("a")),
        finish(second.wait_with_output().unwrap(), &out("b")),
    ];
    let files: Vec<_> = std::fs::read_dir(&cache).unwrap().collect();
    assert_eq!(files.len(), 1, "one cache file, no temporary left");
    let file = files[0].as_ref().unwrap().path();

    // A later run reads it.
    let hit = finish(
        solve(&case, &out("hit"), &cache, &[]).output().unwrap(),
        &out("hit"),
    );
    assert_eq!(hit.cache, "hit");
    assert!(
        hit.stdout.contains("floor  read from the mesh cache"),
        "{}",
        hit.stdout
    );

    // A corrupt cache file is replaced.
    let mut bytes = std::fs::read(&file).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0xff;
    std::fs::write(&file, &bytes).unwrap();
    let repaired = finish(
        solve(&case, &out("repaired"), &cache, &[])
            .output()
            .unwrap(),
        &out("repaired"),
    );
    assert_eq!(repaired.cache, "replaced", "{}", repaired.stdout);
    let again = finish(
        solve(&case, &out("again"), &cache, &[]).output().unwrap(),
        &out("again"),
    );
    assert_eq!(again.cache, "hit");

    for run in runs.iter().chain([&hit, &repaired, &again]) {
        assert!(matches!(run.cache.as_str(), "written" | "hit" | "replaced"));
        assert_eq!(run.csv, reference.csv, "the same solution, bit for bit");
        assert_eq!(run.contacts, reference.contacts);
    }
}
