//! Which pairs of rod edges are not contact: near neighbours along one rod, and rod
//! ends held together by a body. Decided on the geometry present (the current
//! centreline lengths), computed once per evaluation.

use strand_system::{Model, Support, SystemState};

/// The current arc lengths of every rod (m, cumulative along the centreline polyline)
/// and the rules that exclude pairs of edges from contact.
pub(crate) struct Exclusion<'a> {
    model: &'a Model,
    /// `lengths[rod][j]`: current centreline length from vertex 0 to vertex `j`, m.
    lengths: Vec<Vec<f64>>,
}

#[cfg(test)]
thread_local! {
    /// Vertices visited while measuring arc lengths on this thread (a work counter for
    /// the test that the exclusion costs O(vertices) per evaluation, not O(pairs ×
    /// vertices)).
    pub(crate) static ARC_LENGTH_VISITS: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
    /// Pairs of edges asked about on this thread.
    pub(crate) static EXCLUSION_QUERIES: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

impl<'a> Exclusion<'a> {
    /// Measures the current arc lengths of `state`'s rods: O(vertices).
    pub(crate) fn new(model: &'a Model, state: &SystemState) -> Self {
        let lengths = state
            .rods
            .iter()
            .map(|rod| {
                #[cfg(test)]
                ARC_LENGTH_VISITS.with(|c| c.set(c.get() + rod.positions.len()));
                let mut acc = 0.0;
                let mut s = Vec::with_capacity(rod.positions.len());
                s.push(0.0);
                for pair in rod.positions.windows(2) {
                    acc += (pair[1] - pair[0]).norm();
                    s.push(acc);
                }
                s
            })
            .collect();
        Self { model, lengths }
    }

    /// Whether edges `edge_a` of `rod_a` and `edge_b` of `rod_b` are not contact:
    /// - on one rod, the centreline between the two edges is shorter than half a turn
    ///   of the tube, `π r`, *as it is now*: a tube bent to its own radius touches
    ///   itself at that distance, so nearer pieces are neighbours, not contact (a
    ///   compressed start is not an overlap; a loop crossing itself is);
    /// - on two rods that end at one body, both edges within the sum of the radii
    ///   (current length) from the ends at that body.
    pub(crate) fn excluded(
        &self,
        rod_a: usize,
        edge_a: usize,
        rod_b: usize,
        edge_b: usize,
    ) -> bool {
        #[cfg(test)]
        EXCLUSION_QUERIES.with(|c| c.set(c.get() + 1));
        let rods = &self.model.system().rods;
        let (a, b) = (&rods[rod_a], &rods[rod_b]);
        let (ra, rb) = (a.rod.section().outer_radius, b.rod.section().outer_radius);
        if rod_a == rod_b {
            let s = &self.lengths[rod_a];
            let (first, second) = (edge_a.min(edge_b), edge_a.max(edge_b));
            return s[second] - s[first + 1] < std::f64::consts::PI * ra.max(rb);
        }
        let reach = ra + rb;
        let body_of = |support: &Support| match support {
            Support::Port { body, .. } => Some(body.0),
            _ => None,
        };
        let from_end = |rod: usize, edge: usize, at_end: bool| {
            let s = &self.lengths[rod];
            if at_end {
                s[s.len() - 1] - s[edge + 1]
            } else {
                s[edge]
            }
        };
        for (end_a, at_end_a) in [(&a.start, false), (&a.end, true)] {
            for (end_b, at_end_b) in [(&b.start, false), (&b.end, true)] {
                let (Some(body_a), Some(body_b)) =
                    (body_of(&end_a.support), body_of(&end_b.support))
                else {
                    continue;
                };
                if body_a == body_b
                    && from_end(rod_a, edge_a, at_end_a) < reach
                    && from_end(rod_b, edge_b, at_end_b) < reach
                {
                    return true;
                }
            }
        }
        false
    }
}
