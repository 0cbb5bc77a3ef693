//! Events between consecutive poses of a motion, found by comparing their results: a
//! contact closing or opening, a clip reaching or leaving a joint limit, a limit
//! (`min_bend_radius`, `min_clearance`) crossed. Snap-throughs and stability changes
//! come from the path following itself (`strand_case::motion::MotionEvent`).

use serde::Serialize;

use crate::{FindingKind, ResultDoc};

/// One event of a motion, for `DIR/events.csv` and the plot.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MotionEventRecord {
    /// `contact_closed`, `contact_opened`, `clip_at_limit`, `clip_off_limit`,
    /// `<limit>_limit_crossed` and `<limit>_limit_cleared` for the limits
    /// `bend_radius`, `clearance`, `connector_force`, `connector_moment`, `snap_through`,
    /// `stability_lost`, `stability_regained`.
    pub kind: String,
    /// What it concerns (`hose3 / brackets`, a clip's name).
    pub what: String,
    /// The last pose before it and the first after it, motion's unit.
    pub between: [f64; 2],
    /// Best estimate of where it happens, motion's unit: for a contact closing, where
    /// the clearance of the two poses before extrapolates to zero (within `between`);
    /// otherwise the first pose after it.
    pub at: f64,
    /// Details for people.
    pub detail: String,
}

fn record(
    kind: &str,
    what: String,
    between: [f64; 2],
    at: f64,
    detail: String,
) -> MotionEventRecord {
    MotionEventRecord {
        kind: kind.to_string(),
        what,
        between,
        at,
        detail,
    }
}

fn pairs(doc: &ResultDoc) -> Vec<(String, String)> {
    let mut p: Vec<(String, String)> = doc
        .contacts
        .iter()
        .map(|c| (c.rod.clone(), c.with.clone()))
        .collect();
    p.sort();
    p.dedup();
    p
}

fn clearance_of(doc: &ResultDoc, rod: &str, with: &str) -> Option<f64> {
    doc.clearance
        .iter()
        .filter(|c| c.rod == rod && c.with == with)
        .map(|c| c.distance_m)
        .reduce(f64::min)
}

/// Where the clearance of `(rod, with)` at poses `earlier`, `previous` extrapolates to
/// zero, clamped to `[previous, next]` (the midpoint if it cannot be extrapolated).
fn closing_at(
    earlier: Option<(f64, &ResultDoc)>,
    previous: (f64, &ResultDoc),
    next: f64,
    rod: &str,
    with: &str,
) -> f64 {
    let mid = 0.5 * (previous.0 + next);
    let Some((v0, d0)) = earlier.and_then(|(v, doc)| clearance_of(doc, rod, with).map(|d| (v, d)))
    else {
        return mid;
    };
    let Some(d1) = clearance_of(previous.1, rod, with) else {
        return mid;
    };
    let v1 = previous.0;
    if d0 <= d1 || d1 < 0.0 {
        return mid;
    }
    let at = v1 + d1 * (v1 - v0) / (d0 - d1);
    let (lo, hi) = if v1 < next { (v1, next) } else { (next, v1) };
    at.clamp(lo, hi)
}

/// The events between pose `previous` (value, result) and pose `next`; `earlier` is
/// the pose before `previous` (for extrapolating a clearance to zero), if any.
pub fn doc_events(
    earlier: Option<(f64, &ResultDoc)>,
    previous: (f64, &ResultDoc),
    next: (f64, &ResultDoc),
) -> Vec<MotionEventRecord> {
    let between = [previous.0, next.0];
    let mut out = Vec::new();
    let (before, after) = (pairs(previous.1), pairs(next.1));
    for (rod, with) in after.iter().filter(|p| !before.contains(p)) {
        let at = closing_at(earlier, previous, next.0, rod, with);
        let force: f64 = next
            .1
            .contacts
            .iter()
            .filter(|c| &c.rod == rod && &c.with == with)
            .map(|c| c.force_n)
            .sum();
        out.push(record(
            "contact_closed",
            format!("{rod} / {with}"),
            between,
            at,
            format!("contact force {force:.4} N after it"),
        ));
    }
    for (rod, with) in before.iter().filter(|p| !after.contains(p)) {
        let gap = clearance_of(next.1, rod, with)
            .map_or(String::new(), |d| format!("clearance {:.4e} m after it", d));
        out.push(record(
            "contact_opened",
            format!("{rod} / {with}"),
            between,
            next.0,
            gap,
        ));
    }
    for clip in &next.1.clips {
        let was = previous
            .1
            .clips
            .iter()
            .find(|c| c.name == clip.name)
            .is_some_and(|c| c.at_limit);
        if clip.at_limit != was {
            let kind = if clip.at_limit {
                "clip_at_limit"
            } else {
                "clip_off_limit"
            };
            out.push(record(
                kind,
                clip.name.clone(),
                between,
                next.0,
                String::new(),
            ));
        }
    }
    let key = |f: &crate::Finding| (f.kind, f.rod.clone(), f.with.clone());
    let name = |k: FindingKind| match k {
        FindingKind::BendRadius => "bend_radius",
        FindingKind::Clearance => "clearance",
        FindingKind::ConnectorForce => "connector_force",
        FindingKind::ConnectorMoment => "connector_moment",
    };
    let what = |f: &crate::Finding| match &f.with {
        Some(w) => format!("{} / {w}", f.rod),
        None => f.rod.clone(),
    };
    for f in &next.1.findings {
        if !previous.1.findings.iter().any(|g| key(g) == key(f)) {
            out.push(record(
                &format!("{}_limit_crossed", name(f.kind)),
                what(f),
                between,
                next.0,
                f.describe(1.0, "m"),
            ));
        }
    }
    for f in &previous.1.findings {
        if !next.1.findings.iter().any(|g| key(g) == key(f)) {
            out.push(record(
                &format!("{}_limit_cleared", name(f.kind)),
                what(f),
                between,
                next.0,
                String::new(),
            ));
        }
    }
    out
}

/// `DIR/events.csv`: `kind,what,from [unit],to [unit],at [unit],detail`.
pub fn events_csv(events: &[MotionEventRecord], unit: &str) -> String {
    let field = |t: &str| {
        if t.contains([',', '"', '\n']) {
            format!("\"{}\"", t.replace('"', "\"\""))
        } else {
            t.to_string()
        }
    };
    let mut csv = format!("kind,what,from [{unit}],to [{unit}],at [{unit}],detail\n");
    for e in events {
        csv.push_str(&format!(
            "{},{},{},{},{},{}\n",
            field(&e.kind),
            field(&e.what),
            e.between[0],
            e.between[1],
            e.at,
            field(&e.detail)
        ));
    }
    csv
}
