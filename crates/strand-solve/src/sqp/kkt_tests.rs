//! The KKT system of one rod's many rows ([`super::kkt`]) against a brute-force QP
//! solution, and its work counted at two rod lengths: with rows in proportion to the
//! rod's length, the KKT step grows like `(unknowns + rows) × bandwidth` (4× for 4×
//! the length), where a solve over the whole rod per row grows like `rows × unknowns`
//! (16×).

use nalgebra::DVector;
use strand_system::HessianPattern;

use super::exact::{ExactStepWork, GroupMethod, exact_step_counted};
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
    let elements: Vec<Vec<usize>> = (0..blocks - 2).map(|b| vec![b, b + 1, b + 2]).collect();
    let pattern = HessianPattern::new(blocks, elements.iter().map(|e| e.as_slice()));
    let mut seed = seed;
    let (values, dense) = random_matrix(&pattern, &mut seed);
    let mut cholesky = SparseCholesky::try_new(&pattern).unwrap();
    assert!(cholesky.is_envelope());
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
    let mut rod = chain(blocks, 5);
    let newton = rod.newton.as_slice().to_vec();
    let (first, _) = exact_step_counted(
        &mut rod.cholesky,
        &rod.rows,
        &[],
        &newton,
        GroupMethod::Automatic,
    )
    .expect("the exact step settles");
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
