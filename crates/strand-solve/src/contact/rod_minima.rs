//! One rod–rod row per local contact: of the gaps between an edge and the consecutive
//! edges of another rod (or of its own rod beyond the excluded neighbours), only those
//! at a local minimum of the gap along that rod are kept, as the mesh gaps keep one row
//! per smooth patch. Two hoses crossing give the rows at the crossing; a hose lying
//! along itself (or along another) one row per edge and side, not one per partner edge
//! within the margin, whose number grows like `margin / h` (quadratic cost at fine
//! discretisation: 2·r + margin reaches past the self-exclusion π·r on every straight
//! hose). The rows dropped are never nearer than a kept one along the same partner run.

use strand_contact::{Gap, Obstacle};

/// Relative tolerance (of the partner gaps' scale, m) under which two neighbouring
/// partner gaps count as equal: both are kept (a contact at the vertex they share).
const TIE_M: f64 = 1e-12;

/// Keeps, per (rod, edge, partner rod), the gaps at local minima along the partner's
/// consecutive edges (a missing neighbour — excluded or beyond the margin — does not
/// count). Mesh gaps pass unchanged; the order of the kept gaps is preserved.
pub(crate) fn local_minima(gaps: Vec<Gap>) -> Vec<Gap> {
    // (rod, edge, partner rod, partner edge, index) of every rod–rod gap, sorted.
    let mut order: Vec<(usize, usize, usize, usize, usize)> = gaps
        .iter()
        .enumerate()
        .filter_map(|(i, g)| match g.with {
            Obstacle::Rod { rod, edge, .. } => Some((g.rod, g.edge, rod, edge, i)),
            _ => None,
        })
        .collect();
    order.sort_unstable();
    let mut keep = vec![true; gaps.len()];
    for (k, &(rod, edge, partner, partner_edge, i)) in order.iter().enumerate() {
        let neighbour = |j: Option<usize>, step: isize| {
            j.and_then(|j| order.get(j)).and_then(|&(r, e, p, pe, n)| {
                ((r, e, p) == (rod, edge, partner) && pe as isize == partner_edge as isize + step)
                    .then_some(gaps[n].gap)
            })
        };
        let before = neighbour(k.checked_sub(1), -1);
        let after = neighbour(Some(k + 1), 1);
        let g = gaps[i].gap;
        let tie = TIE_M.max(1e-9 * g.abs());
        if before.is_some_and(|b| b < g - tie) || after.is_some_and(|a| a < g - tie) {
            keep[i] = false;
        }
    }
    gaps.into_iter()
        .zip(keep)
        .filter_map(|(g, k)| k.then_some(g))
        .collect()
}
