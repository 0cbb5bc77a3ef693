//! A bounding-volume hierarchy in two plain arrays: a binary tree over the clusters of
//! a [`super::TriangleTree`], which are consecutive along the Morton curve.
//!
//! The nodes are stored in depth-first preorder: node `i`'s left child is node `i + 1`
//! and its right child the node named by `links[i]`; the subtree of a node over `m`
//! clusters occupies the `2m − 1` nodes from it. A leaf holds one cluster and its link
//! is [`LEAF`] plus the cluster number. The leaves in depth-first order are the
//! clusters `0, 1, 2, …` in turn, so every depth-first search (left child first)
//! meets the triangles in the order of the cluster list, whatever the tree's shape.
//!
//! The tree splits a run of clusters where the highest bit of their Morton codes
//! changes (the first triangles' codes; halves of a run of equal codes), the same
//! octree-like splits as a linear BVH (Karras 2012). It is built in parallel
//! ([`FlatBvh::build`], `O(n)` plus a binary search per node) and the arrays are
//! stored verbatim in the mesh cache, so a cache hit uses them after one read.

mod build;
mod search;
#[cfg(test)]
mod tests;

/// A node's box: minimum x, y, z then maximum x, y, z, m.
pub(crate) type NodeBox = [f64; 6];

/// The link of a leaf: this bit plus its cluster number.
pub(crate) const LEAF: u32 = 1 << 31;

/// A binary BVH over clusters, in preorder (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct FlatBvh {
    /// Every node's box (`2 clusters − 1` of them), m.
    pub(crate) boxes: Vec<NodeBox>,
    /// Every node's link: the index of its right child, or [`LEAF`] plus its cluster.
    pub(crate) links: Vec<u32>,
}

impl FlatBvh {
    /// Bytes held by the two arrays.
    pub(crate) fn heap_bytes(&self) -> usize {
        self.boxes.capacity() * std::mem::size_of::<NodeBox>()
            + self.links.capacity() * std::mem::size_of::<u32>()
    }

    /// Whether the arrays form a tree as described in the [module docs](self) over
    /// `clusters` clusters (what a cache file read back must satisfy before a search
    /// follows its links): every node met once in preorder, the leaves naming the
    /// clusters in turn, and no deeper than the searches' stack holds. `O(nodes)`.
    pub(crate) fn is_well_formed(&self, clusters: usize) -> bool {
        let nodes = self.boxes.len();
        if self.links.len() != nodes || nodes != (2 * clusters).saturating_sub(1) {
            return false;
        }
        if nodes == 0 {
            return true;
        }
        let (mut next_node, mut next_cluster) = (0usize, 0usize);
        // (node, its depth): a search holds at most the siblings of a node's ancestors
        // and its two children, `depth + 2` nodes.
        let mut stack = vec![(0usize, 0usize)];
        while let Some((node, depth)) = stack.pop() {
            if node != next_node {
                return false;
            }
            next_node += 1;
            let link = self.links[node];
            if link & LEAF != 0 {
                if (link & !LEAF) as usize != next_cluster {
                    return false;
                }
                next_cluster += 1;
            } else {
                let right = link as usize;
                if right <= node + 1 || right >= nodes || depth + 2 > search::STACK_CAPACITY {
                    return false;
                }
                stack.push((right, depth + 1));
                stack.push((node + 1, depth + 1));
            }
        }
        next_node == nodes && next_cluster == clusters
    }
}
