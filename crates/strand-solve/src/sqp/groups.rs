//! The rows of a constrained step split into independent groups: two rows are in one
//! group when their gradients reach the same independent block of the Hessian
//! ([`Components`]), directly or through other rows (a rod–rod contact joins the blocks
//! of its two rods). The QP separates into one small QP per group: the step of a group
//! moves only its blocks' unknowns, and its Schur complement couples only its rows.

use crate::constraints::Row;
use crate::linear::{Components, union_find_root as root};

/// The independent groups of a list of rows.
pub(crate) struct RowGroups {
    /// Per group: its rows, ascending.
    pub rows: Vec<Vec<usize>>,
    /// Per group: the unknowns its steps can move (those of the Hessian blocks its rows
    /// touch), block after block, ascending within each block.
    pub unknowns: Vec<Vec<usize>>,
    /// Per row: its group.
    pub of_row: Vec<usize>,
}

impl RowGroups {
    /// Groups `rows` by the Hessian blocks of `components`: O(blocks touched + Σ row
    /// entries + unknowns of the touched blocks), plus one flag per block. A row without
    /// gradient entries is a group of its own that moves nothing.
    pub(crate) fn new(components: &Components, rows: &[Row]) -> Self {
        // Union–find over the blocks the rows touch (parent[c] == c for untouched).
        let mut parent: Vec<usize> = (0..components.count()).collect();
        for row in rows {
            let mut entries = row.gradient.iter().map(|&(k, _)| components.of(k));
            if let Some(first) = entries.next() {
                for c in entries {
                    let (a, b) = (root(&mut parent, first), root(&mut parent, c));
                    if a != b {
                        parent[a.max(b)] = a.min(b);
                    }
                }
            }
        }
        let mut group_of_root = vec![usize::MAX; components.count()];
        let mut block_listed = vec![false; components.count()];
        let mut groups = RowGroups {
            rows: Vec::new(),
            unknowns: Vec::new(),
            of_row: Vec::with_capacity(rows.len()),
        };
        for (i, row) in rows.iter().enumerate() {
            let group = match row.gradient.first() {
                None => groups.push_group(),
                Some(&(k, _)) => {
                    let r = root(&mut parent, components.of(k));
                    if group_of_root[r] == usize::MAX {
                        group_of_root[r] = groups.push_group();
                    }
                    group_of_root[r]
                }
            };
            groups.rows[group].push(i);
            groups.of_row.push(group);
            for &(k, _) in &row.gradient {
                let c = components.of(k);
                if !block_listed[c] {
                    block_listed[c] = true;
                    groups.unknowns[group].extend_from_slice(components.unknowns(c));
                }
            }
        }
        groups
    }

    /// Number of groups.
    pub(crate) fn count(&self) -> usize {
        self.rows.len()
    }

    /// Appends an empty group; returns its index.
    fn push_group(&mut self) -> usize {
        self.rows.push(Vec::new());
        self.unknowns.push(Vec::new());
        self.rows.len() - 1
    }
}
