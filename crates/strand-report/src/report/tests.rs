//! Tests of the HTML report: well-formed XHTML, every hose and result present, table
//! numbers equal to values recomputed here from the documents.

use super::*;
use crate::result::{ClearanceResult, ContactResult, EnvironmentOutline, ReactionResult};
use crate::study::tests::doc;

/// Two results of two rods ("rod" and "other"); the second has forces scaled by 1.5,
/// a contact, a clearance, a bend-radius limit and an environment outline.
fn docs() -> (ResultDoc, ResultDoc) {
    let mut base = doc(1.0);
    let mut longer = doc(1.5);
    for d in [&mut base, &mut longer] {
        d.rods[0].curvature_1pm[1] = [3.0, 4.0, 7.0]; // |K_b| = 5 1/m: radius 200 mm
        d.rods[0].tangential_force_n = vec![0.5, -2.0, 1.0];
        d.rods[1].torsion_nm = vec![0.1, 0.0, -0.3];
        d.reactions.push(ReactionResult {
            name: "wall".into(),
            kind: "connector".into(),
            rod: "rod".into(),
            end: "start".into(),
            position_m: [0.0, 0.0, 0.0],
            force_n: [3.0, 4.0, 0.0],
            moment_nm: [0.0, 0.0, 1.0],
            max_force_n: None,
            max_moment_nm: None,
        });
        // "other" hangs from a junction port at its end: arc length from the end.
        d.reactions.push(ReactionResult {
            name: "tee.a".into(),
            kind: "port".into(),
            rod: "other".into(),
            end: "end".into(),
            position_m: [1.0, 0.0, 0.0],
            force_n: [0.0, 1.0, 0.0],
            moment_nm: [0.0; 3],
            max_force_n: None,
            max_moment_nm: None,
        });
    }
    longer.rods[0].min_bend_radius_m = Some(0.25);
    longer.contacts.push(ContactResult {
        rod: "other".into(),
        s_m: 0.5,
        point_m: [0.5, 0.0, 0.0],
        normal: [0.0, 0.0, 1.0],
        force_n: 12.5,
        with: "bracket".into(),
    });
    longer.clearance.push(ClearanceResult {
        rod: "rod".into(),
        with: "bracket".into(),
        distance_m: 0.0042,
        s_m: 0.25,
    });
    longer.environment.push(EnvironmentOutline {
        name: "bracket".into(),
        segments_m: vec![
            [[0.0, -0.1, -0.1], [1.0, -0.1, -0.1]],
            [[1.0, -0.1, -0.1], [1.0, 0.1, 0.2]],
            [[1.0, 0.1, 0.2], [0.0, -0.1, -0.1]],
        ],
        truncated: false,
        surface_m: Vec::new(),
        surface_cell_m: None,
        diagnostics: None,
    });
    (base, longer)
}

const LABELS: [&str; 2] = ["base", "long&er <v2>"];

fn render(base: &ResultDoc, longer: &ResultDoc) -> String {
    let runs = [
        ReportRun {
            label: LABELS[0],
            doc: base,
        },
        ReportRun {
            label: LABELS[1],
            doc: longer,
        },
    ];
    report_html("Review of \"sample\"", &runs)
}

fn parse(html: &str) -> roxmltree::Document<'_> {
    let body = html
        .strip_prefix("<!DOCTYPE html>\n")
        .expect("starts with the HTML5 doctype");
    roxmltree::Document::parse(body).expect("well-formed XHTML")
}

/// The cells of table `id` as (data-result, data-rod, header → text).
/// A table row: `data-result`, `data-rod`, and (header, cell text) pairs.
type ParsedRow = (String, String, Vec<(String, String)>);

fn table(xml: &roxmltree::Document, id: &str) -> Vec<ParsedRow> {
    let table = xml
        .descendants()
        .find(|n| n.has_tag_name("table") && n.attribute("id") == Some(id))
        .unwrap_or_else(|| panic!("no table {id}"));
    let text = |n: roxmltree::Node| {
        n.descendants()
            .filter(|t| t.is_text())
            .filter_map(|t| t.text())
            .collect::<String>()
    };
    let headers: Vec<String> = table
        .descendants()
        .filter(|n| n.has_tag_name("th"))
        .map(text)
        .collect();
    table
        .descendants()
        .filter(|n| n.has_tag_name("tr") && n.attribute("data-result").is_some())
        .map(|row| {
            let cells: Vec<String> = row
                .children()
                .filter(|n| n.has_tag_name("td"))
                .map(text)
                .collect();
            assert_eq!(cells.len(), headers.len(), "{id}: row width");
            (
                row.attribute("data-result").unwrap().to_string(),
                row.attribute("data-rod").unwrap_or("").to_string(),
                headers.iter().cloned().zip(cells).collect(),
            )
        })
        .collect()
}

fn cell<'a>(row: &'a [(String, String)], header: &str) -> &'a str {
    &row.iter()
        .find(|(h, _)| h == header)
        .unwrap_or_else(|| panic!("no column {header}"))
        .1
}

/// Asserts that `text` is `expected` to the 4 significant digits shown.
fn assert_shown(text: &str, expected: f64, what: &str) {
    let shown: f64 = text
        .parse()
        .unwrap_or_else(|_| panic!("{what}: {text:?} is not a number"));
    assert!(
        (shown - expected).abs() <= 5e-4 * expected.abs() + 1e-15,
        "{what}: shown {shown}, expected {expected}"
    );
}

fn norm(v: &[f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

#[test]
fn report_is_well_formed_and_names_every_hose_and_result() {
    let (base, longer) = docs();
    let html = render(&base, &longer);
    let xml = parse(&html);
    assert_eq!(xml.root_element().tag_name().name(), "html");
    // Every table scrolls on its own on a narrow screen; a print style is there.
    let tables: Vec<_> = xml
        .descendants()
        .filter(|n| n.has_tag_name("table"))
        .collect();
    assert!(tables.len() > 5);
    for table in &tables {
        let parent = table.parent_element().unwrap();
        assert_eq!(
            (parent.tag_name().name(), parent.attribute("class")),
            ("div", Some("scroll")),
            "{:?}",
            table.attribute("id")
        );
    }
    assert!(html.contains("@media print"));
    assert_eq!(
        xml.root_element().tag_name().namespace(),
        Some("http://www.w3.org/1999/xhtml")
    );
    let text: String = xml
        .descendants()
        .filter(|n| n.is_text())
        .filter_map(|n| n.text())
        .collect::<Vec<_>>()
        .join("|");
    for needle in [
        "rod",
        "other",
        LABELS[0],
        LABELS[1],
        "Review of \"sample\"",
        "bracket",
    ] {
        assert!(text.contains(needle), "missing {needle:?}");
    }
    // One plot per hose, with every quantity of every result.
    let svg_ns = Some("http://www.w3.org/2000/svg");
    let plots: Vec<_> = xml
        .descendants()
        .filter(|n| n.has_tag_name("svg") && n.attribute("class") == Some("hose-plot"))
        .collect();
    assert_eq!(plots.len(), 2);
    for plot in &plots {
        assert_eq!(plot.tag_name().namespace(), svg_ns);
        let curves: Vec<_> = plot
            .descendants()
            .filter(|n| n.attribute("class") == Some("curve"))
            .collect();
        assert_eq!(curves.len(), 6 * 2, "6 quantities × 2 results");
        for label in LABELS {
            let dashed = curves
                .iter()
                .filter(|c| c.attribute("data-result") == Some(label))
                .map(|c| c.attribute("stroke-dasharray").is_some())
                .collect::<Vec<_>>();
            assert_eq!(
                dashed,
                vec![label != LABELS[0]; 6],
                "{label}: reference solid, others dashed"
            );
        }
    }
    // Side, top and front view of every result, with every rod and (where given) the
    // outline.
    let views: Vec<_> = xml
        .descendants()
        .filter(|n| n.attribute("class") == Some("projection"))
        .collect();
    assert_eq!(views.len(), 6);
    for view in &views {
        let rods: Vec<_> = view
            .descendants()
            .filter(|n| n.attribute("class") == Some("rod"))
            .collect();
        assert_eq!(rods.len(), 2);
        for rod in &rods {
            // One line per edge (2 edges).
            assert_eq!(rod.children().filter(|n| n.has_tag_name("line")).count(), 2);
        }
        let outline = view
            .descendants()
            .find(|n| n.attribute("class") == Some("environment"));
        if view.attribute("data-result") == Some(LABELS[1]) {
            let d = outline.expect("outline drawn").attribute("d").unwrap();
            assert_eq!((d.matches('M').count(), d.matches('L').count()), (3, 3));
        } else {
            assert!(outline.is_none());
        }
    }
    // Self-contained: inline scripts only (the 3D view), no links or remote resources.
    assert!(!html.contains("src=") && !html.contains("href") && !html.contains("url("));
    assert_eq!(html.matches("<script").count(), 2);
    assert!(!html.contains("NaN"));
}

#[test]
fn table_numbers_match_the_documents() {
    let (base, longer) = docs();
    let html = render(&base, &longer);
    let xml = parse(&html);
    let docs = [(LABELS[0], &base), (LABELS[1], &longer)];
    let peaks = table(&xml, "peaks");
    assert_eq!(peaks.len(), 4);
    for (label, rod_name, row) in &peaks {
        let doc = docs.iter().find(|(l, _)| l == label).unwrap().1;
        let rod = doc.rods.iter().find(|r| &r.name == rod_name).unwrap();
        // Brute force: the vertex of the largest magnitude.
        let (mut f_peak, mut f_at) = (0.0, 0);
        for (j, f) in rod.force_n.iter().enumerate() {
            if norm(f) > f_peak {
                (f_peak, f_at) = (norm(f), j);
            }
        }
        assert_shown(cell(row, "peak |f| [N]"), f_peak, "peak |f|");
        // "other" is measured from its end (junction port).
        let s = if rod_name == "other" {
            rod.length_m - rod.s_m[f_at]
        } else {
            rod.s_m[f_at]
        };
        assert_shown(cell(row, "s of peak |f| [mm]"), 1e3 * s, "s of peak |f|");
        let m_peak = rod.moment_nm.iter().map(norm).fold(0.0, f64::max);
        assert_shown(cell(row, "peak |m| [N·m]"), m_peak, "peak |m|");
        let signed_extreme =
            |v: &[f64]| *v.iter().max_by(|a, b| a.abs().total_cmp(&b.abs())).unwrap();
        assert_shown(
            cell(row, "extreme f_t [N]"),
            signed_extreme(&rod.tangential_force_n),
            "f_t",
        );
        assert_shown(
            cell(row, "extreme m_t [N·m]"),
            signed_extreme(&rod.torsion_nm),
            "m_t",
        );
        let max = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
        assert_shown(cell(row, "peak f_s [N]"), max(&rod.shear_force_n), "f_s");
        assert_shown(
            cell(row, "peak m_b [N·m]"),
            max(&rod.bending_moment_nm),
            "m_b",
        );
    }
    // Signs are kept: rod's f_t extreme is −2.
    assert_eq!(cell(&peaks[0].2, "extreme f_t [N]"), "-2.000");

    let summary = table(&xml, "summary");
    assert_eq!(summary.len(), 2);
    assert_eq!(cell(&summary[0].2, "converged"), "yes");
    assert_shown(
        cell(&summary[1].2, "tolerance [N]"),
        longer.tolerance_n,
        "tolerance",
    );

    let differences = table(&xml, "differences");
    assert_eq!(
        differences.len(),
        2,
        "one row per hose of the second result"
    );
    let peak_f = |d: &ResultDoc, r: usize| d.rods[r].force_n.iter().map(norm).fold(0.0, f64::max);
    let expected = 100.0 * (peak_f(&longer, 0) - peak_f(&base, 0)) / peak_f(&base, 0);
    assert_shown(
        cell(&differences[0].2, "change |f| [%]"),
        expected,
        "change |f|",
    );
    assert_shown(
        cell(&differences[0].2, "largest vertex displacement [mm]"),
        0.0,
        "same positions",
    );

    let reactions = table(&xml, "reactions");
    assert_eq!(reactions.len(), 4);
    assert_shown(cell(&reactions[0].2, "|F| [N]"), 5.0, "|F| of (3, 4, 0)");

    let contacts = table(&xml, "contacts");
    assert_eq!(contacts.len(), 1);
    assert_eq!(
        (contacts[0].0.as_str(), contacts[0].1.as_str()),
        (LABELS[1], "other")
    );
    assert_shown(cell(&contacts[0].2, "force [N]"), 12.5, "contact force");
    let clearance = table(&xml, "clearance");
    assert_shown(cell(&clearance[0].2, "clearance [mm]"), 4.2, "clearance");

    let bend = table(&xml, "bend-radius");
    assert_eq!(bend.len(), 4);
    // |K_b| = |(3, 4)| = 5 1/m at vertex 1 (s = 0.5 m): radius 200 mm.
    assert_shown(
        cell(&bend[0].2, "smallest bend radius [mm]"),
        200.0,
        "bend radius",
    );
    assert_shown(cell(&bend[0].2, "at s [mm]"), 500.0, "where");
    assert_eq!(cell(&bend[0].2, "check"), "–", "no limit given");
    assert_eq!(cell(&bend[1].2, "smallest bend radius [mm]"), "straight");
    assert_eq!(
        cell(&bend[2].2, "check"),
        "VIOLATED",
        "200 mm < 250 mm allowed"
    );
    assert_shown(cell(&bend[2].2, "allowed minimum [mm]"), 250.0, "allowed");
}

#[test]
fn without_contact_the_report_says_so() {
    let (base, _) = docs();
    let runs = [ReportRun {
        label: "only",
        doc: &base,
    }];
    let html = report_html("t", &runs);
    let xml = parse(&html);
    let ids: Vec<&str> = xml
        .descendants()
        .filter_map(|n| n.attribute("id"))
        .collect();
    assert!(
        ids.contains(&"no-contact") && ids.contains(&"no-clearance"),
        "{ids:?}"
    );
    assert!(!ids.contains(&"contacts") && !ids.contains(&"differences"));
    assert!(html.contains("No contact"));
}

#[test]
fn inconsistent_arrays_are_refused_by_name() {
    let (mut base, _) = docs();
    assert_eq!(check_result(&base), Ok(()));
    base.rods[1].torsion_nm.pop();
    let err = check_result(&base).unwrap_err();
    assert_eq!(
        err,
        ReportInputError::ArrayLength {
            rod: "other".into(),
            array: "torsion_Nm",
            found: 2,
            expected: 3
        }
    );
    assert!(err.to_string().contains("rod 'other': torsion_Nm"));
}

/// The per-hose input table: section, length, outer and inner diameter, mass,
/// segments and the limits, in mm and kg, from the reference result; and the page
/// says when it was made.
#[test]
fn the_input_table_lists_every_hose_with_its_section_and_diameters() {
    let (mut base, longer) = docs();
    base.rods[0].section = Some("hose_large".into());
    base.rods[0].outer_radius_m = Some(0.0184);
    base.rods[0].inner_radius_m = Some(0.0144);
    base.rods[0].mass_kg = Some(0.18);
    base.rods[0].min_bend_radius_m = Some(0.06);
    base.rods[0].min_clearance_m = Some(0.005);
    let html = render(&base, &longer);
    let xml = parse(&html);
    let rows = table(&xml, "limits");
    assert_eq!(rows.len(), 2, "one row per hose of the reference");
    let (result, rod, cells) = &rows[0];
    assert_eq!((result.as_str(), rod.as_str()), ("base", "rod"));
    assert_eq!(cell(cells, "section"), "hose_large");
    assert_shown(
        cell(cells, "length [mm]"),
        1e3 * base.rods[0].length_m,
        "length",
    );
    assert_shown(cell(cells, "outer diameter [mm]"), 36.8, "OD");
    assert_shown(cell(cells, "inner diameter [mm]"), 28.8, "ID");
    assert_shown(cell(cells, "mass [kg]"), 0.18, "mass");
    assert_eq!(cell(cells, "segments"), base.rods[0].segments.to_string());
    assert_shown(cell(cells, "min bend radius [mm]"), 60.0, "bend limit");
    assert_shown(cell(cells, "min clearance [mm]"), 5.0, "clearance limit");
    // The other hose states none of these: dashes, not zeros.
    for header in ["section", "inner diameter [mm]", "min clearance [mm]"] {
        assert_eq!(cell(&rows[1].2, header), "–", "{header}");
    }
    let created = xml
        .descendants()
        .find(|n| n.attribute("class") == Some("created"))
        .and_then(|n| n.text())
        .unwrap();
    assert!(
        created.len() == 20 && created.starts_with("20") && created.ends_with('Z'),
        "{created}"
    );
}
