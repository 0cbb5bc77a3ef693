//! Conservative advancement: how far a step may go before some rod edge could reach an
//! obstacle that no contact row represents.
//!
//! Rows exist for the pairs within the search margin; everything farther is invisible
//! to the step. An edge whose capsule is `c` away from every mesh may therefore move by
//! half of `max(margin, c)`, and two rod edges `c` apart (beyond the excluded near
//! neighbours) may approach each other by half of `max(margin, c)`: their relative
//! move, not their own, counts. A hose falling through free space thus moves by half
//! its clearance per step, not by half the margin.

use nalgebra::Vector3;
use strand_contact::Obstacle;
use strand_system::{Model, SystemState};

use super::exclusion::Exclusion;
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
    /// `target` such that every edge moves by at most half of `max(margin, clearance)`
    /// (m), its clearance measured at `state` against every mesh and every other rod
    /// (looked for up to twice the edge's move: `t` above 1 is a lower bound).
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
        let moves: Vec<Vec<f64>> = deltas
            .iter()
            .map(|rod| {
                rod.windows(2)
                    .map(|w| w[0].norm().max(w[1].norm()))
                    .collect()
            })
            .collect();
        let farthest = moves.iter().flatten().copied().fold(0.0, f64::max);
        if farthest <= half_margin {
            return Ok(if farthest > 0.0 {
                half_margin / farthest
            } else {
                f64::INFINITY
            });
        }
        let centrelines = centrelines(state);
        // Clearance of every edge, m, looked for up to twice its move (beyond that it
        // does not limit the step).
        let mut clearance: Vec<Vec<f64>> = moves
            .iter()
            .map(|edges| edges.iter().map(|d| 2.0 * d).collect())
            .collect();
        for (rod, (vertices, edges)) in centrelines.iter().zip(&moves).enumerate() {
            let radius = model.system().rods[rod].rod.section().outer_radius;
            for (edge, &moved) in edges.iter().enumerate() {
                if moved <= half_margin {
                    continue;
                }
                let (a, b) = (&vertices[edge], &vertices[edge + 1]);
                for mesh in &self.meshes {
                    let reach = clearance[rod][edge] + radius;
                    if let Some(near) = mesh.segment_proximity(a, b, reach) {
                        clearance[rod][edge] = (near.distance - radius).max(0.0);
                    }
                }
            }
        }
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
                fraction = fraction.min(0.5 * gap.gap.max(self.margin_m) / relative);
            }
        }
        for edges in &moves {
            for &moved in edges {
                if moved > 0.0 {
                    fraction = fraction.min(0.5 * reach.max(self.margin_m) / moved);
                }
            }
        }
        for (edges, room) in moves.iter().zip(&clearance) {
            for (&moved, &c) in edges.iter().zip(room) {
                if moved > half_margin {
                    fraction = fraction.min(0.5 * c.max(self.margin_m) / moved);
                } else if moved > 0.0 {
                    fraction = fraction.min(half_margin / moved);
                }
            }
        }
        Ok(fraction)
    }
}
