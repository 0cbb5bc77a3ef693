//! Moulded hoses held by clips (issue 17), `cases/moulded_clipped_hose.ron`: mounted at
//! the nominal clip frames without gravity the hose stays as moulded with zero
//! reactions; under gravity the connectors and clips carry exactly its weight.

use nalgebra::Vector3;
use strand_solve::SolverSettings;

fn built(gravity: bool) -> strand_case::BuiltCase {
    let path = crate::common::cases_dir().join("moulded_clipped_hose.ron");
    let mut text = std::fs::read_to_string(&path).unwrap();
    if !gravity {
        text = text.replace("gravity: (0, 0, -9.81)", "gravity: (0, 0, 0)");
    }
    strand_case::Case::from_str(&text, path.to_str().unwrap())
        .unwrap()
        .build(None)
        .unwrap()
}

#[test]
fn a_moulded_hose_at_its_nominal_clip_frames_is_stress_free_without_gravity() {
    let built = built(false);
    assert_eq!(built.model.system().clips.len(), 2);
    let solution = built
        .solve_from(built.initial.clone(), &SolverSettings::default())
        .unwrap();
    assert!(solution.report.converged, "{:?}", solution.report);
    assert_eq!(solution.report.iterations, 0, "{:?}", solution.report);
    let reactions = built.model.reactions(&solution.state);
    assert_eq!(reactions.len(), 4, "two connectors and two clips");
    for r in &reactions {
        assert!(
            r.force.norm() < 1e-9 && r.moment.norm() < 1e-9,
            "{}: force {} N, moment {} N m",
            r.name,
            r.force.norm(),
            r.moment.norm()
        );
    }
    // The solution is the nominal shape: the clipped vertices at the stations along
    // the CAD centreline (a leg along x from the origin, 100 mm in; 320 mm: on the
    // second leg along y at x = 210 mm, 320 − 150 − 30π mm past its start y = 60), to
    // the accuracy of the smooth curve through the points (0.1 mm here: the cubic
    // pieces next to a bend given every 15° only approximate the arc and the leg).
    let system = built.model.system();
    let expected = [
        Vector3::new(0.1, 0.0, 0.0),
        Vector3::new(0.21, 0.06 + 0.32 - 0.15 - 0.03 * std::f64::consts::PI, 0.0),
    ];
    for (clip, expected) in system.clips.iter().zip(expected) {
        let p = solution.state.rods[0].positions[clip.vertex];
        assert!((p - expected).norm() < 1e-4, "{}: {p}", clip.name);
    }
}

#[test]
fn under_gravity_the_clips_and_connectors_carry_the_moulded_hose() {
    let built = built(true);
    let solution = built
        .solve_from(built.initial.clone(), &SolverSettings::default())
        .unwrap();
    assert!(solution.report.converged, "{:?}", solution.report);
    assert!(solution.report.stable);
    let system = built.model.system();
    let reactions = built.model.reactions(&solution.state);
    let mut force = Vector3::zeros();
    let mut moment = Vector3::zeros();
    for r in &reactions {
        force += r.force;
        moment += r.moment + r.position.cross(&r.force);
    }
    let mut weight = Vector3::zeros();
    for (j, p) in solution.state.rods[0].positions.iter().enumerate() {
        let w = system.rods[0].rod.vertex_mass(j) * system.gravity;
        weight += w;
        moment += p.cross(&w);
    }
    // Weight of the hose: ρ A L g with the nominal curve's length 400 + 60π mm.
    let area = std::f64::consts::PI * (0.0129f64.powi(2) - 0.0094f64.powi(2));
    let length = 0.4 + 0.06 * std::f64::consts::PI;
    assert!((weight.norm() - 1100.0 * area * length * 9.81).abs() < 1e-3 * weight.norm());
    force += weight;
    assert!(
        force.norm() <= 1e-9 * weight.norm(),
        "force imbalance {force}"
    );
    assert!(
        moment.norm() <= 1e-9 * weight.norm(),
        "moment imbalance {moment}"
    );
    assert!(
        reactions
            .iter()
            .filter(|r| r.kind == strand_system::ReactionKind::Clip)
            .all(|r| r.force.norm() > 1e-3)
    );
}
