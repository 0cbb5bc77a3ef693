//! Welded vertices and the uses of every welded edge, in flat arrays: linear in the
//! triangles (a bucket per vertex, sorted by the other end), no allocation or hashing
//! per edge. A 1M-triangle mesh has 1.5M edges; a map from edge to a list of its
//! triangles made the topology analysis most of the mesh load.

use nalgebra::Point3;

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
/// distinct positions. `O(n log n)` by a sort of the position bits.
pub(crate) fn weld(vertices: &[Point3<f64>]) -> (Vec<u32>, usize) {
    let mut keyed: Vec<([u64; 3], u32)> = vertices
        .iter()
        .enumerate()
        .map(|(i, p)| ([p.x, p.y, p.z].map(|x| (x + 0.0).to_bits()), i as u32))
        .collect();
    count(keyed.len() as u64);
    keyed.sort_unstable_by(|a, b| {
        count(1);
        a.cmp(b)
    });
    let mut welded = vec![0; vertices.len()];
    let mut distinct = 0;
    for run in keyed.chunk_by(|a, b| a.0 == b.0) {
        // Sorted by (bits, index): the first of a run has the smallest index.
        let first = run[0].1;
        distinct += 1;
        for &(_, i) in run {
            welded[i as usize] = first;
        }
    }
    (welded, distinct)
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
        let sides = |indices: &[u32; 3]| {
            let w = indices.map(|i| welded[i as usize]);
            (0..3).map(move |k| (w[k], w[(k + 1) % 3]))
        };
        // Counting sort by the smaller end, then a short sort per bucket.
        let mut start = vec![0usize; welded.len() + 1];
        for (u, v) in triangles.iter().flat_map(sides) {
            start[u.min(v) as usize + 1] += 1;
        }
        for k in 1..start.len() {
            start[k] += start[k - 1];
        }
        let mut next = start.clone();
        let mut uses = vec![
            EdgeUse {
                high: 0,
                triangle: 0,
                forward: false,
            };
            3 * triangles.len()
        ];
        count(uses.len() as u64);
        for (t, indices) in triangles.iter().enumerate() {
            for (u, v) in sides(indices) {
                let slot = &mut next[u.min(v) as usize];
                uses[*slot] = EdgeUse {
                    high: u.max(v),
                    triangle: t as u32,
                    forward: u < v,
                };
                *slot += 1;
            }
        }
        for bucket in start.windows(2) {
            uses[bucket[0]..bucket[1]].sort_unstable_by(|a, b| {
                count(1);
                (a.high, a.triangle).cmp(&(b.high, b.triangle))
            });
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
    fn grid(n: usize) -> (Vec<Point3<f64>>, Vec<[u32; 3]>) {
        let mut vertices = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                vertices.push(Point3::new(i as f64, j as f64, 0.0));
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

    #[test]
    fn welding_and_edge_uses_match_a_map_of_edges() {
        let (vertices, triangles) = grid(7);
        let (welded, distinct) = weld(&vertices);
        assert_eq!(distinct, 64);
        assert!(welded.iter().all(|&w| (w as usize) < 64));
        let edges = EdgeUses::new(&welded, &triangles);
        let found: Vec<Vec<(u32, bool)>> = edges
            .groups()
            .map(|g| g.iter().map(EdgeUse::user).collect())
            .collect();
        assert_eq!(found, reference(&welded, &triangles));
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
