//! The independent blocks of a Hessian pattern: the connected components of its graph
//! of 3×3 blocks (two blocks are connected when the pattern couples them). Unknowns of
//! different components never couple, neither in the matrix nor in its Cholesky factor
//! (no fill crosses components), so `A⁻¹ b` on one component depends only on the part
//! of `b` in that component — e.g. the harness bays of a batch of identical copies.

use strand_system::HessianPattern;

/// The connected components of a pattern's block graph, each with its unknowns.
#[derive(Clone, Debug)]
pub(crate) struct Components {
    /// Per unknown: its component (0-based, numbered by first unknown).
    of_unknown: Vec<usize>,
    /// The unknowns of every component, component after component, ascending within each.
    unknowns: Vec<usize>,
    /// Per component: where its unknowns start in `unknowns` (length `count + 1`).
    start: Vec<usize>,
}

impl Components {
    /// Union–find over the pattern's blocks: O(stored blocks), once per model.
    pub(crate) fn of_pattern(pattern: &HessianPattern) -> Self {
        let (block_ptr, block_rows) = pattern.block_structure();
        let blocks = block_ptr.len() - 1;
        let mut parent: Vec<usize> = (0..blocks).collect();
        for col in 0..blocks {
            for &row in &block_rows[block_ptr[col]..block_ptr[col + 1]] {
                let (a, b) = (
                    union_find_root(&mut parent, row),
                    union_find_root(&mut parent, col),
                );
                if a != b {
                    // The smaller index stays the root: components numbered in order.
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
        let mut number = vec![usize::MAX; blocks];
        let mut count = 0;
        let mut of_block = Vec::with_capacity(blocks);
        for b in 0..blocks {
            let r = union_find_root(&mut parent, b);
            if number[r] == usize::MAX {
                number[r] = count;
                count += 1;
            }
            of_block.push(number[r]);
        }
        let of_unknown: Vec<usize> = (0..pattern.dim()).map(|k| of_block[k / 3]).collect();
        let mut start = vec![0usize; count + 1];
        for &c in &of_unknown {
            start[c + 1] += 1;
        }
        for c in 0..count {
            start[c + 1] += start[c];
        }
        let mut next = start.clone();
        let mut unknowns = vec![0usize; of_unknown.len()];
        for (k, &c) in of_unknown.iter().enumerate() {
            unknowns[next[c]] = k;
            next[c] += 1;
        }
        Self {
            of_unknown,
            unknowns,
            start,
        }
    }

    /// Number of components.
    pub(crate) fn count(&self) -> usize {
        self.start.len() - 1
    }

    /// The component of unknown `k`.
    pub(crate) fn of(&self, k: usize) -> usize {
        self.of_unknown[k]
    }

    /// The unknowns of component `c`, ascending.
    pub(crate) fn unknowns(&self, c: usize) -> &[usize] {
        &self.unknowns[self.start[c]..self.start[c + 1]]
    }
}

/// The root of `x` in the union–find forest `parent` (`parent[r] == r` at a root),
/// halving the path on the way.
pub(crate) fn union_find_root(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_coupled_directly_or_through_others_share_a_component() {
        // Blocks 0–1–3 chained, 2 alone, 4–5 coupled.
        let elements: Vec<Vec<usize>> = vec![vec![0, 1], vec![1, 3], vec![4, 5]];
        let pattern = HessianPattern::new(6, elements.iter().map(|e| e.as_slice()));
        let components = Components::of_pattern(&pattern);
        assert_eq!(components.count(), 3);
        let expected_block = [0, 0, 1, 0, 2, 2];
        for k in 0..18 {
            assert_eq!(components.of(k), expected_block[k / 3], "unknown {k}");
        }
        let first: Vec<usize> = (0..6).chain(9..12).collect();
        assert_eq!(components.unknowns(0), first.as_slice());
        assert_eq!(components.unknowns(1), &[6, 7, 8]);
        assert_eq!(components.unknowns(2), &[12, 13, 14, 15, 16, 17]);
    }
}
