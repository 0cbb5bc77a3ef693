//! Design sensitivities (`strand_solve::sensitivity`) against central differences of
//! full solves of the bundled cases: every output derivative (reactions, peaks, bend
//! radii, clearances, junction pose, contact forces) with respect to lengths,
//! connector positions, end positions and the T's mass, warm-started solves at
//! `p ± fd` and `p ± 2fd` extrapolated (Richardson), to 1e-5 relative or 1e-9
//! absolute.

use std::collections::BTreeMap;

use strand_case::{Case, CaseDesign, DesignParameter, DesignedCase};
use strand_report::OutputValue;
use strand_solve::sensitivity::{Design, Sample, Sensitivities, SensitivitySettings};
use strand_solve::{Solution, SolverSettings};
use strand_study::sensitivity::{ENERGY, outputs_at};

use crate::common::cases_dir;

/// Tolerance of the full solves of the reference (N): 1e-11 N where the case's
/// round-off floor allows it (the reference's noise is this over `2 fd`), else 1e-10 N.
fn settings(built: &DesignedCase) -> SolverSettings {
    let floor = 4.0 * 2.0 * f64::EPSILON * largest_axial_stiffness_n(built);
    SolverSettings {
        tolerance_n: if floor < 2e-12 { 1e-11 } else { 1e-10 },
        ..built.built.settings.clone()
    }
}

/// The largest axial or shear stiffness of the case's rods, N.
fn largest_axial_stiffness_n(built: &DesignedCase) -> f64 {
    built
        .built
        .model
        .system()
        .rods
        .iter()
        .map(|r| r.rod.section().strain_stiffness().max())
        .fold(0.0, f64::max)
}

fn solve(built: &DesignedCase, start: strand_system::SystemState) -> Solution {
    solve_from(built, start, None)
}

/// Solves from `start`, or from `fallback` when `start` overlaps an obstacle (the
/// base state against a bracket moved towards the hose).
fn solve_from(
    built: &DesignedCase,
    start: strand_system::SystemState,
    fallback: Option<strand_system::SystemState>,
) -> Solution {
    let solution = match (built.built.solve_from(start, &settings(built)), fallback) {
        (Err(strand_solve::SolveError::StartsInside(_)), Some(other)) => {
            built.built.solve_from(other, &settings(built)).unwrap()
        }
        (result, _) => result.unwrap(),
    };
    assert!(solution.report.converged, "{:?}", solution.report);
    solution
}

/// Named outputs of a design at a solution (peaks read at the base's arg when `pins`
/// are given), those of `sensitivity.json` (without the optimiser's energy).
fn outputs(
    built: &DesignedCase,
    solution: &Solution,
    pins: Option<&[OutputValue]>,
) -> BTreeMap<String, Sample> {
    outputs_at(built, solution, pins)
        .unwrap()
        .into_iter()
        .filter(|o| o.name != ENERGY)
        .map(|o| {
            (
                o.name,
                Sample {
                    value: o.value,
                    arg: o.arg,
                },
            )
        })
        .collect()
}

/// A parameter: item, component, scale (item units) and the difference step of the
/// reference solves (item units).
struct Param(&'static str, Option<usize>, f64, f64);

/// Checks every output's derivative for every parameter of `case` against the
/// differences of full solves; returns the number of derivatives compared. Outputs
/// starting with a name listed in `must` must be among them, and at least
/// `min_active` rows (contacts, joint stops) must be active.
fn check(case: &str, params: &[Param], must: &[&str], min_active: usize) -> usize {
    let case = Case::from_path(cases_dir().join(case)).unwrap();
    let design = CaseDesign::new(
        &case,
        params
            .iter()
            .map(|p| DesignParameter {
                item: p.0.into(),
                component: p.1,
                scale: p.2,
            })
            .collect(),
    );
    let zeros = vec![0.0; params.len()];
    let base_built = design.build(&zeros).unwrap();
    let base = solve(&base_built, base_built.built.initial.clone());
    let s = Sensitivities::compute(&design, &base, &SensitivitySettings::default()).unwrap();
    let pins: Vec<OutputValue> = outputs(&base_built, &base, None)
        .into_iter()
        .map(|(name, s)| OutputValue {
            name,
            value: s.value,
            arg: s.arg,
        })
        .collect();
    let names: Vec<String> = pins.iter().map(|o| o.name.clone()).collect();
    for m in must {
        assert!(
            names.iter().any(|n| n.starts_with(m)),
            "no output {m} in {names:?}"
        );
    }
    assert!(
        s.active.len() >= min_active,
        "{} active rows, expected at least {min_active}",
        s.active.len()
    );
    let mut compared = 0;
    for (j, p) in params.iter().enumerate() {
        let exact = s
            .derivative(&design, &base, j, |built, at| {
                let here = outputs(built, at, Some(&pins));
                names
                    .iter()
                    .map(|n| {
                        here.get(n).copied().unwrap_or(Sample {
                            value: f64::NAN,
                            arg: usize::MAX,
                        })
                    })
                    .collect()
            })
            .unwrap();
        let at = |t: f64| {
            let mut offsets = zeros.clone();
            offsets[j] = t;
            let built = design.build(&offsets).unwrap();
            // Warm-started from the base state, or (when that overlaps a moved
            // obstacle) from the first-order path point: the start only picks the
            // branch, the solve converges to the tolerance at the changed design.
            let (_, near) = s.path_point(&design, &base, j, t).unwrap();
            let solution = solve_from(&built, base.state.clone(), Some(near.state));
            outputs(&built, &solution, Some(&pins))
        };
        let fd = p.3;
        let (up, down, up2, down2) = (at(fd), at(-fd), at(2.0 * fd), at(-2.0 * fd));
        let mut failures = Vec::new();
        for (k, name) in names.iter().enumerate() {
            let e = exact[k];
            let get = |m: &BTreeMap<String, Sample>| m.get(name).copied();
            let (Some(a), Some(b), Some(a2), Some(b2)) =
                (get(&up), get(&down), get(&up2), get(&down2))
            else {
                continue;
            };
            // Peaks are read at the base's arg-max on both sides (the derivative at the
            // arg-max), whether or not the location jumps within the steps.
            let _ = (a.arg, b.arg, a2.arg, b2.arg, e.one_sided);
            let fine = (a.value - b.value) / (2.0 * fd);
            let coarse = (a2.value - b2.value) / (4.0 * fd);
            let reference = (4.0 * fine - coarse) / 3.0;
            let error = (e.derivative - reference).abs();
            compared += 1;
            if error > 1e-5 * reference.abs() && error > 1e-9 {
                failures.push(format!(
                    "d {name} / d {}: sensitivity {:.9e}, solves {reference:.9e} (error {error:.2e})",
                    p.0, e.derivative
                ));
            }
        }
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }
    compared
}

#[test]
fn elastica_tip_force_follows_the_prescribed_tip_position() {
    let n = check(
        "elastica_fig2.ron",
        &[
            Param("rods.rod.end.position", Some(0), 1000.0, 0.01),
            Param("rods.rod.end.position", Some(1), 1000.0, 0.01),
        ],
        &[
            "rod.end.force_N.x",
            "rod.end.force_N.y",
            "rod.peak_moment_Nm",
        ],
        0,
    );
    assert!(n > 10);
}

#[test]
fn cooler_hose_outputs_follow_lengths_connector_positions_and_the_t_mass() {
    let n = check(
        "cooler_hose.ron",
        &[
            Param("rods.hose2.length", None, 1000.0, 0.05),
            Param("rods.hose1.length", None, 1000.0, 0.05),
            Param("connectors.oil_cooler.position", Some(2), 1000.0, 0.05),
            Param("junctions.tee.mass", None, 100.0, 0.01),
        ],
        &[
            "tee.position_m.z",
            "hose2.peak_force_N",
            "oil_cooler.force_N.z",
        ],
        0,
    );
    assert!(n > 50);
}

#[test]
fn harness_outputs_follow_lengths_and_connectors_with_the_hinge_on_its_stop() {
    let n = check(
        "harness_clips.ron",
        &[
            Param("rods.trunk.length", None, 1000.0, 0.1),
            Param("connectors.lamp_left.position", Some(2), 1000.0, 0.2),
        ],
        &["hinge.joint_value", "breakout.position_m.z"],
        1, // the hinge on its +0.02 rad stop
    );
    assert!(n > 50);
}

#[test]
fn contact_forces_and_clearances_follow_the_connectors_and_the_bracket() {
    let n = check(
        "cooler_hose_contact.ron",
        &[
            Param("connectors.engine_stub.position", Some(2), 1000.0, 0.05),
            Param("rods.hose3.length", None, 1000.0, 0.05),
            Param("environment.brackets.position", Some(2), 1000.0, 0.05),
        ],
        &["hose3.min_clearance_m", "hose3.contact_force_N."],
        1,
    );
    assert!(n > 20);
}

#[test]
fn the_command_writes_the_contract_and_rejects_bad_parameters_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sens");
    let case = cases_dir().join("cooler_hose.ron");
    let (exit, stdout, stderr) = crate::common::strand(&[
        "sensitivity",
        case.to_str().unwrap(),
        "--param",
        "hose2.length",
        "--param",
        "tee.mass",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(exit, strand_cli::Exit::Success, "{stderr}");
    assert!(stdout.contains("d/dhose2.length"), "{stdout}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("sensitivity.json")).unwrap())
            .unwrap();
    assert_eq!(json["parameters"][0]["name"], "hose2.length");
    assert_eq!(json["parameters"][0]["unit"], "mm");
    assert_eq!(json["parameters"][1]["unit"], "kg");
    let outputs = json["outputs"].as_array().unwrap();
    let peak = outputs
        .iter()
        .find(|o| o["name"] == "hose2.peak_force_N")
        .unwrap();
    assert!(peak["value"].as_f64().unwrap() > 0.0);
    // A longer hose 2 lets the T down and relieves it (the study's finding).
    assert!(peak["d"]["hose2.length"].as_f64().unwrap() < 0.0);
    let csv = std::fs::read_to_string(out.join("sensitivity.csv")).unwrap();
    assert!(csv.starts_with("output,value,d/dhose2.length [per mm],d/dtee.mass [per kg]"));
    assert_eq!(csv.lines().count(), outputs.len() + 1);

    // `strand report` on the folder (it holds the base solve's result.json too) says
    // what one more millimetre of hose 2 does, with the derivatives of the file.
    let report = dir.path().join("report.html");
    let (exit, _, stderr) = crate::common::strand(&[
        "report",
        out.to_str().unwrap(),
        "--out",
        report.to_str().unwrap(),
    ]);
    assert_eq!(exit, strand_cli::Exit::Success, "{stderr}");
    let html = std::fs::read_to_string(&report).unwrap();
    let page = roxmltree::Document::parse(html.strip_prefix("<!DOCTYPE html>\n").unwrap()).unwrap();
    let sentence: String = page
        .descendants()
        .find(|n| n.attribute("data-parameter") == Some("hose2.length"))
        .expect("a sentence for hose2.length")
        .descendants()
        .filter_map(|n| n.text())
        .collect();
    let d = peak["d"]["hose2.length"].as_f64().unwrap();
    assert!(sentence.starts_with("hose2.length +1 mm:"), "{sentence}");
    let expected = format!("hose2 peak |f| {:.4} N", d).replace('-', "−");
    assert!(sentence.contains(&expected), "{sentence} lacks {expected}");
    let rows = page
        .descendants()
        .filter(|n| n.has_tag_name("tr") && n.attribute("data-output").is_some())
        .count();
    assert_eq!(rows, outputs.len());

    let bad = dir.path().join("bad");
    for param in ["hose2.segments", "nothing.length"] {
        let (exit, _, stderr) = crate::common::strand(&[
            "sensitivity",
            case.to_str().unwrap(),
            "--param",
            param,
            "--out",
            bad.to_str().unwrap(),
        ]);
        assert_eq!(exit, strand_cli::Exit::InvalidInput, "{stderr}");
        assert!(stderr.contains(param), "{stderr}");
        assert!(!bad.exists());
    }
}
