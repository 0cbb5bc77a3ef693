//! Design sensitivities (`strand_solve::sensitivity`) against central differences of
//! full solves of the bundled cases: every output derivative (reactions, peaks, bend
//! radii, clearances, junction pose, contact forces) with respect to lengths,
//! connector positions and directions, junction port directions, end positions, the
//! T's mass, clip stations and base poses, and section stiffnesses, warm-started
//! solves at `p ± fd` and `p ± 2fd` extrapolated (Richardson), to 1e-5 relative or
//! 1e-9 absolute.

use std::collections::BTreeMap;

use strand_case::{Case, CaseDesign, DesignParameter, DesignedCase};
use strand_report::OutputValue;
use strand_solve::sensitivity::{Design, PathRows, Sample, Sensitivities, SensitivitySettings};
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

/// The unit a parameter's derivatives are judged in, in the parameter's unit: a
/// Young's modulus per MPa (per Pa, 1e-9 absolute would pass any derivative of a
/// hose, whose outputs change by micro-units per pascal), every other per its unit.
fn judged_per(item: &str) -> f64 {
    if item.ends_with(".youngs_modulus") {
        1e6
    } else {
        1.0
    }
}

/// Ten radians in degrees: the scale of a `direction` parameter (turns in deg), as
/// `strand sensitivity`'s.
const TEN_RADIANS_DEG: f64 = 1800.0 / std::f64::consts::PI;

/// Checks every output's derivative for every parameter of `case` against the
/// differences of full solves; returns the number of derivatives compared. Outputs
/// starting with a name listed in `must` must be among them, and at least
/// `min_active` rows (contacts, joint stops) must be active.
fn check(case: &str, params: &[Param], must: &[&str], min_active: usize) -> usize {
    check_case(
        &Case::from_path(cases_dir().join(case)).unwrap(),
        params,
        must,
        min_active,
    )
}

/// [`check`] of a parsed case.
fn check_case(case: &Case, params: &[Param], must: &[&str], min_active: usize) -> usize {
    check_held(case, params, must, min_active, false)
}

/// [`check_case`]; `held_by_rows`: whether the energy Hessian alone must be indefinite
/// at the base (the active rows holding the equilibrium).
fn check_held(
    case: &Case,
    params: &[Param],
    must: &[&str],
    min_active: usize,
    held_by_rows: bool,
) -> usize {
    let design = CaseDesign::new(
        case,
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
    assert_eq!(s.held_by_active_rows, held_by_rows);
    let mut compared = 0;
    for (j, p) in params.iter().enumerate() {
        let exact = s
            .derivative(&design, &base, j, PathRows::Active, |built, at| {
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
            let (_, near) = s
                .path_point(&design, &base, j, t, PathRows::Active)
                .unwrap();
            let solution = solve_from(&built, base.state.clone(), Some(near.state));
            (
                outputs(&built, &solution, Some(&pins)),
                solution.report.residual.combined_n,
            )
        };
        let fd = p.3;
        let ((up, r_up), (down, r_down), (up2, r_up2), (down2, r_down2)) =
            (at(fd), at(-fd), at(2.0 * fd), at(-2.0 * fd));
        // What the reference can resolve where the sensitivity is exactly zero (an
        // output the parameter cannot reach, e.g. across a clip held on its stop): the
        // four solves stop at residuals r (N), so the extrapolated difference of an
        // output carries about (4/3)·2r/(2·fd) + (1/3)·2r/(4·fd) = 1.5·r/fd of
        // iteration noise per unit of the parameter.
        let resolution = judged_per(p.0) * 1.5 * r_up.max(r_down).max(r_up2).max(r_down2) / fd;
        let mut failures = Vec::new();
        let (mut worst_absolute, mut worst_relative) = (0.0f64, 0.0f64);
        let mut structural_zeros = 0;
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
            let per = judged_per(p.0);
            let reference = per * (4.0 * fine - coarse) / 3.0;
            let derivative = per * e.derivative;
            let error = (derivative - reference).abs();
            compared += 1;
            if e.derivative == 0.0 {
                // Structurally zero: the reference must be noise.
                structural_zeros += 1;
                if reference.abs() > resolution.max(1e-9) {
                    failures.push(format!(
                        "d {name} / d {} (per {per} of its unit): sensitivity exactly 0, solves {reference:.9e} (above their resolution {resolution:.2e})",
                        p.0
                    ));
                }
                continue;
            }
            if reference.abs() > 1e-9 {
                worst_relative = worst_relative.max(error / reference.abs());
            }
            worst_absolute = worst_absolute.max(error);
            // An error within the reference's own resolution (its iteration noise, as
            // for the structural zeros above) is not the sensitivity's.
            if error > 1e-5 * reference.abs() && error > resolution.max(1e-9) {
                failures.push(format!(
                    "d {name} / d {} (per {per} of its unit): sensitivity {derivative:.9e}, solves {reference:.9e} (error {error:.2e})",
                    p.0
                ));
            }
        }
        println!(
            "{}{}: {} outputs, largest error {worst_absolute:.2e}, largest relative error {worst_relative:.2e} (of derivatives above 1e-9); {structural_zeros} exactly zero (reference resolution {resolution:.1e})",
            p.0,
            p.1.map_or(String::new(), |c| format!(".{}", ["x", "y", "z"][c])),
            names.len()
        );
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }
    compared
}

/// Every output of `sensitivity.json` is named once (other tools read it by name):
/// a clip's reaction, which the result lists among the reactions and under the clips,
/// came twice (`grommet.force_N.x`, …, 54 of the harness's 171 outputs), with the same
/// values. Checked on cases with clips, ports and contacts.
#[test]
fn every_output_is_named_once() {
    for name in [
        "harness_clips.ron",
        "cooler_hose.ron",
        "cooler_hose_contact.ron",
    ] {
        let case = Case::from_path(cases_dir().join(name)).unwrap();
        let design = CaseDesign::new(&case, Vec::new());
        let built = design.build(&[]).unwrap();
        let solution = solve(&built, built.built.initial.clone());
        let outputs = outputs_at(&built, &solution, None).unwrap();
        let mut names: Vec<&str> = outputs.iter().map(|o| o.name.as_str()).collect();
        let count = names.len();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), count, "{name}: outputs named twice");
        if name == "harness_clips.ron" {
            // Each clip's force, moment and joint value are there.
            for clip in ["grommet", "hinge", "strain_relief"] {
                for output in ["force_N.z", "moment_Nm.x", "joint_value"] {
                    let wanted = format!("{clip}.{output}");
                    assert!(names.contains(&wanted.as_str()), "{wanted}");
                }
            }
        }
    }
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

/// A cable wrapped around two vertical edges of a box: its contacts are ridge rows
/// (curved across the edge), whose curvature the first solve leaves out and the
/// refinement carries. The reactions' changes are 1e-8 of the cable's axial
/// stiffness terms: refined only to 1e-9 of those, they were 1e-4 off.
#[test]
fn a_cable_wrapped_around_the_edges_of_a_box_follows_its_connectors_and_length() {
    let n = check(
        "cable_over_box.ron",
        &[
            Param("connectors.a.position", Some(2), 1000.0, 0.05),
            Param("connectors.b.position", Some(0), 1000.0, 0.05),
            Param("rods.cable.length", None, 1000.0, 0.05),
        ],
        &["cable.contact_force_N.", "cable.peak_force_N"],
        2,
    );
    assert!(n > 20);
}

#[test]
fn cooler_hose_outputs_follow_connector_and_port_directions_and_the_tube_modulus() {
    let n = check(
        "cooler_hose.ron",
        &[
            Param(
                "connectors.oil_cooler.direction",
                Some(0),
                TEN_RADIANS_DEG,
                0.05,
            ),
            Param(
                "connectors.radiator_outlet.direction",
                Some(2),
                TEN_RADIANS_DEG,
                0.05,
            ),
            Param(
                "junctions.tee.ports.hose2.direction",
                Some(2),
                TEN_RADIANS_DEG,
                0.05,
            ),
            Param("junctions.tee.ports.hose3.position", Some(1), 1000.0, 0.05),
            // Scales as `strand sensitivity`'s (100 times the value).
            Param("sections.hose_small.youngs_modulus", None, 5e8, 5e4),
            Param("sections.hose_large.youngs_modulus", None, 5e8, 5e4),
        ],
        &[
            "tee.position_m.z",
            "tee.rotation_vector_rad.x",
            "hose2.peak_moment_Nm",
            "oil_cooler.moment_Nm.x",
        ],
        0,
    );
    assert!(n > 200);
}

#[test]
fn helix_outputs_follow_every_stiffness_of_an_explicit_section() {
    // Fig. 4's helix with GJ = 0.8 EI: with GJ = EI it is free of forces, where the
    // peak |f| (a norm at zero) has no derivative; here it carries forces and moments.
    let path = cases_dir().join("helix_fig4.ron");
    let text = std::fs::read_to_string(&path).unwrap();
    let changed = text.replace("ei: 1, gj: 1,", "ei: 1, gj: 0.8,");
    assert_ne!(changed, text);
    let case = Case::from_str(&changed, path.to_str().unwrap()).unwrap();
    let n = check_case(
        &case,
        &[
            // Scales as `strand sensitivity`'s (100 times the value); reference steps
            // of 2 % (the reference's noise, 1e-11 N over 4e-2, stays below 1e-9 N
            // per unit; the truncation is O(fd⁴)).
            Param("sections.paper.ei", None, 100.0, 0.02),
            Param("sections.paper.gj", None, 80.0, 0.016),
            Param("sections.paper.ea", None, 30e5, 600.0),
            Param("sections.paper.ga", None, 10e5, 200.0),
        ],
        &["helix.start.moment_Nm.x", "helix.peak_moment_Nm"],
        0,
    );
    assert!(n > 40);
}

#[test]
fn harness_outputs_follow_clip_stations_clip_base_poses_and_directions() {
    let n = check(
        "harness_clips.ron",
        &[
            // A clip moved along its rod compresses the piece ahead of it (136 N/mm
            // at the grommet): the moments respond strongly nonlinearly, so the
            // reference steps are small.
            Param("clips.grommet.at", None, 1000.0, 0.02),
            Param("clips.ball.at", None, 1000.0, 0.02),
            Param("clips.ball.base.position", Some(2), 1000.0, 0.1),
            Param("clips.rail.base.position", Some(1), 1000.0, 0.04),
            Param(
                "clips.bracket.base.direction",
                Some(1),
                TEN_RADIANS_DEG,
                0.05,
            ),
            Param(
                "clips.twin_left.base.direction",
                Some(2),
                TEN_RADIANS_DEG,
                0.05,
            ),
            Param(
                "connectors.lamp_left.direction",
                Some(2),
                TEN_RADIANS_DEG,
                0.05,
            ),
            Param(
                "junctions.breakout.ports.left.direction",
                Some(1),
                TEN_RADIANS_DEG,
                0.05,
            ),
        ],
        &[
            "hinge.joint_value",
            "bracket.force_N.z",
            "breakout.position_m.z",
        ],
        1, // the hinge on its +0.02 rad stop
    );
    assert!(n > 300);
}

#[test]
fn a_hose_held_in_its_groove_by_contact_alone_is_differentiated() {
    // The 1060 mm hose between connectors 1000 mm apart lies in the V-groove under
    // axial compression: its energy Hessian alone is indefinite, the flanks' contact
    // rows hold it (the solve reports it stable). Sensitivities used to stop there
    // with `NotPositiveDefinite`.
    let case = Case::from_path(cases_dir().join("hose_in_groove.ron")).unwrap();
    let n = check_held(
        &case,
        &[
            Param("gravity", Some(2), 10.0, 0.01),
            Param("connectors.a.position", Some(2), 1000.0, 0.05),
            Param("rods.hose.length", None, 1000.0, 0.05),
            Param("environment.groove.position", Some(2), 1000.0, 0.01),
        ],
        &["hose.contact_force_N.groove.", "a.force_N.z"],
        4,
        true,
    );
    assert!(n > 100);
}

#[test]
fn a_round_cable_pinned_at_both_ends_is_differentiated_with_its_twist_held() {
    // Pinned at both ends, the round cable may turn freely about its own axis: a
    // neutral direction of the Hessian that no output depends on, held as the solve
    // holds it (its gauge).
    let case = Case::from_path(cases_dir().join("pinned_cable.ron")).unwrap();
    let built = case.build(None).unwrap();
    let solution = built
        .solve_from(built.initial.clone(), &built.settings)
        .unwrap();
    assert!(solution.report.gauge_freedoms >= 1, "{:?}", solution.report);
    let n = check_case(
        &case,
        &[
            Param("gravity", Some(2), 10.0, 0.01),
            Param("connectors.stud_right.position", Some(0), 1000.0, 0.05),
            Param("rods.cable.length", None, 1000.0, 0.05),
        ],
        &["stud_left.force_N.z", "cable.peak_moment_Nm"],
        0,
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
