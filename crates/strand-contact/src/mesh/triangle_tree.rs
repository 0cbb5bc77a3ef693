//! The kept triangles of a mesh and their BVH: a [`FlatBvh`] over clusters of up to
//! [`CLUSTER_SIZE`] triangles that are neighbours along a Morton (Z-order) curve of
//! their centroids.
//!
//! A leaf per cluster of four close triangles (instead of one per triangle) cuts the
//! nodes by four; a query tests the (at most four) triangles of a leaf it reaches,
//! each first against its own bounding box. The tree is split along the same Morton
//! codes, in parallel, and lives in two plain arrays that the mesh cache stores as
//! they are. The triangles keep their order (triangle `t` is the `t`-th kept triangle
//! of the file): `order` lists them cluster by cluster, and every depth-first search
//! meets them in that order.

use nalgebra::Point3;
use rayon::prelude::*;

use super::flat_bvh::{FlatBvh, NodeBox};
use super::radix_sort::sorted_by_key;

/// Triangles per BVH leaf (the last leaf may hold fewer).
pub(crate) const CLUSTER_SIZE: usize = 4;

/// The triangles of a mesh in its own frame (m) and their BVH.
#[derive(Clone)]
pub(crate) struct TriangleTree {
    /// Vertex positions, m.
    pub(crate) vertices: Vec<[f64; 3]>,
    /// The kept triangles, 0-based into `vertices`.
    pub(crate) indices: Vec<[u32; 3]>,
    /// Every triangle once, cluster by cluster: leaf `k` of the BVH holds
    /// `order[CLUSTER_SIZE k .. CLUSTER_SIZE (k + 1)]`.
    pub(crate) order: Vec<u32>,
    /// The BVH with one leaf per cluster.
    pub(crate) bvh: FlatBvh,
}

impl TriangleTree {
    /// Clusters `indices` (non-empty, in range, non-degenerate) along the Morton curve
    /// of their centroids inside `bounding_box` (m) and builds the BVH of the clusters.
    #[cfg(test)]
    pub(crate) fn build(
        vertices: Vec<[f64; 3]>,
        indices: Vec<[u32; 3]>,
        bounding_box: [Point3<f64>; 2],
    ) -> Self {
        let (order, bvh) = Self::order_and_bvh(&vertices, &indices, bounding_box);
        Self {
            vertices,
            indices,
            order,
            bvh,
        }
    }

    /// The cluster order and the BVH of [`TriangleTree::build`], from borrowed
    /// vertices and triangles (which the tree then owns).
    pub(crate) fn order_and_bvh(
        vertices: &[[f64; 3]],
        indices: &[[u32; 3]],
        bounding_box: [Point3<f64>; 2],
    ) -> (Vec<u32>, FlatBvh) {
        let [min, max] = bounding_box;
        let scale = [0, 1, 2].map(|k| {
            let extent = max[k] - min[k];
            if extent > 0.0 {
                MORTON_CELLS / extent
            } else {
                0.0
            }
        });
        let keyed: Vec<(u64, u32)> = indices
            .par_iter()
            .enumerate()
            .map(|(t, corners)| {
                let [a, b, c] = [0, 1, 2].map(|k| &vertices[corners[k] as usize]);
                let mut cell = [0u64; 3];
                for k in 0..3 {
                    let centroid = (a[k] + b[k] + c[k]) / 3.0;
                    cell[k] =
                        ((centroid - min[k]) * scale[k]).clamp(0.0, MORTON_CELLS - 1.0) as u64;
                }
                (morton(cell), t as u32)
            })
            .collect();
        // Keys given in triangle order: the order of sorting the (key, triangle) pairs.
        let sorted = sorted_by_key(keyed);
        let codes: Vec<u64> = sorted.iter().step_by(CLUSTER_SIZE).map(|p| p.0).collect();
        let order: Vec<u32> = sorted.into_iter().map(|(_, t)| t).collect();
        let cluster_box = |cluster: usize| -> NodeBox {
            let start = cluster * CLUSTER_SIZE;
            let mut bounds = [f64::INFINITY, f64::INFINITY, f64::INFINITY, 0.0, 0.0, 0.0];
            bounds[3..].fill(f64::NEG_INFINITY);
            for &t in &order[start..(start + CLUSTER_SIZE).min(order.len())] {
                for i in indices[t as usize] {
                    let p = vertices[i as usize];
                    for k in 0..3 {
                        bounds[k] = bounds[k].min(p[k]);
                        bounds[k + 3] = bounds[k + 3].max(p[k]);
                    }
                }
            }
            bounds
        };
        let bvh = FlatBvh::build(&codes, &cluster_box);
        (order, bvh)
    }

    /// The triangles of BVH leaf `leaf`.
    #[inline]
    pub(crate) fn cluster(&self, leaf: u32) -> &[u32] {
        let start = leaf as usize * CLUSTER_SIZE;
        &self.order[start..(start + CLUSTER_SIZE).min(self.order.len())]
    }

    /// The corners of triangle `t`, m.
    #[inline]
    pub(crate) fn triangle(&self, t: usize) -> [Point3<f64>; 3] {
        self.indices[t].map(|i| Point3::from(self.vertices[i as usize]))
    }

    /// Bytes held: vertices, triangles, cluster order and the BVH.
    pub(crate) fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.vertices.capacity() * std::mem::size_of::<[f64; 3]>()
            + self.indices.capacity() * std::mem::size_of::<[u32; 3]>()
            + self.order.capacity() * std::mem::size_of::<u32>()
            + self.bvh.heap_bytes()
    }
}

/// Cells of the Morton grid along each axis (21 bits, three of them fill a `u64`).
const MORTON_CELLS: f64 = (1u64 << 21) as f64;

/// The Morton code of a cell: the bits of x, y and z interleaved.
fn morton(cell: [u64; 3]) -> u64 {
    let spread = |mut v: u64| {
        v &= 0x1f_ffff;
        v = (v | v << 32) & 0x001f_0000_0000_ffff;
        v = (v | v << 16) & 0x001f_0000_ff00_00ff;
        v = (v | v << 8) & 0x100f_00f0_0f00_f00f;
        v = (v | v << 4) & 0x10c3_0c30_c30c_30c3;
        (v | v << 2) & 0x1249_2492_4924_9249
    };
    spread(cell[0]) | spread(cell[1]) << 1 | spread(cell[2]) << 2
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn morton_interleaves_the_bits_of_each_axis() {
        assert_eq!(morton([1, 0, 0]), 0b001);
        assert_eq!(morton([0, 1, 0]), 0b010);
        assert_eq!(morton([0, 0, 1]), 0b100);
        assert_eq!(morton([3, 0, 0]), 0b001_001);
        let top = (1 << 20) as u64;
        assert_eq!(morton([top, top, top]), 0b111 << 60);
    }

    #[test]
    fn every_triangle_is_in_one_cluster_inside_its_leaf_box() {
        // A 10 x 10 grid of unit squares in scrambled order.
        let n = 10u32;
        let vertices: Vec<[f64; 3]> = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| [i as f64, j as f64, 0.5 * i as f64]))
            .collect();
        let index = |i: u32, j: u32| j * (n + 1) + i;
        let mut indices = Vec::new();
        for j in 0..n {
            for i in 0..n {
                indices.push([index(i, j), index(i + 1, j), index(i + 1, j + 1)]);
                indices.push([index(i, j), index(i + 1, j + 1), index(i, j + 1)]);
            }
        }
        indices.reverse();
        let bounding_box = [Point3::new(0.0, 0.0, 0.0), Point3::new(10.0, 10.0, 5.0)];
        let tree = TriangleTree::build(vertices, indices, bounding_box);
        let mut seen = vec![0; tree.indices.len()];
        let leaves = tree.indices.len().div_ceil(CLUSTER_SIZE) as u32;
        assert!(tree.bvh.is_well_formed(leaves as usize));
        let mut met = Vec::new();
        tree.bvh.depth_first(
            |_, _| true,
            |leaf| {
                met.push(leaf);
                let node = tree
                    .bvh
                    .boxes
                    .iter()
                    .zip(&tree.bvh.links)
                    .find(|&(_, &link)| link == super::super::flat_bvh::LEAF | leaf)
                    .map(|(b, _)| *b)
                    .expect("a leaf per cluster");
                for &t in tree.cluster(leaf) {
                    seen[t as usize] += 1;
                    for p in tree.triangle(t as usize) {
                        assert!((0..3).all(|k| node[k] <= p[k] && p[k] <= node[k + 3]));
                    }
                }
            },
        );
        assert_eq!(met, (0..leaves).collect::<Vec<_>>());
        assert!(seen.iter().all(|&k| k == 1));
    }
}
