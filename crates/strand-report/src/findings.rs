//! Findings: the places where a solved design violates a limit its case states
//! (`result.json`: `findings`; printed by `strand solve`; the first section of the HTML
//! report). Two limits are checked:
//!
//! - **bend radius** — the section's `min_bend_radius` (`RodResult::min_bend_radius_m`)
//!   against the bend radius `1/|(K1, K2)|` at the vertices: one finding per
//!   contiguous stretch of vertices bent tighter than allowed, at its tightest vertex;
//! - **clearance** — the rod's `min_clearance` (`RodResult::min_clearance_m`) against
//!   its smallest surface-to-surface distance to every mesh and every other rod
//!   (`result.json`: `clearance`; 0 at contact): one finding per obstacle closer than
//!   required.
//!
//! The findings are a pure function of the document ([`find`]), so `report` finds the
//! same in an older `result.json` as `solve` wrote into a new one.

use std::fmt::Write;

use serde::{Deserialize, Serialize};

use crate::result::{ResultDoc, RodResult};

/// What limit a finding violates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FindingKind {
    /// The hose is bent tighter than its section's `min_bend_radius`.
    BendRadius,
    /// The hose comes closer to an obstacle than its `min_clearance`.
    Clearance,
}

impl FindingKind {
    /// Words for people: `bend radius`, `clearance`.
    pub fn words(self) -> &'static str {
        match self {
            FindingKind::BendRadius => "bend radius",
            FindingKind::Clearance => "clearance",
        }
    }
}

/// One violated limit.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Finding {
    /// The limit violated.
    pub kind: FindingKind,
    /// The hose (rod).
    pub rod: String,
    /// For a clearance: the obstacle (an environment mesh or another rod).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub with: Option<String>,
    /// Where: reference arc length from the rod's start of the worst point, m.
    pub s_m: f64,
    /// For a bend radius: the stretch of arc length bent tighter than allowed,
    /// `[from, to]`, m (the vertices where it is violated).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stretch_m: Option<[f64; 2]>,
    /// The value found (bend radius or clearance), m.
    pub value_m: f64,
    /// The limit (allowed minimum bend radius or required clearance), m.
    pub limit_m: f64,
}

impl Finding {
    /// One line for people, lengths in the unit of `metres` metres per unit named
    /// `symbol` (e.g. `0.001`, `"mm"`): `hose3: bend radius 52.1 mm < 60 mm allowed at
    /// s = 120 mm (110 to 130 mm)`, `hose3: clearance to brackets 0 mm < 5 mm required
    /// at s = 120 mm`.
    pub fn describe(&self, metres: f64, symbol: &str) -> String {
        let l = |v: f64| format!("{} {symbol}", number(v / metres));
        let mut text = match self.kind {
            FindingKind::BendRadius => format!(
                "{}: bend radius {} < {} allowed at s = {}",
                self.rod,
                l(self.value_m),
                l(self.limit_m),
                l(self.s_m)
            ),
            FindingKind::Clearance => format!(
                "{}: clearance to {} {} < {} required at s = {}",
                self.rod,
                self.with.as_deref().unwrap_or("?"),
                l(self.value_m),
                l(self.limit_m),
                l(self.s_m)
            ),
        };
        if let Some([from, to]) = self.stretch_m
            && from < to
        {
            let _ = write!(text, " ({} to {})", number(from / metres), l(to));
        }
        text
    }
}

/// `value` with 4 significant digits, trailing zeros dropped (`52.1`, `0`, `1.235e-5`).
pub fn number(value: f64) -> String {
    let text = crate::report::sig(value);
    if text.contains('.') && !text.contains('e') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// The bend radius `1/|(K1, K2)|` of every vertex of `rod`, m (infinite where straight).
pub fn bend_radii(rod: &RodResult) -> Vec<f64> {
    rod.curvature_1pm
        .iter()
        .map(|k| 1.0 / k[0].hypot(k[1]))
        .collect()
}

/// Every finding of `doc`, rod by rod in document order: bend radius first, then
/// clearances by obstacle name.
pub fn find(doc: &ResultDoc) -> Vec<Finding> {
    let mut findings = Vec::new();
    for rod in &doc.rods {
        if let Some(limit) = rod.min_bend_radius_m {
            bend_findings(rod, limit, &mut findings);
        }
        if let Some(limit) = rod.min_clearance_m {
            let mut close: Vec<_> = doc
                .clearance
                .iter()
                .filter(|c| c.rod == rod.name && violates(c.distance_m, limit))
                .collect();
            close.sort_by(|a, b| a.with.cmp(&b.with));
            findings.extend(close.into_iter().map(|c| Finding {
                kind: FindingKind::Clearance,
                rod: rod.name.clone(),
                with: Some(c.with.clone()),
                s_m: c.s_m,
                stretch_m: None,
                value_m: c.distance_m,
                limit_m: limit,
            }));
        }
    }
    findings
}

/// Whether `value` is below `limit` or not a number (a broken result never passes).
fn violates(value: f64, limit: f64) -> bool {
    use std::cmp::Ordering::{Equal, Greater};
    !matches!(value.partial_cmp(&limit), Some(Greater | Equal))
}

/// One finding per contiguous run of vertices of `rod` whose bend radius is below
/// `limit` (or not a number), at the run's tightest vertex.
fn bend_findings(rod: &RodResult, limit: f64, findings: &mut Vec<Finding>) {
    let radii = bend_radii(rod);
    let s = |j: usize| rod.s_m.get(j).copied().unwrap_or(f64::NAN);
    let mut j = 0;
    while j < radii.len() {
        if !violates(radii[j], limit) {
            j += 1;
            continue;
        }
        let first = j;
        while j < radii.len() && violates(radii[j], limit) {
            j += 1;
        }
        let worst = (first..j)
            .min_by(|&a, &b| {
                // NaN first: a broken result is the worst finding.
                match (radii[a].is_nan(), radii[b].is_nan()) {
                    (true, false) => std::cmp::Ordering::Less,
                    (false, true) => std::cmp::Ordering::Greater,
                    _ => radii[a].total_cmp(&radii[b]),
                }
            })
            .unwrap_or(first);
        findings.push(Finding {
            kind: FindingKind::BendRadius,
            rod: rod.name.clone(),
            with: None,
            s_m: s(worst),
            stretch_m: Some([s(first), s(j - 1)]),
            value_m: radii[worst],
            limit_m: limit,
        });
    }
}

/// The findings as terminal lines (`strand solve`), lengths in the unit of `metres`
/// metres named `symbol`: `findings    none (limits checked: …)` or a count followed
/// by one indented line per finding. Empty when `doc` states no limit at all.
pub fn findings_text(doc: &ResultDoc, findings: &[Finding], metres: f64, symbol: &str) -> String {
    let limits = limits_stated(doc);
    let mut text = String::new();
    if limits.is_empty() {
        return text;
    }
    if findings.is_empty() {
        let _ = writeln!(text, "findings    none ({} respected)", limits.join(", "));
    } else {
        let _ = writeln!(
            text,
            "findings    {} limit violation(s) ({} checked):",
            findings.len(),
            limits.join(", ")
        );
        for f in findings {
            let _ = writeln!(text, "  {}", f.describe(metres, symbol));
        }
    }
    text
}

/// Which limits `doc` states: `min_bend_radius` and/or `min_clearance`.
pub fn limits_stated(doc: &ResultDoc) -> Vec<&'static str> {
    let mut limits = Vec::new();
    if doc.rods.iter().any(|r| r.min_bend_radius_m.is_some()) {
        limits.push("min_bend_radius");
    }
    if doc.rods.iter().any(|r| r.min_clearance_m.is_some()) {
        limits.push("min_clearance");
    }
    limits
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::result::ClearanceResult;
    use crate::study::tests::doc;

    /// `doc(1)` with rod 0 bent to radii 0.5, 0.2, 0.4 m at its three vertices (s = 0,
    /// 0.5, 1 m) and a clearance of 4 mm to "bracket" at s = 0.25 m.
    fn bent() -> ResultDoc {
        let mut d = doc(1.0);
        d.rods[0].curvature_1pm = vec![[2.0, 0.0, 9.0], [3.0, 4.0, 0.0], [0.0, 2.5, 0.0]];
        d.clearance.push(ClearanceResult {
            rod: "rod".into(),
            with: "bracket".into(),
            distance_m: 0.004,
            s_m: 0.25,
        });
        d
    }

    #[test]
    fn a_bend_radius_finding_appears_exactly_below_the_limit() {
        let mut d = bent();
        // Tightest 0.2 m: a limit just below it is respected.
        d.rods[0].min_bend_radius_m = Some(0.2 * (1.0 - 1e-9));
        assert!(find(&d).is_empty());
        d.rods[0].min_bend_radius_m = Some(0.2 * (1.0 + 1e-9));
        let found = find(&d);
        assert_eq!(found.len(), 1, "{found:?}");
        let f = &found[0];
        assert_eq!(f.kind, FindingKind::BendRadius);
        assert_eq!((f.rod.as_str(), f.s_m), ("rod", 0.5));
        assert_eq!(f.stretch_m, Some([0.5, 0.5]));
        assert!((f.value_m - 0.2).abs() < 1e-15);
        // A limit of 0.45 m: vertices 1 and 2 (0.2, 0.4) are one stretch; vertex 0
        // (0.5) is fine.
        d.rods[0].min_bend_radius_m = Some(0.45);
        let found = find(&d);
        assert_eq!(found.len(), 1);
        assert_eq!(found[0].stretch_m, Some([0.5, 1.0]));
        assert_eq!(found[0].s_m, 0.5);
        assert_eq!(
            found[0].describe(1e-3, "mm"),
            "rod: bend radius 200 mm < 450 mm allowed at s = 500 mm (500 to 1000 mm)"
        );
        // Two separate stretches: 0.2, 0.5, 0.25 against 0.3.
        d.rods[0].curvature_1pm = vec![[0.0, 5.0, 0.0], [2.0, 0.0, 0.0], [0.0, 4.0, 0.0]];
        d.rods[0].min_bend_radius_m = Some(0.3);
        let found = find(&d);
        assert_eq!(found.len(), 2, "{found:?}");
        assert_eq!(
            found.iter().map(|f| f.s_m).collect::<Vec<_>>(),
            vec![0.0, 1.0]
        );
        assert_eq!(found[1].value_m, 0.25);
    }

    #[test]
    fn a_clearance_finding_appears_exactly_below_the_requirement() {
        let mut d = bent();
        d.rods[0].min_clearance_m = Some(0.004);
        assert!(find(&d).is_empty(), "equal to the requirement is fine");
        d.rods[0].min_clearance_m = Some(0.005);
        let found = find(&d);
        assert_eq!(found.len(), 1);
        let f = &found[0];
        assert_eq!(f.kind, FindingKind::Clearance);
        assert_eq!(f.with.as_deref(), Some("bracket"));
        assert_eq!((f.s_m, f.value_m, f.limit_m), (0.25, 0.004, 0.005));
        assert_eq!(
            f.describe(1e-3, "mm"),
            "rod: clearance to bracket 4 mm < 5 mm required at s = 250 mm"
        );
        // The other rod states no limit: its clearances are not checked.
        d.clearance[0].rod = "other".into();
        assert!(find(&d).is_empty());
    }

    #[test]
    fn findings_round_trip_through_json_and_print_one_line_each() {
        let mut d = bent();
        d.rods[0].min_bend_radius_m = Some(0.3);
        d.rods[0].min_clearance_m = Some(0.01);
        let found = find(&d);
        assert_eq!(found.len(), 2);
        let json = serde_json::to_value(&found).unwrap();
        assert_eq!(json[0]["kind"], "bend_radius");
        assert_eq!(json[1]["kind"], "clearance");
        assert_eq!(json[1]["with"], "bracket");
        assert!(json[1].get("stretch_m").is_none());
        let back: Vec<Finding> = serde_json::from_value(json).unwrap();
        assert_eq!(back, found);
        let text = findings_text(&d, &found, 1e-3, "mm");
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3, "{text}");
        assert!(lines[0].starts_with("findings    2 limit violation(s)"));
        assert_eq!(lines[2], format!("  {}", found[1].describe(1e-3, "mm")));
        assert!(findings_text(&doc(1.0), &[], 1e-3, "mm").is_empty());
        d.rods[0].min_bend_radius_m = Some(0.1);
        d.rods[0].min_clearance_m = Some(0.001);
        assert_eq!(
            findings_text(&d, &find(&d), 1e-3, "mm"),
            "findings    none (min_bend_radius, min_clearance respected)\n"
        );
    }
}
