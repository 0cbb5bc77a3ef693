//! The active rows reduced to an independent set before the inertia is counted.
//!
//! The reduced Hessian `Zᵀ H Z` depends only on the space the active rows span, not on
//! the rows themselves, so a row in the span of others (the same contact twice, two
//! features of a mesh reporting one touching point) constrains nothing more. In the
//! bordered matrix `[H' Aᵀ; A −δI]` such a row is not harmless, though: the border's
//! Schur complement `−δI − A H'⁻¹ Aᵀ` is then singular up to `δ`, and its pivot of the
//! size of `δ`, left by cancellation, has the sign round-off gives it: faer's `LDLᵀ`
//! can miss a negative direction there or stop on a zero pivot. Dropping the dependent
//! rows first makes the count independent of luck.
//!
//! Rows interact only through the unknowns they share, so each row is compared with the
//! earlier kept rows that share an unknown with it (its neighbours): it is dependent
//! when its gradient lies in their span (least squares by a modified Gram–Schmidt over
//! their few unknowns). The work is that of each row's neighbourhood, so it grows with
//! the number of rows, not with its square — a hose lying in a groove holds a chain of
//! a thousand rows that share vertices pairwise. (A dependence only through a long
//! chain of rows, none of them a neighbour, is not a contact's.)

use std::collections::HashMap;

use crate::constraints::Row;

/// A row is dependent when what is left of its gradient after removing its projection
/// on the span of its neighbours is below this fraction of its norm: round-off of a
/// repeated or recombined row, far below any real angle between two contacts' normals
/// (1e-8 rad).
pub const DEPENDENCE_TOLERANCE: f64 = 1e-8;

/// The rows of `active` that span what all of them span, in their order: every row
/// whose gradient lies within [`DEPENDENCE_TOLERANCE`] of the span of the earlier kept
/// rows sharing an unknown with it (and every zero row) is left out.
pub fn independent_rows<'r>(active: &[&'r Row]) -> Vec<&'r Row> {
    kept_rows(active).0
}

/// [`independent_rows`] and the work it took (entries visited in the projections).
fn kept_rows<'r>(active: &[&'r Row]) -> (Vec<&'r Row>, usize) {
    let mut kept: Vec<&'r Row> = Vec::with_capacity(active.len());
    // Per unknown, the kept rows (indices into `kept`) touching it.
    let mut rows_of_unknown: HashMap<usize, Vec<usize>> = HashMap::new();
    let mut work = 0;
    for &row in active {
        let mut neighbours: Vec<usize> = row
            .gradient
            .iter()
            .filter_map(|(unknown, _)| rows_of_unknown.get(unknown))
            .flatten()
            .copied()
            .collect();
        neighbours.sort_unstable();
        neighbours.dedup();
        let local: Vec<&Row> = neighbours.iter().map(|&k| kept[k]).collect();
        let (independent, visited) = independent_of(row, &local);
        work += visited;
        if independent {
            for &(unknown, _) in &row.gradient {
                let touching = rows_of_unknown.entry(unknown).or_default();
                if touching.last() != Some(&kept.len()) {
                    touching.push(kept.len());
                }
            }
            kept.push(row);
        }
    }
    (kept, work)
}

/// Whether `row`'s gradient has a part beyond [`DEPENDENCE_TOLERANCE`] of its norm
/// outside the span of the `neighbours`' gradients (modified Gram–Schmidt over their
/// unknowns), and the entries visited.
fn independent_of(row: &Row, neighbours: &[&Row]) -> (bool, usize) {
    let mut column_of: HashMap<usize, usize> = HashMap::new();
    for r in neighbours.iter().copied().chain(std::iter::once(row)) {
        for &(unknown, _) in &r.gradient {
            let next = column_of.len();
            column_of.entry(unknown).or_insert(next);
        }
    }
    let width = column_of.len();
    let dense = |r: &Row| {
        let mut v = vec![0.0; width];
        for &(unknown, a) in &r.gradient {
            v[column_of[&unknown]] += a;
        }
        v
    };
    let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
    // An orthonormal basis of the neighbours' span.
    let mut basis: Vec<Vec<f64>> = Vec::with_capacity(neighbours.len());
    let mut visited = 0;
    let mut project_out = |v: &mut Vec<f64>, basis: &[Vec<f64>]| {
        // Twice (re-orthogonalisation) so the residual of a dependent row is round-off.
        for _ in 0..2 {
            for q in basis {
                let along: f64 = q.iter().zip(v.iter()).map(|(a, b)| a * b).sum();
                v.iter_mut().zip(q).for_each(|(x, a)| *x -= along * a);
                visited += 2 * width;
            }
        }
    };
    for &neighbour in neighbours {
        let mut q = dense(neighbour);
        let size = norm(&q);
        project_out(&mut q, &basis);
        let left = norm(&q);
        if left > DEPENDENCE_TOLERANCE * size {
            q.iter_mut().for_each(|x| *x /= left);
            basis.push(q);
        }
    }
    let mut v = dense(row);
    let size = norm(&v);
    project_out(&mut v, &basis);
    (
        size > 0.0 && norm(&v) > DEPENDENCE_TOLERANCE * size,
        visited,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraints::RowKey;

    fn row(key: u64, gradient: &[(usize, f64)]) -> Row {
        Row {
            key: RowKey::Contact(key),
            value: 0.0,
            gradient: gradient.to_vec(),
            curvature: None,
        }
    }

    fn keys(rows: &[&Row]) -> Vec<RowKey> {
        rows.iter().map(|r| r.key).collect()
    }

    #[test]
    fn a_repeated_or_recombined_row_is_left_out() {
        let a = row(0, &[(0, 1.0), (1, 2.0)]);
        let b = row(1, &[(1, 1.0), (2, -1.0)]);
        // a − 3b, entries in another order and one unknown listed twice.
        let c = row(2, &[(2, 3.0), (0, 1.0), (1, -0.5), (1, -0.5)]);
        let twice = row(3, &[(0, 2.0), (1, 4.0)]);
        let separate = row(4, &[(7, 1.0)]);
        let zero = row(5, &[(9, 0.0)]);
        let active = [&a, &b, &c, &twice, &separate, &zero];
        assert_eq!(
            keys(&independent_rows(&active)),
            vec![RowKey::Contact(0), RowKey::Contact(1), RowKey::Contact(4)]
        );
    }

    #[test]
    fn nearly_parallel_rows_beyond_the_tolerance_are_kept() {
        let a = row(0, &[(0, 1.0), (1, 0.0)]);
        let tilted = row(1, &[(0, 1.0), (1, 1e-6)]);
        let rounded = row(2, &[(0, 1.0), (1, 1e-12)]);
        assert_eq!(independent_rows(&[&a, &tilted]).len(), 2);
        assert_eq!(independent_rows(&[&a, &rounded]).len(), 1);
    }

    #[test]
    fn rows_sharing_no_unknown_are_never_compared() {
        // Each row alone: all kept, with no projection at all.
        let rows: Vec<Row> = (0..50).map(|i| row(i, &[(2 * i as usize, 1.0)])).collect();
        let active: Vec<&Row> = rows.iter().collect();
        assert_eq!(kept_rows(&active), (active.clone(), 0));
    }

    /// A chain of `m` rows, each sharing an unknown with the next (a hose's contacts
    /// along a groove), every tenth one repeated.
    fn chain(m: usize) -> Vec<Row> {
        let mut rows = Vec::new();
        for i in 0..m {
            let r = row(
                i as u64,
                &[(3 * i, 1.0), (3 * i + 1, 0.5), (3 * i + 3, -1.0)],
            );
            if i % 10 == 0 {
                let mut twice = r.clone();
                twice.key = RowKey::Contact(1_000_000 + i as u64);
                rows.push(r);
                rows.push(twice);
            } else {
                rows.push(r);
            }
        }
        rows
    }

    #[test]
    fn a_chain_of_rows_costs_in_proportion_to_its_length() {
        let (short, long) = (chain(200), chain(2000));
        let short_active: Vec<&Row> = short.iter().collect();
        let long_active: Vec<&Row> = long.iter().collect();
        let (kept_short, work_short) = kept_rows(&short_active);
        let (kept_long, work_long) = kept_rows(&long_active);
        // The repeated rows are left out, every other row kept.
        assert_eq!((kept_short.len(), kept_long.len()), (200, 2000));
        assert!(kept_long.iter().all(|r| r.key < RowKey::Contact(1_000_000)));
        // Linear: 10× the rows, 10× the work (a group-wide Gram–Schmidt would be 100×).
        assert!(work_short > 0);
        assert!(
            work_long <= 11 * work_short,
            "work {work_short} -> {work_long}"
        );
    }
}
