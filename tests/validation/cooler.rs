//! The cooler-hose study of the paper (§4, Fig. 7) on `cases/cooler_hose.ron`: three
//! rubber hoses joined by a free-hanging 1 kg T-junction, and the variant with hose 2
//! 50 mm longer, solved warm-started from the base as `strand study` does.
//!
//! Checks the paper's finding with our geometry: in the base design the short hose 2
//! carries the highest internal force; with 50 mm more the peak internal force of
//! every hose drops by at least 30 %, while the peak internal moment of every hose
//! changes by less than 25 %. Both solves converge (residual ≤ 1e-9 N) to stable
//! equilibria, and the connectors carry the whole weight, in force and in moment
//! (≤ 1e-9 relative).

use nalgebra::Vector3;
use strand_case::{BuiltCase, Case, warm_start};
use strand_report::{ArcOrigin, StudyPeak, StudyRun, Timing, arc_origin, collect, study_peaks};
use strand_solve::{Solution, SolverSettings, solve};
use strand_system::ReactionKind;

use crate::common::cases_dir;

const HOSES: [&str; 3] = ["hose1", "hose2", "hose3"];

fn case() -> Case {
    Case::from_path(cases_dir().join("cooler_hose.ron")).unwrap()
}

fn assert_solved(built: &BuiltCase, solution: &Solution, what: &str) {
    let report = &solution.report;
    assert!(report.converged, "{what}: not converged: {report:?}");
    assert!(
        report.residual.combined_n <= 1e-9,
        "{what}: residual {} N",
        report.residual.combined_n
    );
    assert!(report.stable, "{what}: equilibrium not stable");
    // The connectors carry the hoses and the junction: force and moment balance.
    let system = built.model.system();
    let state = &solution.state;
    let reactions = built.model.reactions(state);
    let connectors: Vec<_> = reactions
        .iter()
        .filter(|r| r.kind == ReactionKind::Connector)
        .collect();
    assert_eq!(connectors.len(), 3, "{what}");
    assert_eq!(
        reactions
            .iter()
            .filter(|r| r.kind == ReactionKind::Port)
            .count(),
        3,
        "{what}"
    );
    let tee = &system.bodies[0];
    let mass: f64 = system.rods.iter().map(|r| r.rod.mass()).sum::<f64>() + tee.mass;
    let weight = mass * system.gravity;
    let force: Vector3<f64> = connectors.iter().map(|r| r.force).sum::<Vector3<f64>>() + weight;
    assert!(
        force.norm() <= 1e-9 * weight.norm(),
        "{what}: force imbalance {force:?} (weight {weight:?})"
    );
    let com = state.bodies[0].transform_point(&tee.center_of_mass);
    for point in [Vector3::zeros(), Vector3::new(0.3, -0.2, 0.5)] {
        let mut moment = (com - point).cross(&(tee.mass * system.gravity));
        for r in &connectors {
            moment += (r.position - point).cross(&r.force) + r.moment;
        }
        for (spec, rod) in system.rods.iter().zip(&state.rods) {
            for (j, p) in rod.positions.iter().enumerate() {
                moment += (p - point).cross(&(spec.rod.vertex_mass(j) * system.gravity));
            }
        }
        assert!(
            moment.norm() <= 1e-9 * weight.norm(),
            "{what}: moment imbalance about {point:?}: {moment:?}"
        );
    }
}

/// Base and `hose2_plus50` solved, and their peaks (arc length from the junction).
fn study() -> Vec<StudyPeak> {
    let case = case();
    let base = case.build(None).unwrap();
    let variant = case.build_variant("hose2_plus50", None).unwrap();
    let base_solution = solve(&base.model, base.initial.clone(), &base.settings).unwrap();
    assert_solved(&base, &base_solution, "base");
    let initial = warm_start(&base.model, &base_solution.state, &variant.model);
    let settings = SolverSettings {
        nested_iteration: false,
        ..variant.settings.clone()
    };
    let variant_solution = solve(&variant.model, initial, &settings).unwrap();
    assert_solved(&variant, &variant_solution, "hose2_plus50");

    let origins: Vec<ArcOrigin> = (0..3).map(|r| arc_origin(&base.model, r)).collect();
    // Hose 1 runs from the radiator to the junction; hoses 2 and 3 leave it.
    assert_eq!(
        origins,
        [ArcOrigin::End, ArcOrigin::Start, ArcOrigin::Start]
    );
    let docs = [
        collect(&case.name, &base.model, &base_solution, Timing::default()),
        collect(
            &case.name,
            &variant.model,
            &variant_solution,
            Timing::default(),
        ),
    ];
    let runs = [
        StudyRun {
            variant: "base",
            doc: &docs[0],
        },
        StudyRun {
            variant: "hose2_plus50",
            doc: &docs[1],
        },
    ];
    study_peaks(&runs, &origins)
}

fn peak<'a>(peaks: &'a [StudyPeak], variant: &str, rod: &str) -> &'a StudyPeak {
    peaks
        .iter()
        .find(|p| p.variant == variant && p.rod == rod)
        .unwrap_or_else(|| panic!("no peak for {variant} {rod}"))
}

#[test]
fn longer_hose2_relieves_every_hose_while_moments_stay() {
    let peaks = study();
    let base = |rod| peak(&peaks, "base", rod);
    let longer = |rod| peak(&peaks, "hose2_plus50", rod);
    // Hose 2 carries the highest internal force in the base design.
    for rod in ["hose1", "hose3"] {
        assert!(
            base("hose2").peak_force_n > base(rod).peak_force_n,
            "hose2 {} N vs {rod} {} N",
            base("hose2").peak_force_n,
            base(rod).peak_force_n
        );
    }
    for rod in HOSES {
        let (b, l) = (base(rod), longer(rod));
        let force_change = l.force_change_pct.unwrap();
        let moment_change = l.moment_change_pct.unwrap();
        assert!(
            force_change <= -30.0,
            "{rod}: peak |f| {} -> {} N ({force_change:.1} %)",
            b.peak_force_n,
            l.peak_force_n
        );
        assert!(
            moment_change.abs() < 25.0,
            "{rod}: peak |m| {} -> {} N·m ({moment_change:.1} %)",
            b.peak_moment_nm,
            l.peak_moment_nm
        );
        assert!(
            (force_change - 100.0 * (l.peak_force_n / b.peak_force_n - 1.0)).abs() < 1e-9,
            "{rod}"
        );
    }
}
