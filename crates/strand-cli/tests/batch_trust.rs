//! `strand batch` on a shared machine, through the real executable: damaged stored
//! files are found and repaired bit for bit, a batch directory is locked against other
//! batches (but shared by the shards of one), and a killed run's temporary files are
//! removed on resume.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

const GRID: [&str; 4] = [
    "--vary",
    "hose2.length=+0mm..+40mm:10mm",
    "--vary",
    "tee.mass=0.5kg,1kg,1.5kg",
];

fn cooler() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../cases/cooler_hose.ron")
        .to_str()
        .unwrap()
        .to_string()
}

fn command(dir: &Path, extra: &[&str]) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_strand"));
    cmd.arg("batch")
        .arg(cooler())
        .arg("--out")
        .arg(dir)
        .args(extra)
        .env_remove("RUST_BACKTRACE");
    cmd
}

fn output(mut cmd: Command) -> (Option<i32>, String, String) {
    let out = cmd.output().unwrap();
    (
        out.status.code(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

fn batch(dir: &Path, extra: &[&str]) -> (Option<i32>, String, String) {
    output(command(dir, extra))
}

fn spawn(dir: &Path, extra: &[&str]) -> Child {
    command(dir, extra)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

fn finish(child: Child) -> (Option<i32>, String, String) {
    let out = child.wait_with_output().unwrap();
    (
        out.status.code(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

/// `summary.csv` without its `time_s` column (wall-clock times differ run to run).
fn timeless(dir: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(dir.join("summary.csv")).unwrap();
    let rows: Vec<Vec<String>> = text
        .lines()
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    let time = rows[0].iter().position(|h| h == "time_s").unwrap();
    rows.into_iter()
        .map(|mut r| {
            r.remove(time);
            r
        })
        .collect()
}

/// A small seeded generator (SplitMix64), for reproducible damage.
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) % n as u64) as usize
    }
}

fn variant_ids(dir: &Path) -> Vec<String> {
    let mut ids: Vec<String> = std::fs::read_dir(dir.join("variants"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    ids.sort();
    ids
}

/// Every `.strand-*.tmp` file under `dir`.
fn temporaries(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            if path.is_dir() {
                stack.push(path);
            } else if name.starts_with(".strand-") && name.ends_with(".tmp") {
                found.push(path);
            }
        }
    }
    found
}

#[test]
fn truncated_state_and_result_files_are_repaired_bit_for_bit() {
    let tmp = tempfile::tempdir().unwrap();
    let whole = tmp.path().join("whole");
    let (code, out, err) = batch(&whole, &GRID);
    assert_eq!(code, Some(0), "{out}{err}");
    let reference = timeless(&whole);
    let ids = variant_ids(&whole);
    assert_eq!(ids.len(), 15);
    for seed in [1_u64, 2, 3] {
        let mut rng = Rng(seed);
        let dir = tmp.path().join(format!("damaged{seed}"));
        assert_eq!(batch(&dir, &GRID).0, Some(0));
        // Damage 4 variants (state.json or result.json cut at a random byte) and
        // lose 3 others entirely, so that some damaged variants have pending
        // dependants that must start from their (recomputed) states.
        let mut picked: Vec<usize> = Vec::new();
        while picked.len() < 7 {
            let k = rng.below(ids.len());
            if !picked.contains(&k) {
                picked.push(k);
            }
        }
        let mut damaged = Vec::new();
        for &k in &picked[..4] {
            let file = ["state.json", "result.json"][rng.below(2)];
            let path = dir.join("variants").join(&ids[k]).join(file);
            let len = std::fs::metadata(&path).unwrap().len() as usize;
            let cut = rng.below(len);
            File::options()
                .write(true)
                .open(&path)
                .unwrap()
                .set_len(cut as u64)
                .unwrap();
            damaged.push((ids[k].clone(), file));
        }
        for &k in &picked[4..] {
            std::fs::remove_dir_all(dir.join("variants").join(&ids[k])).unwrap();
        }
        let (code, out, err) = batch(&dir, &GRID);
        assert_eq!(code, Some(0), "seed {seed}: {out}{err}");
        assert!(out.contains("computed 7, skipped 8"), "seed {seed}: {out}");
        for (id, file) in &damaged {
            assert!(
                out.contains(&format!("repaired    {id} ({file}: ")),
                "seed {seed}: {id} {file} not reported: {out}"
            );
        }
        assert_eq!(out.matches("repaired    ").count(), 4, "{out}");
        assert_eq!(timeless(&dir), reference, "seed {seed}");
        // Everything repaired: a second resume finds nothing to do.
        let (code, out, _) = batch(&dir, &GRID);
        assert_eq!(code, Some(0));
        assert!(out.contains("computed 0, skipped 15"), "{out}");
    }
}

/// Holds a lock file of `dir` as a running batch would (exclusive or shared),
/// with `content` as its holder record.
fn hold(path: &Path, shared: bool, content: Option<&str>) -> File {
    let file = File::options()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)
        .unwrap();
    if shared {
        file.lock_shared().unwrap();
    } else {
        file.lock().unwrap();
    }
    if let Some(text) = content {
        file.set_len(0).unwrap();
        std::fs::write(path, text).unwrap();
    }
    file
}

/// Runs `run` until `still_held` says its outcome is not a refusal by a lock this
/// process has just dropped, at most 50 times 0.1 s apart. The lock of a dropped file
/// lives on in a child that another test thread of this process forked at that moment
/// until the child calls exec (its copy of the descriptor closes only then): under
/// load that can take a while, and the refusal is then right.
fn once_released<T>(run: impl Fn() -> T, still_held: impl Fn(&T) -> bool) -> T {
    let mut outcome = run();
    for _ in 0..50 {
        if !still_held(&outcome) {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
        outcome = run();
    }
    outcome
}

#[test]
fn a_held_directory_refuses_other_batches_and_admits_the_other_shards() {
    let tmp = tempfile::tempdir().unwrap();
    // A whole batch "running" on another node: refused, naming it; nothing written.
    let dir = tmp.path().join("held");
    std::fs::create_dir_all(&dir).unwrap();
    let holder = r#"{"host":"node7","pid":4242,"role":"the whole batch","shards":0,"batch":"0123456789abcdef","started_unix_s":0}"#;
    let folder = hold(&dir.join(".strand-lock"), false, None);
    let record = hold(&dir.join(".strand-holder-all"), false, Some(holder));
    let (code, _, err) = batch(&dir, &GRID);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("is in use by the whole batch on host node7, PID 4242"),
        "{err}"
    );
    assert!(!dir.join("batch.json").exists() && !dir.join("variants").exists());
    drop((folder, record));
    // Once it is gone (its locks die with it), the directory is free.
    let (code, out, err) = once_released(
        || batch(&dir, &GRID),
        |(code, _, err)| *code == Some(2) && err.contains("is in use"),
    );
    assert_eq!(code, Some(0), "{out}{err}");

    // Shard 1/2 of the batch "running": shard 2/2 proceeds; a second shard 1/2, the
    // whole batch, a 1/3 shard and `strand merge` into the directory are refused.
    let shared = tmp.path().join("shared");
    let shard = |i: &str| {
        let mut args = GRID.to_vec();
        args.extend(["--shard", i]);
        batch(&shared, &args)
    };
    assert_eq!(shard("1/2").0, Some(0));
    let record_path = shared.join(".strand-holder-shard-1-of-2");
    let record_text = std::fs::read_to_string(&record_path).unwrap();
    assert!(record_text.contains("\"pid\": "), "{record_text}");
    let folder = hold(&shared.join(".strand-lock"), true, None);
    let record = hold(&record_path, false, None);
    let (code, out, err) = shard("2/2");
    assert_eq!(code, Some(0), "{out}{err}");
    for (args, code_wanted) in [("1/2", 2), ("1/3", 2)] {
        let (code, _, err) = shard(args);
        assert_eq!(code, Some(code_wanted), "{args}: {err}");
        assert!(err.contains("is in use by shard 1/2 on host"), "{err}");
    }
    let (code, _, err) = batch(&shared, &GRID);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("PID"), "{err}");
    let merge = Command::new(env!("CARGO_BIN_EXE_strand"))
        .arg("merge")
        .arg(&shared)
        .output()
        .unwrap();
    assert_eq!(merge.status.code(), Some(2));
    drop((folder, record));
    let merge = once_released(
        || {
            Command::new(env!("CARGO_BIN_EXE_strand"))
                .arg("merge")
                .arg(&shared)
                .output()
                .unwrap()
        },
        |m| m.status.code() == Some(2) && String::from_utf8_lossy(&m.stderr).contains("is in use"),
    );
    assert_eq!(merge.status.code(), Some(0), "{merge:?}");
    assert_eq!(timeless(&shared), timeless(&dir));
}

/// A longer batch (105 variants on one thread), so that runs overlap.
const LONG: [&str; 6] = [
    "--vary",
    "hose2.length=+0mm..+100mm:5mm",
    "--vary",
    "tee.mass=0.5kg..1.5kg:0.25kg",
    "--jobs",
    "1",
];

#[test]
fn of_two_batches_started_into_one_directory_exactly_one_proceeds() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("race");
    let other = ["--vary", "hose2.length=+0mm..+100mm:5mm", "--jobs", "1"];
    let a = spawn(&dir, &LONG);
    let b = spawn(&dir, &other);
    let (a, b) = (finish(a), finish(b));
    let codes = [a.0, b.0];
    assert!(
        codes.contains(&Some(0)) && codes.contains(&Some(2)),
        "{a:?} {b:?}"
    );
    let long_won = a.0 == Some(0);
    let loser = if long_won { &b } else { &a };
    // The refusal names the other batch's process (running, or the last one).
    assert!(loser.2.contains("PID"), "{}", loser.2);
    let plan = std::fs::read_to_string(dir.join("batch.json")).unwrap();
    assert_eq!(plan.contains("tee.mass"), long_won, "{plan}");
    // The summary belongs to the batch that ran.
    let rows = std::fs::read_to_string(dir.join("summary.csv")).unwrap();
    let width = if long_won { 106 } else { 22 };
    assert_eq!(rows.lines().count(), width);

    // Two shards of one batch into one directory at once: both proceed and merge to
    // the unsharded summary.
    let shared = tmp.path().join("shards");
    let with = |i: &'static str| {
        let mut args = LONG.to_vec();
        args.extend(["--shard", i]);
        args
    };
    let (one, two) = (spawn(&shared, &with("1/2")), spawn(&shared, &with("2/2")));
    let (one, two) = (finish(one), finish(two));
    assert_eq!((one.0, two.0), (Some(0), Some(0)), "{one:?} {two:?}");
    let merge = Command::new(env!("CARGO_BIN_EXE_strand"))
        .arg("merge")
        .arg(&shared)
        .output()
        .unwrap();
    assert_eq!(merge.status.code(), Some(0), "{merge:?}");
    let whole = tmp.path().join("whole");
    assert_eq!(batch(&whole, &LONG).0, Some(0));
    assert_eq!(timeless(&shared), timeless(&whole));
}

#[test]
fn a_killed_batch_leaves_no_temporary_files_after_its_resume() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("killed");
    let mut child = spawn(&dir, &LONG);
    // Kill it once it has written some variants (SIGKILL: nothing is cleaned up).
    loop {
        let done = std::fs::read_dir(dir.join("variants"))
            .map(|e| e.count())
            .unwrap_or(0);
        if done >= 10 || child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::yield_now();
    }
    child.kill().unwrap();
    child.wait().unwrap();
    // Temporary files of dead writers, wherever a writer could have left them.
    let ids = variant_ids(&dir);
    let planted = [
        dir.join(".strand-AbC123.tmp"),
        dir.join("variants")
            .join(&ids[0])
            .join(".strand-XyZ789.tmp"),
    ];
    for p in &planted {
        std::fs::write(p, "partial").unwrap();
    }
    let (code, out, err) = batch(&dir, &LONG);
    assert_eq!(code, Some(0), "{out}{err}");
    assert!(out.contains("cleaned     "), "{out}");
    assert_eq!(temporaries(&dir), Vec::<PathBuf>::new());
    let whole = tmp.path().join("whole");
    assert_eq!(batch(&whole, &LONG).0, Some(0));
    assert_eq!(timeless(&dir), timeless(&whole));

    // A shard removes only the temporary files of the variants it owns (another
    // shard's may be live writes).
    let shared = tmp.path().join("shared");
    let mut args = GRID.to_vec();
    args.extend(["--shard", "1/2"]);
    assert_eq!(batch(&shared, &args).0, Some(0));
    let other_dir = shared.join("variants").join("someone_elses");
    std::fs::create_dir_all(&other_dir).unwrap();
    std::fs::write(other_dir.join(".strand-live01.tmp"), "x").unwrap();
    let mine = variant_ids(&shared)
        .into_iter()
        .find(|id| id != "someone_elses")
        .unwrap();
    std::fs::write(
        shared
            .join("variants")
            .join(&mine)
            .join(".strand-dead01.tmp"),
        "x",
    )
    .unwrap();
    assert_eq!(batch(&shared, &args).0, Some(0));
    assert_eq!(
        temporaries(&shared),
        vec![other_dir.join(".strand-live01.tmp")]
    );
}

#[test]
fn limits_are_checked_before_anything_is_written() {
    let tmp = tempfile::tempdir().unwrap();
    // More threads than cores: capped, with a note.
    let dir = tmp.path().join("capped");
    let mut args = GRID.to_vec();
    args.extend(["--jobs", "100000"]);
    let (code, out, err) = batch(&dir, &args);
    assert_eq!(code, Some(0), "{out}{err}");
    assert!(err.contains("note: --jobs 100000 capped at the"), "{err}");
    assert!(
        out.starts_with("plan        15 variant(s), about "),
        "{out}"
    );
    // Forced beyond the hard maximum, a 1000 × 1000 grid: refused, nothing written.
    let refused = tmp.path().join("refused");
    let mut args = GRID.to_vec();
    args.extend(["--jobs", "100000", "--force-jobs"]);
    let (code, _, err) = batch(&refused, &args);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("at most 1024 worker threads"), "{err}");
    let huge = [
        "--vary",
        "hose2.length=+0mm..+999mm:1mm",
        "--vary",
        "tee.mass=1g..1000g:1g",
    ];
    let (code, _, err) = batch(&refused, &huge);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("1000000 variant(s) ×") && err.contains("pass --yes to go ahead"),
        "{err}"
    );
    assert!(err.contains("--keep summary for about"), "{err}");
    assert!(!refused.exists());
}

#[test]
fn kept_files_shrink_but_the_summary_stays_the_same() {
    let tmp = tempfile::tempdir().unwrap();
    let mut summaries = Vec::new();
    // Without --keep a batch keeps `results`: two files a variant.
    for given in ["all", "results", "summary", ""] {
        let keep = if given.is_empty() { "results" } else { given };
        let dir = tmp
            .path()
            .join(if given.is_empty() { "default" } else { given });
        let mut args = GRID.to_vec();
        if !given.is_empty() {
            args.extend(["--keep", given]);
        }
        let (code, out, err) = batch(&dir, &args);
        assert_eq!(code, Some(0), "{out}{err}");
        assert!(out.contains(&format!("--keep {keep})")), "{out}");
        let variant = dir
            .join("variants")
            .join("hose2.length_p10mm__tee.mass_1.5kg");
        let mut files: Vec<String> = std::fs::read_dir(&variant)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
            .collect();
        files.sort();
        let expected: &[&str] = match keep {
            "all" => &[
                "hose1.csv",
                "hose2.csv",
                "hose3.csv",
                "result.json",
                "rods.vtp",
                "state.json",
                "tubes.obj",
                "tubes.stl",
            ],
            _ => &["result.json", "state.json"],
        };
        assert_eq!(files, expected, "{keep}");
        summaries.push(timeless(&dir));
        // A resume trusts the kept files (their checksums pass).
        let (code, out, _) = batch(&dir, &args);
        assert_eq!(code, Some(0));
        assert!(out.contains("computed 0, skipped 15"), "{keep}: {out}");
    }
    assert_eq!(summaries[1], summaries[0]);
    assert_eq!(summaries[2], summaries[0]);
    assert_eq!(summaries[3], summaries[0]);
}
