//! Design limits end to end: `strand solve` with bend-radius, clearance and
//! connector-load limits just inside and just outside the solved design.

use std::path::{Path, PathBuf};

use strand_report::{Finding, FindingKind, ResultDoc, bend_radii};

use crate::Exit;
use crate::tests::strand;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// `cases/cooler_hose_contact.ron` written into `dir` as `name.ron` (meshes by
/// absolute path), with `min_bend_radius` (mm) on the large hoses' section and
/// `min_clearance` (mm) on hose1, when given; solved into `dir/name`.
fn solve(
    dir: &Path,
    name: &str,
    bend: Option<f64>,
    clearance: Option<f64>,
) -> (String, String, ResultDoc) {
    let text = std::fs::read_to_string(repo().join("cases/cooler_hose_contact.ron")).unwrap();
    let assets = repo().join("assets").canonicalize().unwrap();
    let mut text = text.replace("\"../assets", &format!("\"{}", assets.display()));
    if let Some(bend) = bend {
        text = text.replacen(
            "inner_radius: 14.4, outer_radius: 18.4)",
            &format!("inner_radius: 14.4, outer_radius: 18.4, min_bend_radius: {bend:?})"),
            1,
        );
    }
    if let Some(clearance) = clearance {
        text = text.replacen(
            "name: \"hose1\",",
            &format!("name: \"hose1\", min_clearance: {clearance:?},"),
            1,
        );
    }
    solve_text(dir, name, &text)
}

/// `text` (a case) written into `dir` as `name.ron` and solved into `dir/name`.
fn solve_text(dir: &Path, name: &str, text: &str) -> (String, String, ResultDoc) {
    let case = dir.join(format!("{name}.ron"));
    std::fs::write(&case, text).unwrap();
    let out_dir = dir.join(name);
    let (exit, out, err) = strand(&[
        "solve",
        case.to_str().unwrap(),
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(exit, Exit::Success, "{out}\n{err}");
    let doc: ResultDoc =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("result.json")).unwrap())
            .unwrap();
    (out, err, doc)
}

/// The lines `strand solve` printed under `findings`.
fn printed(out: &str) -> Vec<String> {
    out.lines()
        .skip_while(|l| !l.starts_with("findings"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .map(|l| l.trim().to_string())
        .collect()
}

fn described(findings: &[Finding]) -> Vec<String> {
    findings.iter().map(|f| f.describe(1e-3, "mm")).collect()
}

#[test]
fn limits_just_inside_and_just_outside_the_solved_design() {
    let dir = tempfile::tempdir().unwrap();
    let (out, _, free) = solve(dir.path(), "free", None, None);
    assert!(free.findings.is_empty());
    assert!(
        !out.contains("findings"),
        "no limits, no findings line: {out}"
    );
    // The solved design: smallest bend radius of the large hoses (hose1, hose3) and
    // hose1's clearance to the radiator, mm.
    let tightest = free
        .rods
        .iter()
        .filter(|r| r.name != "hose2")
        .flat_map(|r| {
            bend_radii(r)
                .into_iter()
                .enumerate()
                .map(move |(j, b)| (b, r, j))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap();
    let (bend_mm, bend_rod, bend_vertex) = (1e3 * tightest.0, tightest.1.name.clone(), tightest.2);
    let radiator = free
        .clearance
        .iter()
        .find(|c| c.rod == "hose1" && c.with == "radiator")
        .expect("hose1 near the radiator");
    let clear_mm = 1e3 * radiator.distance_m;
    assert!(clear_mm > 5.0, "{clear_mm}");

    // Just loose enough: no finding; the limits are in result.json.
    let (out, err, loose) = solve(
        dir.path(),
        "loose",
        Some(0.999 * bend_mm),
        Some(0.999 * clear_mm),
    );
    assert!(loose.findings.is_empty(), "{:?}", loose.findings);
    assert!(
        out.contains("findings    none (min_bend_radius, min_clearance respected)"),
        "{out}"
    );
    assert!(!err.contains("limit violation"), "{err}");
    let hose1 = &loose.rods[0];
    assert!((hose1.min_bend_radius_m.unwrap() - 0.999e-3 * bend_mm).abs() < 1e-12);
    assert!((hose1.min_clearance_m.unwrap() - 0.999e-3 * clear_mm).abs() < 1e-12);
    assert_eq!(
        loose.rods[1].min_bend_radius_m, None,
        "hose2's section has none"
    );
    assert_eq!(loose.rods[2].min_clearance_m, None);

    // Just too tight: exactly one bend finding at the tightest vertex and one
    // clearance finding against the radiator, printed as in result.json.
    let (out, err, tight) = solve(
        dir.path(),
        "tight",
        Some(1.001 * bend_mm),
        Some(1.001 * clear_mm),
    );
    let bends: Vec<&Finding> = tight
        .findings
        .iter()
        .filter(|f| f.kind == FindingKind::BendRadius)
        .collect();
    assert_eq!(bends.len(), 1, "{:?}", tight.findings);
    assert_eq!(bends[0].rod, bend_rod);
    let rod = tight.rods.iter().find(|r| r.name == bend_rod).unwrap();
    assert_eq!(bends[0].s_m, rod.s_m[bend_vertex]);
    assert!((1e3 * bends[0].value_m.unwrap() - bend_mm).abs() < 1e-9);
    let clear: Vec<&Finding> = tight
        .findings
        .iter()
        .filter(|f| f.kind == FindingKind::Clearance)
        .collect();
    assert!(
        clear
            .iter()
            .any(|f| f.rod == "hose1" && f.with.as_deref() == Some("radiator")),
        "{clear:?}"
    );
    assert!(
        clear
            .iter()
            .all(|f| f.rod == "hose1" && f.value_m < f.limit_m)
    );
    assert_eq!(printed(&out), described(&tight.findings), "{out}");
    assert!(
        err.contains(&format!("{} limit violation(s)", tight.findings.len())),
        "{err}"
    );

    // The report opens with the same findings.
    let html = dir.path().join("review.html");
    let (exit, _, err) = strand(&[
        "report",
        dir.path().join("tight").to_str().unwrap(),
        dir.path().join("loose").to_str().unwrap(),
        "--out",
        html.to_str().unwrap(),
    ]);
    assert_eq!(exit, Exit::Success, "{err}");
    let html = std::fs::read_to_string(html).unwrap();
    let rows = |label: &str| {
        html.lines()
            .filter(|l| l.starts_with(&format!("<tr data-result=\"{label}\"")))
            .filter(|l| l.contains("data-kind="))
            .count()
    };
    assert_eq!(rows("tight"), tight.findings.len());
    assert_eq!(rows("loose"), 0);
    // The environment is drawn: outlines in every view, contacts marked.
    assert!(!html.contains("TODO"));
    assert!(html.matches("class=\"environment\"").count() >= 3 * 2 * 5);
    assert!(html.contains("class=\"contact\""));
}

#[test]
fn a_negative_clearance_is_refused_with_its_item() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(repo().join("cases/cooler_hose.ron")).unwrap();
    let text = text.replacen("name: \"hose1\",", "name: \"hose1\", min_clearance: -1,", 1);
    let case = dir.path().join("bad.ron");
    std::fs::write(&case, text).unwrap();
    let (exit, _, err) = strand(&["check", case.to_str().unwrap()]);
    assert_eq!(exit, Exit::InvalidInput);
    assert!(err.contains("rods[0] 'hose1'.min_clearance"), "{err}");
}

/// A connector's `max_force` / `max_moment` 0.1 % below the load it takes in the
/// solved design is a finding (with the value and limit in N / N·m), 0.1 % above
/// is none; the result carries the limits and the provenance of the case file.
#[test]
fn connector_load_limits_just_inside_and_just_outside() {
    let dir = tempfile::tempdir().unwrap();
    let (_, _, free) = solve(dir.path(), "free_load", None, None);
    let reaction = free
        .reactions
        .iter()
        .find(|r| r.name == "radiator_outlet")
        .expect("the radiator connector's reaction");
    let force = strand_report::magnitude(&reaction.force_n);
    let moment = strand_report::magnitude(&reaction.moment_nm);
    assert!(force > 1.0 && moment > 1e-3, "{force} N, {moment} N·m");
    let text = std::fs::read_to_string(repo().join("cases/cooler_hose_contact.ron")).unwrap();
    let assets = repo().join("assets").canonicalize().unwrap();
    let text = text.replace("\"../assets", &format!("\"{}", assets.display()));
    let with_limits = |f: f64, m: f64| {
        let at = text.find("\"radiator_outlet\": (").unwrap();
        // Before the tuple's closing parenthesis (after `normal: (…)`).
        let close = at + text[at..].find(")),").unwrap() + 1;
        format!(
            "{}, max_force: {f:?}, max_moment: {m:?}{}",
            &text[..close],
            &text[close..]
        )
    };
    let (out, err, loose) = solve_text(
        dir.path(),
        "loose_load",
        &with_limits(1.001 * force, 1.001 * moment),
    );
    assert!(loose.findings.is_empty(), "{:?}", loose.findings);
    assert!(out.contains("max_force, max_moment respected"), "{out}");
    assert!(!err.contains("limit violation"), "{err}");
    let limited = loose
        .reactions
        .iter()
        .find(|r| r.name == "radiator_outlet")
        .unwrap();
    assert!((limited.max_force_n.unwrap() - 1.001 * force).abs() < 1e-9 * force);
    let provenance = loose.provenance.as_ref().expect("provenance");
    assert_eq!(provenance.strand_version, env!("CARGO_PKG_VERSION"));
    assert_eq!(
        provenance.case_fnv1a64.as_deref(),
        Some(
            strand_report::fnv1a64(with_limits(1.001 * force, 1.001 * moment).as_bytes()).as_str()
        )
    );
    assert!(
        provenance.solver_settings["max_iterations"]
            .as_u64()
            .is_some()
    );

    let (out, err, tight) = solve_text(
        dir.path(),
        "tight_load",
        &with_limits(0.999 * force, 0.999 * moment),
    );
    let kinds: Vec<FindingKind> = tight.findings.iter().map(|f| f.kind).collect();
    assert_eq!(
        kinds,
        [FindingKind::ConnectorForce, FindingKind::ConnectorMoment]
    );
    let (f, m) = (&tight.findings[0], &tight.findings[1]);
    assert_eq!(f.with.as_deref(), Some("radiator_outlet"));
    assert_eq!(f.rod, "hose1");
    // The same solve as `free`: the same load, against the limits set.
    assert!((f.value_n.unwrap() - force).abs() < 1e-6 * force);
    assert!((f.limit_n.unwrap() - 0.999 * force).abs() < 1e-9 * force);
    assert!((m.value_nm.unwrap() - moment).abs() < 1e-6 * moment);
    assert!(f.value_m.is_none() && m.value_n.is_none());
    assert_eq!(printed(&out), described(&tight.findings), "{out}");
    assert!(out.contains("force on connector radiator_outlet"), "{out}");
    assert!(err.contains("2 limit violation(s)"), "{err}");
}
