//! Incremental proximity (issue 11): each rod feature keeps its candidate triangles
//! from its last mesh search and is searched again only after moving more than the
//! slack. The bundled contact cases solve the same with it as with a full search of
//! every feature at every evaluation (`ProximitySettings::full_queries`): the same
//! iterations, the same contacts carrying force, the same positions. The groove and
//! corner scenes (`groove.rs`) and the drop scenes (`drop.rs`) check the same in their
//! own solves.

use strand_case::Case;

use crate::common::{assert_same_as_full_queries, cases_dir};

/// Solves `file` (in `cases/`) with its own settings, then with full queries.
fn same_as_full_queries(file: &str) {
    let built = Case::from_path(cases_dir().join(file))
        .unwrap()
        .build(None)
        .unwrap();
    let contact = built.contact().expect("a case with an environment");
    let solution = strand_solve::solve_constrained(
        &built.model,
        &contact,
        built.initial.clone(),
        &built.settings,
    )
    .unwrap();
    assert!(solution.report.converged, "{file}: {:?}", solution.report);
    assert_same_as_full_queries(
        &built.model,
        &contact,
        built.initial.clone(),
        &built.settings,
        &solution,
        file,
    );
}

#[test]
fn the_cooler_hoses_in_their_engine_bay_solve_the_same_with_incremental_proximity() {
    same_as_full_queries("cooler_hose_contact.ron");
}

#[test]
fn a_hose_in_a_groove_solves_the_same_with_incremental_proximity() {
    same_as_full_queries("hose_in_groove.ron");
}

#[test]
fn a_cable_over_a_box_solves_the_same_with_incremental_proximity() {
    same_as_full_queries("cable_over_box.ron");
}
