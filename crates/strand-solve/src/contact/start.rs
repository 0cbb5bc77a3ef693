//! Checks of a starting configuration: no overlap with an obstacle or another piece of
//! rod, and no rod inside a closed part.

use strand_contact::{Obstacle, ObstacleMesh};
use strand_system::{Model, Support, SystemState};

use super::{Contact, START_OVERLAP_M};
use crate::constraints::{ConstraintError, StartHint};

/// The hint for a start of `rod` (its name) in `model` that does not clear: move its
/// route, or give it one when the start was the solver's guess.
pub(super) fn start_hint(model: &Model, rod: &str) -> StartHint {
    let routed = model
        .system()
        .rods
        .iter()
        .find(|r| r.name == rod)
        .is_some_and(|r| r.route.is_some());
    if routed {
        StartHint::MoveRoute
    } else {
        StartHint::GiveRoute
    }
}

/// A gap error of the start check as the user reads it: a centreline through an
/// obstacle is a start through it, with the hint.
pub(super) fn at_start(model: &Model, error: ConstraintError) -> ConstraintError {
    match error {
        ConstraintError::CentrelineTouches {
            rod,
            what,
            point_mm,
        } => ConstraintError::StartsThrough {
            hint: start_hint(model, &rod),
            rod,
            what,
            point_mm,
        },
        other => other,
    }
}

impl Contact {
    /// `Err` naming the deepest overlap of a rod's surface with a mesh or another rod
    /// (beyond [`START_OVERLAP_M`]) at `state`.
    pub(super) fn check_overlap(
        &self,
        model: &Model,
        state: &SystemState,
    ) -> Result<(), ConstraintError> {
        // Only overlaps count, so the search reaches no further than touching: with the
        // contact margin it listed every feature near a surface, about 18 times an
        // evaluation's work (`cooler_hose_contact.ron --segments 2000`: 1.13 G of its
        // 5.6 G instructions, five checks).
        let gaps = self
            .gaps(model, state, 0.0)
            .map_err(|e| at_start(model, e))?;
        // (A held end vertex overlapping a mesh was named before, by
        // [`Contact::check_held_ends`].)
        let deepest = gaps
            .iter()
            .filter(|g| g.gap < -START_OVERLAP_M)
            .min_by(|a, b| a.gap.total_cmp(&b.gap));
        let Some(g) = deepest else {
            return Ok(());
        };
        let rod = &model.system().rods[g.rod];
        let s = rod.rod.arc_lengths();
        let at = s[g.edge] + g.s * (s[g.edge + 1] - s[g.edge]);
        Err(ConstraintError::StartsOverlapping {
            rod: rod.name.clone(),
            kind: match g.with {
                Obstacle::Mesh(_) => "mesh",
                Obstacle::Rod { .. } => "rod",
            },
            obstacle: self.obstacle_name(model, &g.with),
            overlap_mm: -g.gap * 1e3,
            s_mm: at * 1e3,
            point_mm: [g.point.x * 1e3, g.point.y * 1e3, g.point.z * 1e3],
            hint: start_hint(model, &rod.name),
        })
    }

    /// `Err` naming the first held rod end (a connector, pin, clamp or port) that lies
    /// inside a closed mesh at `state`, or closer to a mesh than the rod's radius: no
    /// start of the rod clears the part then, and the fix is the support, not a route.
    /// Checked before any other overlap, whose check would first name a guess's
    /// centreline through the part (with the hint to give a route).
    pub(super) fn check_held_ends(
        &self,
        model: &Model,
        state: &SystemState,
    ) -> Result<(), ConstraintError> {
        for (r, rod_state) in state.rods.iter().enumerate() {
            let spec = &model.system().rods[r];
            let last = rod_state.positions.len() - 1;
            for (end, j) in [(&spec.start, 0), (&spec.end, last)] {
                if end.support == Support::Free {
                    continue;
                }
                let p = nalgebra::Point3::from(rod_state.positions[j]);
                // A free junction's port is where its given position puts it.
                let at_junction = matches!(end.support, Support::Port { body, .. }
                    if !model.system().bodies[body.0].fixed);
                let (inside, overlaps) = if at_junction {
                    (StartHint::MoveJunction, StartHint::MoveJunction)
                } else {
                    (StartHint::MoveSupport, StartHint::EndOverlaps)
                };
                if let Some(mesh) = self.closed_meshes().find(|m| m.encloses(&p)) {
                    return Err(starts_enclosed(model, state, r, j, mesh, inside));
                }
                let radius = spec.rod.section().outer_radius;
                for (index, mesh) in self.meshes.iter().enumerate() {
                    let Some(near) = mesh.point_proximity(&p, radius - START_OVERLAP_M) else {
                        continue;
                    };
                    return Err(ConstraintError::StartsOverlapping {
                        rod: spec.name.clone(),
                        kind: "mesh",
                        obstacle: self.obstacle_name(model, &Obstacle::Mesh(index)),
                        overlap_mm: (radius - near.distance) * 1e3,
                        s_mm: spec.rod.arc_lengths()[j] * 1e3,
                        point_mm: [p.x * 1e3, p.y * 1e3, p.z * 1e3],
                        hint: overlaps,
                    });
                }
            }
        }
        Ok(())
    }

    /// `Err` naming the first rod vertex (by rod, then arc length) that lies inside a
    /// closed mesh at `state`. Open meshes have no inside and are not checked.
    pub(super) fn check_enclosed(
        &self,
        model: &Model,
        state: &SystemState,
    ) -> Result<(), ConstraintError> {
        for (r, rod_state) in state.rods.iter().enumerate() {
            for mesh in self.closed_meshes() {
                let enclosed = |p: &nalgebra::Vector3<f64>| mesh.encloses(&(*p).into());
                if let Some(j) = rod_state.positions.iter().position(enclosed) {
                    let hint = start_hint(model, &model.system().rods[r].name);
                    return Err(starts_enclosed(model, state, r, j, mesh, hint));
                }
            }
        }
        Ok(())
    }

    /// The meshes that have an inside (closed ones).
    fn closed_meshes(&self) -> impl Iterator<Item = &ObstacleMesh> {
        self.meshes
            .iter()
            .map(|m| m.as_ref())
            .filter(|m| m.diagnostics().closed)
    }
}

/// The error of vertex `j` of rod `r` at `state` starting inside `mesh`, with `hint`.
fn starts_enclosed(
    model: &Model,
    state: &SystemState,
    r: usize,
    j: usize,
    mesh: &ObstacleMesh,
    hint: StartHint,
) -> ConstraintError {
    let rod = &model.system().rods[r];
    let p = state.rods[r].positions[j];
    ConstraintError::StartsEnclosed {
        rod: rod.name.clone(),
        mesh: mesh.name().to_string(),
        s_mm: rod.rod.arc_lengths()[j] * 1e3,
        point_mm: [p.x * 1e3, p.y * 1e3, p.z * 1e3],
        hint,
    }
}
