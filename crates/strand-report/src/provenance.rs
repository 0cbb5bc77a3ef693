//! Where a result comes from (`result.json`: `provenance`): Strand's version, the case
//! file as named and a hash of its content, when it was solved (UTC) and the solver
//! settings, so that a report can say what it shows and warn when it compares results
//! of different cases.

use std::path::Path;

use serde::{Deserialize, Serialize};

/// The origin of one result.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    /// Version of Strand that solved it (`CARGO_PKG_VERSION`).
    pub strand_version: String,
    /// The case file as the user named it.
    pub case_path: String,
    /// FNV-1a (64 bit) of the case file's bytes, 16 hex digits (detects a changed
    /// file; not a cryptographic hash); absent when the file could not be read again.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub case_fnv1a64: Option<String>,
    /// When the result was made, UTC, ISO 8601 to the second (`2026-12-01T00:30:00Z`).
    pub created_utc: String,
    /// The solver settings used (every field, defaults included).
    pub solver_settings: serde_json::Value,
}

impl Provenance {
    /// The provenance of a result solved now from the case file `case_path` with
    /// `settings`.
    pub fn now(case_path: &str, settings: &strand_solve::SolverSettings) -> Self {
        Provenance {
            strand_version: env!("CARGO_PKG_VERSION").to_string(),
            case_path: case_path.to_string(),
            case_fnv1a64: std::fs::read(Path::new(case_path))
                .ok()
                .map(|b| fnv1a64(&b)),
            created_utc: utc_now(),
            solver_settings: serde_json::to_value(settings).unwrap_or(serde_json::Value::Null),
        }
    }
}

/// The current time, UTC, as [`utc`] writes it.
pub fn utc_now() -> String {
    utc(std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs()))
}

/// FNV-1a (64 bit) of `bytes`, 16 hex digits.
pub fn fnv1a64(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// `seconds` since 1970-01-01T00:00:00Z as ISO 8601 (`YYYY-MM-DDThh:mm:ssZ`), by the
/// proleptic Gregorian calendar (Howard Hinnant's `civil_from_days`).
pub fn utc(seconds: u64) -> String {
    let days = (seconds / 86_400) as i64;
    let rest = seconds % 86_400;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        rest / 3600,
        rest % 3600 / 60,
        rest % 60
    )
}

/// A warning when `docs` (label, document) come from different cases: different case
/// names, or the same case file with different content hashes. `None` when they agree
/// (or say nothing to compare).
pub fn mixed_cases(docs: &[(&str, &crate::ResultDoc)]) -> Option<String> {
    let (first_label, first) = docs.first()?;
    let key = |d: &crate::ResultDoc| {
        (
            d.case.clone(),
            d.provenance.as_ref().and_then(|p| p.case_fnv1a64.clone()),
        )
    };
    let reference = key(first);
    let differ: Vec<String> = docs[1..]
        .iter()
        .filter(|(_, d)| {
            let other = key(d);
            other.0 != reference.0
                || matches!((&other.1, &reference.1), (Some(a), Some(b)) if a != b)
        })
        .map(|(label, d)| {
            format!(
                "{label} (case {}{})",
                d.case,
                d.provenance
                    .as_ref()
                    .and_then(|p| p.case_fnv1a64.as_deref())
                    .map_or(String::new(), |h| format!(", file hash {h}"))
            )
        })
        .collect();
    (!differ.is_empty()).then(|| {
        format!(
            "the results come from different cases or case files: {} differ from {first_label} (case {}{}); their differences mix design and input changes",
            differ.join(", "),
            first.case,
            reference
                .1
                .as_deref()
                .map_or(String::new(), |h| format!(", file hash {h}"))
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_follow_the_calendar() {
        assert_eq!(utc(0), "1970-01-01T00:00:00Z");
        // 2000-02-29 (a leap day of a century leap year) 12:34:56.
        assert_eq!(utc(951_827_696), "2000-02-29T12:34:56Z");
        // 2100 is no leap year: 2100-03-01 follows 2100-02-28.
        assert_eq!(utc(4_107_456_000), "2100-02-28T00:00:00Z");
        assert_eq!(utc(4_107_456_000 + 86_400), "2100-03-01T00:00:00Z");
        // The last second of 2026.
        assert_eq!(utc(1_798_761_599), "2026-12-31T23:59:59Z");
    }

    #[test]
    fn the_hash_is_fnv1a64() {
        // Published FNV-1a 64 test vectors.
        assert_eq!(fnv1a64(b""), "cbf29ce484222325");
        assert_eq!(fnv1a64(b"a"), "af63dc4c8601ec8c");
        assert_eq!(fnv1a64(b"foobar"), "85944171f73967e8");
    }

    #[test]
    fn results_of_different_cases_are_flagged() {
        let a = crate::study::tests::doc(1.0);
        let mut b = a.clone();
        assert_eq!(mixed_cases(&[("a", &a), ("b", &b)]), None);
        b.case = "other".into();
        let warning = mixed_cases(&[("a", &a), ("b", &b)]).unwrap();
        assert!(warning.contains("b (case other)"), "{warning}");
        // Same name, edited file.
        let mut c = a.clone();
        let mut d = a.clone();
        let settings = strand_solve::SolverSettings::default();
        c.provenance = Some(Provenance::now("/nonexistent/case.ron", &settings));
        d.provenance = c.provenance.clone();
        assert_eq!(mixed_cases(&[("c", &c), ("d", &d)]), None);
        c.provenance.as_mut().unwrap().case_fnv1a64 = Some("0000000000000001".into());
        d.provenance.as_mut().unwrap().case_fnv1a64 = Some("0000000000000002".into());
        assert!(mixed_cases(&[("c", &c), ("d", &d)]).is_some());
    }
}
