//! `DIR/summary.csv`: one row per variant, in grid order, made from the files in
//! `DIR/variants/` only (so a merged batch gives the same file as an unsharded one).
//!
//! Columns: `id`; one per parameter (`hose2.length [mm]`, the value as written);
//! `status` (`ok`, `failed`, `missing`), `stage` and `reason` of a failure;
//! `warm_start`; `residual_N`; `iterations`; `time_s`; per rod `<rod> peak |f| [N]`
//! and `<rod> peak |m| [N·m]`; per attachment (connector, port, clip)
//! `<name> max |reaction| [N]`; `min clearance [m]` (empty without contact
//! geometry); per rod `<rod> min bend radius [m]`, `<rod> allowed bend radius [m]`
//! (the section's `min_bend_radius`, empty if none) and `<rod> bend ok`.

use std::path::Path;

use strand_report::{ResultDoc, magnitude};

use super::manifest::Manifest;
use super::state::FailedVariant;

/// What the directory of one variant holds.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub enum Outcome {
    /// A converged result.
    Solved(Box<ResultDoc>),
    /// A recorded failure.
    Failed(FailedVariant),
    /// Nothing (not run yet, or another shard's).
    Missing,
}

/// Reads the outcome of the variant in `dir` (`DIR/variants/<id>`).
pub fn read_outcome(dir: &Path) -> Result<Outcome, String> {
    let read = |name: &str| -> Result<Option<String>, String> {
        let path = dir.join(name);
        match std::fs::read_to_string(&path) {
            Ok(text) => Ok(Some(text)),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(format!("cannot read {}: {e}", path.display())),
        }
    };
    let bad = |name: &str, e: serde_json::Error| {
        format!(
            "{} is damaged ({e}); delete it to solve the variant again",
            dir.join(name).display()
        )
    };
    if let Some(text) = read("result.json")? {
        let doc = serde_json::from_str(&text).map_err(|e| bad("result.json", e))?;
        return Ok(Outcome::Solved(Box::new(doc)));
    }
    if let Some(text) = read("failed.json")? {
        let failed = serde_json::from_str(&text).map_err(|e| bad("failed.json", e))?;
        return Ok(Outcome::Failed(failed));
    }
    Ok(Outcome::Missing)
}

/// Largest `|v|` of a list of vectors (0 for none).
pub(crate) fn peak(values: &[[f64; 3]]) -> f64 {
    values.iter().map(magnitude).fold(0.0, f64::max)
}

/// Smallest bend radius `1 / |(K1, K2)|` over the vertices, m (infinite if straight).
pub(crate) fn min_bend_radius(curvatures: &[[f64; 3]]) -> f64 {
    let most = curvatures
        .iter()
        .map(|k| k[0].hypot(k[1]))
        .fold(0.0, f64::max);
    1.0 / most
}

/// Names in order of first appearance over the solved variants.
fn union<'a>(
    outcomes: &'a [Outcome],
    names: impl Fn(&'a ResultDoc) -> Vec<&'a str>,
) -> Vec<&'a str> {
    let mut all: Vec<&str> = Vec::new();
    for o in outcomes {
        if let Outcome::Solved(doc) = o {
            for n in names(doc) {
                if !all.contains(&n) {
                    all.push(n);
                }
            }
        }
    }
    all
}

/// A CSV field, quoted when needed.
fn field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x}")
    } else if x > 0.0 {
        "inf".into()
    } else {
        String::new()
    }
}

/// The summary CSV of `manifest`'s variants with their `outcomes` (same order).
pub fn summary_csv(manifest: &Manifest, outcomes: &[Outcome]) -> String {
    let rods = union(outcomes, |d| {
        d.rods.iter().map(|r| r.name.as_str()).collect()
    });
    let attachments = union(outcomes, |d| {
        d.reactions.iter().map(|r| r.name.as_str()).collect()
    });
    let mut header: Vec<String> = vec!["id".into()];
    for p in &manifest.parameters {
        header.push(if p.unit.is_empty() {
            p.label.clone()
        } else {
            format!("{} [{}]", p.label, p.unit)
        });
    }
    header.extend(
        [
            "status",
            "stage",
            "reason",
            "warm_start",
            "residual_N",
            "iterations",
            "time_s",
        ]
        .map(String::from),
    );
    for r in &rods {
        header.push(format!("{r} peak |f| [N]"));
        header.push(format!("{r} peak |m| [N·m]"));
    }
    for a in &attachments {
        header.push(format!("{a} max |reaction| [N]"));
    }
    header.push("min clearance [m]".into());
    for r in &rods {
        header.push(format!("{r} min bend radius [m]"));
        header.push(format!("{r} allowed bend radius [m]"));
        header.push(format!("{r} bend ok"));
    }
    let mut csv = header
        .iter()
        .map(|h| field(h))
        .collect::<Vec<_>>()
        .join(",");
    csv.push('\n');
    for (entry, outcome) in manifest.variants.iter().zip(outcomes) {
        let mut row: Vec<String> = vec![entry.id.clone()];
        for (p, &k) in manifest.parameters.iter().zip(&entry.index) {
            row.push(p.texts[k].clone());
        }
        let blanks = 2 * rods.len() + attachments.len() + 1 + 3 * rods.len();
        match outcome {
            Outcome::Missing => {
                row.extend(["missing", "", "", "", "", "", ""].map(String::from));
                row.extend(std::iter::repeat_n(String::new(), blanks));
            }
            Outcome::Failed(f) => {
                row.push("failed".into());
                row.push(f.stage.clone());
                row.push(f.reason.clone());
                row.push(f.warm_start.to_string());
                row.push(f.residual_n.map(num).unwrap_or_default());
                row.push(f.iterations.map(|i| i.to_string()).unwrap_or_default());
                row.push(num(f.time_s));
                row.extend(std::iter::repeat_n(String::new(), blanks));
            }
            Outcome::Solved(doc) => {
                row.extend([
                    if doc.converged { "ok" } else { "failed" }.to_string(),
                    String::new(),
                    if doc.converged {
                        String::new()
                    } else {
                        format!("not converged ({})", doc.termination)
                    },
                    doc.warm_start.to_string(),
                    num(doc.residual_n),
                    doc.iterations.to_string(),
                    num(doc.timing_s.total),
                ]);
                let rod = |name: &str| doc.rods.iter().find(|r| r.name == name);
                for r in &rods {
                    let found = rod(r);
                    row.push(found.map(|r| num(peak(&r.force_n))).unwrap_or_default());
                    row.push(found.map(|r| num(peak(&r.moment_nm))).unwrap_or_default());
                }
                for a in &attachments {
                    let most = doc
                        .reactions
                        .iter()
                        .filter(|r| r.name == *a)
                        .map(|r| magnitude(&r.force_n))
                        .fold(f64::NAN, f64::max);
                    row.push(num(most));
                }
                let clearance = doc
                    .clearance
                    .iter()
                    .map(|c| c.distance_m)
                    .fold(f64::NAN, f64::min);
                row.push(num(clearance));
                for r in &rods {
                    match rod(r) {
                        None => row.extend([String::new(), String::new(), String::new()]),
                        Some(r) => {
                            let radius = min_bend_radius(&r.curvature_1pm);
                            row.push(num(radius));
                            row.push(r.min_bend_radius_m.map(num).unwrap_or_default());
                            row.push(
                                r.min_bend_radius_m
                                    .map(|a| (radius >= a).to_string())
                                    .unwrap_or_default(),
                            );
                        }
                    }
                }
            }
        }
        csv.push_str(&row.iter().map(|c| field(c)).collect::<Vec<_>>().join(","));
        csv.push('\n');
    }
    csv
}
