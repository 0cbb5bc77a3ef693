//! The envelope backend against the residual of the matrix itself and against faer's
//! factorisation of the same matrix.

use strand_system::HessianPattern;

use super::envelope::EnvelopeCholesky;
use super::faer_llt::FaerCholesky;
use super::{SparseCholesky, symmetric_product, symmetric_products};

/// A deterministic pseudo-random number in [-1, 1).
pub(crate) fn next(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(1_442_695_040_888_963_407);
    (*seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// The pattern of a rod of `edges` edges numbered as the model numbers it (vertex
/// position, edge rotation, vertex position, …): a stretch-shear element couples
/// `(v_i, e_i, v_i+1)`, a bend-twist element `(e_i, e_i+1)`.
pub(crate) fn rod_pattern(edges: usize) -> HessianPattern {
    let mut elements: Vec<Vec<usize>> = Vec::new();
    for e in 0..edges {
        elements.push(vec![2 * e, 2 * e + 1, 2 * e + 2]);
        if e + 1 < edges {
            elements.push(vec![2 * e + 1, 2 * e + 3]);
        }
    }
    HessianPattern::new(2 * edges + 1, elements.iter().map(|e| e.as_slice()))
}

/// Random values on `pattern`, made positive definite by diagonal dominance (each
/// diagonal entry exceeds the sum of the magnitudes in its row by `margin`).
fn spd_values(pattern: &HessianPattern, seed: u64, margin: f64) -> Vec<f64> {
    let mut seed = seed;
    let n = pattern.dim();
    let mut values: Vec<f64> = (0..pattern.nnz()).map(|_| next(&mut seed)).collect();
    let mut row_sums = vec![0.0; n];
    for col in 0..n {
        for k in pattern.col_ptr[col]..pattern.col_ptr[col + 1] {
            let row = pattern.row_idx[k];
            if row != col {
                row_sums[row] += values[k].abs();
                row_sums[col] += values[k].abs();
            }
        }
    }
    for col in 0..n {
        for k in pattern.col_ptr[col]..pattern.col_ptr[col + 1] {
            if pattern.row_idx[k] == col {
                values[k] = row_sums[col] + margin;
            }
        }
    }
    values
}

fn residual_norm(pattern: &HessianPattern, values: &[f64], x: &[f64], b: &[f64]) -> f64 {
    let mut ax = vec![0.0; b.len()];
    symmetric_product(pattern, values, x, &mut ax);
    ax.iter()
        .zip(b)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn a_rod_pattern_is_factorised_in_its_envelope_and_solves_to_round_off() {
    for edges in [1, 2, 19, 200] {
        let pattern = rod_pattern(edges);
        let mut cholesky = SparseCholesky::try_new(&pattern).unwrap();
        assert!(cholesky.is_envelope(), "{edges} edges");
        // Rows of a rotation block reach back to the previous rotation: at most 4
        // blocks, 12 entries per row, far below the dense n²/2.
        assert!(cholesky.factor_nnz() <= 12 * pattern.dim());
        for seed in 0..3 {
            // A margin of 1e-3 leaves the matrix ill-conditioned enough for round-off
            // to show if an entry of the factor were wrong.
            let values = spd_values(&pattern, seed, 1e-3);
            assert!(cholesky.factor(&values));
            let mut s = seed + 100;
            let b: Vec<f64> = (0..pattern.dim()).map(|_| next(&mut s)).collect();
            let mut x = b.clone();
            cholesky.solve_in_place(&mut x);
            let b_norm = b.iter().map(|v| v * v).sum::<f64>().sqrt();
            let r = residual_norm(&pattern, &values, &x, &b);
            assert!(
                r <= 1e-12 * b_norm,
                "{edges} edges, seed {seed}: residual {r:e}"
            );

            let mut faer = FaerCholesky::try_new(&pattern).unwrap();
            assert!(faer.factor(&values));
            let mut y = b.clone();
            faer.solve_in_place(&mut y);
            let difference = x
                .iter()
                .zip(&y)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            let size = y.iter().map(|v| v.abs()).fold(0.0, f64::max);
            assert!(
                difference <= 1e-10 * size,
                "differs from faer by {difference:e}"
            );
        }
    }
}

#[test]
fn a_matrix_that_is_not_positive_definite_is_rejected_like_faer_rejects_it() {
    let pattern = rod_pattern(19);
    let mut envelope = EnvelopeCholesky::new(&pattern);
    let mut faer = FaerCholesky::try_new(&pattern).unwrap();
    let values = spd_values(&pattern, 7, 1e-3);
    assert!(envelope.factor(&values) && faer.factor(&values));
    // A negative eigenvalue deep inside: shift one diagonal entry far down.
    let mut indefinite = values.clone();
    let col = pattern.dim() / 2;
    let diagonal = pattern.col_ptr[col + 1] - 1;
    assert_eq!(pattern.row_idx[diagonal], col);
    indefinite[diagonal] = -1.0;
    assert!(!envelope.factor(&indefinite));
    assert!(!faer.factor(&indefinite));
    // Not a number anywhere: not positive definite either.
    let mut nan = values.clone();
    nan[diagonal - 1] = f64::NAN;
    assert!(!envelope.factor(&nan));
    // The factorisation recovers on the next good matrix (no state left behind).
    assert!(envelope.factor(&values));
}

/// Two rods of `edges` edges (position and frame blocks alternating, each edge coupling
/// its two vertices and its frame to the next), the last block of the second coupled to
/// the first block of the first: a closed loop, whose natural numbering's envelope spans
/// the whole matrix.
fn two_rods_in_a_loop(edges: usize) -> HessianPattern {
    let blocks_per_rod = 2 * edges + 1;
    let mut elements: Vec<Vec<usize>> = Vec::new();
    for rod in 0..2 {
        let base = rod * blocks_per_rod;
        for e in 0..edges {
            elements.push(vec![base + 2 * e, base + 2 * e + 1, base + 2 * e + 2]);
            if e + 1 < edges {
                elements.push(vec![base + 2 * e + 1, base + 2 * e + 3]);
            }
        }
    }
    elements.push(vec![0, 2 * blocks_per_rod - 1]);
    HessianPattern::new(2 * blocks_per_rod, elements.iter().map(|e| e.as_slice()))
}

#[test]
fn two_rods_joined_at_their_far_ends_use_faer_where_its_ordering_wins() {
    // Two rods of 40 edges, the last block of the second coupled to the first block of
    // the first (a closed loop): the envelope of the natural numbering spans the whole
    // matrix, a fill-reducing ordering does not.
    let pattern = two_rods_in_a_loop(40);
    let mut cholesky = SparseCholesky::try_new(&pattern).unwrap();
    assert!(!cholesky.is_envelope());
    let values = spd_values(&pattern, 3, 1e-3);
    assert!(cholesky.factor(&values));
    let b: Vec<f64> = (0..pattern.dim()).map(|i| (i as f64).sin()).collect();
    let mut x = b.clone();
    cholesky.solve_in_place(&mut x);
    let b_norm = b.iter().map(|v| v * v).sum::<f64>().sqrt();
    assert!(residual_norm(&pattern, &values, &x, &b) <= 1e-12 * b_norm);
}

#[test]
fn blocks_inside_the_envelope_that_the_pattern_lacks_fill_in_correctly() {
    // A chain of 30 blocks with extra couplings three blocks back: rows with gaps
    // (blocks 1 and 2 before the diagonal absent, block 3 present), which the
    // factorisation fills in. Factorised twice with different values, so a gap left
    // with the first matrix's fill would show in the second solve.
    let mut elements: Vec<Vec<usize>> = (0..29).map(|b| vec![b, b + 1]).collect();
    elements.extend((0..27).step_by(4).map(|b| vec![b, b + 3]));
    let pattern = HessianPattern::new(30, elements.iter().map(|e| e.as_slice()));
    assert!(pattern.is_banded());
    let mut envelope = EnvelopeCholesky::new(&pattern);
    let mut faer = FaerCholesky::try_new(&pattern).unwrap();
    for seed in [11, 12] {
        let values = spd_values(&pattern, seed, 1e-3);
        assert!(envelope.factor(&values) && faer.factor(&values));
        let b: Vec<f64> = (0..pattern.dim()).map(|i| (0.3 * i as f64).cos()).collect();
        let (mut x, mut y) = (b.clone(), b.clone());
        envelope.solve_in_place(&mut x);
        faer.solve_in_place(&mut y);
        let b_norm = b.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(residual_norm(&pattern, &values, &x, &b) <= 1e-12 * b_norm);
        let size = y.iter().map(|v| v.abs()).fold(0.0, f64::max);
        assert!(x.iter().zip(&y).all(|(a, b)| (a - b).abs() <= 1e-10 * size));
    }
}

#[test]
fn the_signed_factorisation_counts_negative_eigenvalues_and_solves_indefinite_systems() {
    for (edges, seed) in [(1, 0), (3, 1), (19, 2), (19, 3)] {
        let pattern = rod_pattern(edges);
        let n = pattern.dim();
        // Diagonally dominant, then every third diagonal negated: still dominant, so
        // nonsingular with as many negative eigenvalues as negated diagonals.
        let mut values = spd_values(&pattern, seed, 1e-1);
        let mut negated = 0;
        for col in (0..n).step_by(3) {
            values[pattern.col_ptr[col + 1] - 1] *= -1.0;
            negated += 1;
        }
        let mut dense = nalgebra::DMatrix::zeros(n, n);
        for col in 0..n {
            for k in pattern.col_ptr[col]..pattern.col_ptr[col + 1] {
                dense[(pattern.row_idx[k], col)] = values[k];
                dense[(col, pattern.row_idx[k])] = values[k];
            }
        }
        let eigenvalues = nalgebra::SymmetricEigen::new(dense).eigenvalues;
        let below = eigenvalues.iter().filter(|&&l| l < 0.0).count();
        assert_eq!(below, negated, "{edges} edges: the construction");
        let mut cholesky = SparseCholesky::try_new(&pattern).unwrap();
        assert!(!cholesky.factor(&values));
        assert_eq!(cholesky.negative_eigenvalues(&values, 1e-13), Some(below));
        let mut s = seed + 10;
        let b: Vec<f64> = (0..n).map(|_| next(&mut s)).collect();
        let mut x = b.clone();
        cholesky.solve_signed_in_place(&mut x);
        assert!(
            residual_norm(&pattern, &values, &x, &b) < 1e-12,
            "{edges} edges"
        );
    }
}

#[test]
fn a_factoriser_from_a_handed_on_analysis_solves_as_the_analysing_one_does() {
    // One rod (the envelope) and two rods in a loop (faer): a factoriser made from the
    // first one's analysis gives the same solution to the last bit, and the analysis
    // says which pattern it is of.
    for (pattern, envelope) in [(rod_pattern(30), true), (two_rods_in_a_loop(20), false)] {
        let mut first = SparseCholesky::try_new(&pattern).unwrap();
        assert_eq!(first.is_envelope(), envelope);
        let analysis = first.analysis();
        assert!(analysis.is_of(&pattern));
        assert!(!analysis.is_of(&rod_pattern(31)));
        let mut second = SparseCholesky::from_analysis(&analysis).unwrap();
        assert_eq!(second.is_envelope(), envelope);
        let values = spd_values(&pattern, 5, 1e-3);
        assert!(first.factor(&values) && second.factor(&values));
        let b: Vec<f64> = (0..pattern.dim()).map(|i| (0.3 * i as f64).cos()).collect();
        let (mut x1, mut x2) = (b.clone(), b.clone());
        first.solve_in_place(&mut x1);
        second.solve_in_place(&mut x2);
        assert_eq!(x1, x2);
        let b_norm = b.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(residual_norm(&pattern, &values, &x2, &b) <= 1e-12 * b_norm);
    }
}

/// The interleaved product of several vectors (the sensitivities' refinement checks,
/// several parameters at a time) is each vector's own product bit for bit.
#[test]
fn products_of_interleaved_vectors_are_each_vectors_product_bit_for_bit() {
    for pattern in [rod_pattern(7), two_rods_in_a_loop(5)] {
        let values = spd_values(&pattern, 11, 0.5);
        let n = pattern.dim();
        let mut seed = 5;
        let vectors: Vec<Vec<f64>> = (0..4)
            .map(|_| (0..n).map(|_| next(&mut seed)).collect())
            .collect();
        let x: Vec<[f64; 4]> = (0..n)
            .map(|i| [vectors[0][i], vectors[1][i], vectors[2][i], vectors[3][i]])
            .collect();
        let mut y = vec![[0.0; 4]; n];
        symmetric_products(&pattern, &values, &x, &mut y);
        for (k, v) in vectors.iter().enumerate() {
            let mut single = vec![0.0; n];
            symmetric_product(&pattern, &values, v, &mut single);
            let interleaved: Vec<f64> = y.iter().map(|yi| yi[k]).collect();
            assert_eq!(interleaved, single, "vector {k}");
        }
    }
}

/// A cube of `side³` blocks, each coupled to its neighbours along the three axes: a
/// pattern whose factor fills in enough for faer to choose its supernodal
/// factorisation.
fn block_cube(side: usize) -> HessianPattern {
    let at = |i: usize, j: usize, k: usize| (i * side + j) * side + k;
    let mut elements: Vec<Vec<usize>> = Vec::new();
    for i in 0..side {
        for j in 0..side {
            for k in 0..side {
                if i + 1 < side {
                    elements.push(vec![at(i, j, k), at(i + 1, j, k)]);
                }
                if j + 1 < side {
                    elements.push(vec![at(i, j, k), at(i, j + 1, k)]);
                }
                if k + 1 < side {
                    elements.push(vec![at(i, j, k), at(i, j, k + 1)]);
                }
            }
        }
    }
    HessianPattern::new(side * side * side, elements.iter().map(|e| e.as_slice()))
}

/// Several right-hand sides solved in one pass ([`SparseCholesky::solve_columns_in_place`],
/// the sensitivities' ten parameters) give each column's own solve bit for bit, on
/// every backend: the envelope (one rod), faer's simplicial factorisation (two rods
/// in a loop) and its supernodal one (a cube of blocks); column counts across faer's
/// groups of four.
#[test]
fn columns_solved_together_equal_each_columns_own_solve_bit_for_bit() {
    let cases = [
        (rod_pattern(25), Some(true), false),
        (two_rods_in_a_loop(30), Some(false), false),
        (block_cube(8), Some(false), true),
    ];
    for (pattern, envelope, supernodal) in cases {
        let mut cholesky = SparseCholesky::try_new(&pattern).unwrap();
        assert_eq!(Some(cholesky.is_envelope()), envelope);
        if let super::Backend::Faer(f) = &cholesky.backend {
            assert_eq!(f.is_supernodal(), supernodal, "faer's choice");
        }
        let values = spd_values(&pattern, 17, 0.3);
        assert!(cholesky.factor(&values));
        let n = pattern.dim();
        let mut seed = 23;
        for columns in [1, 3, 4, 10] {
            let rhs: Vec<f64> = (0..n * columns).map(|_| next(&mut seed)).collect();
            let mut together = rhs.clone();
            cholesky.solve_columns_in_place(&mut together, columns);
            for (k, b) in rhs.chunks_exact(n).enumerate() {
                let mut alone = b.to_vec();
                cholesky.solve_in_place(&mut alone);
                let same = together[k * n..(k + 1) * n] == alone[..];
                assert!(same, "column {k} of {columns} differs from its own solve");
                let b_norm = b.iter().map(|v| v * v).sum::<f64>().sqrt();
                assert!(residual_norm(&pattern, &values, &alone, b) <= 1e-12 * b_norm);
            }
        }
    }
}
