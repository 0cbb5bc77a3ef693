//! `strand optimize` (`strand_study::optimize`) against dense sweeps of full solves
//! done here with the library: the cooler hose's best hose-2 length (a min–max of the
//! hoses' peak forces, with bend-radius limits), the same with the oil cooler's height
//! (a 2D sweep), and a hose that must keep 10 mm from a bracket (the optimum on the
//! clearance constraint, its multiplier against differences of full solves). Then the
//! binary's contract: the files, and bad input written nowhere.

use std::collections::BTreeMap;

use strand_case::{Case, CaseDesign, DesignParameter};
use strand_solve::SolverSettings;
use strand_solve::sensitivity::Design;
use strand_study::optimize::{
    Limit, Objective, OptimizeSettings, Optimum, Problem, Variable, optimize,
};
use strand_study::sensitivity::outputs_at;
use strand_system::SystemState;

use crate::common::cases_dir;

/// The cooler hose with a `min_bend_radius` of 60 mm on hose 2's section.
fn cooler_with_bend_limit() -> Case {
    let path = cases_dir().join("cooler_hose.ron");
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text.replace(
        "inner_radius: 9.4, outer_radius: 12.9)",
        "inner_radius: 9.4, outer_radius: 12.9, min_bend_radius: 60)",
    );
    assert!(text.contains("min_bend_radius: 60"));
    Case::from_str(&text, path.to_str().unwrap()).unwrap()
}

fn variable(
    name: &str,
    item: &str,
    component: Option<usize>,
    origin: f64,
    lo: f64,
    hi: f64,
) -> Variable {
    Variable {
        name: name.into(),
        unit: "mm".into(),
        parameter: DesignParameter {
            item: item.into(),
            component,
            scale: 1000.0,
        },
        origin: Some(origin),
        lower: lo - origin,
        upper: hi - origin,
    }
}

/// The length of rod `rod` in mm, from `origin` (the case's) between `lo` and `hi`.
fn rod_length(rod: &str, origin: f64, lo: f64, hi: f64) -> Variable {
    variable(
        &format!("{rod}.length"),
        &format!("rods.{rod}.length"),
        None,
        origin,
        lo,
        hi,
    )
}

fn run(case: &Case, variables: Vec<Variable>, limits: &[&str]) -> Optimum {
    let problem = Problem {
        variables,
        objective: Objective::PeakForce,
        limits: limits.iter().map(|l| Limit::parse(l).unwrap()).collect(),
    };
    optimize(case, &problem, &OptimizeSettings::default(), &mut |_| {}).unwrap()
}

/// A sweep of full solves, each warm-started from the previous point's state.
struct Sweep<'c> {
    case: &'c Case,
    parameters: Vec<DesignParameter>,
    state: Option<SystemState>,
    solves: usize,
}

impl<'c> Sweep<'c> {
    fn new(case: &'c Case, variables: &[Variable]) -> Self {
        Self {
            case,
            parameters: variables.iter().map(|v| v.parameter.clone()).collect(),
            state: None,
            solves: 0,
        }
    }

    /// Every output at `offsets` (item units from the case).
    fn at(&mut self, offsets: &[f64]) -> BTreeMap<String, f64> {
        let built = CaseDesign::new(self.case, self.parameters.clone())
            .build(offsets)
            .unwrap();
        let b = &built.built;
        let (start, settings) = match self.state.take() {
            Some(mut s) => {
                b.model.enforce_supports(&mut s);
                (
                    s,
                    SolverSettings {
                        nested_iteration: false,
                        ..b.settings.clone()
                    },
                )
            }
            None => (b.initial.clone(), b.settings.clone()),
        };
        let solution = b.solve_from(start, &settings).unwrap();
        self.solves += 1;
        assert!(
            solution.report.converged,
            "{offsets:?}: {:?}",
            solution.report
        );
        let outputs = outputs_at(&built, &solution, None).unwrap();
        self.state = Some(solution.state);
        outputs.into_iter().map(|o| (o.name, o.value)).collect()
    }
}

/// Every output at offsets `x + h` and `x − h` of `variable` (its unit), by full
/// solves warm-started from `x`: `(up, down)`.
fn either_side(
    case: &Case,
    variable: Variable,
    x: f64,
    h: f64,
) -> (BTreeMap<String, f64>, BTreeMap<String, f64>) {
    let mut sweep = Sweep::new(case, &[variable]);
    sweep.at(&[x]);
    (sweep.at(&[x + h]), sweep.at(&[x - h]))
}

/// The largest peak |f| over the cooler's hoses and which hose carries it.
fn peak(o: &BTreeMap<String, f64>) -> (f64, &'static str) {
    ["hose1", "hose2", "hose3"]
        .iter()
        .map(|h| (o[&format!("{h}.peak_force_N")], *h))
        .fold(
            (f64::NEG_INFINITY, ""),
            |a, b| if b.0 > a.0 { b } else { a },
        )
}

/// The optimum is the kink where hose 3's peak meets hose 2's, found with at least 10×
/// fewer equilibrium solves than the sweep's `sweep_solves`.
fn assert_kink_in_fewer_solves(optimum: &Optimum, sweep_solves: usize) {
    for hose in ["hose2.peak_force_N", "hose3.peak_force_N"] {
        assert!(
            optimum.attained_by.iter().any(|a| a == hose),
            "{:?}",
            optimum.attained_by
        );
    }
    assert!(
        10 * optimum.solves <= sweep_solves,
        "{} solves against {sweep_solves}",
        optimum.solves
    );
}

#[test]
fn the_best_hose2_length_matches_a_1mm_sweep_with_ten_times_fewer_solves() {
    let case = cooler_with_bend_limit();
    let length = || rod_length("hose2", 190.0, 150.0, 300.0);
    // The reference: every millimetre from 150 to 300 mm.
    let mut sweep = Sweep::new(&case, &[length()]);
    let points: Vec<(f64, BTreeMap<String, f64>)> = (150..=300)
        .map(|mm| (mm as f64, sweep.at(&[mm as f64 - 190.0])))
        .collect();
    let best = |least_radius_m: f64| {
        points
            .iter()
            .filter(|(_, o)| o["hose2.min_bend_radius_m"] >= least_radius_m)
            .min_by(|a, b| peak(&a.1).0.total_cmp(&peak(&b.1).0))
            .unwrap()
    };

    // 1. Hose 2's own limit (60 mm) bounds the length from below only: the optimum is
    // the kink where hose 3's peak overtakes hose 2's.
    let optimum = run(&case, vec![length()], &["bend_radius>=min"]);
    let (mm, outputs) = best(0.060);
    assert!(optimum.converged, "{}", optimum.message);
    assert!(
        (optimum.values[0] - mm).abs() <= 1.0,
        "optimum {} mm, sweep {mm} mm",
        optimum.values[0]
    );
    // No grid point is better than the optimum.
    assert!(optimum.objective <= peak(outputs).0 * (1.0 + 1e-9));
    // The sweep shows the kink: hose 2 carries the peak just below, hose 3 just above.
    let at = |x: f64| &points.iter().find(|(m, _)| *m == x).unwrap().1;
    assert_eq!(peak(at(optimum.values[0].floor())).1, "hose2");
    assert_eq!(peak(at(optimum.values[0].ceil() + 1.0)).1, "hose3");
    assert_kink_in_fewer_solves(&optimum, sweep.solves);

    // 2. A 70 mm limit on hose 2 excludes the kink: the optimum sits on the limit,
    // which is active with a positive multiplier.
    let optimum = run(&case, vec![length()], &["bend_radius:hose2>=70mm"]);
    let (mm, _) = best(0.070);
    assert!(optimum.converged, "{}", optimum.message);
    assert!(
        (optimum.values[0] - mm).abs() <= 1.0,
        "optimum {} mm, sweep {mm} mm",
        optimum.values[0]
    );
    let row = &optimum.constraints[0];
    assert!(row.active && row.multiplier > 0.0, "{row:?}");
    assert!((row.value - 0.070).abs() <= 1e-7, "{row:?}");
    assert!(10 * optimum.solves <= sweep.solves);
}

#[test]
fn hose2_length_and_the_oil_cooler_height_agree_with_a_2d_sweep() {
    let case = cooler_with_bend_limit();
    let vars = || {
        vec![
            rod_length("hose2", 190.0, 230.0, 300.0),
            variable(
                "oil_cooler.position.z",
                "connectors.oil_cooler.position",
                Some(2),
                75.0,
                15.0,
                95.0,
            ),
        ]
    };
    let optimum = run(&case, vars(), &["bend_radius>=min"]);
    assert!(optimum.converged, "{}", optimum.message);
    // The reference: a 5 mm grid over the bounds, then 1 mm around its best. The
    // objective is a V-shaped valley along the line where hose 3's peak overtakes
    // hose 2's, so a grid point is only as good as its distance to that line: along
    // each 1 mm row of heights the floor of the valley is where the two peaks cross,
    // interpolated linearly between the 1 mm solves on either side.
    let mut sweep = Sweep::new(&case, &vars());
    let feasible = |o: &BTreeMap<String, f64>| o["hose2.min_bend_radius_m"] >= 0.060;
    let mut rows = |lengths: &[f64], heights: &[f64]| -> Vec<Vec<BTreeMap<String, f64>>> {
        heights
            .iter()
            .enumerate()
            .map(|(i, &z)| {
                // Snake order: every point warm-starts from its neighbour.
                let mut row: Vec<(f64, BTreeMap<String, f64>)> = lengths
                    .iter()
                    .enumerate()
                    .map(|(k, _)| if i % 2 == 0 { k } else { lengths.len() - 1 - k })
                    .map(|k| (lengths[k], sweep.at(&[lengths[k] - 190.0, z - 75.0])))
                    .collect();
                row.sort_by(|a, b| a.0.total_cmp(&b.0));
                row.into_iter().map(|(_, o)| o).collect()
            })
            .collect()
    };
    let steps = |from: f64, to: f64, h: f64| -> Vec<f64> {
        (0..=((to - from) / h).round() as usize)
            .map(|k| from + h * k as f64)
            .collect()
    };
    let (lengths, heights) = (steps(230.0, 300.0, 5.0), steps(15.0, 95.0, 5.0));
    let coarse = rows(&lengths, &heights);
    let mut best = (f64::INFINITY, 0.0, 0.0);
    for (row, z) in coarse.iter().zip(&heights) {
        for (o, l) in row.iter().zip(&lengths) {
            if feasible(o) && peak(o).0 < best.0 {
                best = (peak(o).0, *l, *z);
            }
        }
    }
    let lengths = steps((best.1 - 10.0).max(230.0), (best.1 + 10.0).min(300.0), 1.0);
    let heights = steps((best.2 - 10.0).max(15.0), (best.2 + 10.0).min(95.0), 1.0);
    let fine = rows(&lengths, &heights);
    let mut floor = (f64::INFINITY, 0.0, 0.0);
    for (row, &z) in fine.iter().zip(&heights) {
        for k in 0..row.len() {
            let (o, l) = (&row[k], lengths[k]);
            if feasible(o) && peak(o).0 < floor.0 {
                floor = (peak(o).0, l, z);
            }
            let Some(next) = row.get(k + 1) else { continue };
            let gap = |o: &BTreeMap<String, f64>| o["hose2.peak_force_N"] - o["hose3.peak_force_N"];
            if feasible(o) && feasible(next) && gap(o) > 0.0 && gap(next) <= 0.0 {
                let t = gap(o) / (gap(o) - gap(next));
                let value = o["hose2.peak_force_N"]
                    + t * (next["hose2.peak_force_N"] - o["hose2.peak_force_N"]);
                if value < floor.0 {
                    floor = (value, l + t, z);
                }
            }
        }
    }
    assert!(
        (optimum.objective - floor.0).abs() <= 1e-3 * floor.0,
        "optimum {} N at {:?}, sweep {} N at ({}, {})",
        optimum.objective,
        optimum.values,
        floor.0,
        floor.1,
        floor.2
    );
    for (k, reference) in [floor.1, floor.2].iter().enumerate() {
        assert!(
            (optimum.values[k] - reference).abs() <= 1.0,
            "optimum {:?}, sweep ({}, {})",
            optimum.values,
            floor.1,
            floor.2
        );
    }
    assert_kink_in_fewer_solves(&optimum, sweep.solves);
}

/// A trial point whose design the case forbids (the pinned cable shortened to 500 mm
/// between studs 640 mm apart: beyond the 10 % of strain the builder allows) is a
/// rejected trial that names the point and the rule, not the end of the run (it was
/// an error naming a variant 'sensitivity' the case does not have): minimising the
/// peak moment drives the length down, and the run ends converged at a length the
/// case allows.
#[test]
fn a_trial_the_case_forbids_is_rejected_and_the_run_goes_on() {
    let case = Case::from_path(cases_dir().join("pinned_cable.ron")).unwrap();
    let problem = Problem {
        variables: vec![rod_length("cable", 800.0, 500.0, 900.0)],
        objective: Objective::Output("cable.peak_moment_Nm".into()),
        limits: Vec::new(),
    };
    let optimum = optimize(&case, &problem, &OptimizeSettings::default(), &mut |_| {}).unwrap();
    let rejected: Vec<&str> = optimum
        .history
        .iter()
        .map(|i| i.note.as_str())
        .filter(|note| note.contains("cannot be built"))
        .collect();
    assert!(!rejected.is_empty(), "{:?}", optimum.history);
    for note in &rejected {
        assert!(
            note.contains("the design at rods.cable.length -") && note.contains("apart"),
            "{note}"
        );
        assert!(
            !note.contains("variant") && !note.contains("hint"),
            "{note}"
        );
    }
    assert!(optimum.converged, "{}", optimum.message);
    assert!(optimum.solution.report.converged);
    assert!(optimum.values[0] >= 640.0 / 1.1, "{:?}", optimum.values);
}

/// `--minimize peak_moment:<rod>` is the rod's peak |m| output and `peak_moment` the
/// largest over the rods (a min–max): on the pinned cable (one rod) both find the
/// optimum of the output objective `cable.peak_moment_Nm`, attained by that output;
/// an unknown rod is an input error naming the rods.
#[test]
fn peak_moment_objectives_minimise_the_rods_peak_moments() {
    let case = Case::from_path(cases_dir().join("pinned_cable.ron")).unwrap();
    let run = |objective: Objective| {
        let problem = Problem {
            variables: vec![rod_length("cable", 800.0, 650.0, 900.0)],
            objective,
            limits: Vec::new(),
        };
        optimize(&case, &problem, &OptimizeSettings::default(), &mut |_| {})
    };
    let by_output = run(Objective::Output("cable.peak_moment_Nm".into())).unwrap();
    assert!(by_output.converged, "{}", by_output.message);
    for text in ["peak_moment", "peak_moment:cable"] {
        let optimum = run(Objective::parse(text).unwrap()).unwrap();
        assert!(optimum.converged, "{text}: {}", optimum.message);
        assert_eq!(optimum.values, by_output.values, "{text}");
        assert_eq!(optimum.objective, by_output.objective, "{text}");
        assert_eq!(optimum.attained_by, ["cable.peak_moment_Nm"], "{text}");
    }
    let unknown = run(Objective::parse("peak_moment:hose").unwrap());
    let message = unknown.expect_err("an unknown rod").to_string();
    assert!(
        message.contains("there is no rod 'hose'") && message.contains("cable"),
        "{message}"
    );
}

/// An optimum on a variable's bound reports the bound active with the objective's
/// slope there as its multiplier: the cooler hose's largest peak moment falls with hose
/// 2's length up to its 300 mm bound. The interior-point step ended 1.9e-5 mm short of
/// it (1.3e-7 of the width, beyond the snap of 1e-7) and the run reported no bound
/// active. The multiplier (N·m per mm beyond the bound) against central differences of
/// full solves there.
#[test]
fn an_optimum_on_a_bound_reports_it_active_with_the_objectives_slope() {
    let case = Case::from_path(cases_dir().join("cooler_hose.ron")).unwrap();
    let length = || rod_length("hose2", 190.0, 150.0, 300.0);
    let problem = Problem {
        variables: vec![length()],
        objective: Objective::parse("peak_moment").unwrap(),
        limits: Vec::new(),
    };
    let optimum = optimize(&case, &problem, &OptimizeSettings::default(), &mut |_| {}).unwrap();
    assert!(optimum.converged, "{}", optimum.message);
    assert_eq!(optimum.values, [300.0]);
    let row = optimum
        .constraints
        .iter()
        .find(|c| c.active)
        .unwrap_or_else(|| panic!("no active bound: {:?}", optimum.constraints));
    assert_eq!(row.name, "hose2.length <= 300mm", "{row:?}");
    let [attained] = optimum.attained_by.as_slice() else {
        panic!("{:?}", optimum.attained_by)
    };
    let h = 0.1;
    let (up, down) = either_side(&case, length(), optimum.offsets[0], h);
    let slope = (up[attained.as_str()] - down[attained.as_str()]) / (2.0 * h);
    assert!(slope < 0.0, "{attained} falls with the length: {slope}");
    assert!(
        (row.multiplier + slope).abs() <= 1e-3 * slope.abs(),
        "multiplier {} N·m/mm, full solves {} N·m/mm",
        row.multiplier,
        -slope
    );
}

#[test]
fn a_hose_kept_10mm_from_the_bracket_ends_on_the_clearance_with_its_multiplier() {
    let case = Case::from_path(cases_dir().join("cooler_hose_contact.ron")).unwrap();
    let length = || rod_length("hose3", 350.0, 290.0, 350.0);
    // The case rests hose 3 on the bracket (contact): the start is infeasible.
    let optimum = run(&case, vec![length()], &["clearance>=10mm"]);
    assert!(optimum.converged, "{}", optimum.message);
    let row = optimum
        .constraints
        .iter()
        .find(|c| c.active)
        .expect("an active constraint");
    assert_eq!(row.output, "hose3.clearance_m.brackets");
    assert!((row.value - 0.010).abs() <= 1e-6, "{row:?}");
    assert!(
        row.multiplier > 0.0 && row.d_objective_d_bound > 0.0,
        "{row:?}"
    );
    // The multiplier against differences of full solves at the optimum: on the
    // constraint, ∇F = μ ∇c, so μ = (dF/dx) / (dc/dx) (N per m of clearance).
    let h = 0.1;
    let (up, down) = either_side(&case, length(), optimum.offsets[0], h);
    let d = |name: &str| (up[name] - down[name]) / (2.0 * h);
    let (df, dc) = (d("hose2.peak_force_N"), d("hose3.clearance_m.brackets"));
    assert!(
        df < 0.0 && dc < 0.0,
        "a longer hose 3 relieves hose 2 and sags: {df} {dc}"
    );
    let reference = df / dc;
    assert!(
        (row.multiplier - reference).abs() <= 1e-3 * reference,
        "multiplier {} N/m, full solves {reference} N/m",
        row.multiplier
    );
    // The optimum is the longest hose 3 with 10 mm to spare: 0.1 mm longer violates it.
    assert!(up["hose3.clearance_m.brackets"] < 0.010);
}

#[test]
fn the_command_writes_the_contract_and_rejects_bad_input_without_writing() {
    let dir = tempfile::tempdir().unwrap();
    let case_path = dir.path().join("cooler_bend.ron");
    let text = std::fs::read_to_string(cases_dir().join("cooler_hose.ron"))
        .unwrap()
        .replace(
            "inner_radius: 9.4, outer_radius: 12.9)",
            "inner_radius: 9.4, outer_radius: 12.9, min_bend_radius: 60)",
        );
    std::fs::write(&case_path, text).unwrap();
    let case = case_path.to_str().unwrap();
    let out = dir.path().join("opt");
    let (exit, stdout, stderr) = crate::common::strand(&[
        "optimize",
        case,
        "--vary",
        "hose2.length=150mm..300mm",
        "--minimize",
        "peak_force",
        "--subject-to",
        "bend_radius>=min",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(exit, strand_cli::Exit::Success, "{stdout}\n{stderr}");
    assert!(stdout.contains("optimum     hose2.length = "), "{stdout}");
    let mut files: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    // Written atomically: no temporary file is left.
    // (and the optimum's results, for `strand report`).
    assert_eq!(
        files,
        [
            "cooler_bend_optimum.ron",
            "history.csv",
            "history.svg",
            "hose1.csv",
            "hose2.csv",
            "hose3.csv",
            "optimum.json",
            "result.json",
            "rods.vtp",
            "tubes.obj",
            "tubes.stl"
        ]
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("optimum.json")).unwrap()).unwrap();
    assert_eq!(json["converged"], true);
    let length = &json["parameters"]["hose2.length"];
    assert_eq!(length["unit"], "mm");
    let value = length["value"].as_f64().unwrap();
    assert!((150.0..=300.0).contains(&value));
    assert_eq!(json["objective"]["name"], "peak_force");
    let objective = json["objective"]["value"].as_f64().unwrap();
    assert!(json["active_constraints"].is_array());
    let solves = json["solves"].as_u64().unwrap();
    let history = json["history"].as_array().unwrap();
    assert!(solves >= history.len() as u64);
    let csv = std::fs::read_to_string(out.join("history.csv")).unwrap();
    assert!(
        csv.starts_with("iteration,solves,hose2.length [mm],peak_force [N],"),
        "{csv}"
    );
    assert_eq!(csv.lines().count(), history.len() + 1);
    let svg = std::fs::read_to_string(out.join("history.svg")).unwrap();
    let tree = roxmltree::Document::parse(&svg).unwrap();
    assert_eq!(
        tree.descendants()
            .filter(|n| n.attribute("class") == Some("trial"))
            .count(),
        history.len()
    );
    // The optimal case is ready to solve, from anywhere, and gives the objective.
    let optimal = Case::from_path(out.join("cooler_bend_optimum.ron")).unwrap();
    let built = optimal.build(None).unwrap();
    assert!(
        (optimal.file.rods[1].length.unwrap() - value).abs() <= 1e-9,
        "{:?}",
        optimal.file.rods[1].length
    );
    let solution = built
        .solve_from(built.initial.clone(), &built.settings)
        .unwrap();
    assert!(solution.report.converged);
    let designed = strand_case::DesignedCase::new(built);
    let outputs: BTreeMap<String, f64> = outputs_at(&designed, &solution, None)
        .unwrap()
        .into_iter()
        .map(|o| (o.name, o.value))
        .collect();
    assert!((peak(&outputs).0 - objective).abs() <= 1e-6 * objective);

    // `strand report` on the folder shows the optimisation: the optimum and every
    // trial point of the history.
    let report = dir.path().join("report.html");
    let (exit, stdout, stderr) = crate::common::strand(&[
        "report",
        out.to_str().unwrap(),
        "--out",
        report.to_str().unwrap(),
    ]);
    assert_eq!(exit, strand_cli::Exit::Success, "{stderr}");
    assert!(
        stdout.contains("studies     optimum: optimisation"),
        "{stdout}"
    );
    let html = std::fs::read_to_string(&report).unwrap();
    let page = roxmltree::Document::parse(html.strip_prefix("<!DOCTYPE html>\n").unwrap()).unwrap();
    let section = page
        .descendants()
        .find(|n| n.attribute("class") == Some("optimum"))
        .expect("an optimisation section");
    assert_eq!(section.attribute("data-converged"), Some("true"));
    let trials = section
        .descendants()
        .filter(|n| n.has_tag_name("tr") && n.attribute("data-accepted").is_some())
        .count();
    assert_eq!(trials, history.len());

    let bad = dir.path().join("bad");
    let contact = cases_dir().join("cooler_hose_contact.ron");
    let plain = cases_dir().join("cooler_hose.ron");
    for (case, args, named) in [
        (
            case,
            vec!["--vary", "hose2.length=300mm..150mm"],
            "300mm..150mm",
        ),
        (
            case,
            vec!["--vary", "nothing.length=1..2"],
            "nothing.length",
        ),
        (
            case,
            vec!["--vary", "hose2.segments=10..20"],
            "hose2.segments",
        ),
        (
            case,
            vec!["--vary", "hose2.length=150mm..300mm:1mm"],
            ":1mm",
        ),
        (
            case,
            vec![
                "--vary",
                "hose2.length=150mm..300mm",
                "--minimize",
                "peak_force:hose9",
            ],
            "hose9",
        ),
        (
            case,
            vec![
                "--vary",
                "hose2.length=150mm..300mm",
                "--minimize",
                "hose9.peak_force_N",
            ],
            "hose9.peak_force_N",
        ),
        (
            case,
            vec![
                "--vary",
                "hose2.length=150mm..300mm",
                "--subject-to",
                "clearance=10mm",
            ],
            "clearance=10mm",
        ),
        (
            case,
            vec![
                "--vary",
                "hose2.length=150mm..300mm",
                "--subject-to",
                "clearance>=10mm",
            ],
            "no environment",
        ),
        (
            case,
            vec![
                "--vary",
                "hose2.length=150mm..300mm",
                "--subject-to",
                "clearance>=10N",
            ],
            "clearance>=10N",
        ),
        (
            plain.to_str().unwrap(),
            vec![
                "--vary",
                "hose2.length=150mm..300mm",
                "--subject-to",
                "bend_radius>=min",
            ],
            "min_bend_radius",
        ),
        (
            contact.to_str().unwrap(),
            vec![
                "--vary",
                "hose3.length=290mm..350mm",
                "--subject-to",
                "clearance:hose7>=10mm",
            ],
            "hose7",
        ),
    ] {
        let mut all = vec!["optimize", case];
        all.extend(args.iter().copied());
        all.extend(["--out", bad.to_str().unwrap()]);
        let (exit, _, stderr) = crate::common::strand(&all);
        assert_eq!(exit, strand_cli::Exit::InvalidInput, "{args:?}: {stderr}");
        assert!(stderr.contains(named), "{args:?}: {stderr}");
        assert!(!bad.exists(), "{args:?} wrote {}", bad.display());
    }
}
