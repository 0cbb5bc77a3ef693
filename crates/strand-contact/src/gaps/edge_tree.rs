//! A bounding-box tree over the edges of all rods in their (rod, edge) order, for the
//! rod–rod broad phase.
//!
//! Rods are chains, so a run of consecutive edges is spatially compact: the tree is an
//! implicit complete binary tree over the edge list (node `k` has children `2k` and
//! `2k + 1`, leaves from `size`), built bottom-up in `O(edges)` without sorting. A
//! query skips every node whose edges all come before a given index, which is how the
//! near neighbours along a rod (excluded from contact) are never enumerated: at fine
//! discretisations they are hundreds per edge, and listing them made every contact
//! evaluation quadratic in the segments.

use super::broad_phase::Aabb;
use nalgebra::Point3;

#[cfg(test)]
thread_local! {
    /// Tree nodes visited by queries on this thread (a work counter for the test that
    /// the broad phase costs `O(edges · log edges + pairs)`).
    pub(crate) static NODES_VISITED: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// The boxes of a list of edges in a complete binary tree.
pub(crate) struct EdgeTree {
    /// Number of leaves (a power of two ≥ the number of edges).
    size: usize,
    /// Number of edges.
    edges: usize,
    /// `boxes[k]` bounds the boxes of node `k`'s leaves (`boxes[0]` is unused; padding
    /// leaves are empty boxes that overlap nothing).
    boxes: Vec<Aabb>,
}

impl EdgeTree {
    /// The tree of `boxes` (one per edge, in order).
    pub(crate) fn new(leaves: &[Aabb]) -> Self {
        let size = leaves.len().next_power_of_two().max(1);
        let empty = Aabb {
            min: Point3::from([f64::INFINITY; 3]),
            max: Point3::from([f64::NEG_INFINITY; 3]),
        };
        let mut boxes = vec![empty; 2 * size];
        boxes[size..size + leaves.len()].copy_from_slice(leaves);
        for k in (1..size).rev() {
            let (a, b) = (boxes[2 * k], boxes[2 * k + 1]);
            boxes[k] = Aabb {
                min: a.min.inf(&b.min),
                max: a.max.sup(&b.max),
            };
        }
        Self {
            size,
            edges: leaves.len(),
            boxes,
        }
    }

    /// The box of all the edges' boxes (empty for no edges).
    pub(crate) fn bounds(&self) -> Aabb {
        self.boxes[1]
    }

    /// Calls `found(j)` for every edge `j ≥ from` whose box overlaps `query` (touching
    /// counts), in increasing `j`.
    pub(crate) fn overlapping_from(&self, query: &Aabb, from: usize, mut found: impl FnMut(usize)) {
        let no_runs = |_: usize, _: usize, _: usize| None::<()>;
        self.runs_from(query, from, no_runs, |report| {
            if let Found::Edge(j) = report {
                found(j);
            }
        });
    }

    /// As [`EdgeTree::overlapping_from`], but a node of more than one edge that
    /// overlaps `query` is first offered whole to `certify(node, first, end)` (its
    /// edges `first..end` from `from` on); if that returns a value, the node is reported
    /// as one [`Found::Run`] with it and not descended. Reports come in increasing edge
    /// order.
    pub(crate) fn runs_from<T>(
        &self,
        query: &Aabb,
        from: usize,
        mut certify: impl FnMut(usize, usize, usize) -> Option<T>,
        mut found: impl FnMut(Found<T>),
    ) {
        if from >= self.edges {
            return;
        }
        let mut stack = vec![(1usize, 0usize, self.size)];
        while let Some((node, first, count)) = stack.pop() {
            #[cfg(test)]
            NODES_VISITED.with(|c| c.set(c.get() + 1));
            if first + count <= from || first >= self.edges || !self.boxes[node].overlaps(query) {
                continue;
            }
            if count == 1 {
                found(Found::Edge(first));
                continue;
            }
            let (start, end) = (first.max(from), (first + count).min(self.edges));
            if end - start > 1
                && let Some(value) = certify(node, start, end)
            {
                found(Found::Run { start, end, value });
                continue;
            }
            let half = count / 2;
            stack.push((2 * node + 1, first + half, half));
            stack.push((2 * node, first, half));
        }
    }
}

/// What [`EdgeTree::runs_from`] reports.
pub(crate) enum Found<T> {
    /// One edge whose box overlaps the query.
    Edge(usize),
    /// The edges `start..end` of a node the caller certified, with its value.
    Run {
        /// First edge.
        start: usize,
        /// One past the last edge.
        end: usize,
        /// What the certificate returned.
        value: T,
    },
}
