//! Edge topology: is a mesh closed (watertight) and consistently oriented?

use std::collections::HashMap;

use super::TriangleMesh;

/// How the triangles of a mesh share their edges.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct EdgeReport {
    /// Number of distinct undirected edges.
    pub edges: usize,
    /// Edges used by exactly one triangle (the rim of an open surface).
    pub boundary_edges: usize,
    /// Edges used by three or more triangles.
    pub non_manifold_edges: usize,
    /// Edges used by two triangles that run along it in the same direction (the two
    /// triangles disagree about which side is outside).
    pub misoriented_edges: usize,
    /// Triangles with a repeated vertex index.
    pub degenerate_triangles: usize,
}

impl EdgeReport {
    /// Every edge is shared by exactly two triangles that traverse it in opposite
    /// directions, and no triangle repeats a vertex: a closed, consistently oriented
    /// surface (watertight).
    pub fn is_closed_and_oriented(&self) -> bool {
        self.boundary_edges == 0
            && self.non_manifold_edges == 0
            && self.misoriented_edges == 0
            && self.degenerate_triangles == 0
    }
}

impl TriangleMesh {
    /// Counts boundary, non-manifold and misoriented edges (by vertex index: vertices
    /// at the same position but with different indices are different vertices).
    pub fn edge_report(&self) -> EdgeReport {
        // Per undirected edge: (uses, uses in the min → max direction).
        let mut uses: HashMap<(u32, u32), (u32, u32)> =
            HashMap::with_capacity(self.triangles.len() * 3 / 2);
        let mut report = EdgeReport::default();
        for t in &self.triangles {
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                report.degenerate_triangles += 1;
                continue;
            }
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let entry = uses.entry((a.min(b), a.max(b))).or_insert((0, 0));
                entry.0 += 1;
                entry.1 += u32::from(a < b);
            }
        }
        report.edges = uses.len();
        for &(count, forward) in uses.values() {
            match count {
                1 => report.boundary_edges += 1,
                2 if forward != 1 => report.misoriented_edges += 1,
                2 => {}
                _ => report.non_manifold_edges += 1,
            }
        }
        report
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Point3;

    use crate::{TriangleMesh, axis_box};

    #[test]
    fn a_flipped_triangle_and_a_missing_triangle_are_detected() {
        let closed = axis_box(Point3::origin(), Point3::new(1.0, 1.0, 1.0));
        let report = closed.edge_report();
        assert!(report.is_closed_and_oriented());
        assert_eq!(report.edges, 18); // 12 box edges + 6 face diagonals

        let mut flipped = closed.clone();
        flipped.triangles[0].swap(1, 2);
        let report = flipped.edge_report();
        assert_eq!(report.misoriented_edges, 3);
        assert!(!report.is_closed_and_oriented());

        let mut open = closed.clone();
        open.triangles.pop();
        assert_eq!(open.edge_report().boundary_edges, 3);

        let mut degenerate = TriangleMesh::new();
        degenerate.push_vertex(Point3::origin());
        degenerate.push_triangle(0, 0, 0);
        assert_eq!(degenerate.edge_report().degenerate_triangles, 1);
    }
}
