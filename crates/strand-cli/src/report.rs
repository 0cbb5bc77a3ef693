//! `strand report RESULT_DIR… --out FILE`: reads each directory's `result.json` and
//! writes one self-contained HTML design review ([`strand_report::report_html`]),
//! atomically. The first result is the reference.

use std::io::Write;
use std::path::{Path, PathBuf};

use strand_report::{
    MotionAxis, OptimumDoc, ReportRun, ReportStudies, ResultDoc, SensitivityDoc, check_result,
    motion_report_html, report_html_with_studies, write_atomic,
};

use crate::Exit;
use crate::commands::Failure;

fn invalid(message: String) -> Failure {
    Failure {
        exit: Exit::InvalidInput,
        message,
    }
}

/// The `result.json` of `dir` (or `dir` itself when it is a file).
fn result_path(dir: &Path) -> PathBuf {
    if dir.is_file() {
        dir.to_path_buf()
    } else {
        dir.join("result.json")
    }
}

/// Reads and checks one result document.
fn load(dir: &Path) -> Result<ResultDoc, Failure> {
    let path = result_path(dir);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        invalid(format!(
            "{}: cannot read the result: {e} (give a directory written by `strand solve --out DIR` or `strand study`)",
            path.display()
        ))
    })?;
    let doc: ResultDoc = serde_json::from_str(&text).map_err(|e| {
        invalid(format!(
            "{}:{}:{}: not a strand result.json: {e} (write it again with `strand solve`)",
            path.display(),
            e.line(),
            e.column()
        ))
    })?;
    check_result(&doc).map_err(|e| invalid(format!("{}: {e}", path.display())))?;
    Ok(doc)
}

/// A study document `name` of result folder `dir`, if the folder holds one.
fn load_study<T: serde::de::DeserializeOwned>(
    dir: &Path,
    name: &str,
) -> Result<Option<T>, Failure> {
    if dir.is_file() {
        return Ok(None);
    }
    let path = dir.join(name);
    let Ok(text) = std::fs::read_to_string(&path) else {
        return Ok(None);
    };
    serde_json::from_str(&text).map(Some).map_err(|e| {
        invalid(format!(
            "{}:{}:{}: not a strand {name}: {e} (write it again with `strand {}`)",
            path.display(),
            e.line(),
            e.column(),
            if name.starts_with("optimum") {
                "optimize"
            } else {
                "sensitivity"
            }
        ))
    })
}

/// Labels: the given ones, else each result's variant or its directory's name; made
/// unique by appending ` (2)`, ` (3)`, ….
fn labels(dirs: &[PathBuf], docs: &[ResultDoc], given: &[String]) -> Vec<String> {
    let mut labels: Vec<String> = Vec::with_capacity(docs.len());
    for (k, (dir, doc)) in dirs.iter().zip(docs).enumerate() {
        let base = given.get(k).cloned().unwrap_or_else(|| {
            doc.variant.clone().unwrap_or_else(|| {
                let dir = if dir.is_file() {
                    dir.parent().unwrap_or(dir)
                } else {
                    dir
                };
                std::fs::canonicalize(dir)
                    .ok()
                    .and_then(|d| d.file_name().map(|n| n.to_string_lossy().into_owned()))
                    .unwrap_or_else(|| format!("result {}", k + 1))
            })
        });
        let mut label = base.clone();
        let mut n = 2;
        while labels.contains(&label) {
            label = format!("{base} ({n})");
            n += 1;
        }
        labels.push(label);
    }
    labels
}

/// Whether `dir` is a `strand motion` output folder (`motion.csv` and `steps/`).
fn is_motion(dir: &Path) -> bool {
    dir.join("motion.csv").is_file() && dir.join("steps").is_dir()
}

/// The poses of a motion folder, in the order of `motion.csv`.
struct MotionDir {
    name: String,
    unit: String,
    values: Vec<f64>,
    dirs: Vec<PathBuf>,
    docs: Vec<ResultDoc>,
}

/// Reads `DIR/motion.csv` (its second column is `<motion> [<unit>]`) and the result of
/// every pose solved (`ok` or `not_converged`; failed poses have no folder).
fn load_motion(dir: &Path) -> Result<MotionDir, Failure> {
    let path = dir.join("motion.csv");
    let bad = |what: String| {
        invalid(format!(
            "{}: {what} (write it again with `strand motion`)",
            path.display()
        ))
    };
    let text = std::fs::read_to_string(&path).map_err(|e| bad(format!("cannot read it: {e}")))?;
    let mut lines = text.lines();
    let header = lines.next().ok_or_else(|| bad("empty file".into()))?;
    let column = header
        .split(',')
        .nth(1)
        .ok_or_else(|| bad("no parameter column".into()))?;
    let (name, unit) = column
        .strip_suffix(']')
        .and_then(|c| c.split_once(" ["))
        .ok_or_else(|| {
            bad(format!(
                "the second column '{column}' is not '<motion> [<unit>]'"
            ))
        })?;
    let mut motion = MotionDir {
        name: name.to_string(),
        unit: unit.to_string(),
        values: Vec::new(),
        dirs: Vec::new(),
        docs: Vec::new(),
    };
    for (k, line) in lines.enumerate() {
        let fields: Vec<&str> = line.split(',').collect();
        let [id, value, status, ..] = fields[..] else {
            return Err(bad(format!("line {}: fewer than 3 columns", k + 2)));
        };
        if id.is_empty() || status == "failed" {
            continue;
        }
        let value: f64 = value
            .parse()
            .map_err(|_| bad(format!("line {}: '{value}' is not a number", k + 2)))?;
        let step = dir.join("steps").join(id);
        motion.docs.push(load(&step)?);
        motion.values.push(value);
        motion.dirs.push(step);
    }
    if motion.docs.is_empty() {
        return Err(bad("no solved pose".into()));
    }
    Ok(motion)
}

pub(crate) fn run(
    dirs: &[PathBuf],
    file: &Path,
    given_labels: &[String],
    title: Option<&str>,
    out: &mut dyn Write,
) -> Result<Exit, Failure> {
    if !given_labels.is_empty() && given_labels.len() != dirs.len() {
        return Err(invalid(format!(
            "--labels: {} label(s) for {} result directories; give one label per directory",
            given_labels.len(),
            dirs.len()
        )));
    }
    let motion = match dirs {
        [dir] if is_motion(dir) => Some(load_motion(dir)?),
        _ => {
            if let Some(dir) = dirs.iter().find(|d| is_motion(d)) {
                return Err(invalid(format!(
                    "{}: a motion folder (motion.csv, steps/) is reported on its own\n  hint: run `strand report {}` alone, or give its poses' folders under steps/",
                    dir.display(),
                    dir.display()
                )));
            }
            None
        }
    };
    let (dirs, docs, axis) = match motion {
        Some(m) => (m.dirs, m.docs, Some((m.name, m.unit, m.values))),
        None => (
            dirs.to_vec(),
            dirs.iter()
                .map(|d| load(d))
                .collect::<Result<Vec<_>, _>>()?,
            None,
        ),
    };
    let dirs = dirs.as_slice();
    if !given_labels.is_empty() && given_labels.len() != dirs.len() {
        return Err(invalid(format!(
            "--labels: {} label(s) for {} poses of the motion; give one label per pose, or none",
            given_labels.len(),
            dirs.len()
        )));
    }
    // The design studies of each folder (a motion's poses have none).
    let sensitivities = dirs
        .iter()
        .map(|d| load_study::<SensitivityDoc>(d, "sensitivity.json"))
        .collect::<Result<Vec<_>, _>>()?;
    let optima = dirs
        .iter()
        .map(|d| load_study::<OptimumDoc>(d, "optimum.json"))
        .collect::<Result<Vec<_>, _>>()?;
    let studies: Vec<ReportStudies> = sensitivities
        .iter()
        .zip(&optima)
        .map(|(s, o)| ReportStudies {
            sensitivity: s.as_ref(),
            optimum: o.as_ref(),
        })
        .collect();
    let labels = labels(dirs, &docs, given_labels);
    let runs: Vec<ReportRun> = labels
        .iter()
        .zip(&docs)
        .map(|(label, doc)| ReportRun { label, doc })
        .collect();
    let mut cases: Vec<&str> = docs.iter().map(|d| d.case.as_str()).collect();
    cases.dedup();
    let title = title
        .map(str::to_string)
        .unwrap_or_else(|| format!("Design review: {}", cases.join(", ")));
    let html = match &axis {
        Some((name, unit, values)) => {
            motion_report_html(&title, &runs, &MotionAxis { name, unit, values })
        }
        None => report_html_with_studies(&title, &runs, &studies),
    };
    let not_written = |message: String| Failure {
        exit: Exit::Failure,
        message: format!("{}: report not written: {message}", file.display()),
    };
    if let Some(parent) = file.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(|e| not_written(e.to_string()))?;
    }
    write_atomic(file, html.as_bytes()).map_err(|e| not_written(e.to_string()))?;
    let _ = writeln!(
        out,
        "report      {} ({} result(s): {}; reference {})",
        file.display(),
        runs.len(),
        labels.join(", "),
        labels.first().map_or("none", String::as_str)
    );
    let shown: Vec<String> = labels
        .iter()
        .zip(&studies)
        .filter_map(|(l, s)| {
            let parts: Vec<&str> = [
                s.sensitivity.map(|_| "sensitivities"),
                s.optimum.map(|_| "optimisation"),
            ]
            .into_iter()
            .flatten()
            .collect();
            (!parts.is_empty()).then(|| format!("{l}: {}", parts.join(" and ")))
        })
        .collect();
    if !shown.is_empty() {
        let _ = writeln!(out, "studies     {}", shown.join("; "));
    }
    let unconverged: Vec<&str> = runs
        .iter()
        .filter(|r| !r.doc.converged)
        .map(|r| r.label)
        .collect();
    if !unconverged.is_empty() {
        let _ = writeln!(
            out,
            "note        not converged (marked in the report): {}",
            unconverged.join(", ")
        );
    }
    let pairs: Vec<(&str, &ResultDoc)> = runs.iter().map(|r| (r.label, r.doc)).collect();
    if let Some(warning) = strand_report::mixed_cases(&pairs) {
        let _ = writeln!(out, "warning     {warning} (said at the top of the report)");
    }
    Ok(Exit::Success)
}
