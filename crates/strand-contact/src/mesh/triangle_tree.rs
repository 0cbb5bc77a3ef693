//! The kept triangles of a mesh and their BVH: parry's [`Bvh`] over clusters of up to
//! [`CLUSTER_SIZE`] triangles that are neighbours along a Morton (Z-order) curve of
//! their centroids.
//!
//! One BVH leaf per triangle costs 112 bytes per triangle in parry's node array alone
//! and an `O(n log n)` build over all `n` triangles; a leaf per cluster of four close
//! triangles cuts both by four; a query tests the (at most four) triangles of a leaf it
//! reaches, each first against its own bounding box. Measured against one leaf per
//! triangle (`cargo bench -p strand-contact --bench mesh`, 1000 segment queries), a
//! query costs about 1.5x at 1k and 1.6x at 1M triangles, for 68 instead of 176 bytes
//! per triangle held and 64 bytes per triangle in the cache file. The triangles keep
//! their order (triangle `t` is the `t`-th kept
//! triangle of the file): `order` lists them cluster by cluster.

use nalgebra::Point3;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Vector as GlamVector;
use parry3d_f64::partitioning::{Bvh, BvhBuildStrategy};
use rayon::prelude::*;

use super::radix_sort::values_by_key;

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
    /// parry's BVH with one leaf per cluster (leaf data = cluster number).
    pub(crate) bvh: Bvh,
}

impl TriangleTree {
    /// Clusters `indices` (non-empty, in range, non-degenerate) along the Morton curve
    /// of their centroids inside `bounding_box` (m) and builds the BVH of the clusters.
    pub(crate) fn build(
        vertices: Vec<[f64; 3]>,
        indices: Vec<[u32; 3]>,
        bounding_box: [Point3<f64>; 2],
    ) -> Self {
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
                let [a, b, c] = corners.map(|i| vertices[i as usize]);
                let cell = [0, 1, 2].map(|k| {
                    let centroid = (a[k] + b[k] + c[k]) / 3.0;
                    ((centroid - min[k]) * scale[k]).clamp(0.0, MORTON_CELLS - 1.0) as u64
                });
                (morton(cell), t as u32)
            })
            .collect();
        // Keys given in triangle order: the order of sorting the (key, triangle) pairs.
        let order = values_by_key(keyed);
        let leaves: Vec<Aabb> = order
            .par_chunks(CLUSTER_SIZE)
            .map(|cluster| {
                let mut mins = GlamVector::splat(f64::INFINITY);
                let mut maxs = GlamVector::splat(f64::NEG_INFINITY);
                for &t in cluster {
                    for i in indices[t as usize] {
                        let p = GlamVector::from_array(vertices[i as usize]);
                        mins = mins.min(p);
                        maxs = maxs.max(p);
                    }
                }
                Aabb::new(mins, maxs)
            })
            .collect();
        let bvh = Bvh::from_leaves(BvhBuildStrategy::Binned, &leaves);
        Self {
            vertices,
            indices,
            order,
            bvh,
        }
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

    /// Bytes held: vertices, triangles, cluster order and parry's BVH.
    pub(crate) fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.vertices.capacity() * std::mem::size_of::<[f64; 3]>()
            + self.indices.capacity() * std::mem::size_of::<[u32; 3]>()
            + self.order.capacity() * std::mem::size_of::<u32>()
            + self.bvh.heap_memory_size()
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
        for leaf in 0..leaves {
            let node = tree.bvh.leaf_node(leaf).expect("a leaf per cluster");
            for &t in tree.cluster(leaf) {
                seen[t as usize] += 1;
                for p in tree.triangle(t as usize) {
                    let (lo, hi) = (node.mins(), node.maxs());
                    assert!(lo.x <= p.x && p.x <= hi.x && lo.y <= p.y && p.y <= hi.y);
                    assert!(lo.z <= p.z && p.z <= hi.z);
                }
            }
        }
        assert!(seen.iter().all(|&k| k == 1));
    }
}
