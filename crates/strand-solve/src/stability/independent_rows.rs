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
//! Rows interact only through the unknowns they share, so the rows are grouped by
//! shared unknowns (union–find) and each group of two or more is reduced by a modified
//! Gram–Schmidt over its own unknowns: `O(nnz)` to group, then work per group of its
//! size squared times its unknowns, whatever the model's size.

use std::collections::HashMap;

use crate::constraints::Row;

/// A row is dependent when what is left of its gradient after removing its projection
/// on the earlier independent rows of its group is below this fraction of its norm:
/// round-off of a repeated or recombined row, far below any real angle between two
/// contacts' normals (1e-8 rad).
pub const DEPENDENCE_TOLERANCE: f64 = 1e-8;

/// The rows of `active` that span what all of them span, in their order: every row
/// whose gradient lies within [`DEPENDENCE_TOLERANCE`] of the span of the earlier kept
/// rows of its group (and every zero row) is left out.
pub fn independent_rows<'r>(active: &[&'r Row]) -> Vec<&'r Row> {
    if active.len() < 2 {
        return active
            .iter()
            .copied()
            .filter(|row| gradient_norm(row) > 0.0)
            .collect();
    }
    let groups = groups_by_shared_unknowns(active);
    let mut keep = vec![false; active.len()];
    for group in groups.values() {
        reduce_group(active, group, &mut keep);
    }
    active
        .iter()
        .zip(&keep)
        .filter(|&(_, &kept)| kept)
        .map(|(&row, _)| row)
        .collect()
}

fn gradient_norm(row: &Row) -> f64 {
    row.gradient.iter().map(|&(_, a)| a * a).sum::<f64>().sqrt()
}

/// The rows of `active` (indices, in order) grouped by the unknowns they share: two
/// rows are in one group when a chain of rows sharing unknowns joins them.
fn groups_by_shared_unknowns(active: &[&Row]) -> HashMap<usize, Vec<usize>> {
    let mut parent: Vec<usize> = (0..active.len()).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut first_row_of_unknown: HashMap<usize, usize> = HashMap::new();
    for (i, row) in active.iter().enumerate() {
        for &(unknown, _) in &row.gradient {
            let other = *first_row_of_unknown.entry(unknown).or_insert(i);
            let (a, b) = (root(&mut parent, i), root(&mut parent, other));
            if a != b {
                parent[a.max(b)] = a.min(b);
            }
        }
    }
    let mut groups: HashMap<usize, Vec<usize>> = HashMap::new();
    for i in 0..active.len() {
        let r = root(&mut parent, i);
        groups.entry(r).or_default().push(i);
    }
    groups
}

/// Marks in `keep` the rows of `group` (indices into `active`, in order) that are
/// independent of the earlier kept rows of the group: modified Gram–Schmidt over the
/// group's unknowns.
fn reduce_group(active: &[&Row], group: &[usize], keep: &mut [bool]) {
    let mut column_of: HashMap<usize, usize> = HashMap::new();
    for &i in group {
        for &(unknown, _) in &active[i].gradient {
            let next = column_of.len();
            column_of.entry(unknown).or_insert(next);
        }
    }
    let width = column_of.len();
    // Orthonormal basis of the kept rows' span, dense over the group's unknowns.
    let mut basis: Vec<Vec<f64>> = Vec::new();
    for &i in group {
        let mut v = vec![0.0; width];
        for &(unknown, a) in &active[i].gradient {
            v[column_of[&unknown]] += a;
        }
        let norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
        if norm == 0.0 {
            continue;
        }
        // Twice (re-orthogonalisation) so the residual of a dependent row is round-off.
        for _ in 0..2 {
            for q in &basis {
                let along: f64 = q.iter().zip(&v).map(|(a, b)| a * b).sum();
                v.iter_mut().zip(q).for_each(|(x, a)| *x -= along * a);
            }
        }
        let residual = v.iter().map(|a| a * a).sum::<f64>().sqrt();
        if residual > DEPENDENCE_TOLERANCE * norm {
            v.iter_mut().for_each(|x| *x /= residual);
            basis.push(v);
            keep[i] = true;
        }
    }
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
        // Each row alone in its group: all kept, even parallel-looking ones.
        let rows: Vec<Row> = (0..50).map(|i| row(i, &[(2 * i as usize, 1.0)])).collect();
        let active: Vec<&Row> = rows.iter().collect();
        assert_eq!(independent_rows(&active).len(), 50);
        assert_eq!(groups_by_shared_unknowns(&active).len(), 50);
        // A chain of rows sharing neighbours is one group.
        let chain: Vec<Row> = (0..10)
            .map(|i| row(i, &[(i as usize, 1.0), (i as usize + 1, 1.0)]))
            .collect();
        let chained: Vec<&Row> = chain.iter().collect();
        assert_eq!(groups_by_shared_unknowns(&chained).len(), 1);
        assert_eq!(independent_rows(&chained).len(), 10);
    }
}
