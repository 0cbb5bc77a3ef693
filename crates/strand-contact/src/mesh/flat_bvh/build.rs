//! Building a [`FlatBvh`] over clusters in Morton order, both halves of every large
//! run in parallel.

use super::{FlatBvh, LEAF, NodeBox};

/// Runs of at least this many clusters build their two halves on two threads.
const PARALLEL_CLUSTERS: usize = 4096;

impl FlatBvh {
    /// The tree over `codes.len()` clusters (fewer than 2³⁰) whose Morton codes,
    /// ascending, are `codes` (each cluster's first triangle), `cluster_box(c)` the box
    /// (m) of cluster `c`: a run is split where the highest bit of its codes changes, a
    /// run of equal codes in halves (see the [module docs](super)). Depth at most
    /// 64 + 30, work `O(n)` plus a binary search of the codes per node.
    pub(crate) fn build(codes: &[u64], cluster_box: &(impl Fn(usize) -> NodeBox + Sync)) -> Self {
        assert!(codes.len() < 1 << 30, "too many clusters for 31-bit links");
        let nodes = (2 * codes.len()).saturating_sub(1);
        let mut boxes = vec![[0.0; 6]; nodes];
        let mut links = vec![0u32; nodes];
        if nodes > 0 {
            let at = Subtree {
                first_cluster: 0,
                first_node: 0,
            };
            at.build(codes, &mut boxes, &mut links, cluster_box);
        }
        Self { boxes, links }
    }
}

/// Where a subtree goes: its first cluster and the index of its root node.
#[derive(Clone, Copy)]
struct Subtree {
    first_cluster: usize,
    first_node: usize,
}

impl Subtree {
    /// Fills `boxes` and `links` (the subtree's `2 codes.len() − 1` nodes) and returns
    /// its root box.
    fn build(
        self,
        codes: &[u64],
        boxes: &mut [NodeBox],
        links: &mut [u32],
        cluster_box: &(impl Fn(usize) -> NodeBox + Sync),
    ) -> NodeBox {
        if codes.len() == 1 {
            let leaf = cluster_box(self.first_cluster);
            boxes[0] = leaf;
            links[0] = LEAF | self.first_cluster as u32;
            return leaf;
        }
        let split = split_point(codes);
        let left_nodes = 2 * split - 1;
        let (root_box, rest_boxes) = boxes.split_at_mut(1);
        let (root_link, rest_links) = links.split_at_mut(1);
        let (left_boxes, right_boxes) = rest_boxes.split_at_mut(left_nodes);
        let (left_links, right_links) = rest_links.split_at_mut(left_nodes);
        let (left_codes, right_codes) = codes.split_at(split);
        let left = Subtree {
            first_cluster: self.first_cluster,
            first_node: self.first_node + 1,
        };
        let right = Subtree {
            first_cluster: self.first_cluster + split,
            first_node: self.first_node + 1 + left_nodes,
        };
        let (a, b) = if codes.len() >= PARALLEL_CLUSTERS {
            rayon::join(
                || left.build(left_codes, left_boxes, left_links, cluster_box),
                || right.build(right_codes, right_boxes, right_links, cluster_box),
            )
        } else {
            (
                left.build(left_codes, left_boxes, left_links, cluster_box),
                right.build(right_codes, right_boxes, right_links, cluster_box),
            )
        };
        let union = std::array::from_fn(|k| {
            if k < 3 {
                a[k].min(b[k])
            } else {
                a[k].max(b[k])
            }
        });
        root_box[0] = union;
        root_link[0] = right.first_node as u32;
        union
    }
}

/// Where to split a run of ascending Morton codes (two or more): before the first
/// code with the highest differing bit set, or in the middle of equal codes. In
/// `1..codes.len()`.
pub(super) fn split_point(codes: &[u64]) -> usize {
    let (first, last) = (codes[0], codes[codes.len() - 1]);
    if first == last {
        return codes.len() / 2;
    }
    let bit = 63 - (first ^ last).leading_zeros();
    codes.partition_point(|&code| (code ^ first) >> bit == 0)
}
