//! An oriented box per BVH node: axes from the node's mean normal and the extent of
//! its triangles along them, a second lower bound of the distance to anything in the
//! node.
//!
//! On a tilted surface a node's axis-aligned box sticks out of the surface by about the
//! node's size times the slope, so the box is much nearer to a feature above the
//! surface than any triangle in it: a search for the triangles within the contact's
//! distance of a hose resting on a finely faceted drum entered hundreds of nodes beside
//! the contact on every query (issue 11). A box aligned with the node's mean normal
//! hugs a smooth patch much more closely (its thickness is the patch's sag, the node's
//! size squared over the curvature radius, against the size times the slope). A node
//! is pruned when either box is out of reach; both are lower bounds of the exact
//! distance, so what a search finds does not change, only how much it looks at.
//!
//! Computed lazily, a chunk at a time, and shared by every copy and placement of the
//! mesh: the tree is cut into subtrees of at most [`CHUNK_CLUSTERS`] clusters, and a
//! chunk's boxes are computed (in one pass up the subtree) the first time a search
//! reaches it, so a solve against a mesh of millions of triangles pays only for the
//! parts near its rods. The few nodes above the chunks have no oriented box.

use std::sync::OnceLock;

use nalgebra::{Point3, Vector3};
use parry3d_f64::math::Vector as GlamVector;

use super::ObstacleMesh;
use super::flat_bvh::LEAF;
use super::segment_box::{box_box_distance, segment_box_distance};
use super::triangle_tree::CLUSTER_SIZE;

/// Clusters of a chunk at most (256 triangles): computing a chunk costs about as much as
/// a few dozen node tests of the searches that reach it (larger chunks computed parts no
/// search needed: 4096 triangles cost the 1M-triangle contact case 6 % more).
const CHUNK_CLUSTERS: u32 = 64;

/// The oriented boxes of a mesh's nodes, computed a chunk at a time
/// ([`ObstacleMesh::node_frame`]).
#[derive(Debug, Default)]
pub(crate) struct NodeFrames {
    /// The chunks in preorder, found on first use.
    chunks: OnceLock<Chunks>,
}

/// The chunks of a tree and the chunk of every node.
#[derive(Debug)]
struct Chunks {
    chunks: Vec<Chunk>,
    /// The chunk of each node (preorder), or `u32::MAX` above the chunks.
    chunk_of: Vec<u32>,
}

/// A subtree of at most [`CHUNK_CLUSTERS`] clusters whose parent has more.
#[derive(Debug)]
struct Chunk {
    /// Its root (preorder index); its nodes are `root .. root + len`.
    root: u32,
    len: u32,
    /// The boxes of its nodes (in preorder), computed on first use.
    frames: OnceLock<Box<[NodeFrame]>>,
}

impl NodeFrames {
    /// Bytes held by the chunks computed so far.
    pub(crate) fn memory_bytes(&self) -> usize {
        self.chunks.get().map_or(0, |chunks| {
            chunks.chunk_of.len() * std::mem::size_of::<u32>()
                + chunks
                    .chunks
                    .iter()
                    .map(|c| {
                        std::mem::size_of::<Chunk>()
                            + c.frames
                                .get()
                                .map_or(0, |f| f.len() * std::mem::size_of::<NodeFrame>())
                    })
                    .sum::<usize>()
        })
    }
}

/// The box `low ≤ (a₀ · x, a₁ · x, a₂ · x) ≤ high` (m) holding every vertex of a node's
/// triangles, its axes `a` ([`NodeFrame::axes`]) from the node's mean normal; a zero
/// normal (the triangles face every way) bounds nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct NodeFrame {
    /// The box's axes ([`NodeFrame::axes`]): first the unit mean normal of the node's
    /// triangles (area-weighted), or all zero for a node without a box. Kept rather
    /// than derived from the normal at each test (a normalisation and two cross
    /// products per node a search enters).
    axes: [Vector3<f64>; 3],
    /// Least coordinates of the node's vertices along the axes, m.
    low: [f64; 3],
    /// Greatest coordinates of the node's vertices along the axes, m.
    high: [f64; 3],
}

impl NodeFrame {
    /// What a node whose triangles face every way has: no bound.
    const NONE: Self = Self {
        axes: [Vector3::new(0.0, 0.0, 0.0); 3],
        low: [0.0; 3],
        high: [0.0; 3],
    };

    /// The box's axes: the unit normal `n`, `t = n × e / |n × e|` with `e` the coordinate
    /// axis least along `n`, and `n × t`. The same bits at the build and every query.
    #[inline]
    fn axes(normal: &Vector3<f64>) -> [Vector3<f64>; 3] {
        let least = normal.iamin();
        let tangent = normal.cross(&Vector3::ith(least, 1.0)).normalize();
        [*normal, tangent, normal.cross(&tangent)]
    }

    /// Whether the node has a box (its triangles do not face every way).
    #[inline]
    fn is_box(&self) -> bool {
        self.axes[0] != Vector3::zeros()
    }

    /// A lower bound (m) of the distance between segment `[p0, p1]` and anything in
    /// the box: the exact distance to it, up to the rounding of the change of frame
    /// (a few ulps of the coordinates; the caller's rounding allowance covers it).
    /// Zero for a node without a box.
    #[cfg(test)]
    pub(crate) fn distance(&self, p0: &Point3<f64>, p1: &Point3<f64>) -> f64 {
        self.distance_within(p0, p1, f64::INFINITY)
    }

    /// [`NodeFrame::distance`], or a lower bound of it already above `limit` (m): the
    /// distance between the box and the segment's box in the same axes, which rules
    /// out most nodes beside a contact (those beyond reach along the normal) for a
    /// few products instead of the segment–box distance.
    #[inline]
    pub(crate) fn distance_within(&self, p0: &Point3<f64>, p1: &Point3<f64>, limit: f64) -> f64 {
        if !self.is_box() {
            return 0.0;
        }
        let axes = &self.axes;
        let local = |p: &Point3<f64>| {
            GlamVector::new(
                axes[0].dot(&p.coords),
                axes[1].dot(&p.coords),
                axes[2].dot(&p.coords),
            )
        };
        let (start, end) = (local(p0), local(p1));
        let (low, high) = (GlamVector::from(self.low), GlamVector::from(self.high));
        let cheap = box_box_distance(low, high, start.min(end), start.max(end));
        if cheap > limit || start == end {
            cheap
        } else {
            segment_box_distance(start, end - start, low, high)
        }
    }
}

/// A node whose triangles' area vectors sum to less than this fraction of their areas
/// (they face widely different ways: a box's corner, both sides of a thin part) gets no
/// oriented box: it would be no tighter than the axis-aligned one.
const LEAST_ALIGNMENT: f64 = 0.5;

/// A node keeps its oriented box only when its axis-aligned box is more than this many
/// times thicker along the normal ([`NodeFrame::if_tighter`]).
const TIGHTER: f64 = 2.0;

impl ObstacleMesh {
    /// The oriented box of BVH node `node` (its index in preorder; see the module
    /// documentation); no box above the chunks.
    pub(crate) fn node_frame(&self, node: usize) -> &NodeFrame {
        static NONE: NodeFrame = NodeFrame::NONE;
        let chunks = self.node_frames.chunks.get_or_init(|| self.chunks());
        let Some(chunk) = chunks.chunks.get(chunks.chunk_of[node] as usize) else {
            return &NONE;
        };
        let offset = node - chunk.root as usize;
        let frames = chunk
            .frames
            .get_or_init(|| self.subtree_frames(chunk.root as usize, chunk.len as usize));
        &frames[offset]
    }

    /// The chunks of the tree in preorder: a walk down from the root that stops at the
    /// first node of at most [`CHUNK_CLUSTERS`] clusters.
    fn chunks(&self) -> Chunks {
        let links = &self.tree.bvh.links;
        let mut chunks = Vec::new();
        let mut chunk_of = vec![u32::MAX; links.len()];
        if links.is_empty() {
            return Chunks { chunks, chunk_of };
        }
        let mut pending = vec![(0u32, links.len().div_ceil(2) as u32)];
        while let Some((node, clusters)) = pending.pop() {
            let link = links[node as usize];
            if clusters <= CHUNK_CLUSTERS || link & LEAF != 0 {
                let nodes = node as usize..(node + 2 * clusters - 1) as usize;
                chunk_of[nodes].fill(chunks.len() as u32);
                chunks.push(Chunk {
                    root: node,
                    len: 2 * clusters - 1,
                    frames: OnceLock::new(),
                });
            } else {
                let left = (link - node) / 2;
                pending.push((link, clusters - left));
                pending.push((node + 1, left));
            }
        }
        Chunks { chunks, chunk_of }
    }

    /// The boxes of the `len` nodes from `root` (a whole subtree, in preorder), bottom
    /// up in `O(len)`: a leaf's box from its vertices, an inner node's from its
    /// children's boxes (each child's vertices lie in both its axis-aligned and its
    /// oriented box, so the lesser of their extents along an axis bounds them).
    fn subtree_frames(&self, root: usize, len: usize) -> Box<[NodeFrame]> {
        let bvh = &self.tree.bvh;
        let mut frames = vec![NodeFrame::NONE; len];
        // Area vectors (twice the area along the normal) and areas, summed bottom up.
        let mut sums = vec![(Vector3::zeros(), 0.0); len];
        for node in (root..root + len).rev() {
            let here = node - root;
            let link = bvh.links[node];
            let children = [node + 1, link as usize];
            let mut corners = [[Point3::origin(); 3]; CLUSTER_SIZE];
            let leaf = (link & LEAF != 0).then(|| {
                let cluster = self.tree.cluster(link & !LEAF);
                for (c, &t) in corners.iter_mut().zip(cluster) {
                    *c = self.local_triangle(t as usize);
                }
                &corners[..cluster.len()]
            });
            sums[here] = match leaf {
                Some(corners) => corners
                    .iter()
                    .map(|[a, b, c]| {
                        let n = (b - a).cross(&(c - a));
                        (n, n.norm())
                    })
                    .fold((Vector3::zeros(), 0.0), |(n, a), (m, b)| (n + m, a + b)),
                None => {
                    let [left, right] = children.map(|c| sums[c - root]);
                    (left.0 + right.0, left.1 + right.1)
                }
            };
            let Some(normal) = aligned(sums[here]) else {
                continue;
            };
            let mut frame = NodeFrame::empty(normal);
            let axes = frame.axes;
            let mut take = |(low, high): ([f64; 3], [f64; 3])| {
                for k in 0..3 {
                    frame.low[k] = frame.low[k].min(low[k]);
                    frame.high[k] = frame.high[k].max(high[k]);
                }
            };
            match leaf {
                Some(corners) => corners.iter().flatten().for_each(|p| {
                    let s = axes.map(|a| a.dot(&p.coords));
                    take((s, s));
                }),
                None => {
                    for child in children {
                        let (mut low, mut high) = aabb_extent(&bvh.boxes[child], &axes);
                        let own = &frames[child - root];
                        if own.is_box() {
                            let (l, h) = own.extent(&axes);
                            for k in 0..3 {
                                (low[k], high[k]) = (low[k].max(l[k]), high[k].min(h[k]));
                            }
                        }
                        take((low, high));
                    }
                }
            }
            frames[here] = frame.if_tighter(&bvh.boxes[node], &axes);
        }
        frames.into_boxed_slice()
    }
}

/// The unit mean normal of triangles whose area vectors sum to `sum` over total area
/// `area`, if they are aligned enough ([`LEAST_ALIGNMENT`]).
fn aligned((sum, area): (Vector3<f64>, f64)) -> Option<Vector3<f64>> {
    let length = sum.norm();
    (length > LEAST_ALIGNMENT * area).then(|| sum / length)
}

/// The least and greatest coordinates along `axes` (m) of the axis-aligned box `node`
/// (minimum x, y, z then maximum).
fn aabb_extent(node: &[f64; 6], axes: &[Vector3<f64>; 3]) -> ([f64; 3], [f64; 3]) {
    let centre = Vector3::new(node[0] + node[3], node[1] + node[4], node[2] + node[5]) * 0.5;
    let half = Vector3::new(node[3] - node[0], node[4] - node[1], node[5] - node[2]) * 0.5;
    box_extent(
        &[Vector3::x(), Vector3::y(), Vector3::z()],
        centre,
        half,
        axes,
    )
}

/// The least and greatest coordinates along `axes` (m) of the box of centre `centre`
/// and half extents `half` (m, both in coordinates along the orthonormal `box_axes`).
fn box_extent(
    box_axes: &[Vector3<f64>; 3],
    centre: Vector3<f64>,
    half: Vector3<f64>,
    axes: &[Vector3<f64>; 3],
) -> ([f64; 3], [f64; 3]) {
    let mut low = [0.0; 3];
    let mut high = [0.0; 3];
    for k in 0..3 {
        // The direction in the box's axes.
        let along = Vector3::from(box_axes.map(|a| a.dot(&axes[k])));
        let (middle, spread) = (along.dot(&centre), along.abs().dot(&half));
        (low[k], high[k]) = (middle - spread, middle + spread);
    }
    (low, high)
}

impl NodeFrame {
    /// The least and greatest coordinates along `axes` (m) of this (non-empty) box.
    fn extent(&self, axes: &[Vector3<f64>; 3]) -> ([f64; 3], [f64; 3]) {
        let centre = Vector3::from([0, 1, 2].map(|k| 0.5 * (self.low[k] + self.high[k])));
        let half = Vector3::from([0, 1, 2].map(|k| 0.5 * (self.high[k] - self.low[k])));
        box_extent(&self.axes, centre, half, axes)
    }

    /// This box if it is much thinner along its normal than the node's axis-aligned
    /// box `node` is ([`TIGHTER`]), else none: a face parallel to a coordinate plane
    /// (most of a CAD part's) is bounded as tightly by its axis-aligned box, and
    /// testing the oriented one too would only cost.
    fn if_tighter(self, node: &[f64; 6], axes: &[Vector3<f64>; 3]) -> Self {
        let (low, high) = aabb_extent(node, axes);
        if high[0] - low[0] > TIGHTER * (self.high[0] - self.low[0]) {
            self
        } else {
            Self::NONE
        }
    }

    /// A box of axes from `normal` holding nothing yet.
    fn empty(normal: Vector3<f64>) -> Self {
        Self {
            axes: Self::axes(&normal),
            low: [f64::INFINITY; 3],
            high: [f64::NEG_INFINITY; 3],
        }
    }
}
