//! The KKT system of one rod's many rows ([`super::kkt`]) against a brute-force QP
//! solution, and its work counted at two rod lengths: with rows in proportion to the
//! rod's length, the KKT step grows like `(unknowns + rows) × bandwidth` (4× for 4×
//! the length), where a solve over the whole rod per row grows like `rows × unknowns`
//! (16×).

use nalgebra::DVector;
use strand_system::HessianPattern;

use super::ConstrainedStep;
use super::exact::{ExactStepWork, GroupMethod, exact_step_counted};
use super::kkt::KktInput;
use super::scaling_tests::{assert_brute_force_step, brute_force, next, random_matrix, row};
use crate::SparseCholesky;
use crate::constraints::Row;

/// A rod-like chain of `blocks` 3×3 blocks (every block coupled to the two before it:
/// banded, factorised in its envelope) with a random positive definite matrix, its
/// Newton step for a random gradient, and one row per even block `2k` reaching blocks
/// `2k` and `2k + 2` (a contact on a segment), valued so that the Newton step violates
/// about half of them.
pub(super) struct Chain {
    pub cholesky: SparseCholesky,
    pub dense: nalgebra::DMatrix<f64>,
    pub newton: DVector<f64>,
    pub rows: Vec<Row>,
}

pub(super) fn chain(blocks: usize, seed: u64) -> Chain {
    chain_with_body(blocks, seed, false)
}

/// [`chain`], with one more block after the chain when `body` is set: a junction body
/// numbered after its rods, coupled to the chain's first, middle and last blocks (three
/// rod ends meeting at a T), so its profile row reaches back over the whole chain.
fn chain_with_body(blocks: usize, seed: u64, body: bool) -> Chain {
    let mut elements: Vec<Vec<usize>> = (0..blocks - 2).map(|b| vec![b, b + 1, b + 2]).collect();
    if body {
        elements.extend([
            vec![0, blocks],
            vec![blocks / 2, blocks],
            vec![blocks - 1, blocks],
        ]);
    }
    let pattern = HessianPattern::new(
        blocks + usize::from(body),
        elements.iter().map(|e| e.as_slice()),
    );
    let mut seed = seed;
    let (values, dense) = random_matrix(&pattern, &mut seed);
    let mut cholesky = SparseCholesky::try_new(&pattern).unwrap();
    assert!(body || cholesky.is_envelope());
    assert!(cholesky.factor(&values));
    let n = pattern.dim();
    let gradient = DVector::from_fn(n, |_, _| next(&mut seed));
    let newton = -dense.clone().cholesky().unwrap().solve(&gradient);
    let rows = (0..(blocks - 1) / 2)
        .map(|k| {
            let gradient: Vec<(usize, f64)> = (0..3)
                .flat_map(|c| [6 * k + c, 6 * k + 6 + c])
                .map(|u| (u, next(&mut seed)))
                .collect();
            let reach: f64 = gradient.iter().map(|&(u, a)| a * newton[u]).sum();
            row(k as u64, -reach + 0.3 * next(&mut seed), gradient)
        })
        .collect();
    Chain {
        cholesky,
        dense,
        newton,
        rows,
    }
}

#[test]
fn the_kkt_step_of_one_rod_with_many_rows_is_the_brute_force_qp_solution() {
    let mut rod = chain(23, 11);
    assert_eq!(rod.rows.len(), 11);
    let (expected_step, expected_multipliers) = brute_force(&rod.dense, &rod.newton, &rod.rows);
    let held = expected_multipliers.iter().filter(|&&l| l > 0.0).count();
    assert!(
        held >= 3,
        "only {held} rows active: the check would be weak"
    );
    let all: Vec<usize> = (0..rod.rows.len()).collect();
    for method in [GroupMethod::Automatic, GroupMethod::Kkt] {
        for hint in [&[][..], &[1, 4, 7], &all] {
            let (result, work) = exact_step_counted(
                &mut rod.cholesky,
                &rod.rows,
                hint,
                rod.newton.as_slice(),
                method,
            )
            .expect("the exact step settles");
            // Forced, the KKT system alone (the automatic choice keeps the columns of
            // these few rows on a short band, or switches once they cost more).
            if method == GroupMethod::Kkt {
                assert_eq!(work.solves, 0);
                assert!(work.products > 0, "{work:?}");
            }
            assert_brute_force_step(
                &result.step,
                &result.multipliers,
                &expected_step,
                &expected_multipliers,
            );
        }
    }
}

/// The work of the settled step of a chain of `blocks` blocks by `method`, started
/// from its own active set (one pass), as multiply–adds: solves × the factor's size,
/// plus the written entries and the KKT products.
fn settled_work(blocks: usize, method: GroupMethod) -> (usize, usize) {
    settled_work_of(chain(blocks, 5), method)
}

/// The automatic exact step of `rod` from an empty start, and its work.
fn from_an_empty_start(rod: &mut Chain) -> (ConstrainedStep, ExactStepWork) {
    let newton = rod.newton.as_slice().to_vec();
    let method = GroupMethod::Automatic;
    exact_step_counted(&mut rod.cholesky, &rod.rows, &[], &newton, method)
        .expect("the exact step settles")
}

/// [`settled_work`] of a given chain.
fn settled_work_of(mut rod: Chain, method: GroupMethod) -> (usize, usize) {
    let newton = rod.newton.as_slice().to_vec();
    let (first, _) = from_an_empty_start(&mut rod);
    let active: Vec<usize> = (0..rod.rows.len())
        .filter(|&i| first.multipliers[i] > 0.0)
        .collect();
    assert!(
        5 * active.len() >= rod.rows.len(),
        "{} active",
        active.len()
    );
    let (result, work): (_, ExactStepWork) =
        exact_step_counted(&mut rod.cholesky, &rod.rows, &active, &newton, method)
            .expect("the exact step settles");
    for (a, b) in result.step.iter().zip(&first.step) {
        assert!(
            (a - b).abs() < 1e-10 * (1.0 + b.abs()),
            "{method:?}: {a} vs {b}"
        );
    }
    let cost = work.solves * rod.cholesky.factor_nnz() + work.entries + work.products;
    (cost, rod.rows.len())
}

#[test]
fn the_kkt_step_grows_like_rows_times_bandwidth_not_rows_times_unknowns() {
    let (short, short_rows) = settled_work(101, GroupMethod::Automatic);
    let (long, long_rows) = settled_work(401, GroupMethod::Automatic);
    assert_eq!((short_rows, long_rows), (50, 200));
    // 4× the rod and the rows: 4× the work (banded), allowing 25 % for the active sets'
    // different sizes.
    let ratio = long as f64 / short as f64;
    assert!(
        ratio < 5.0,
        "KKT work grew {ratio:.1}× for 4× the rod and rows"
    );
    // The planted bug: one solve over the whole rod per row grows 16×, and fails.
    let (short_columns, _) = settled_work(101, GroupMethod::Columns);
    let (long_columns, _) = settled_work(401, GroupMethod::Columns);
    let columns_ratio = long_columns as f64 / short_columns as f64;
    assert!(
        columns_ratio > 10.0,
        "the column step grew {columns_ratio:.1}× (expected about 16×)"
    );
    // And the KKT step is the cheaper one already on the short rod.
    assert!(short < short_columns, "{short} vs {short_columns}");
}

/// The local numbering of the group holding every unknown of `rod`, and its KKT input.
fn whole_group(rod: &Chain) -> (Vec<usize>, Vec<usize>) {
    let n = rod.newton.len();
    ((0..n).collect(), (0..n).collect())
}

#[test]
fn a_junction_numbered_after_its_rods_costs_the_kkt_step_its_band_not_its_square() {
    // The estimate of a KKT pass is the factorisation's own count: a body's long row
    // costs its length times the band (each earlier row shares a few columns with it),
    // not its length squared, which kept a hose meeting a T at 8000 segments on the
    // columns (a solve over all unknowns per contact).
    for blocks in [101, 401] {
        let rod = chain_with_body(blocks, 5, true);
        let (unknowns, local) = whole_group(&rod);
        let input = KktInput {
            col_ptr: rod.cholesky.matrix().0,
            row_idx: rod.cholesky.matrix().1,
            values: rod.cholesky.matrix().2,
            rows: &rod.rows,
            unknowns: &unknowns,
            local: &local,
        };
        let costs = input.costs().expect("a narrow band on average");
        let mut products = 0;
        let factor = input
            .factor(&[], &[], &mut products)
            .expect("H is definite");
        let profile = (factor.substitution_products + factor.size()) / 2;
        assert_eq!(costs.kkt_pass, factor.factorisation_products + 3 * profile);
    }
    // The automatic step takes the KKT system: its work grows with the rod, not with
    // rows × unknowns.
    let work = |blocks| settled_work_of(chain_with_body(blocks, 5, true), GroupMethod::Automatic);
    let ((short, short_rows), (long, long_rows)) = (work(101), work(401));
    assert_eq!((short_rows, long_rows), (50, 200));
    let ratio = long as f64 / short as f64;
    assert!(
        ratio < 5.0,
        "the step's work grew {ratio:.1}× for 4× the rod"
    );
    // From an empty start the kept columns add one row per pass, each pass cheaper than
    // a KKT pass; they stop once their passes so far cost one (a few solves), not when
    // the next pass alone would (about 30 here, each a solve over every unknown).
    for blocks in [101, 401] {
        let (_, work) = from_an_empty_start(&mut chain_with_body(blocks, 5, true));
        assert!(work.solves <= 4, "{blocks} blocks: {work:?}");
    }
}

#[test]
fn a_row_that_depends_on_the_held_rows_is_held_out_and_the_step_is_the_qp_solution() {
    // An edge's row on a flat face is its two vertices' rows interpolated: the same
    // gradient and value combination. Started from every row, such a trio made the
    // KKT system (or the Schur matrix) singular and the step failed whole.
    let mut rod = chain(23, 11);
    let (expected_step, expected_multipliers) = brute_force(&rod.dense, &rod.newton, &rod.rows);
    let held: Vec<usize> = (0..rod.rows.len())
        .filter(|&i| expected_multipliers[i] > 0.0)
        .collect();
    assert!(held.len() >= 3, "only {} rows held", held.len());
    let (a, b) = (held[0], held[1]);
    let mut gradient = Vec::new();
    for (row, weight) in [(a, 0.3), (b, 0.7)] {
        gradient.extend(rod.rows[row].gradient.iter().map(|&(u, g)| (u, weight * g)));
    }
    let value = 0.3 * rod.rows[a].value + 0.7 * rod.rows[b].value;
    rod.rows.push(row(99, value, gradient));
    let all: Vec<usize> = (0..rod.rows.len()).collect();
    for method in [
        GroupMethod::Automatic,
        GroupMethod::Kkt,
        GroupMethod::Columns,
    ] {
        let (result, _) = exact_step_counted(
            &mut rod.cholesky,
            &rod.rows,
            &all,
            rod.newton.as_slice(),
            method,
        )
        .unwrap_or_else(|| panic!("{method:?}: the exact step settles"));
        for (x, y) in result.step.iter().zip(expected_step.iter()) {
            assert!(
                (x - y).abs() < 1e-12 * (1.0 + y.abs()),
                "{method:?}: {x} vs {y}"
            );
        }
        // The forces: the same `Aᵀ λ` whichever of the dependent rows carries them.
        let force = |multipliers: &[f64]| {
            let mut f = vec![0.0; rod.newton.len()];
            for (r, &l) in rod.rows.iter().zip(multipliers) {
                for &(u, g) in &r.gradient {
                    f[u] += l * g;
                }
            }
            f
        };
        let mut expected = expected_multipliers.clone();
        expected.push(0.0);
        for (x, y) in force(&result.multipliers).iter().zip(force(&expected)) {
            assert!(
                (x - y).abs() < 1e-10 * (1.0 + y.abs()),
                "{method:?}: {x} vs {y}"
            );
        }
        assert!(result.multipliers.iter().all(|&l| l >= 0.0), "{method:?}");
    }
}
