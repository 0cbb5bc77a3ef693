//! Findings: the places where a solved design violates a limit its case states
//! (`result.json`: `findings`; printed by `strand solve`; the first section of the HTML
//! report). Three kinds of limit are checked:
//!
//! - **bend radius** — the section's `min_bend_radius` (`RodResult::min_bend_radius_m`)
//!   against the bend radius `1/|(K1, K2)|` at the vertices: one finding per
//!   contiguous stretch of vertices bent tighter than allowed, at its tightest vertex;
//! - **clearance** — the rod's `min_clearance` (`RodResult::min_clearance_m`) against
//!   its smallest surface-to-surface distance to every mesh and every other rod
//!   (`result.json`: `clearance`; 0 at contact): one finding per obstacle closer than
//!   required;
//! - **connector load** — a named connector's `max_force` / `max_moment`
//!   (`ReactionResult::max_force_n`, `max_moment_nm`) against the magnitude of the
//!   force / moment it takes from the hose (`reactions`): one finding per limit
//!   exceeded.
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
    /// A connector takes a larger force from the hose than its `max_force`.
    ConnectorForce,
    /// A connector takes a larger moment from the hose than its `max_moment`.
    ConnectorMoment,
}

impl FindingKind {
    /// Words for people: `bend radius`, `clearance`, `connector force`,
    /// `connector moment`.
    pub fn words(self) -> &'static str {
        match self {
            FindingKind::BendRadius => "bend radius",
            FindingKind::Clearance => "clearance",
            FindingKind::ConnectorForce => "connector force",
            FindingKind::ConnectorMoment => "connector moment",
        }
    }

    /// The key in `result.json`: `bend_radius`, `clearance`, `connector_force`,
    /// `connector_moment`.
    pub fn key(self) -> &'static str {
        match self {
            FindingKind::BendRadius => "bend_radius",
            FindingKind::Clearance => "clearance",
            FindingKind::ConnectorForce => "connector_force",
            FindingKind::ConnectorMoment => "connector_moment",
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
    /// For a clearance: the obstacle (an environment mesh or another rod); for a
    /// connector load: the connector.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub with: Option<String>,
    /// Where: reference arc length from the rod's start of the worst point (for a
    /// connector: of the held end), m.
    pub s_m: f64,
    /// For a bend radius: the stretch of arc length bent tighter than allowed,
    /// `[from, to]`, m (the vertices where it is violated).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stretch_m: Option<[f64; 2]>,
    /// The value found, a length (bend radius or clearance), m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value_m: Option<f64>,
    /// The limit (allowed minimum bend radius or required clearance), m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limit_m: Option<f64>,
    /// The value found, a force (connector force magnitude), N.
    #[serde(default, rename = "value_N", skip_serializing_if = "Option::is_none")]
    pub value_n: Option<f64>,
    /// The limit (allowed connector force), N.
    #[serde(default, rename = "limit_N", skip_serializing_if = "Option::is_none")]
    pub limit_n: Option<f64>,
    /// The value found, a moment (connector moment magnitude), N·m.
    #[serde(default, rename = "value_Nm", skip_serializing_if = "Option::is_none")]
    pub value_nm: Option<f64>,
    /// The limit (allowed connector moment), N·m.
    #[serde(default, rename = "limit_Nm", skip_serializing_if = "Option::is_none")]
    pub limit_nm: Option<f64>,
}

/// A value of a finding with its unit (`Finding::value_m`, `value_N` or `value_Nm`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FindingValue {
    /// A length, m.
    Metres(f64),
    /// A force, N.
    Newtons(f64),
    /// A moment, N·m.
    NewtonMetres(f64),
}

impl FindingValue {
    /// The number, in its unit.
    pub fn number(self) -> f64 {
        match self {
            FindingValue::Metres(v) | FindingValue::Newtons(v) | FindingValue::NewtonMetres(v) => v,
        }
    }

    /// The unit suffix of keys: `m`, `N`, `Nm`.
    pub fn suffix(self) -> &'static str {
        match self {
            FindingValue::Metres(_) => "m",
            FindingValue::Newtons(_) => "N",
            FindingValue::NewtonMetres(_) => "Nm",
        }
    }

    /// For people: a length in the unit of `metres` m named `symbol`, a force in N, a
    /// moment in N·m (`52.1 mm`, `310 N`).
    pub fn describe(self, metres: f64, symbol: &str) -> String {
        match self {
            FindingValue::Metres(v) => format!("{} {symbol}", number(v / metres)),
            FindingValue::Newtons(v) => format!("{} N", number(v)),
            FindingValue::NewtonMetres(v) => format!("{} N·m", number(v)),
        }
    }
}

impl Finding {
    /// A finding of `kind` on `rod` (obstacle or connector `with`) at `s_m` over
    /// `stretch_m`, with the value found and the limit in the same unit.
    pub fn new(
        kind: FindingKind,
        rod: &str,
        with: Option<&str>,
        s_m: f64,
        stretch_m: Option<[f64; 2]>,
        value: FindingValue,
        limit: FindingValue,
    ) -> Self {
        let mut f = Finding {
            kind,
            rod: rod.to_string(),
            with: with.map(str::to_string),
            s_m,
            stretch_m,
            value_m: None,
            limit_m: None,
            value_n: None,
            limit_n: None,
            value_nm: None,
            limit_nm: None,
        };
        for (x, is_value) in [(value, true), (limit, false)] {
            let slot = match (x, is_value) {
                (FindingValue::Metres(_), true) => &mut f.value_m,
                (FindingValue::Metres(_), false) => &mut f.limit_m,
                (FindingValue::Newtons(_), true) => &mut f.value_n,
                (FindingValue::Newtons(_), false) => &mut f.limit_n,
                (FindingValue::NewtonMetres(_), true) => &mut f.value_nm,
                (FindingValue::NewtonMetres(_), false) => &mut f.limit_nm,
            };
            *slot = Some(x.number());
        }
        f
    }

    /// The value found with its unit (NaN m when the document holds none).
    pub fn value(&self) -> FindingValue {
        pick(self.value_m, self.value_n, self.value_nm)
    }

    /// The limit with its unit (NaN m when the document holds none).
    pub fn limit(&self) -> FindingValue {
        pick(self.limit_m, self.limit_n, self.limit_nm)
    }

    /// One line for people, lengths in the unit of `metres` metres per unit named
    /// `symbol` (e.g. `0.001`, `"mm"`): `hose3: bend radius 52.1 mm < 60 mm allowed at
    /// s = 120 mm (110 to 130 mm)`, `hose3: clearance to brackets 0 mm < 5 mm required
    /// at s = 120 mm`.
    pub fn describe(&self, metres: f64, symbol: &str) -> String {
        let l = |v: f64| format!("{} {symbol}", number(v / metres));
        let (value, limit) = (
            self.value().describe(metres, symbol),
            self.limit().describe(metres, symbol),
        );
        let with = self.with.as_deref().unwrap_or("?");
        let mut text = match self.kind {
            FindingKind::BendRadius => format!(
                "{}: bend radius {value} < {limit} allowed at s = {}",
                self.rod,
                l(self.s_m)
            ),
            FindingKind::Clearance => format!(
                "{}: clearance to {with} {value} < {limit} required at s = {}",
                self.rod,
                l(self.s_m)
            ),
            FindingKind::ConnectorForce | FindingKind::ConnectorMoment => format!(
                "{}: {} on connector {with} {value} > {limit} allowed (end at s = {})",
                self.rod,
                if self.kind == FindingKind::ConnectorForce {
                    "force"
                } else {
                    "moment"
                },
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

fn pick(m: Option<f64>, n: Option<f64>, nm: Option<f64>) -> FindingValue {
    match (m, n, nm) {
        (Some(v), _, _) => FindingValue::Metres(v),
        (None, Some(v), _) => FindingValue::Newtons(v),
        (None, None, Some(v)) => FindingValue::NewtonMetres(v),
        (None, None, None) => FindingValue::Metres(f64::NAN),
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
/// clearances by obstacle name; then the connector loads in the order of the
/// reactions.
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
            findings.extend(close.into_iter().map(|c| {
                Finding::new(
                    FindingKind::Clearance,
                    &rod.name,
                    Some(&c.with),
                    c.s_m,
                    None,
                    FindingValue::Metres(c.distance_m),
                    FindingValue::Metres(limit),
                )
            }));
        }
    }
    connector_findings(doc, &mut findings);
    findings
}

/// A connector-load check: the finding's kind, the limit, the load vector and the unit
/// of its magnitude.
type LoadCheck<'a> = (
    FindingKind,
    Option<f64>,
    &'a [f64; 3],
    fn(f64) -> FindingValue,
);

/// The connector-load findings of `doc`: every reaction whose force (moment)
/// magnitude exceeds its `max_force_n` (`max_moment_nm`) or is not a number.
fn connector_findings(doc: &ResultDoc, findings: &mut Vec<Finding>) {
    for r in &doc.reactions {
        let Some(rod) = doc.rods.iter().find(|rod| rod.name == r.rod) else {
            continue;
        };
        let s_m = if r.end == "end" { rod.length_m } else { 0.0 };
        let checks: [LoadCheck; 2] = [
            (
                FindingKind::ConnectorForce,
                r.max_force_n,
                &r.force_n,
                FindingValue::Newtons,
            ),
            (
                FindingKind::ConnectorMoment,
                r.max_moment_nm,
                &r.moment_nm,
                FindingValue::NewtonMetres,
            ),
        ];
        for (kind, limit, vector, unit) in checks {
            let Some(limit) = limit else {
                continue;
            };
            let value = crate::study::magnitude(vector);
            // Above the limit, or not a number: `violates` with the signs turned.
            if violates(-value, -limit) {
                findings.push(Finding::new(
                    kind,
                    &rod.name,
                    Some(&r.name),
                    s_m,
                    None,
                    unit(value),
                    unit(limit),
                ));
            }
        }
    }
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
        findings.push(Finding::new(
            FindingKind::BendRadius,
            &rod.name,
            None,
            s(worst),
            Some([s(first), s(j - 1)]),
            FindingValue::Metres(radii[worst]),
            FindingValue::Metres(limit),
        ));
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

/// Which limits `doc` states: `min_bend_radius`, `min_clearance`, `max_force`,
/// `max_moment`.
pub fn limits_stated(doc: &ResultDoc) -> Vec<&'static str> {
    let mut limits = Vec::new();
    if doc.rods.iter().any(|r| r.min_bend_radius_m.is_some()) {
        limits.push("min_bend_radius");
    }
    if doc.rods.iter().any(|r| r.min_clearance_m.is_some()) {
        limits.push("min_clearance");
    }
    if doc.reactions.iter().any(|r| r.max_force_n.is_some()) {
        limits.push("max_force");
    }
    if doc.reactions.iter().any(|r| r.max_moment_nm.is_some()) {
        limits.push("max_moment");
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
        assert!((f.value_m.unwrap() - 0.2).abs() < 1e-15);
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
        assert_eq!(found[1].value_m, Some(0.25));
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
        assert_eq!(
            (f.s_m, f.value_m, f.limit_m),
            (0.25, Some(0.004), Some(0.005))
        );
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
