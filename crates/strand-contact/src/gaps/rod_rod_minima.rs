//! Rod–rod gaps at local minima: one gap per local contact between rods.
//!
//! Of the gaps between an edge and the consecutive edges of another rod (or of its own
//! rod beyond the excluded neighbours), only those at a local minimum of the gap along
//! that rod are kept, as the mesh gaps keep one per smooth patch. Two hoses crossing
//! give the gaps at the crossing; a hose lying along itself (or along another) one per
//! edge and side, not one per partner edge within the margin.
//!
//! Listing every pair within the margin first ([`rod_rod_gaps_of`](super::rod_rod_gaps_of)
//! and [`rod_rod_local_minima`]) costs `(2 r + margin − π r) / h` partners per edge on
//! every straight stretch of a hose (2 r + margin reaches past its self-exclusion π r):
//! quadratic in the segments of a given cable (a 21 mm cable of 3247 segments: 440,000
//! candidate pairs and 207,000 gaps per evaluation for 3,000 kept). [`rod_rod_minima_of`]
//! finds the same gaps without them: a run of partner edges (a node of the edge tree,
//! with its bounding sphere and the cone of its directions) along which the distance
//! from the edge provably grows (or shrinks) strictly holds no local minimum inside, so
//! only its two end edges are evaluated.

use nalgebra::Point3;

use super::chain_shape::{ChainShapes, Shape};
use super::edge_tree::{EdgeTree, Found};
use super::mesh_gaps::check_margin;
use super::rod_rod_gaps::{edge_pair_gap, edges_and_boxes, first_partner};
use super::{Gap, GapError, Obstacle, RodGeometry, validate};

/// Absolute tolerance (m) under which two neighbouring partner gaps count as equal:
/// both are kept (a contact at the vertex they share).
const TIE_M: f64 = 1e-12;
/// The same, relative to the gap.
const TIE_RELATIVE: f64 = 1e-9;

/// Least angle (rad) between a right angle and the angle of every partner edge's
/// direction to every line from the edge to it for a run to count as monotone: the
/// distance then changes by at least `sin(0.17) h ≈ 0.17 h` per partner edge of
/// length `h`, far above the tie tolerance.
const MONOTONE_ANGLE_RAD: f64 = 0.17;

/// How the distance from an edge changes along a run of partner edges.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Trend {
    /// Strictly growing with the partner's edge index.
    Growing,
    /// Strictly shrinking.
    Shrinking,
}

/// The gaps of [`rod_rod_gaps_of`](super::rod_rod_gaps_of) that
/// [`rod_rod_local_minima`] keeps, the same gaps with the same numbers in the same
/// order, without listing every pair within the margin.
///
/// On top of the contract of [`rod_rod_gaps`](super::rod_rod_gaps) on `exclude`:
/// the excluded partners of an edge on another rod (or on its own rod past the
/// excluded run next to it) form runs that reach a rod's end, so a run of partners
/// whose two ends are not excluded holds none that is (true of rod ends held
/// together by a junction, excluded by their arc length from the end).
pub fn rod_rod_minima_of(
    rods: &[RodGeometry],
    margin: f64,
    mut exclude: impl FnMut(usize, usize, usize, usize) -> bool,
    owners: Option<&[Vec<bool>]>,
) -> Result<Vec<Gap>, GapError> {
    validate(rods)?;
    check_margin(margin)?;
    let (edges, boxes) = edges_and_boxes(rods, margin);
    let tree = EdgeTree::new(&boxes);
    let shapes: Vec<Shape> = (edges.iter())
        .map(|&(rod, edge)| {
            let vertices = &rods[rod].vertices;
            Shape::of_edge(rod, &vertices[edge], &vertices[edge + 1])
        })
        .collect();
    let shapes = ChainShapes::new(&shapes);
    // Gaps lie in [−2 r, margin]: the largest tie any comparison can use.
    let largest_radius = rods.iter().map(|r| r.radius).fold(0.0, f64::max);
    let largest_tie = TIE_M.max(TIE_RELATIVE * margin.max(2.0 * largest_radius));
    let mut gaps = Vec::new();
    let mut found = Vec::new();
    let mut partners = Vec::new();
    for (first, &(rod_a, edge_a)) in edges.iter().enumerate() {
        if owners.is_some_and(|owners| !owners[rod_a][edge_a]) {
            continue;
        }
        let segments = rods[rod_a].vertices.len() - 1;
        let along = first_partner(edge_a, segments, |b| exclude(rod_a, edge_a, rod_a, b));
        let (a0, a1) = (
            &rods[rod_a].vertices[edge_a],
            &rods[rod_a].vertices[edge_a + 1],
        );
        let (centre, half) = (nalgebra::center(a0, a1), 0.5 * (a1 - a0).norm());
        found.clear();
        tree.runs_from(
            &boxes[first],
            first + (along - edge_a),
            |node, start, end| {
                let trend = trend(shapes.node(node), &centre, half, largest_tie)?;
                let ((rod_s, edge_s), (rod_e, edge_e)) = (edges[start], edges[end - 1]);
                let asked = !exclude(rod_a, edge_a, rod_s, edge_s)
                    && !exclude(rod_a, edge_a, rod_e, edge_e);
                asked.then_some(trend)
            },
            |report| found.push(report),
        );
        partners.clear();
        for report in found.drain(..) {
            match report {
                Found::Edge(second) => {
                    let (rod_b, edge_b) = edges[second];
                    if (rod_a == rod_b && edge_b <= edge_a + 1)
                        || exclude(rod_a, edge_a, rod_b, edge_b)
                    {
                        continue;
                    }
                    let gap = edge_pair_gap(rods, (rod_a, edge_a), (rod_b, edge_b), margin)?;
                    partners.extend(gap.map(|gap| Partner::alone(second, gap)));
                }
                Found::Run { start, end, value } => {
                    // Inside the run every edge has a nearer neighbour: only its ends
                    // can be minima, and its inner neighbours are nearer or farther as
                    // the trend says (within the margin where the end is).
                    let inner = end - start > 2;
                    for (second, edge_is_start) in [(start, true), (end - 1, false)] {
                        let (rod_b, edge_b) = edges[second];
                        let Some(gap) =
                            edge_pair_gap(rods, (rod_a, edge_a), (rod_b, edge_b), margin)?
                        else {
                            continue;
                        };
                        let nearer_inside = inner && (edge_is_start == (value == Trend::Shrinking));
                        partners.push(Partner {
                            index: second,
                            gap,
                            nearer_before: nearer_inside && !edge_is_start,
                            nearer_after: nearer_inside && edge_is_start,
                        });
                    }
                }
            }
        }
        keep_minima(&partners, &edges, &mut gaps);
    }
    Ok(gaps)
}

/// A partner edge within the margin of the current edge.
struct Partner {
    /// Index of the partner edge in (rod, edge) order.
    index: usize,
    /// Its gap.
    gap: Gap,
    /// Whether the partner edge before it is known nearer without being listed.
    nearer_before: bool,
    /// Whether the one after it is.
    nearer_after: bool,
}

impl Partner {
    fn alone(index: usize, gap: Gap) -> Self {
        Self {
            index,
            gap,
            nearer_before: false,
            nearer_after: false,
        }
    }
}

/// Appends the gaps of `partners` (in increasing index) at a local minimum along their
/// rod: no neighbouring partner edge on the same rod is nearer by more than the tie.
fn keep_minima(partners: &[Partner], edges: &[(usize, usize)], gaps: &mut Vec<Gap>) {
    for (k, partner) in partners.iter().enumerate() {
        let g = partner.gap.gap;
        let tie = TIE_M.max(TIE_RELATIVE * g.abs());
        let neighbour = |other: Option<&Partner>, step: isize| {
            other.and_then(|other| {
                (other.index as isize == partner.index as isize + step
                    && edges[other.index].0 == edges[partner.index].0)
                    .then_some(other.gap.gap)
            })
        };
        let before = neighbour(k.checked_sub(1).and_then(|j| partners.get(j)), -1);
        let after = neighbour(partners.get(k + 1), 1);
        let nearer = |other: Option<f64>| other.is_some_and(|other| other < g - tie);
        if !(partner.nearer_before || partner.nearer_after || nearer(before) || nearer(after)) {
            gaps.push(partner.gap);
        }
    }
}

/// Whether the distance from the segment held by the sphere (`centre`, `half`) to the
/// points of the run `shape` grows or shrinks strictly along the run, by more than
/// twice `tie` per edge; `None` where that is not certain.
///
/// For a point `p` of the segment and a point `x(s)` of the run, `d|x − p|/ds` is the
/// cosine of the angle between the run's direction and `x − p`; the directions lie in
/// the run's cone and the `x − p` in the cone from the segment's sphere to the run's,
/// so the angle is within `bearing ± (spread + cone)`. The distance from the segment
/// (the least over `p`) then changes at the same rate or faster.
fn trend(shape: &Shape, centre: &Point3<f64>, half: f64, tie: f64) -> Option<Trend> {
    if shape.rod.is_none() || !shape.spread.is_finite() {
        return None;
    }
    if MONOTONE_ANGLE_RAD.sin() * shape.shortest <= 2.0 * tie {
        return None;
    }
    let offset = shape.centre - centre;
    let distance = offset.norm();
    let reach = half + shape.radius;
    // Apart by more than round-off: no pair in the run touches (NaN: not certain).
    let apart = distance - reach > 1e-9 * distance;
    if !apart {
        return None;
    }
    let cone = (reach / distance).asin();
    let bearing = (shape.axis.dot(&offset) / distance).clamp(-1.0, 1.0).acos();
    let slack = shape.spread + cone + MONOTONE_ANGLE_RAD;
    if bearing + slack <= std::f64::consts::FRAC_PI_2 {
        Some(Trend::Growing)
    } else if bearing - slack >= std::f64::consts::FRAC_PI_2 {
        Some(Trend::Shrinking)
    } else {
        None
    }
}

/// Keeps, per (rod, edge, partner rod), the gaps at local minima along the partner's
/// consecutive edges (a missing neighbour — excluded or beyond the margin — does not
/// count; two neighbours within the tie of each other are both kept). Mesh gaps pass
/// unchanged; the order of the kept gaps is preserved. The reference for
/// [`rod_rod_minima_of`] over every pair of [`rod_rod_gaps_of`](super::rod_rod_gaps_of).
pub fn rod_rod_local_minima(gaps: Vec<Gap>) -> Vec<Gap> {
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
        let tie = TIE_M.max(TIE_RELATIVE * g.abs());
        if before.is_some_and(|b| b < g - tie) || after.is_some_and(|a| a < g - tie) {
            keep[i] = false;
        }
    }
    gaps.into_iter()
        .zip(keep)
        .filter_map(|(g, k)| k.then_some(g))
        .collect()
}

#[cfg(test)]
#[path = "rod_rod_minima_tests.rs"]
mod tests;
