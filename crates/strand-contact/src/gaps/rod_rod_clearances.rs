//! Rod–rod clearances: the least gap of every pair of rods (a rod with itself too),
//! searched with a bound that shrinks to the least gap found so far.
//!
//! A report's clearance search reaches far (0.1 m) beyond the contact margin. Listing
//! every pair of edges within that reach ([`super::rod_rod_gaps`]) and taking the least
//! is quadratic at fine discretisation: along a straight rod every edge has its own
//! neighbours within the reach beyond the excluded run (`reach / h` of them: 1,600 per
//! edge for an 8,000-segment cable), and a cable lying on a floor made `strand solve`
//! spend 6 s and 1.9 GB after an 0.8 s solve. Here each pair of rods keeps only its
//! least gap so far, and each edge's query reaches no further than it: after the
//! first edge the bound is the gap to the first partner past the excluded run.

use super::broad_phase::Aabb;
use super::edge_tree::EdgeTree;
use super::mesh_gaps::check_margin;
use super::rod_rod_gaps::{edge_pair_gap, first_partner};
use super::{Gap, GapError, RodGeometry, validate};

/// The least gap `distance − radius_a − radius_b` of every pair of rods `a ≤ b` (each
/// rod with itself included) over their pairs of edges, if at most `margin` (m), in
/// `(a, b)` order; `exclude` and the pairs skipped are those of [`super::rod_rod_gaps`]
/// (the same contract), and the gap is the one it lists first among the least (in
/// `(edge, partner edge)` order), comparing gaps clamped at zero: a pair in contact
/// reports its first contact.
pub fn rod_rod_clearances(
    rods: &[RodGeometry],
    margin: f64,
    mut exclude: impl FnMut(usize, usize, usize, usize) -> bool,
) -> Result<Vec<Gap>, GapError> {
    validate(rods)?;
    check_margin(margin)?;
    // One tree per rod over its capsules' boxes (grown by its radius only).
    let trees: Vec<EdgeTree> = (rods.iter())
        .map(|g| {
            let boxes: Vec<Aabb> = (g.vertices.windows(2))
                .map(|e| Aabb::of_segment(&e[0], &e[1], g.radius))
                .collect();
            EdgeTree::new(&boxes)
        })
        .collect();
    let mut out = Vec::new();
    let mut candidates = Vec::new();
    for (a, rod_a) in rods.iter().enumerate() {
        let segments = rod_a.vertices.len() - 1;
        for b in a..rods.len() {
            let reach = trees[a].bounds().grown(rod_a.radius + margin);
            if !reach.overlaps(&trees[b].bounds()) {
                continue;
            }
            let mut least: Option<Gap> = None;
            let mut bound = margin;
            for edge_a in 0..segments {
                let from = if a == b {
                    first_partner(edge_a, segments, |e| exclude(a, edge_a, a, e))
                } else {
                    0
                };
                let ends = &rod_a.vertices[edge_a..edge_a + 2];
                let query = Aabb::of_segment(&ends[0], &ends[1], rod_a.radius + bound);
                candidates.clear();
                trees[b].overlapping_from(&query, from, |e| candidates.push(e));
                for &edge_b in &candidates {
                    if a == b && edge_b <= edge_a + 1 || exclude(a, edge_a, b, edge_b) {
                        continue;
                    }
                    let Some(gap) = edge_pair_gap(rods, (a, edge_a), (b, edge_b), bound)? else {
                        continue;
                    };
                    if least
                        .as_ref()
                        .is_none_or(|l| gap.gap.max(0.0) < l.gap.max(0.0))
                    {
                        bound = gap.gap.max(0.0);
                        least = Some(gap);
                    }
                }
            }
            out.extend(least);
        }
    }
    Ok(out)
}
