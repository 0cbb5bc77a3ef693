//! Rows left out for features far from the meshes ([`Constraints::rows_leaving_far`]):
//! a step must move every listed vertex by less than its clearance, or the rows of the
//! vertices it moves farther are brought in and the QP solved again.
//!
//! Why the step is the same: a left-out row's value is at least its vertex's clearance
//! `c`, and its linearisation changes by `n · Δp` along the step, `Δp` the linearised
//! move of its point (a vertex's, or an interpolation of its edge's two vertices'), so
//! by at most the larger move of its vertices. A step that moves every listed vertex by
//! less than its clearance satisfies every left-out row strictly; the QP without them
//! (strictly convex: the damped Hessian is positive definite) then has the same
//! solution as the QP with them.
//!
//! [`Constraints::rows_leaving_far`]: crate::Constraints::rows_leaving_far

use nalgebra::Vector3;

use super::Iteration;
use crate::constraints::{FarVertex, Row};
use crate::report::Termination;

/// A listed vertex must move by less than this fraction of its clearance (the rest
/// covers the rounding of the bound and of the move).
const CLEARANCE_USED: f64 = 1.0 - 1e-9;

impl Iteration<'_> {
    /// The listed far vertices (rod, vertex) that `step` (unknowns) moves by at least
    /// their clearance, to first order; empty when the left-out rows hold.
    pub(super) fn far_moved(&self, step: &[f64]) -> Vec<(usize, usize)> {
        let mut moved: Vec<(usize, usize)> = self
            .far
            .iter()
            .filter(|v| self.linear_move(v, step) >= CLEARANCE_USED * v.clearance_m)
            .map(|v| (v.rod, v.vertex))
            .collect();
        moved.sort_unstable();
        moved.dedup();
        moved
    }

    /// The first-order move (m) of vertex `v` along `step`.
    fn linear_move(&self, v: &FarVertex, step: &[f64]) -> f64 {
        // A vertex with unknowns of its own moves by them.
        if let Some(b) = self.model.dofs().vertex(v.rod, v.vertex) {
            return Vector3::new(step[3 * b], step[3 * b + 1], step[3 * b + 2]).norm();
        }
        (0..3)
            .map(|k| {
                self.model
                    .vertex_direction_gradient(&self.state, v.rod, v.vertex, &Vector3::ith(k, 1.0))
                    .iter()
                    .map(|&(i, a)| a * step[i])
                    .sum::<f64>()
                    .powi(2)
            })
            .sum::<f64>()
            .sqrt()
    }

    /// Brings the left-out rows of the features at the vertices `moved` into
    /// `self.rows` (every left-out row where a moved vertex has no unknowns of its own:
    /// carried by a body or a clip): appended where not there yet, with no penalty
    /// shift (a left-out row was not held); those vertices leave the far list. Fails as
    /// the subproblem where the rows cannot be evaluated (not expected: the left-out
    /// features are clear of the meshes).
    pub(super) fn include_far_rows(&mut self, moved: &[(usize, usize)]) -> Result<(), Termination> {
        if self.far.is_empty() {
            return Ok(());
        }
        let dofs = self.model.dofs();
        let blocks: Option<Vec<usize>> = moved
            .iter()
            .map(|&(rod, vertex)| dofs.vertex(rod, vertex))
            .collect();
        let state = self.state.clone();
        let mut found: Vec<Row> = Vec::new();
        let evaluated = match (&blocks, self.constraints) {
            (Some(blocks), Some(c)) => {
                let mut unknowns = vec![false; dofs.len()];
                for &b in blocks {
                    unknowns[3 * b..3 * b + 3].fill(true);
                }
                c.rows_touching(self.model, &state, &unknowns, &mut found)
                    .is_ok()
            }
            _ => self.collect_all_rows(&state, &mut found),
        };
        if !evaluated {
            return Err(Termination::SubproblemFailed);
        }
        let mut present: Vec<_> = self.rows.iter().map(|r| r.key).collect();
        present.sort_unstable();
        self.rows.extend(
            found
                .into_iter()
                .filter(|r| present.binary_search(&r.key).is_err()),
        );
        match blocks {
            Some(_) => self
                .far
                .retain(|v| moved.binary_search(&(v.rod, v.vertex)).is_err()),
            None => self.far.clear(),
        }
        Ok(())
    }
}
