//! The exact derivatives of the local readings along affine parameters
//! (`strand_study::sensitivity::LocalTangents`: the rods linearised once, each
//! parameter one tangent, no point of the path evaluated) against the extrapolated
//! differences of the same readings along the first-order path
//! (`OutputEvaluation::LocalDifferences`, itself equal to the whole table's and
//! checked against full solves in `sensitivity.rs`): every output's derivative and
//! one-sided flag, and the work of the one-sided check, which evaluates only the
//! vertices a first-order bound leaves at the outermost points, however finely the
//! hoses are cut.

use strand_case::{Case, CaseDesign, DesignParameter};
use strand_solve::Solution;
use strand_solve::sensitivity::{Design, SensitivitySettings};
use strand_study::sensitivity::{EnergyOutput, OutputEvaluation, OutputTable, output_table_with};

use crate::common::cases_dir;

fn param(item: &str, component: Option<usize>, scale: f64) -> DesignParameter {
    DesignParameter {
        item: item.into(),
        component,
        scale,
    }
}

/// The cooler hose with every hose cut into `factor` times its segments, solved.
fn cooler(factor: usize) -> (Case, Solution) {
    let path = cases_dir().join("cooler_hose.ron");
    let mut text = std::fs::read_to_string(&path).unwrap();
    for segments in [40, 19, 35] {
        let line = format!("segments: {segments},");
        assert!(text.contains(&line), "{line}");
        text = text.replace(&line, &format!("segments: {},", factor * segments));
    }
    let case = Case::from_str(&text, &path.to_string_lossy()).unwrap();
    let built = case.build(None).unwrap();
    let solution = built
        .solve_from(built.initial.clone(), &built.settings)
        .unwrap();
    assert!(solution.report.converged);
    (case, solution)
}

/// Every kind of affine parameter the cooler hose has: lengths, the T's mass,
/// connector positions, gravity, a tube's Young's modulus, a port's position on the
/// T; and a frame's turn (not affine: differentiated along the path).
fn parameters() -> Vec<DesignParameter> {
    vec![
        param("rods.hose2.length", None, 1000.0),
        param("rods.hose1.length", None, 1000.0),
        param("rods.hose3.length", None, 1000.0),
        param("junctions.tee.mass", None, 100.0),
        param("connectors.oil_cooler.position", Some(2), 1000.0),
        param("connectors.engine_stub.position", Some(0), 1000.0),
        param("connectors.radiator_outlet.position", Some(1), 1000.0),
        param("gravity", Some(2), 10.0),
        param("sections.hose_small.youngs_modulus", None, 5e8),
        param("junctions.tee.ports.hose3.position", Some(1), 1000.0),
        param("connectors.oil_cooler.direction", Some(0), 572.96),
    ]
}

fn table(
    case: &Case,
    solution: &Solution,
    evaluation: OutputEvaluation,
    energy: EnergyOutput,
) -> OutputTable {
    let design = CaseDesign::new(case, parameters()).starting_from(&solution.state);
    output_table_with(
        &design,
        solution,
        &SensitivitySettings::default(),
        evaluation,
        energy,
    )
    .unwrap()
}

/// The error of `a` against `b`, relative to the larger or absolute per 1e-9
/// (whichever is smaller).
fn score(a: f64, b: f64) -> f64 {
    let error = (a - b).abs();
    (error / a.abs().max(b.abs())).min(error / 1e-9)
}

/// Largest error of `exact` against `reference` per output and parameter, relative
/// to the larger derivative or absolute per 1e-9 (whichever is smaller), and the
/// one-sided flags equal.
fn compare(exact: &OutputTable, reference: &OutputTable, skip: Option<&str>) -> f64 {
    let params = parameters();
    assert_eq!(exact.outputs, reference.outputs);
    let mut worst: f64 = 0.0;
    for (k, o) in reference.outputs.iter().enumerate() {
        if Some(o.name.as_str()) == skip {
            continue;
        }
        for (j, p) in params.iter().enumerate() {
            let (a, b) = (exact.derivatives[k][j], reference.derivatives[k][j]);
            let score = score(a, b);
            assert!(
                score <= 1e-6,
                "d {} / d {}: exact {a} vs differences {b}",
                o.name,
                p.item
            );
            worst = worst.max(score);
            assert_eq!(
                exact.one_sided[k][j], reference.one_sided[k][j],
                "one-sided flag of d {} / d {}",
                o.name, p.item
            );
        }
    }
    worst
}

#[test]
fn exact_derivatives_equal_the_differences_along_the_path() {
    let (case, solution) = cooler(1);
    let exact = table(
        &case,
        &solution,
        OutputEvaluation::Local,
        EnergyOutput::Omitted,
    );
    let reference = table(
        &case,
        &solution,
        OutputEvaluation::LocalDifferences,
        EnergyOutput::Omitted,
    );
    let worst = compare(&exact, &reference, None);
    println!(
        "exact against differences: largest error {worst:.2e} (relative, or absolute per 1e-9)"
    );
    assert!(exact.outputs.len() >= 50);
    // The one-sided check evaluated a few candidates, not every vertex.
    println!(
        "vertices at the outermost points: {} exact, {} along the path",
        exact.outer_vertices, reference.outer_vertices
    );
    assert!(exact.outer_vertices * 10 < reference.outer_vertices);
}

/// With the energy among the outputs (read along the path: it has no local reading),
/// every other output keeps its exact derivative.
#[test]
fn the_energy_is_differentiated_along_the_path_and_the_rest_exactly() {
    let (case, solution) = cooler(1);
    let with = table(
        &case,
        &solution,
        OutputEvaluation::Local,
        EnergyOutput::Included,
    );
    let reference = table(
        &case,
        &solution,
        OutputEvaluation::LocalDifferences,
        EnergyOutput::Included,
    );
    let energy = strand_study::sensitivity::ENERGY;
    compare(&with, &reference, Some(energy));
    let k = with.find(energy).unwrap();
    assert_eq!(with.derivatives[k], reference.derivatives[k]);
}

/// The one-sided check's work grows with the candidates a first-order bound leaves,
/// not with the rods' vertices: the candidates cluster around each peak (a band whose
/// count follows the density of vertices there), a tenth of every vertex that the
/// differences along the path evaluate, at the case's segments and cut twice as
/// finely.
#[test]
fn outer_vertices_grow_with_the_candidates_not_the_segments() {
    let mut counts = Vec::new();
    for factor in [1, 2] {
        let (case, solution) = cooler(factor);
        let exact = table(
            &case,
            &solution,
            OutputEvaluation::Local,
            EnergyOutput::Omitted,
        );
        let reference = table(
            &case,
            &solution,
            OutputEvaluation::LocalDifferences,
            EnergyOutput::Omitted,
        );
        compare(&exact, &reference, None);
        println!(
            "{factor}x segments: {} vertices at the outermost points exact, {} along the path",
            exact.outer_vertices, reference.outer_vertices
        );
        counts.push((exact.outer_vertices, reference.outer_vertices));
    }
    // Along the path every vertex, twice per parameter read locally; exactly, a few
    // candidates per peak and side (nine peaks: three per hose).
    assert!(counts[1].1 > counts[0].1 * 19 / 10);
    for (factor, (exact, along)) in [1, 2].into_iter().zip(&counts) {
        assert!(exact * 10 < *along, "{factor}x: {exact} of {along}");
        assert!(
            *exact <= 2 * 9 * 3 * factor * parameters().len(),
            "{factor}x: {exact}"
        );
    }
}

/// `case` (in `cases/`) solved, with its exact table (`OutputEvaluation::Local`) and
/// its whole table (every output differentiated along the path, as checked against
/// full solves in `sensitivity.rs`) for `params`, the mesh queries each took, and
/// the names of the clearances the exclusion of near pairs sets
/// (`strand_report::LeastClearance::at_exclusion`).
fn contact_tables(
    case: &str,
    params: &[DesignParameter],
) -> (OutputTable, OutputTable, [u64; 2], Vec<String>) {
    let case = Case::from_path(cases_dir().join(case)).unwrap();
    let built = case.build(None).unwrap();
    let solution = built
        .solve_from(built.initial.clone(), &built.settings)
        .unwrap();
    assert!(solution.report.converged);
    let work = || {
        let w = strand_contact::query_work();
        w.bvh_nodes + w.box_tests + w.exact_tests
    };
    let table = |evaluation| {
        let design = CaseDesign::new(&case, params.to_vec()).starting_from(&solution.state);
        let before = work();
        let table = output_table_with(
            &design,
            &solution,
            &SensitivitySettings::default(),
            evaluation,
            EnergyOutput::Omitted,
        )
        .unwrap();
        (table, work() - before)
    };
    let (exact, exact_work) = table(OutputEvaluation::Local);
    let (whole, whole_work) = table(OutputEvaluation::WholeTable);
    // The clearances the exclusion of near pairs sets, by output name.
    let design = CaseDesign::new(&case, params.to_vec());
    let base = design.build(&vec![0.0; params.len()]).unwrap();
    let model = &base.built.model;
    let contact = base.contact.as_ref().unwrap();
    let by_exclusion = strand_report::least_clearances(
        model,
        &solution.state,
        contact,
        strand_report::CLEARANCE_SEARCH_M,
    )
    .unwrap()
    .into_iter()
    .filter(|c| c.at_exclusion)
    .map(|c| format!("{}.clearance_m.{}", model.system().rods[c.rod].name, c.with))
    .collect();
    (exact, whole, [exact_work, whole_work], by_exclusion)
}

/// With contact, the clearances (from their least gaps at the base: `n · (dP − dQ)`)
/// and the contact forces (their multipliers' derivatives) are exact too, with every
/// other output: the same derivatives and one-sided flags as the whole table
/// differentiated along the path, for a fraction of its mesh queries (which the whole
/// table repeats at every point of every path). A parameter that moves a mesh (the
/// brackets' height) is not an affine line of the model: it keeps the whole table.
#[test]
fn contact_cases_exact_derivatives_equal_the_whole_tables() {
    let cases = [
        (
            "cooler_hose_contact.ron",
            vec![
                param("rods.hose1.length", None, 1000.0),
                param("rods.hose3.length", None, 1000.0),
                param("junctions.tee.mass", None, 100.0),
                param("connectors.engine_stub.position", Some(2), 1000.0),
                param("connectors.oil_cooler.position", Some(0), 1000.0),
                param("environment.brackets.position", Some(2), 1000.0),
            ],
        ),
        (
            "hose_in_groove.ron",
            vec![
                param("rods.hose.length", None, 1000.0),
                param("connectors.a.position", Some(1), 1000.0),
            ],
        ),
        (
            "cable_over_box.ron",
            vec![
                param("rods.cable.length", None, 1000.0),
                param("connectors.a.position", Some(2), 1000.0),
            ],
        ),
    ];
    for (case, params) in cases {
        let (exact, whole, [exact_work, whole_work], excluded) = contact_tables(case, &params);
        assert_eq!(exact.outputs, whole.outputs);
        let mut worst: f64 = 0.0;
        let mut contact_outputs = 0;
        for (k, o) in whole.outputs.iter().enumerate() {
            contact_outputs +=
                usize::from(o.name.contains("clearance") || o.name.contains("contact"));
            for (j, p) in params.iter().enumerate() {
                let (a, b) = (exact.derivatives[k][j], whole.derivatives[k][j]);
                let error = (a - b).abs();
                // A derivative that vanishes (a connector's pull across the groove's
                // axis) is round-off in both.
                let vanishes = a.abs().max(b.abs()) <= 1e-12;
                let score = if vanishes { 0.0 } else { score(a, b) };
                // A rod's clearance to itself along a straight stretch is attained by
                // every pair of edges at the exclusion distance (a cable's edge length
                // less its diameter), tied to rounding: its derivative is one of
                // theirs (marked one-sided, below), which the differences' steps
                // average. Where the table's value ties so, both are the strain's
                // change of a straight stretch: within 1e-9 m per unit of the
                // parameter.
                let score = if self_clearance(&o.name) && error <= 1e-9 {
                    0.0
                } else {
                    score
                };
                assert!(
                    score <= 1e-6,
                    "{case}: d {} / d {}: exact {a} vs whole table {b}",
                    o.name,
                    p.item
                );
                worst = worst.max(score);
                // A clearance the exclusion of near pairs sets (a rod's to itself, two
                // rods' at the junction they end at; and a least clearance one of
                // them is) holds on one side only: marked in the exact table, which
                // knows its pair; the whole table reads no pair.
                let least_of = |name: &str| {
                    o.name.ends_with(".min_clearance_m")
                        && name.starts_with(o.name.trim_end_matches("min_clearance_m"))
                        && whole
                            .find(name)
                            .is_some_and(|i| whole.outputs[i].value == o.value)
                };
                let by_exclusion = excluded.iter().any(|n| *n == o.name || least_of(n));
                // (A parameter without an affine line, which keeps the whole
                // table, has its derivative bit for bit.)
                if by_exclusion {
                    assert!(
                        exact.one_sided[k][j] || a == b,
                        "{case}: d {} / d {} is one-sided",
                        o.name,
                        p.item
                    );
                    continue;
                }
                assert_eq!(
                    exact.one_sided[k][j], whole.one_sided[k][j],
                    "{case}: one-sided flag of d {} / d {}",
                    o.name, p.item
                );
            }
        }
        println!(
            "{case}: {} outputs ({contact_outputs} clearances and contact forces), largest error {worst:.2e}; mesh queries {exact_work} exact, {whole_work} whole table",
            whole.outputs.len()
        );
        assert!(contact_outputs >= 3, "{case}: {contact_outputs}");
        assert!(
            exact_work * 5 < whole_work * 2,
            "{case}: {exact_work} vs {whole_work}"
        );
    }
}

/// Whether `name` is a rod's clearance to itself (`<rod>.clearance_m.<rod>`).
fn self_clearance(name: &str) -> bool {
    name.split_once(".clearance_m.")
        .is_some_and(|(rod, with)| rod == with)
}
