//! Stagnation at the round-off floor: when the iteration can no longer change the
//! energy beyond round-off and the residual stops decreasing, the state is the
//! equilibrium to within what `f64` resolves, and the residual it reached is the floor
//! of this model. A solve asked for a tolerance below that floor (or whose floor lies
//! above the estimate [`crate::SolveReport::residual_floor_n`], as with junctions and
//! clips, whose terms the estimate does not count) ends there as
//! [`Termination::Stagnated`] with that residual, instead of running its budget and
//! then every continuation, which restarts from the initial state and can only reach
//! the same floor.

use super::Iteration;
use super::globalise::ENERGY_NOISE;
use crate::report::{SolveReport, Termination};

/// Iterations (the current one included) over which the energy must have stayed
/// within round-off for a failed line search to count as a stall at the floor.
pub(super) const STALL_ITERATIONS: usize = 3;

/// A stall counts as one at the round-off floor (no continuation is tried after it)
/// when its residual is at most this (dimensionless) multiple of the estimated floor.
/// Measured: the harness with junctions and clips stalls at 7 times the estimate, the
/// 400-segment cooler hose at 20 times; random cables lying on a mesh at 15 to 29
/// times (three cases) and at 350 to 1700 times (three), where a continuation
/// occasionally ends below the tolerance (one of 40 random cases), so it is still
/// tried there.
pub const ROUND_OFF_STALL: f64 = 100.0;

impl Iteration<'_> {
    /// Why the iteration stops when no trial step is accepted (`stop`): a stall
    /// ([`Termination::Stagnated`]) when the energy of the last [`STALL_ITERATIONS`]
    /// iterates agrees to within round-off (the line search failed in the round-off
    /// regime, where only a decrease of the residual is accepted); `stop` otherwise.
    pub(super) fn stall_or(&self, stop: Termination) -> Termination {
        let n = self.history.len();
        if stop != Termination::LineSearchFailed || n < STALL_ITERATIONS {
            return stop;
        }
        let energy = self.history[n - 1].1;
        let noise = ENERGY_NOISE * energy.abs().max(1e-12);
        let stationary = self.history[n - STALL_ITERATIONS..]
            .iter()
            .all(|&(_, e)| (e - energy).abs() <= noise);
        if stationary {
            Termination::Stagnated
        } else {
            stop
        }
    }
}

/// Whether `report` ends a solve stalled at its round-off floor: stagnated with a
/// residual within [`ROUND_OFF_STALL`] times the estimated floor, or converged at a
/// floor above the loads ([`Termination::FloorAboveLoads`]). Continuation is not
/// tried after such a solve.
pub(crate) fn stalled_at_floor(report: &SolveReport) -> bool {
    // A floor above the loads is this model's too: continuation reaches it again.
    report.termination == Termination::FloorAboveLoads
        || (report.termination == Termination::Stagnated
            && report.residual.combined_n <= ROUND_OFF_STALL * report.residual_floor_n)
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;
    use strand_rod::{Rod, Section};
    use strand_system::{End, Model, initial_state};

    use crate::gauge::tests::one_rod;
    use crate::{SolverSettings, Termination};

    /// A 0.6 m cable of 0.1 kg/m pinned at two points 0.5 m apart under gravity, with
    /// axial and shear stiffness `stretch` (N).
    fn hanging(stretch: f64) -> Model {
        let section = Section::try_explicit(stretch, stretch, 5e-3, 3.8e-3, 0.1, 0.003).unwrap();
        one_rod(
            Rod::try_straight(section, 0.6, 30).unwrap(),
            End::pinned(Vector3::zeros()),
            End::pinned(Vector3::new(0.5, 0.0, 0.0)),
        )
    }
    #[test]
    fn a_floor_above_the_loads_is_not_converged_and_tries_no_continuation() {
        let settings = SolverSettings::default();
        let solve = |stretch: f64| {
            let model = hanging(stretch);
            let start = initial_state(model.system());
            crate::solve(&model, start, &settings).unwrap().report
        };
        // A real cable: converged, its floor far below its weight (0.59 N).
        let real = solve(2e4);
        assert!(real.converged, "{real:?}");
        assert!((real.applied_load_n - 0.1 * 0.6 * 9.81).abs() < 1e-12);
        assert!(real.residual_floor_n < 1e-9 * real.applied_load_n);
        // Stiffnesses 1e15 N: a floor of the size of the weight. Not converged, and
        // said why, without continuation steps that would reach the same floor.
        let stiff = solve(1e15);
        assert!(!stiff.converged && !stiff.stable, "{stiff:?}");
        assert_eq!(stiff.termination, Termination::FloorAboveLoads, "{stiff:?}");
        assert!(stiff.residual_floor_n > crate::ROUND_OFF_RESOLVED * stiff.applied_load_n);
        assert_eq!(stiff.continuation_steps, 0);
    }
}
