//! The two searches of a [`FlatBvh`]: depth first in cluster order, and nearer child
//! first for a best answer.

use super::{FlatBvh, LEAF, NodeBox};

/// Nodes a search keeps pending at most: a tree built by [`FlatBvh::build`] is at most
/// 94 deep; [`FlatBvh::is_well_formed`] rejects any deeper one.
pub(super) const STACK_CAPACITY: usize = 128;

impl FlatBvh {
    /// Visits the tree depth first, left child first: `enter(node, box)` for each node
    /// reached (its index in preorder; `false`: skip it and its subtree), then
    /// `leaf(cluster)` for each leaf entered. The leaves come in increasing cluster
    /// order.
    pub(crate) fn depth_first(
        &self,
        mut enter: impl FnMut(usize, &NodeBox) -> bool,
        mut leaf: impl FnMut(u32),
    ) {
        if self.boxes.is_empty() {
            return;
        }
        let mut stack = [0u32; STACK_CAPACITY];
        let mut pending = 1;
        while pending > 0 {
            pending -= 1;
            let node = stack[pending] as usize;
            if !enter(node, &self.boxes[node]) {
                continue;
            }
            let link = self.links[node];
            if link & LEAF != 0 {
                leaf(link & !LEAF);
            } else {
                stack[pending] = link;
                stack[pending + 1] = node as u32 + 1;
                pending += 2;
            }
        }
    }

    /// Visits the tree depth first, the child of smaller `bound` first, for a search
    /// whose answer (held in `state`) only improves: `bound(state, node, box)` is a
    /// lower bound of the cost of anything in a node (its index in preorder and box); `worth(state, bound, first_cluster)`
    /// says whether a node of that bound, whose first cluster is `first_cluster`, may
    /// still hold a better answer (asked again when the node's turn comes);
    /// `leaf(state, cluster)` looks at each leaf worth it.
    pub(crate) fn nearer_first<S>(
        &self,
        state: &mut S,
        bound: impl Fn(&S, usize, &NodeBox) -> f64,
        worth: impl Fn(&S, f64, u32) -> bool,
        mut leaf: impl FnMut(&mut S, u32),
    ) {
        if self.boxes.is_empty() {
            return;
        }
        // (node, its first cluster, its bound).
        let mut stack = [(0u32, 0u32, 0.0f64); STACK_CAPACITY];
        stack[0].2 = bound(state, 0, &self.boxes[0]);
        let mut pending = 1;
        while pending > 0 {
            pending -= 1;
            let (node, first, node_bound) = stack[pending];
            if !worth(state, node_bound, first) {
                continue;
            }
            let link = self.links[node as usize];
            if link & LEAF != 0 {
                leaf(state, link & !LEAF);
                continue;
            }
            let left = (
                node + 1,
                first,
                bound(state, node as usize + 1, &self.boxes[node as usize + 1]),
            );
            // The left subtree has `link − node − 1 = 2 m − 1` nodes over `m` clusters.
            let right_first = first + (link - node) / 2;
            let right = (
                link,
                right_first,
                bound(state, link as usize, &self.boxes[link as usize]),
            );
            // The nearer child on top (the left one on a tie: cluster order).
            let (top, below) = if right.2 < left.2 {
                (right, left)
            } else {
                (left, right)
            };
            stack[pending] = below;
            stack[pending + 1] = top;
            pending += 2;
        }
    }
}
