//! Helpers shared by the tests that run the real `strand` executable.

use std::path::Path;
use std::process::Command;

/// The path of a bundled case, `cases/<name>`.
pub fn case(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../cases")
        .join(name)
        .to_str()
        .unwrap()
        .to_string()
}

/// Runs `strand` with `args`: exit code, stdout and stderr.
pub fn strand(args: &[&str]) -> (Option<i32>, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_strand"))
        .args(args)
        .env_remove("RUST_BACKTRACE")
        .output()
        .unwrap();
    let text = |b: Vec<u8>| String::from_utf8(b).unwrap();
    (
        output.status.code(),
        text(output.stdout),
        text(output.stderr),
    )
}

/// The JSON document at `path` (a `result.json`, `optimum.json`, …).
pub fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}
