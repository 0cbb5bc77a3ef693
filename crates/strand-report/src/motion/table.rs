//! `DIR/motion.csv`: one row per pose, in order of the motion parameter.
//!
//! Columns: `id` (the pose's folder under `DIR/steps/`); the parameter with its unit
//! (`engine_roll [deg]`); `status` (`ok`, `not_converged`, `failed`); `warm_start`;
//! `iterations` (Newton iterations of every solve since the previous pose, rejected
//! steps included); `solves`; `residual_N`; `stable`; per rod `<rod> peak |f| [N]`,
//! `<rod> peak |m| [N·m]` and `<rod> min bend radius [<unit>]`; per obstacle (mesh
//! or rod within the contact margin) `min clearance to <obstacle> [<unit>]` (empty
//! where nothing came within the margin); per reaction (connector, port)
//! `<name> |F| [N]` and `<name> |M| [N·m]`. Lengths are in the case's unit.

use crate::ResultDoc;
use crate::study::magnitude;

/// One pose of a motion for the table.
#[derive(Clone, Debug)]
pub struct MotionRow<'a> {
    /// The pose's folder name under `DIR/steps/`.
    pub id: String,
    /// Parameter value, in the motion's unit.
    pub value: f64,
    /// The pose's result (`None`: the pose failed).
    pub doc: Option<&'a ResultDoc>,
    /// Solves taken since the previous pose.
    pub solves: usize,
    /// Newton iterations of those solves.
    pub iterations: usize,
}

/// Largest `|v|` of a list of vectors (0 for none).
pub(crate) fn peak(values: &[[f64; 3]]) -> f64 {
    values.iter().map(magnitude).fold(0.0, f64::max)
}

/// Smallest bend radius `1 / |(K1, K2)|` over the vertices, m (infinite if straight).
pub(crate) fn min_bend_radius(curvatures: &[[f64; 3]]) -> f64 {
    1.0 / curvatures
        .iter()
        .map(|k| k[0].hypot(k[1]))
        .fold(0.0, f64::max)
}

/// Smallest clearance of any rod to `with` in `doc`, m.
pub(crate) fn clearance_to(doc: &ResultDoc, with: &str) -> Option<f64> {
    doc.clearance
        .iter()
        .filter(|c| c.with == with)
        .map(|c| c.distance_m)
        .reduce(f64::min)
}

/// Names in order of first appearance over the rows' results.
pub(crate) fn union<'a>(
    rows: impl Iterator<Item = &'a ResultDoc>,
    names: impl Fn(&'a ResultDoc) -> Vec<&'a str>,
) -> Vec<&'a str> {
    let mut all: Vec<&str> = Vec::new();
    for doc in rows {
        for n in names(doc) {
            if !all.contains(&n) {
                all.push(n);
            }
        }
    }
    all
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

fn field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// The motion table: `rows` in order of the parameter `parameter` measured in
/// `unit`; lengths in the case's unit (`metres` m per unit named `length_unit`).
pub fn motion_csv(
    parameter: &str,
    unit: &str,
    rows: &[MotionRow],
    metres: f64,
    length_unit: &str,
) -> String {
    let docs = || rows.iter().filter_map(|r| r.doc);
    let rods = union(docs(), |d| d.rods.iter().map(|r| r.name.as_str()).collect());
    let obstacles = union(docs(), |d| {
        d.clearance.iter().map(|c| c.with.as_str()).collect()
    });
    let reactions = union(docs(), |d| {
        d.reactions.iter().map(|r| r.name.as_str()).collect()
    });
    let mut header: Vec<String> = vec!["id".into(), format!("{parameter} [{unit}]")];
    header.extend(
        [
            "status",
            "warm_start",
            "iterations",
            "solves",
            "residual_N",
            "stable",
        ]
        .map(String::from),
    );
    for r in &rods {
        header.push(format!("{r} peak |f| [N]"));
        header.push(format!("{r} peak |m| [N·m]"));
        header.push(format!("{r} min bend radius [{length_unit}]"));
    }
    for o in &obstacles {
        header.push(format!("min clearance to {o} [{length_unit}]"));
    }
    for a in &reactions {
        header.push(format!("{a} |F| [N]"));
        header.push(format!("{a} |M| [N·m]"));
    }
    let mut csv = header
        .iter()
        .map(|h| field(h))
        .collect::<Vec<_>>()
        .join(",");
    csv.push('\n');
    for row in rows {
        let mut cells = vec![field(&row.id), num(row.value)];
        match row.doc {
            None => {
                cells.push("failed".into());
                cells.resize(header.len(), String::new());
                cells[4] = row.iterations.to_string();
                cells[5] = row.solves.to_string();
            }
            Some(doc) => {
                cells.push(if doc.converged { "ok" } else { "not_converged" }.into());
                cells.push(doc.warm_start.to_string());
                cells.push(row.iterations.to_string());
                cells.push(row.solves.to_string());
                cells.push(num(doc.residual_n));
                cells.push(doc.stable.to_string());
                for r in &rods {
                    match doc.rods.iter().find(|x| x.name == *r) {
                        Some(rod) => {
                            cells.push(num(peak(&rod.force_n)));
                            cells.push(num(peak(&rod.moment_nm)));
                            cells.push(num(min_bend_radius(&rod.curvature_1pm) / metres));
                        }
                        None => cells.extend([String::new(), String::new(), String::new()]),
                    }
                }
                for o in &obstacles {
                    cells.push(clearance_to(doc, o).map_or(String::new(), |d| num(d / metres)));
                }
                for a in &reactions {
                    match doc.reactions.iter().find(|x| x.name == *a) {
                        Some(r) => {
                            cells.push(num(magnitude(&r.force_n)));
                            cells.push(num(magnitude(&r.moment_nm)));
                        }
                        None => cells.extend([String::new(), String::new()]),
                    }
                }
            }
        }
        csv.push_str(&cells.join(","));
        csv.push('\n');
    }
    csv
}
