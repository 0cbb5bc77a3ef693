//! Welded vertices and the uses of every welded edge, in flat arrays: linear in the
//! triangles (a bucket per vertex, sorted by the other end), no allocation or hashing
//! per edge. A 1M-triangle mesh has 1.5M edges; a map from edge to a list of its
//! triangles made the topology analysis most of the mesh load.

#[cfg(test)]
thread_local! {
    /// Entries written and comparisons made while welding and grouping on this
    /// thread: a work counter for the test that the analysis stays `O(n log n)`.
    pub(crate) static WORK: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

/// Adds `n` to the work counter (tests only).
#[inline]
fn count(_n: u64) {
    #[cfg(test)]
    WORK.with(|w| w.set(w.get() + _n));
}

/// Welds vertices at exactly the same position (−0 and +0 alike): `welded[i]` is the
/// smallest index of a vertex at the position of vertex `i`. Also returns the number of
/// distinct positions. `O(n)` expected: a table of the first vertex at each position
/// (open addressing, at most half full), filled in vertex order.
pub(crate) fn weld(vertices: &[[f64; 3]]) -> (Vec<u32>, usize) {
    let bits = |p: &[f64; 3]| p.map(|x| (x + 0.0).to_bits());
    let slots = (2 * vertices.len()).next_power_of_two().max(2);
    let shift = u64::BITS - slots.trailing_zeros();
    let mut table = vec![u32::MAX; slots];
    let mut welded = Vec::with_capacity(vertices.len());
    let mut distinct = 0;
    for (i, p) in vertices.iter().enumerate() {
        let key = bits(p);
        let mut slot = (position_hash(key) >> shift) as usize;
        loop {
            count(1);
            let first = table[slot];
            if first == u32::MAX {
                table[slot] = i as u32;
                welded.push(i as u32);
                distinct += 1;
                break;
            }
            if bits(&vertices[first as usize]) == key {
                welded.push(first);
                break;
            }
            slot = (slot + 1) & (slots - 1);
        }
    }
    (welded, distinct)
}

/// A 64-bit hash of a position's bits whose high bits vary with every bit of the
/// input (folded 128-bit products, then a multiplicative spread).
#[inline]
fn position_hash([x, y, z]: [u64; 3]) -> u64 {
    let fold = |a: u64, b: u64| {
        let product = u128::from(a) * u128::from(b);
        (product as u64) ^ ((product >> 64) as u64)
    };
    let h = fold(x ^ 0x243f_6a88_85a3_08d3, y ^ 0x1319_8a2e_0370_7344)
        ^ fold(z ^ 0xa409_3822_299f_31d0, 0x082e_fa98_ec4e_6c89);
    h.wrapping_mul(0x9e37_79b9_7f4a_7c15)
}

/// Buckets of at most this many uses are sorted by insertion (a vertex of a closed
/// mesh has about six).
const SHORT_BUCKET: usize = 16;

/// `bucket` sorted stably by the larger end of its edges, by insertion.
#[inline]
fn insertion_sort_by_high(bucket: &mut [EdgeUse]) {
    for k in 1..bucket.len() {
        let item = bucket[k];
        let mut at = k;
        while at > 0 && bucket[at - 1].high > item.high {
            count(1);
            bucket[at] = bucket[at - 1];
            at -= 1;
        }
        bucket[at] = item;
    }
}

/// One use of an undirected welded edge `(low, high)` by a triangle.
#[derive(Clone, Copy, Debug)]
pub(crate) struct EdgeUse {
    /// The edge's larger welded vertex.
    high: u32,
    /// The triangle using the edge.
    triangle: u32,
    /// Whether the triangle runs along the edge from `low` to `high`.
    forward: bool,
}

impl EdgeUse {
    /// The triangle and whether it runs along the edge from its smaller to its larger
    /// welded vertex.
    pub(crate) fn user(&self) -> (u32, bool) {
        (self.triangle, self.forward)
    }
}

/// The uses of every welded edge: bucket `low` of `uses` (between `start[low]` and
/// `start[low + 1]`) holds the edges whose smaller welded vertex is `low`, sorted by
/// their larger one.
pub(crate) struct EdgeUses {
    start: Vec<usize>,
    uses: Vec<EdgeUse>,
}

impl EdgeUses {
    /// The edge uses of `triangles` (0-based into the vertices that `welded` maps to
    /// their welded index).
    pub(crate) fn new(welded: &[u32], triangles: &[[u32; 3]]) -> Self {
        // The sides of a triangle as (from, to) welded vertices.
        let sides = |[a, b, c]: [u32; 3]| {
            let [a, b, c] = [a, b, c].map(|i| welded[i as usize]);
            [(a, b), (b, c), (c, a)]
        };
        // Counting sort by the smaller end, then a short sort per bucket. Bucket `k`
        // is counted at `start[k + 2]`, filled from `start[k + 1]` (its beginning
        // after the sums, its end once filled), and so begins at `start[k]` after.
        let mut start = vec![0usize; welded.len() + 2];
        for &indices in triangles {
            for (u, v) in sides(indices) {
                start[u.min(v) as usize + 2] += 1;
            }
        }
        for k in 1..start.len() {
            start[k] += start[k - 1];
        }
        let mut uses = vec![
            EdgeUse {
                high: 0,
                triangle: 0,
                forward: false,
            };
            3 * triangles.len()
        ];
        count(uses.len() as u64);
        for (t, &indices) in triangles.iter().enumerate() {
            for (u, v) in sides(indices) {
                let slot = &mut start[u.min(v) as usize + 1];
                uses[*slot] = EdgeUse {
                    high: u.max(v),
                    triangle: t as u32,
                    forward: u < v,
                };
                *slot += 1;
            }
        }
        start.pop();
        // Each bucket holds its uses in triangle order: sorted stably by the larger
        // end, they are sorted by (larger end, triangle).
        for bucket in start.windows(2) {
            let bucket = &mut uses[bucket[0]..bucket[1]];
            if bucket.len() <= SHORT_BUCKET {
                insertion_sort_by_high(bucket);
            } else {
                bucket.sort_unstable_by(|a, b| {
                    count(1);
                    (a.high, a.triangle).cmp(&(b.high, b.triangle))
                });
            }
        }
        Self { start, uses }
    }

    /// The uses of each welded edge in turn (every slice non-empty, one per edge).
    pub(crate) fn groups(&self) -> impl Iterator<Item = &[EdgeUse]> {
        self.start
            .windows(2)
            .flat_map(|b| self.uses[b[0]..b[1]].chunk_by(|x, y| x.high == y.high))
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;

    /// An `n × n` grid of unit squares, two triangles each, with every vertex given
    /// twice (the second copy unused) so that welding has work to do.
    fn grid(n: usize) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let mut vertices = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                vertices.push([i as f64, j as f64, 0.0]);
            }
        }
        vertices.extend(vertices.clone());
        let index = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                triangles.push([index(i, j), index(i + 1, j), index(i + 1, j + 1)]);
                // The second triangle of every other cell uses the duplicate corner.
                let corner = index(i, j + 1) + if (i + j) % 2 == 1 { index(n, n) + 1 } else { 0 };
                triangles.push([index(i, j), index(i + 1, j + 1), corner]);
            }
        }
        (vertices, triangles)
    }

    /// The edge uses by a map from edge to its users (the straightforward reference).
    fn reference(welded: &[u32], triangles: &[[u32; 3]]) -> Vec<Vec<(u32, bool)>> {
        let mut map: BTreeMap<(u32, u32), Vec<(u32, bool)>> = BTreeMap::new();
        for (t, indices) in triangles.iter().enumerate() {
            let w = indices.map(|i| welded[i as usize]);
            for k in 0..3 {
                let (u, v) = (w[k], w[(k + 1) % 3]);
                map.entry((u.min(v), u.max(v)))
                    .or_default()
                    .push((t as u32, u < v));
            }
        }
        map.into_values().collect()
    }

    /// The users (triangle, winding) of every edge, edge by edge.
    fn users_by_edge(edges: &EdgeUses) -> Vec<Vec<(u32, bool)>> {
        edges
            .groups()
            .map(|g| g.iter().map(EdgeUse::user).collect())
            .collect()
    }

    #[test]
    fn welding_and_edge_uses_match_a_map_of_edges() {
        let (vertices, triangles) = grid(7);
        let (welded, distinct) = weld(&vertices);
        assert_eq!(distinct, 64);
        assert!(welded.iter().all(|&w| (w as usize) < 64));
        let edges = EdgeUses::new(&welded, &triangles);
        let found = users_by_edge(&edges);
        assert_eq!(found, reference(&welded, &triangles));
    }

    #[test]
    fn edge_uses_of_fans_and_shared_edges_match_a_map_of_edges() {
        // Vertex 0 in 40 triangles (a bucket sorted whole), edges used three times,
        // triangles given in scrambled order and both windings.
        let rim = 40u32;
        let mut triangles: Vec<[u32; 3]> = (0..rim)
            .map(|k| [0, 1 + k, 1 + (k + 1) % rim])
            .chain((0..rim).step_by(3).map(|k| [1 + (k + 1) % rim, 1 + k, 0]))
            .chain([[1, 2, 3], [3, 2, 1], [2, 1, 0]])
            .collect();
        triangles.reverse();
        triangles.swap(3, 30);
        let welded: Vec<u32> = (0..=rim).collect();
        let edges = EdgeUses::new(&welded, &triangles);
        let found = users_by_edge(&edges);
        assert_eq!(found, reference(&welded, &triangles));
        assert!(found.iter().any(|g| g.len() >= 3));
    }

    #[test]
    fn welding_matches_a_map_of_positions() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        for n in [0, 1, 2, 3, 100, 5000] {
            // Few distinct values per axis (many repeats), ±0, and neighbours one ulp
            // apart.
            let values = [0.0, -0.0, 1.0, 1.0f64.next_up(), -2.5, 1e-300, 3.0e5];
            let vertices: Vec<[f64; 3]> = (0..n)
                .map(|_| [0; 3].map(|_| values[rng.random_range(0..values.len())]))
                .collect();
            let mut first: BTreeMap<[u64; 3], u32> = BTreeMap::new();
            let expected: Vec<u32> = vertices
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    let key = p.map(|x| (x + 0.0).to_bits());
                    *first.entry(key).or_insert(i as u32)
                })
                .collect();
            assert_eq!(weld(&vertices), (expected, first.len()), "{n} vertices");
        }
    }

    /// Counted, not timed: 16× the triangles costs about 16× the work (times a slowly
    /// growing log of the vertex sort), not 256× (issue 11: the mesh load).
    #[test]
    fn topology_work_grows_linearly_with_the_triangles() {
        let work = |n: usize| {
            let (vertices, triangles) = grid(n);
            WORK.with(|w| w.set(0));
            let (welded, _) = weld(&vertices);
            let edges = EdgeUses::new(&welded, &triangles);
            assert_eq!(edges.groups().count(), 3 * n * n + 2 * n);
            WORK.with(|w| w.get()) as f64
        };
        let (small, large) = (work(50), work(200));
        assert!(
            large / small < 22.0,
            "work ratio {} for 16× the triangles",
            large / small
        );
        assert!(
            large / (2.0 * 200.0 * 200.0) < 40.0,
            "{} per triangle",
            large / 80_000.0
        );
    }
}
