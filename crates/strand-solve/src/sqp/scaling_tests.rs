//! The exact step against a brute-force QP solution (every active set tried with the
//! dense KKT system), and its work counted at two sizes: independent groups of rows
//! share their solves, so copies of one problem cost the same number of solves and
//! entries proportional to the copies (not to copies², as `O(rows × unknowns)` would).

use nalgebra::{DMatrix, DVector};
use strand_system::HessianPattern;

use super::exact::{ExactStepWork, GroupMethod, exact_step_counted};
use crate::SparseCholesky;
use crate::constraints::{Row, RowKey};

/// A deterministic pseudo-random number in [-1, 1).
pub(super) fn next(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    (*seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

pub(super) fn row(key: u64, value: f64, gradient: Vec<(usize, f64)>) -> Row {
    Row {
        key: RowKey::Contact(key),
        value,
        gradient,
        curvature: None,
    }
}

/// A random diagonally dominant matrix on `pattern` (upper values) and its dense copy.
pub(super) fn random_matrix(pattern: &HessianPattern, seed: &mut u64) -> (Vec<f64>, DMatrix<f64>) {
    let n = pattern.dim();
    let mut dense = DMatrix::zeros(n, n);
    for col in 0..n {
        for &r in &pattern.row_idx[pattern.col_ptr[col]..pattern.col_ptr[col + 1]] {
            if r != col {
                let v = next(seed);
                dense[(r, col)] = v;
                dense[(col, r)] = v;
            }
        }
    }
    for i in 0..n {
        dense[(i, i)] = 1.0 + 0.5 * (next(seed) + 1.0) + dense.row(i).abs().sum();
    }
    let mut values = Vec::with_capacity(pattern.nnz());
    for col in 0..n {
        for &r in &pattern.row_idx[pattern.col_ptr[col]..pattern.col_ptr[col + 1]] {
            values.push(dense[(r, col)]);
        }
    }
    (values, dense)
}

/// The QP solution by enumeration: the active set whose KKT point is feasible with
/// non-negative multipliers (unique for a positive definite `h` and independent rows).
pub(super) fn brute_force(
    h: &DMatrix<f64>,
    newton: &DVector<f64>,
    rows: &[Row],
) -> (DVector<f64>, Vec<f64>) {
    let n = h.nrows();
    for set in 0u32..1 << rows.len() {
        let held: Vec<usize> = (0..rows.len()).filter(|i| set >> i & 1 == 1).collect();
        let m = held.len();
        // [H −Aᵀ; A 0] (d − d_N, λ) = (0, −value − A d_N)
        let mut kkt = DMatrix::zeros(n + m, n + m);
        let mut rhs = DVector::zeros(n + m);
        kkt.view_mut((0, 0), (n, n)).copy_from(h);
        for (r, &i) in held.iter().enumerate() {
            for &(k, a) in &rows[i].gradient {
                kkt[(n + r, k)] += a;
                kkt[(k, n + r)] -= a;
            }
            rhs[n + r] = -rows[i].linearised(newton.as_slice());
        }
        let Some(solution) = kkt.lu().solve(&rhs) else {
            continue;
        };
        let step = newton + solution.rows(0, n);
        let mut multipliers = vec![0.0; rows.len()];
        for (r, &i) in held.iter().enumerate() {
            multipliers[i] = solution[n + r];
        }
        let feasible = rows.iter().all(|r| r.linearised(step.as_slice()) >= -1e-12);
        if feasible && multipliers.iter().all(|&l| l >= -1e-12) {
            return (step, multipliers);
        }
    }
    panic!("no active set solves the QP");
}

/// The step and multipliers of an exact step equal the brute-force QP's (1e-12 and
/// 1e-11 relative to 1 + |value|).
pub(super) fn assert_brute_force_step(
    step: &[f64],
    multipliers: &[f64],
    expected_step: &DVector<f64>,
    expected_multipliers: &[f64],
) {
    for (a, b) in step.iter().zip(expected_step.iter()) {
        assert!((a - b).abs() < 1e-12 * (1.0 + b.abs()), "step {a} vs {b}");
    }
    for (a, b) in multipliers.iter().zip(expected_multipliers) {
        assert!(
            (a - b).abs() < 1e-11 * (1.0 + b.abs()),
            "multiplier {a} vs {b}"
        );
    }
}

/// Three independent blocks (blocks {0, 1}, {2}, {3, 4} coupled) and seven rows, two of
/// them joining blocks {0, 1} and {3, 4} (as a contact between two rods does).
fn check_against_brute_force(elements: &[Vec<usize>], blocks: usize, expect_envelope: bool) {
    let pattern = HessianPattern::new(blocks, elements.iter().map(|e| e.as_slice()));
    let mut seed = 7;
    let (values, dense) = random_matrix(&pattern, &mut seed);
    let mut cholesky = SparseCholesky::try_new(&pattern).unwrap();
    assert_eq!(cholesky.is_envelope(), expect_envelope);
    assert!(cholesky.factor(&values));
    let n = pattern.dim();
    let gradient = DVector::from_fn(n, |_, _| next(&mut seed));
    let newton = -dense.clone().cholesky().unwrap().solve(&gradient);
    let supports: [&[usize]; 7] = [
        &[0, 4],
        &[1, 5],
        &[6, 7],
        &[9, 13],
        &[3, 12],
        &[2, 14, 10],
        &[8],
    ];
    let rows: Vec<Row> = (supports.iter().enumerate())
        .map(|(i, support)| {
            let gradient: Vec<(usize, f64)> =
                support.iter().map(|&k| (k % n, next(&mut seed))).collect();
            let reach: f64 = gradient.iter().map(|&(k, a)| a * newton[k]).sum();
            // Values that leave the Newton step violating about half the rows.
            row(i as u64, -reach + 0.3 * next(&mut seed), gradient)
        })
        .collect();
    let (expected_step, expected_multipliers) = brute_force(&dense, &newton, &rows);
    let held = expected_multipliers.iter().filter(|&&l| l > 0.0).count();
    assert!(
        held >= 2,
        "only {held} rows active: the check would be weak"
    );
    let methods = [
        GroupMethod::Automatic,
        GroupMethod::Columns,
        GroupMethod::Kkt,
    ];
    let hints = [vec![], vec![0, 3], (0..rows.len()).collect::<Vec<_>>()];
    for (method, hint) in methods
        .iter()
        .flat_map(|m| hints.iter().map(move |h| (*m, h)))
    {
        let (result, _) = exact_step_counted(&mut cholesky, &rows, hint, newton.as_slice(), method)
            .expect("the exact step settles");
        assert_brute_force_step(
            &result.step,
            &result.multipliers,
            &expected_step,
            &expected_multipliers,
        );
    }
}

#[test]
fn the_grouped_step_is_the_brute_force_qp_solution_in_the_envelope() {
    let elements = vec![vec![0, 1], vec![3, 4]];
    check_against_brute_force(&elements, 5, true);
}

#[test]
fn the_grouped_step_is_the_brute_force_qp_solution_with_faer() {
    // Blocks 0 and 4 coupled across the others (not banded), 2 alone; same grouping.
    let elements = vec![
        vec![0, 1],
        vec![3, 4],
        vec![0, 4, 1],
        vec![0, 5],
        vec![1, 9],
    ];
    check_against_brute_force(&elements, 10, false);
}

/// `copies` independent 3×3 blocks `H = diag(2, 4, 1)`, each with the gradient
/// (−2, 8, −3) and the rows `0.5 + d1 ≥ 0`, `1 − d0 − d2 ≥ 0`, `10 + d0 ≥ 0`: per copy
/// the step is (0, −0.5, 1) with multipliers 6, 2, 0 (by hand: 4 d1 + 8 = λ0 at
/// d1 = −0.5; 2 d0 − 2 = −λ1 = d2 − 3 with d0 + d2 = 1).
fn copies_work(copies: usize) -> ExactStepWork {
    let elements: Vec<Vec<usize>> = vec![];
    let pattern = HessianPattern::new(copies, elements.iter().map(|e| e.as_slice()));
    let mut values = Vec::with_capacity(pattern.nnz());
    for col in 0..pattern.dim() {
        for &r in &pattern.row_idx[pattern.col_ptr[col]..pattern.col_ptr[col + 1]] {
            values.push(if r == col {
                [2.0, 4.0, 1.0][col % 3]
            } else {
                0.0
            });
        }
    }
    let mut cholesky = SparseCholesky::try_new(&pattern).unwrap();
    assert!(cholesky.factor(&values));
    let newton: Vec<f64> = (0..copies).flat_map(|_| [1.0, -2.0, 3.0]).collect();
    let rows: Vec<Row> = (0..copies)
        .flat_map(|c| {
            let o = 3 * c;
            [
                row(3 * c as u64, 0.5, vec![(o + 1, 1.0)]),
                row(3 * c as u64 + 1, 1.0, vec![(o, -1.0), (o + 2, -1.0)]),
                row(3 * c as u64 + 2, 10.0, vec![(o, 1.0)]),
            ]
        })
        .collect();
    // The kept columns throughout (the automatic choice moves such small groups to
    // their KKT systems after a pass or two): their solves are what is shared.
    let (result, work) =
        exact_step_counted(&mut cholesky, &rows, &[], &newton, GroupMethod::Columns).unwrap();
    for c in 0..copies {
        let step = &result.step[3 * c..3 * c + 3];
        for (a, b) in step.iter().zip([0.0, -0.5, 1.0]) {
            assert!((a - b).abs() < 1e-14, "copy {c}: {step:?}");
        }
        let m = &result.multipliers[3 * c..3 * c + 3];
        assert!((m[0] - 6.0).abs() < 1e-13 && (m[1] - 2.0).abs() < 1e-13 && m[2] == 0.0);
    }
    work
}

#[test]
fn independent_copies_share_their_solves_and_cost_entries_linear_in_the_copies() {
    let small = copies_work(4);
    let large = copies_work(64);
    // Two rows join per copy, one per pass: two shared solves at any size (one per
    // row and copy, 8 and 128, before grouping).
    assert_eq!(small.solves, 2);
    assert_eq!(large.solves, small.solves);
    // Columns and step rebuilds touch each copy's 3 unknowns: 16× the entries for 16×
    // the copies (full-length columns and steps would give 256×).
    assert!(small.entries > 0);
    assert_eq!(large.entries, 16 * small.entries);
}

/// A rod-like band of `blocks` 3-blocks, each coupled to the next, with one row per
/// unknown (`x_k ≥ −0.1 k / n`) that the Newton step (every unknown −1) violates: a
/// cable landing on a floor along `3 blocks` contacts.
fn landing(blocks: usize) -> (Vec<f64>, ExactStepWork, Vec<f64>) {
    let couplings: Vec<Vec<usize>> = (0..blocks - 1).map(|b| vec![b, b + 1]).collect();
    let pattern = HessianPattern::new(blocks, couplings.iter().map(|c| c.as_slice()));
    let mut seed = 7;
    let (values, _) = random_matrix(&pattern, &mut seed);
    let mut cholesky = SparseCholesky::try_new(&pattern).unwrap();
    assert!(cholesky.factor(&values));
    let n = pattern.dim();
    let newton = vec![-1.0; n];
    let rows: Vec<Row> = (0..n)
        .map(|k| row(k as u64, 0.1 * k as f64 / n as f64, vec![(k, 1.0)]))
        .collect();
    let (kkt, work) =
        exact_step_counted(&mut cholesky, &rows, &[], &newton, GroupMethod::Kkt).unwrap();
    let (columns, _) =
        exact_step_counted(&mut cholesky, &rows, &[], &newton, GroupMethod::Columns).unwrap();
    (kkt.step, work, columns.step)
}

#[test]
fn a_cable_landing_along_many_contacts_settles_in_a_few_passes() {
    // One row per pass would take a pass (a factorisation of the whole band) per
    // contact: 90 and 360. Batches of every violated row take a few at any size, and
    // settle on the step the kept columns give one row at a time (the QP's solution).
    for blocks in [30, 120] {
        let (kkt, work, columns) = landing(blocks);
        println!("{blocks} blocks: {} passes", work.passes);
        assert!(work.passes <= 6, "{blocks} blocks: {} passes", work.passes);
        for (a, b) in kkt.iter().zip(&columns) {
            assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{a} vs {b}");
        }
    }
}
