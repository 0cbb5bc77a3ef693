//! Listings restricted to some edges against the whole listing: the clearances'
//! least gap to each mesh ([`Contact::clearances`], which lists only the edges that
//! may hold it) against the least of [`Contact::gaps`], and the rows touching some
//! unknowns ([`Constraints::rows_touching`]) against those of [`Constraints::rows`]:
//! the same numbers bit for bit, for much less work.

use std::sync::Arc;

use nalgebra::{Point3, Vector3};
use strand_assets::wavy_surface;
use strand_contact::{Gap, ObstacleMesh, QueryWork, query_work};
use strand_system::{Model, SystemState, initial_state};

use super::Contact;
use super::tests::straight_rod;
use crate::constraints::{Constraints, Row};

/// A report's clearance search (m).
const SEARCH_M: f64 = 0.1;

/// A wavy floor over `[-0.6, 0.6]²` m (amplitude 24 mm) and a 90° groove along x
/// beside it (flanks `z = |y − 0.9| − 0.05`: the rod passes under its near flank).
fn meshes(triangles: usize) -> Vec<Arc<ObstacleMesh>> {
    let floor = wavy_surface(1.2, triangles);
    let floor =
        ObstacleMesh::try_from_triangles("floor", floor.vertices, &floor.triangles).unwrap();
    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    for (k, side) in [-1.0, 1.0].into_iter().enumerate() {
        let base = 4 * k as u32;
        for (x, t) in [(-0.6, 0.0), (1.6, 0.0), (1.6, 0.3), (-0.6, 0.3)] {
            vertices.push(Point3::new(x, 0.9 + side * t, t - 0.05));
        }
        faces.push([base, base + 1, base + 2]);
        faces.push([base, base + 2, base + 3]);
    }
    let groove = ObstacleMesh::try_from_triangles("groove", vertices, &faces).unwrap();
    vec![Arc::new(floor), Arc::new(groove)]
}

/// The straight rod's state bent into a wave across the floor towards the groove,
/// its lowest point `height` (m) above the floor's crests.
fn bent(model: &Model, height: f64, phase: f64) -> SystemState {
    let mut state = initial_state(model.system());
    let rod = &mut state.rods[0];
    let n = rod.positions.len() - 1;
    for j in 0..=n {
        let u = j as f64 / n as f64;
        let wave = 0.03 * (1.0 + (9.0 * u + phase).sin());
        let p = Vector3::new(u - 0.5, 0.7 * u, 0.024 + 0.01 + height + wave);
        rod.set_position(j, p);
    }
    state
}

/// Per mesh, the least gap of `gaps` (the first of equal ones, in their order).
fn least_per_mesh(gaps: &[Gap], meshes: usize) -> Vec<Option<Gap>> {
    let mut least: Vec<Option<Gap>> = vec![None; meshes];
    for gap in gaps {
        let strand_contact::Obstacle::Mesh(i) = gap.with else {
            continue;
        };
        if least[i].as_ref().is_none_or(|l| gap.gap < l.gap) {
            least[i] = Some(*gap);
        }
    }
    least
}

#[test]
fn the_least_gap_to_each_mesh_is_the_whole_listings_least_at_the_same_place() {
    let meshes = meshes(20_000);
    let contact = Contact::new(meshes.clone(), 0.02);
    let mut compared = [0; 2];
    for segments in [40, 333] {
        let model = straight_rod(segments, 0.0);
        for (height, phase) in [(0.0005, 0.0), (0.004, 1.3), (0.03, 2.1), (0.07, 4.0)] {
            let state = bent(&model, height, phase);
            let all = contact.gaps(&model, &state, SEARCH_M).unwrap();
            let least = contact.clearances(&model, &state, SEARCH_M).unwrap();
            let expected = least_per_mesh(&all, meshes.len());
            let found = least_per_mesh(&least, meshes.len());
            for (k, (e, f)) in expected.iter().zip(&found).enumerate() {
                match (e, f) {
                    (Some(e), Some(f)) => {
                        assert_eq!(e.gap.to_bits(), f.gap.to_bits(), "{e:?} vs {f:?}");
                        assert_eq!((e.edge, e.s.to_bits()), (f.edge, f.s.to_bits()));
                        compared[k] += 1;
                    }
                    (None, None) => {}
                    _ => panic!("{segments} segments at {height} m: {e:?} vs {f:?}"),
                }
            }
        }
    }
    assert_eq!(compared, [8, 8], "least gaps compared per mesh");
}

#[test]
fn the_least_gaps_cost_a_fraction_of_the_whole_listing_and_grow_linearly() {
    let meshes = meshes(20_000);
    let contact = Contact::new(meshes, 0.02);
    let total = |w: QueryWork| w.bvh_nodes + w.box_tests + w.exact_tests;
    let work = |segments: usize| {
        let model = straight_rod(segments, 0.0);
        let state = bent(&model, 0.002, 0.5);
        let start = query_work();
        contact.gaps(&model, &state, SEARCH_M).unwrap();
        let middle = query_work();
        contact.clearances(&model, &state, SEARCH_M).unwrap();
        (
            total(middle.since(&start)),
            total(query_work().since(&middle)),
        )
    };
    let (listing, least) = work(200);
    let (_, least_fine) = work(800);
    println!("200 segments: listing {listing}, least {least}; 800 segments: least {least_fine}");
    assert!(least * 4 < listing, "least {least} vs listing {listing}");
    assert!(
        least_fine < 6 * least,
        "{least} → {least_fine} for 4× the segments"
    );
}

#[test]
fn the_rows_touching_a_few_unknowns_are_those_of_the_whole_listing() {
    let meshes = meshes(20_000);
    let contact = Contact::new(meshes, 0.02);
    let total = |w: QueryWork| w.bvh_nodes + w.box_tests + w.exact_tests;
    let model = straight_rod(300, 0.0);
    let state = bent(&model, 0.002, 0.5);
    let start = query_work();
    let mut all: Vec<Row> = Vec::new();
    contact.rows(&model, &state, &mut all).unwrap();
    let whole_work = total(query_work().since(&start));
    assert!(all.len() > 40, "{} rows", all.len());
    // Every 25th row's unknowns, as the active rows' would be.
    let wanted: Vec<&Row> = all.iter().step_by(25).collect();
    let mut unknowns = vec![false; model.dofs().len()];
    for row in &wanted {
        row.gradient.iter().for_each(|&(k, _)| unknowns[k] = true);
    }
    // A contact of its own, so that the near rows are searched afresh (as the whole
    // listing was), not from the kept lists the whole listing left.
    let fresh = Contact::new(self::meshes(20_000), 0.02);
    let start = query_work();
    let mut near: Vec<Row> = Vec::new();
    fresh
        .rows_touching(&model, &state, &unknowns, &mut near)
        .unwrap();
    let near_work = total(query_work().since(&start));
    for row in wanted {
        let found = near
            .iter()
            .find(|r| r.key == row.key)
            .expect("a wanted row");
        assert_eq!(found, row);
    }
    println!(
        "{} rows, {} near the wanted unknowns; work {whole_work} whole, {near_work} near",
        all.len(),
        near.len()
    );
    // The mesh's rows only near the wanted unknowns, each searched afresh where the
    // whole listing was the first too.
    assert!(near.len() <= all.len());
    assert!(near_work * 4 < whole_work, "{near_work} vs {whole_work}");
}

/// The pairs that carry a force ([`Contact::pressing_forces`]: only the edges next to
/// the vertices their rows move are searched) are those of the whole listing
/// ([`Contact::forces`]) with a force, in its order, bit for bit, for a fraction of
/// its work; with no force, none (and no search).
#[test]
fn the_pressing_pairs_are_the_whole_listing_s_pairs_with_a_force() {
    let contact = Contact::new(meshes(20_000), 0.02);
    let total = |w: QueryWork| w.bvh_nodes + w.box_tests + w.exact_tests;
    let model = straight_rod(300, 0.0);
    let state = bent(&model, 0.002, 0.5);
    let mut rows: Vec<Row> = Vec::new();
    contact.rows(&model, &state, &mut rows).unwrap();
    // Every 25th row presses, with a force of its own.
    let constraints: Vec<(Row, f64)> = rows
        .into_iter()
        .enumerate()
        .map(|(i, row)| (row, if i % 25 == 0 { 1.0 + i as f64 } else { 0.0 }))
        .collect();
    let measured = |contact: &Contact, pressing: bool| {
        let start = query_work();
        let forces = if pressing {
            contact.pressing_forces(&model, &state, &constraints)
        } else {
            contact.forces(&model, &state, &constraints)
        };
        (forces.unwrap(), total(query_work().since(&start)))
    };
    let (mut whole, whole_work) = measured(&Contact::new(meshes(20_000), 0.02), false);
    whole.retain(|f| f.force_n > 0.0);
    let (pressing, pressing_work) = measured(&Contact::new(meshes(20_000), 0.02), true);
    assert!(whole.len() > 8, "{} pressing pairs", whole.len());
    assert_eq!(pressing, whole);
    println!(
        "{} pressing pairs; work {whole_work} whole, {pressing_work} pressing",
        whole.len()
    );
    assert!(
        pressing_work * 4 < whole_work,
        "{pressing_work} vs {whole_work}"
    );
    let open: Vec<(Row, f64)> = constraints.iter().map(|(r, _)| (r.clone(), 0.0)).collect();
    let start = query_work();
    let none = contact.pressing_forces(&model, &state, &open).unwrap();
    assert!(none.is_empty());
    assert_eq!(total(query_work().since(&start)), 0);
}
