//! The output table read locally (`strand_study::sensitivity::LocalOutputs`: each
//! output from the elements it depends on) against the whole table it replaces: the
//! same values and args along the first-order path, far from the base too (where the
//! peaks have moved), and the same derivatives and one-sided flags of every output
//! kind it reads (peaks of force and moment, smallest bend radius, connector and port
//! reactions, the junction's position and rotation, the energy). The whole table is
//! itself checked against differences of full solves (`sensitivity.rs`).

use strand_case::{Case, CaseDesign, DesignParameter};
use strand_solve::Solution;
use strand_solve::sensitivity::{Design, PathPlace, PathRows, Sensitivities, SensitivitySettings};
use strand_study::sensitivity::{
    ENERGY, EnergyOutput, LocalOutputs, LocalPath, OutputEvaluation, output_table,
    output_table_with, outputs_at,
};

use crate::common::cases_dir;

fn param(item: &str, component: Option<usize>, scale: f64) -> DesignParameter {
    DesignParameter {
        item: item.into(),
        component,
        scale,
    }
}

fn case(name: &str) -> Case {
    Case::from_path(cases_dir().join(name)).unwrap()
}

/// The bundled case `name` and its equilibrium, solved from the case's own start.
fn solved(name: &str) -> (Case, Solution) {
    let case = case(name);
    let built = case.build(None).unwrap();
    let solution = built
        .solve_from(built.initial.clone(), &built.settings)
        .unwrap();
    assert!(solution.report.converged, "{name}");
    (case, solution)
}

/// The cooler hose's parameters: affine ones (lengths, mass, positions, gravity) and
/// a frame's turn (built by the case builder at every step).
fn cooler_parameters() -> Vec<DesignParameter> {
    vec![
        param("rods.hose2.length", None, 1000.0),
        param("rods.hose1.length", None, 1000.0),
        param("junctions.tee.mass", None, 100.0),
        param("connectors.oil_cooler.position", Some(2), 1000.0),
        param("connectors.engine_stub.position", Some(0), 1000.0),
        param("gravity", Some(2), 10.0),
        param("connectors.oil_cooler.direction", Some(0), 572.96),
    ]
}

#[test]
fn local_outputs_equal_the_whole_table_along_the_path_and_far_from_the_base() {
    let (case, solution) = solved("cooler_hose.ron");
    let params = cooler_parameters();
    let design = CaseDesign::new(&case, params.clone()).starting_from(&solution.state);
    let base = design.build(&vec![0.0; params.len()]).unwrap();
    let outputs = outputs_at(&base, &solution, None).unwrap();
    let plan = LocalOutputs::plan(&base, &solution, &outputs).expect("a local plan");
    // Every kind the plan reads is there.
    for kind in [
        ".peak_force_N",
        ".peak_moment_Nm",
        ".min_bend_radius_m",
        "radiator_outlet.force_N.",
        "tee.hose2.moment_Nm.",
        "tee.position_m.",
        "tee.rotation_vector_rad.",
        ENERGY,
    ] {
        assert!(
            outputs.iter().any(|o| o.name.contains(kind)),
            "no {kind} output"
        );
    }
    let s = Sensitivities::compute(&design, &solution, &SensitivitySettings::default()).unwrap();
    let mut moved_args = 0;
    for j in 0..params.len() {
        // The difference steps, and 10 to 500 times the largest of them (up to 50 mm
        // of a length, 5 kg, 0.5 m/s², 29°): peaks move off their base vertex there.
        let h = s.parameters[j].output_step;
        for t in [h, -2.0 * h, 1e-2 * h, 10.0 * h, 500.0 * h, -50.0 * h] {
            let (point, at) = s
                .path_point(&design, &solution, j, t, PathRows::Active)
                .unwrap();
            let whole = outputs_at(&point, &at, Some(&outputs)).unwrap();
            let local = plan.read(&point.built.model, &at, PathPlace::Outermost);
            assert_eq!(whole.len(), local.len());
            for (w, l) in whole.iter().zip(&local) {
                let scale = w.value.abs().max(l.value.abs());
                assert!(
                    (w.value - l.value).abs() <= 1e-13 * scale,
                    "{} at {t} of {}: local {} vs whole table {}",
                    w.name,
                    params[j].item,
                    l.value,
                    w.value
                );
                assert_eq!(w.arg, l.arg, "{} at {t} of {}: arg", w.name, params[j].item);
            }
            moved_args += whole
                .iter()
                .zip(&outputs)
                .filter(|(w, b)| w.arg != b.arg)
                .count();
            // Inside the steps the base's args are reported, and the same values.
            let inner = plan.read(&point.built.model, &at, PathPlace::Inner);
            for ((i, l), b) in inner.iter().zip(&local).zip(&outputs) {
                assert_eq!(i.value, l.value);
                assert_eq!(i.arg, b.arg);
            }
        }
    }
    assert!(moved_args > 0, "no peak moved: the args were not tested");
}

/// Along an affine parameter the readings are taken without building the design at
/// the path's points (`LocalPath`: the base system with its real numbers moved, only
/// the vertices and edges read moved by the state's derivative): the same values and
/// args as the plan reading the built design and the retracted state, near the base
/// and far from it, at the outermost points (every vertex moved for the args) and
/// inside.
#[test]
fn readings_along_an_affine_line_equal_those_of_the_built_design() {
    let (case, solution) = solved("cooler_hose.ron");
    let params = cooler_parameters();
    let design = CaseDesign::new(&case, params.clone()).starting_from(&solution.state);
    let base = design.build(&vec![0.0; params.len()]).unwrap();
    let with_energy = outputs_at(&base, &solution, None).unwrap();
    let outputs = &with_energy[..with_energy.len() - 1];
    let plan = LocalOutputs::plan(&base, &solution, outputs).expect("a local plan");
    assert!(!plan.reads_energy());
    let s = Sensitivities::compute(&design, &solution, &SensitivitySettings::default()).unwrap();
    let mut lines = 0;
    for j in 0..params.len() {
        let Some(line) = design.affine_line(j).unwrap() else {
            continue;
        };
        lines += 1;
        let mut path = LocalPath::new(&plan, line, &solution.state, &s.parameters[j].state);
        let h = s.parameters[j].output_step;
        for t in [0.0, h, -2.0 * h, 1e-2 * h, 10.0 * h, 500.0 * h, -50.0 * h] {
            let (point, at) = s
                .path_point(&design, &solution, j, t, PathRows::Active)
                .unwrap();
            for place in [PathPlace::Outermost, PathPlace::Inner] {
                let built = plan.read(&point.built.model, &at, place);
                let local = path.read(t, place).unwrap();
                assert_eq!(built.len(), local.len());
                for ((b, l), o) in built.iter().zip(&local).zip(outputs) {
                    let scale = b.value.abs().max(l.value.abs());
                    assert!(
                        (b.value - l.value).abs() <= 1e-13 * scale,
                        "{} at {t} of {} ({place:?}): along the line {} vs built {}",
                        o.name,
                        params[j].item,
                        l.value,
                        b.value
                    );
                    assert_eq!(b.arg, l.arg, "{} at {t} of {}", o.name, params[j].item);
                }
            }
        }
    }
    // Every parameter but the connector's turn is affine.
    assert_eq!(lines, params.len() - 1);
}

#[test]
fn local_output_derivatives_equal_the_whole_tables_for_every_output() {
    let (case, solution) = solved("cooler_hose.ron");
    let params = cooler_parameters();
    let settings = SensitivitySettings::default();
    let table = |evaluation| {
        let design = CaseDesign::new(&case, params.clone()).starting_from(&solution.state);
        output_table_with(
            &design,
            &solution,
            &settings,
            evaluation,
            EnergyOutput::Included,
        )
        .unwrap()
    };
    // The local readings differentiated along the path as the whole table is (the
    // exact derivatives of `OutputEvaluation::Local` are checked against these in
    // `sensitivity_exact.rs`).
    let (local, whole) = (
        table(OutputEvaluation::LocalDifferences),
        table(OutputEvaluation::WholeTable),
    );
    assert_eq!(local.outputs, whole.outputs);
    let mut compared = 0;
    for (k, o) in whole.outputs.iter().enumerate() {
        for j in 0..params.len() {
            let (a, b) = (local.derivatives[k][j], whole.derivatives[k][j]);
            assert!(
                (a - b).abs() <= 1e-12 * b.abs().max(1e-9),
                "d {} / d {}: local {a} vs whole table {b}",
                o.name,
                params[j].item
            );
            assert_eq!(
                local.one_sided[k][j], whole.one_sided[k][j],
                "one-sided flag of d {} / d {}",
                o.name, params[j].item
            );
            compared += 1;
        }
    }
    assert!(compared >= 50 * params.len());
}

/// Without the energy (the default table, what `sensitivity.json` lists) every
/// other output keeps its value, derivatives and one-sided flags bit for bit, read
/// locally (exact derivatives along affine lines, the energy along the path) and as
/// the whole table (each against the same evaluation with the energy): the energy is
/// only left out, nothing shifts.
#[test]
fn a_table_without_the_energy_is_the_table_with_it_less_the_energy() {
    let (case, solution) = solved("cooler_hose.ron");
    let params = cooler_parameters();
    let settings = SensitivitySettings::default();
    let design = || CaseDesign::new(&case, params.clone()).starting_from(&solution.state);
    let table = |evaluation, energy| {
        output_table_with(&design(), &solution, &settings, evaluation, energy).unwrap()
    };
    for (without, with) in [
        (
            output_table(&design(), &solution, &settings).unwrap(),
            table(OutputEvaluation::Local, EnergyOutput::Included),
        ),
        (
            table(OutputEvaluation::WholeTable, EnergyOutput::Omitted),
            table(OutputEvaluation::WholeTable, EnergyOutput::Included),
        ),
    ] {
        assert_eq!(with.outputs.last().map(|o| o.name.as_str()), Some(ENERGY));
        assert!(
            without.find(ENERGY).is_none(),
            "the energy was not left out"
        );
        assert_eq!(without.outputs.len() + 1, with.outputs.len());
        assert_eq!(without.outputs[..], with.outputs[..without.outputs.len()]);
        for k in 0..without.outputs.len() {
            let name = &without.outputs[k].name;
            for j in 0..params.len() {
                let (a, b) = (without.derivatives[k][j], with.derivatives[k][j]);
                assert!(
                    (a - b).abs() <= 1e-12 * b.abs().max(1e-9),
                    "d {name} / d {}: {a} without the energy vs {b} with it",
                    params[j].item
                );
            }
            assert_eq!(without.one_sided[k], with.one_sided[k], "{name}");
        }
    }
}

#[test]
fn cases_with_clips_or_contacts_keep_the_whole_table() {
    for name in ["harness_clips.ron", "cooler_hose_contact.ron"] {
        let (case, solution) = solved(name);
        let design = CaseDesign::new(&case, vec![]).starting_from(&solution.state);
        let base = design.build(&[]).unwrap();
        let outputs = outputs_at(&base, &solution, None).unwrap();
        assert!(
            LocalOutputs::plan(&base, &solution, &outputs).is_none(),
            "{name}: clips, contacts and clearances have no local reading"
        );
    }
}
