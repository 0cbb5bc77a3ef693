//! Conservative advancement: how far a step may go before some rod edge could pass
//! through an obstacle that no contact row represents.
//!
//! Rows exist for the pairs within the search margin; everything farther is invisible
//! to the step. Against the meshes the step is sampled along its path
//! ([`Contact::mesh_advancement`]): an edge's centreline cannot cross a surface between
//! two samples where it is `d₀` and `d₁` away if it moves by less than `d₀ + d₁`, so an
//! edge lying on a face slides by nearly two radii per sample. Two rod edges `c` apart
//! (beyond the excluded near neighbours) may approach each other by half of
//! `max(margin, c)`: their relative move, not their own, counts. A hose falling through
//! free space thus moves by about its clearance per step, not by half the margin. Edges
//! of two different rods may move further where their path, sampled like the meshes',
//! keeps their centrelines apart ([`pair_path`]): two touching hoses slide past each
//! other.

use nalgebra::{Point3, Vector3};
use strand_contact::Obstacle;
use strand_system::{Model, SystemState};

use super::exclusion::Exclusion;
use super::mesh_path::MeshPath;
use super::{Contact, centrelines, describe_error, rod_geometries};
use crate::constraints::ConstraintError;

/// Farthest rod–rod clearance looked for, in search margins or ([`ROD_REACH_EDGES`])
/// mean edge lengths, whichever is longer: the rod–rod broad phase costs in proportion
/// to the neighbours within reach, so no edge moves by more than half of that in one
/// step.
const ROD_REACH: f64 = 8.0;

/// Farthest rod–rod clearance looked for, in mean edge lengths: a coarse rod (a cable
/// of 20 edges falling from upright) may move far per step for few pairs looked at.
const ROD_REACH_EDGES: f64 = 32.0;

impl Contact {
    /// The largest multiple `t` of the straight move of every vertex from `state` to
    /// `target` such that no edge's centreline passes through a mesh on the way
    /// ([`Contact::mesh_advancement`]) and no two rod edges approach each other by more
    /// than half of `max(margin, gap)` (m), the gap measured at `state`, or, for edges
    /// of two different rods, farther where their centrelines stay apart along the
    /// sampled path ([`pair_path`]) (`t` above 1 is a lower bound).
    pub(crate) fn advancement(
        &self,
        model: &Model,
        state: &SystemState,
        target: &SystemState,
    ) -> Result<f64, ConstraintError> {
        let half_margin = 0.5 * self.margin_m;
        // The move of every vertex, m, and the largest of each edge's two.
        let deltas: Vec<Vec<Vector3<f64>>> = state
            .rods
            .iter()
            .zip(&target.rods)
            .map(|(from, to)| {
                from.positions
                    .iter()
                    .zip(&to.positions)
                    .map(|(a, b)| b - a)
                    .collect()
            })
            .collect();
        let moves = edge_moves(&deltas);
        let farthest = moves.iter().flatten().copied().fold(0.0, f64::max);
        if farthest <= half_margin {
            return Ok(if farthest > 0.0 {
                half_margin / farthest
            } else {
                f64::INFINITY
            });
        }
        let centrelines = centrelines(state);
        let rods = rod_geometries(model, &centrelines);
        // Two rods (or two parts of one) close their gap by at most the largest
        // relative move of their edges' ends: parts moving together (a falling hose)
        // do not limit each other. Pairs beyond `reach` are not looked at; each edge
        // then moves by at most half of it.
        let (length, edges) = model.system().rods.iter().fold((0.0, 0), |(l, n), r| {
            (l + r.rod.length(), n + r.rod.segments())
        });
        let mean_edge = length / edges.max(1) as f64;
        let reach =
            (2.0 * farthest).min((ROD_REACH * self.margin_m).max(ROD_REACH_EDGES * mean_edge));
        let exclusion = Exclusion::new(model, state);
        let pairs = strand_contact::rod_rod_gaps(&rods, reach, |ra, ea, rb, eb| {
            exclusion.excluded(ra, ea, rb, eb)
        })
        .map_err(|e| describe_error(model, e))?;
        let mut fraction = f64::INFINITY;
        for gap in &pairs {
            let Obstacle::Rod { rod, edge, .. } = gap.with else {
                continue;
            };
            let mut relative = 0.0f64;
            for own in &deltas[gap.rod][gap.edge..gap.edge + 2] {
                for other in &deltas[rod][edge..edge + 2] {
                    relative = relative.max((own - other).norm());
                }
            }
            if relative > 0.0 {
                let approach = 0.5 * gap.gap.max(self.margin_m) / relative;
                // Between two rods only: along one rod the parts near each other
                // move together, and the longer steps cost the dropped hoses of
                // `tests/validation/drop.rs` (median 23 → 29 iterations).
                let allowed = if self.sampled_advancement && rod != gap.rod {
                    let edge_of = |r: usize, e: usize| {
                        [
                            (centrelines[r][e], deltas[r][e]),
                            (centrelines[r][e + 1], deltas[r][e + 1]),
                        ]
                    };
                    let radius = |r: usize| model.system().rods[r].rod.section().outer_radius;
                    let kept = KEPT_CENTRELINE_DEPTH * (radius(gap.rod) + radius(rod));
                    approach.max(pair_path(
                        edge_of(gap.rod, gap.edge),
                        edge_of(rod, edge),
                        relative,
                        kept,
                    ))
                } else {
                    approach
                };
                fraction = fraction.min(allowed);
            }
        }
        for edges in &moves {
            for &moved in edges {
                if moved > 0.0 {
                    fraction = fraction.min(0.5 * reach.max(self.margin_m) / moved);
                }
            }
        }
        if self.sampled_advancement {
            fraction = fraction.min(self.mesh_advancement(model, &centrelines, &deltas, &moves));
        } else {
            fraction = fraction.min(self.mesh_advancement_by_margin(model, &centrelines, &moves));
        }
        Ok(fraction)
    }

    /// The mesh part of [`Contact::advancement`] by the clearance at `state` alone:
    /// every edge moving by more than half the margin moves by at most half of
    /// `max(margin, clearance)` (m).
    fn mesh_advancement_by_margin(
        &self,
        model: &Model,
        centrelines: &[Vec<Point3<f64>>],
        moves: &[Vec<f64>],
    ) -> f64 {
        let half_margin = 0.5 * self.margin_m;
        let mut fraction = f64::INFINITY;
        for (rod, (vertices, edges)) in centrelines.iter().zip(moves).enumerate() {
            let radius = model.system().rods[rod].rod.section().outer_radius;
            // Every edge looks up to twice its move beyond its radius.
            let farthest = edges.iter().copied().fold(0.0, f64::max);
            let near = self.meshes_near(vertices, 2.0 * farthest + radius);
            for (edge, &moved) in edges.iter().enumerate() {
                if moved <= half_margin {
                    if moved > 0.0 {
                        fraction = fraction.min(half_margin / moved);
                    }
                    continue;
                }
                // Clearance looked for up to twice the edge's move.
                let mut clearance = 2.0 * moved;
                let (a, b) = (&vertices[edge], &vertices[edge + 1]);
                for mesh in near.iter().map(|&index| &self.meshes[index]) {
                    super::nearby::count_mesh_pair();
                    if let Some(near) = mesh.segment_proximity(a, b, clearance + radius) {
                        clearance = (near.distance - radius).max(0.0);
                    }
                }
                fraction = fraction.min(0.5 * clearance.max(self.margin_m) / moved);
            }
        }
        fraction
    }

    /// The mesh part of [`Contact::advancement`] along the path: the largest multiple
    /// `t` (up to [`PATH_SAMPLES`] samples; above 1 a lower bound) of the straight
    /// move for which no edge's centreline reaches a mesh. The distance `d` of a
    /// centreline segment to a mesh changes by at most the larger move of its ends, so
    /// between two samples where an edge is `d₀` and `d₁` away and moves by less than
    /// `d₀ + d₁` it cannot cross a surface: an edge in contact (`d` about its radius)
    /// slides by nearly twice its radius per sample, however close it lies. A trial
    /// that ends inside an obstacle is seen by its own rows (its centreline is then
    /// within a radius of the surface); one that passes through a thin part is not,
    /// which this excludes.
    ///
    /// The distances are lower bounds (`ObstacleMesh::segment_distance_bound`, at
    /// least 15/16 of the exact distance): the test `move < d₀ + d₁` with bounds below
    /// `d₀` and `d₁` implies it with the exact distances, so a sample found clear is
    /// clear and the step never lets a centreline cross a surface; the bound only makes
    /// the samples a little shorter than the exact distances would (and costs a
    /// fraction of an exact nearest-point search on a fine mesh). Each is looked for
    /// only as far as the stride and the fit need it ([`MeshPath`]), with the same
    /// result as looking for every one within the edge's whole remaining move.
    fn mesh_advancement(
        &self,
        model: &Model,
        centrelines: &[Vec<Point3<f64>>],
        deltas: &[Vec<Vector3<f64>>],
        moves: &[Vec<f64>],
    ) -> f64 {
        if self.meshes.is_empty() {
            return f64::INFINITY;
        }
        let radii: Vec<f64> = model
            .system()
            .rods
            .iter()
            .map(|r| r.rod.section().outer_radius)
            .collect();
        MeshPath::new(self, centrelines, deltas, moves, radii).advance()
    }
}

/// The largest multiple `t` of the step (up to [`PATH_SAMPLES`] samples; above 1 a
/// lower bound) for which the centrelines of two edges of different rods, each given
/// as its two vertices (m) with their moves at the full step (m), stay at least `kept`
/// (m) apart: their distance `D` changes by at most their largest relative move
/// `relative` (m at the full step), so between two samples where they are `D₀` and
/// `D₁ ≥ kept` apart and move relative to each other by `D₀ − kept` it stays above
/// `(D₁ + kept) / 2 ≥ kept` (as for the meshes, [`Contact::mesh_advancement`]). Two
/// touching hoses slide past each other by nearly the sum of their radii per sample,
/// however close they lie, where half the margin would hold them back (a cable
/// swinging down across another crept 2.5 mm per iteration and did not converge in
/// 2000). A trial that ends with them overlapping is seen by their own row.
fn pair_path(
    first: [(Point3<f64>, Vector3<f64>); 2],
    second: [(Point3<f64>, Vector3<f64>); 2],
    relative: f64,
    kept: f64,
) -> f64 {
    let at = |edge: &[(Point3<f64>, Vector3<f64>); 2], t: f64| {
        [edge[0].0 + edge[0].1 * t, edge[1].0 + edge[1].1 * t]
    };
    let distance = |t: f64| {
        let ([p0, p1], [q0, q1]) = (at(&first, t), at(&second, t));
        strand_contact::closest_segment_segment(&p0, &p1, &q0, &q1).distance
    };
    let mut t = 0.0;
    let mut d = distance(0.0);
    for _ in 0..PATH_SAMPLES {
        if t >= 1.0 || d <= kept {
            break;
        }
        let next = t + (d - kept) / relative;
        let d_next = distance(next);
        // A move straight at the other edge lands on `kept` itself, up to round-off.
        if d_next < kept * (1.0 - 1e-9) {
            break;
        }
        (t, d) = (next, d_next);
    }
    t
}

/// The larger move of each edge's two ends (m), per rod, from the moves of the
/// vertices (m).
pub(super) fn edge_moves(deltas: &[Vec<Vector3<f64>>]) -> Vec<Vec<f64>> {
    deltas
        .iter()
        .map(|rod| {
            rod.windows(2)
                .map(|w| w[0].norm().max(w[1].norm()))
                .collect()
        })
        .collect()
}

/// How far (m) an edge may move between two samples of [`Contact::mesh_advancement`]
/// whose centreline distances to the meshes are `d0` and `d1` (m), its radius
/// `radius`: the distance changes by at most the move, so below `d0 + d1 − 2f` it
/// stays above `f` on the way. `f` is [`KEPT_CENTRELINE_DEPTH`] of the radius, or half
/// of `d0` where that is less: a step may sink an edge's centreline to within that of
/// the surface but no further, so a trial cannot leave a centreline on a surface (a
/// tube sunk through its whole radius), from where no later move fits (`d0 = 0`); an
/// edge already deeper may at most halve its distance per step (continuous in `d0`).
pub(super) fn path_room(d0: f64, d1: f64, radius: f64) -> f64 {
    let floor = (KEPT_CENTRELINE_DEPTH * radius).min(0.5 * d0);
    d0 + d1 - 2.0 * floor
}

/// The distance from a mesh, as a fraction of its radius, that [`path_room`] keeps an
/// edge's centreline above while it is farther: below 0.2 an edge in contact (`d`
/// about its radius) still slides [`PATH_STRIDE`] radii per sample.
const KEPT_CENTRELINE_DEPTH: f64 = 0.1;

/// Largest number of samples of [`Contact::mesh_advancement`] along a step.
pub(super) const PATH_SAMPLES: usize = 8;

/// Move of an edge from one sample to the next of [`Contact::mesh_advancement`], as a
/// fraction of its distance to the meshes there (at least its radius): below 2, the
/// next sample is found clear when the distance there is at least `stride − 1` of it.
pub(super) const PATH_STRIDE: f64 = 1.6;

#[cfg(test)]
mod tests {
    use super::*;

    /// The lowest centreline distance a path of length `moved` between samples at
    /// distances `d0` and `d1` can reach when the distance is 1-Lipschitz in the move.
    fn lowest_on_path(d0: f64, d1: f64, moved: f64) -> f64 {
        0.5 * (d0 + d1 - moved)
    }

    /// Two edges crossing at right angles, the second `gap` (m) above the first,
    /// moved by `moves` (m, both vertices of the second edge alike).
    fn crossing(gap: f64, moves: Vector3<f64>) -> [[(Point3<f64>, Vector3<f64>); 2]; 2] {
        let still = Vector3::zeros();
        [
            [
                (Point3::new(-0.1, 0.0, 0.0), still),
                (Point3::new(0.1, 0.0, 0.0), still),
            ],
            [
                (Point3::new(0.0, -0.1, gap), moves),
                (Point3::new(0.0, 0.1, gap), moves),
            ],
        ]
    }

    #[test]
    fn a_hose_sliding_across_another_moves_a_stride_of_their_distance_per_sample() {
        // 5 mm apart (two touching hoses of 2.5 mm), the upper sliding 0.3 m along
        // the lower: the distance stays 5 mm, so every sample moves 4.5 mm.
        let (gap, kept) = (5e-3, 0.5e-3);
        let [first, second] = crossing(gap, Vector3::new(0.3, 0.0, 0.0));
        let t = pair_path(first, second, 0.3, kept);
        let expected = PATH_SAMPLES as f64 * (gap - kept) / 0.3;
        assert!((t - expected).abs() < 1e-12, "{t} vs {expected}");
        // Half the margin (5 mm) would allow 2.5 mm in all.
        assert!(t * 0.3 > 10.0 * 2.5e-3);
    }

    #[test]
    fn a_hose_moving_through_another_stops_before_their_centrelines_meet() {
        // Straight down through the lower edge: the centrelines would meet at a move
        // of `gap`. Sampled densely, the path up to the bound keeps `kept` between them.
        for (gap, kept, down) in [
            (5e-3, 0.5e-3, 0.3),
            (2e-2, 1e-3, 0.05),
            (3e-3, 0.3e-3, 3e-3),
        ] {
            let moves = Vector3::new(0.0, 0.0, -down);
            let [first, second] = crossing(gap, moves);
            let t = pair_path(first, second, down, kept);
            assert!(t > 0.0);
            for k in 0..=1000 {
                let s = t * k as f64 / 1000.0;
                let distance = gap - down * s;
                assert!(distance.abs() >= kept * (1.0 - 1e-9), "{gap} {down}: {s}");
            }
        }
    }

    #[test]
    fn a_move_that_fits_keeps_the_centreline_off_the_surface() {
        let radius = 2e-3;
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..10_000 {
            let d0 = 3.0 * radius * next();
            let d1 = 3.0 * radius * next();
            let moved = 0.999 * path_room(d0, d1, radius) * next();
            if moved <= 0.0 {
                continue;
            }
            let lowest = lowest_on_path(d0, d1, moved);
            // Above the kept depth, or above half of a start that was already deeper.
            let floor = (KEPT_CENTRELINE_DEPTH * radius).min(0.5 * d0);
            assert!(lowest > floor, "{d0} {d1} {moved}: {lowest} <= {floor}");
            assert!(lowest > 0.0);
        }
    }

    #[test]
    fn an_edge_in_contact_slides_a_whole_stride_and_a_deep_one_can_still_move() {
        let radius = 1.75e-3;
        // Touching (centreline a radius away) at both samples: a whole stride fits.
        assert!(PATH_STRIDE * radius < path_room(radius, radius, radius));
        // Sinking from touching to the surface does not fit any move longer than the
        // room left above the kept depth.
        let room = path_room(radius, 0.0, radius);
        assert!(room < radius);
        assert!((room - (1.0 - 2.0 * KEPT_CENTRELINE_DEPTH) * radius).abs() < 1e-15);
        // An edge already deeper than the kept depth may move outwards or sideways by
        // a positive amount (the room is continuous in its distance, and positive).
        let deep = 0.05 * radius;
        assert!(path_room(deep, deep, radius) > 0.0);
        let just_above = KEPT_CENTRELINE_DEPTH * radius * (1.0 + 1e-9);
        let just_below = KEPT_CENTRELINE_DEPTH * radius * (1.0 - 1e-9);
        let gap = path_room(just_above, radius, radius) - path_room(just_below, radius, radius);
        assert!(gap.abs() < 1e-9 * radius, "{gap}");
    }
}
