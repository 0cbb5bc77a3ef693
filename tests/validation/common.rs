//! Builders shared by the validation modules.

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use strand_rod::{Rod, Section};
use strand_solve::{Solution, SolverSettings, solve};
use strand_system::{End, Model, RodSpec, System, initial_state};

/// The paper's Elastica/helix section: EA = 30 kN, GA = 10 kN, EI = GJ = 1 N m².
pub fn paper_section() -> Section {
    Section::try_explicit(3e4, 1e4, 1.0, 1.0, 0.0, 0.0).unwrap()
}

/// A frame whose tangent `a3` is +x.
pub fn frame_along_x() -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2)
}

/// A frame from director columns `(d1, d2, d3)`.
pub fn frame_from_matrix(m: Matrix3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m))
}

/// One rod of the paper's section and length 1 m, clamped at the origin along +x.
pub fn clamped_rod(segments: usize, end: End) -> System {
    System {
        rods: vec![RodSpec {
            name: "rod".into(),
            rod: Rod::try_straight(paper_section(), 1.0, segments).unwrap(),
            start: End::clamped(Vector3::zeros(), frame_along_x()),
            end,
            route: None,
        }],
        bodies: vec![],
        clips: Vec::new(),
        gravity: Vector3::zeros(),
    }
}

/// Solves from the default initial guess and asserts convergence and stability.
pub fn solve_converged(system: System) -> (Model, Solution) {
    solve_converged_with(system, &SolverSettings::default())
}

/// As [`solve_converged`] with explicit settings.
pub fn solve_converged_with(system: System, settings: &SolverSettings) -> (Model, Solution) {
    let model = Model::try_new(system).unwrap();
    let solution = solve(&model, initial_state(model.system()), settings).unwrap();
    let report = &solution.report;
    assert!(report.converged, "not converged: {report:?}");
    assert!(
        report.residual.combined_n <= settings.tolerance_n,
        "residual {}",
        report.residual.combined_n
    );
    assert!(report.stable, "equilibrium not stable: {report:?}");
    (model, solution)
}

/// Observed orders `log2(e_k / e_{k+1})` of a sequence of errors on meshes refined by 2.
pub fn observed_orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

/// `[1.234e-5, …]`: a list of numbers for assertion messages.
pub fn sci(values: &[f64]) -> String {
    let items: Vec<String> = values.iter().map(|v| format!("{v:.3e}")).collect();
    format!("[{}]", items.join(", "))
}

/// The bundled `cases/` directory.
pub fn cases_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases")
}

/// Runs `strand ARGS` through the CLI's library entry point (the code path of the
/// binary); returns the exit status, stdout and stderr.
pub fn strand(args: &[&str]) -> (strand_cli::Exit, String, String) {
    let (mut out, mut err) = (Vec::new(), Vec::new());
    let exit = strand_cli::run(
        std::iter::once("strand").chain(args.iter().copied()),
        &mut out,
        &mut err,
    );
    (
        exit,
        String::from_utf8(out).unwrap(),
        String::from_utf8(err).unwrap(),
    )
}

/// Solves again from `start` with a full BVH search of every feature at every
/// evaluation (`ProximitySettings::full_queries`) and asserts that the incremental
/// proximity of `contact` gave the same answer: the same convergence and iterations,
/// the same contact rows carrying force (by key) and vertex positions within 1e-9 m.
pub fn assert_same_as_full_queries(
    model: &strand_system::Model,
    contact: &strand_solve::contact::Contact,
    start: strand_system::SystemState,
    settings: &SolverSettings,
    solution: &Solution,
    label: &str,
) {
    use strand_solve::contact::ProximitySettings;
    assert!(contact.proximity().incremental, "{label}: not incremental");
    let full = contact
        .clone()
        .with_proximity(ProximitySettings::full_queries());
    let reference = strand_solve::solve_constrained(model, &full, start, settings).unwrap();
    let active = |s: &Solution| {
        let mut keys: Vec<_> = s
            .constraints
            .iter()
            .filter(|(_, force)| *force > 0.0)
            .map(|(row, _)| row.key)
            .collect();
        keys.sort();
        keys
    };
    assert_eq!(
        solution.report.converged, reference.report.converged,
        "{label}: convergence differs from full queries"
    );
    assert_eq!(
        solution.report.iterations, reference.report.iterations,
        "{label}: iterations differ from full queries"
    );
    assert_eq!(
        active(solution),
        active(&reference),
        "{label}: active contacts differ from full queries"
    );
    let mut largest = 0.0f64;
    for (a, b) in solution.state.rods.iter().zip(&reference.state.rods) {
        for (p, q) in a.positions.iter().zip(&b.positions) {
            largest = largest.max((p - q).norm());
        }
    }
    println!("{label}: incremental vs full queries: positions differ by {largest:.1e} m");
    assert!(largest <= 1e-9, "{label}: positions differ by {largest} m");
}
