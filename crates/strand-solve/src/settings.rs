//! Solver settings: one plain struct with serde defaults and `validate()`, so the same
//! struct loads from a case file and builds in code (as Clarabel.rs does).
//!
//! Every tuning value of the iteration lives here with its meaning and unit; the
//! iteration itself ([`crate::Solver`]) has no magic constants.

use serde::{Deserialize, Serialize};

/// Settings of the Newton/SQP solver.
///
/// ```
/// use strand_solve::SolverSettings;
/// let settings = SolverSettings { tolerance_n: 1e-8, ..SolverSettings::default() };
/// assert!(settings.validate().is_ok());
/// let bad = SolverSettings { damping_increase: 0.5, ..SolverSettings::default() };
/// assert_eq!(bad.validate().unwrap_err().field, "damping_increase");
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SolverSettings {
    /// Convergence threshold on the residual (largest out-of-balance vertex force, and
    /// edge moment per rod length) in N. Two ulps of strain times the stiffest strain
    /// stiffness (the least the residual resolves to) are used instead when they are
    /// larger; a solve that stalls within 4 × the model's round-off floor (see
    /// [`crate::SolveReport::residual_floor_n`]) is converged at round-off.
    pub tolerance_n: f64,
    /// Maximum number of Newton iterations of one solve (per level of nested
    /// iteration and per continuation step).
    pub max_iterations: usize,
    /// Trust radius for rotations: largest rotation increment of any edge in one step,
    /// rad.
    pub max_rotation_step_rad: f64,
    /// Trust radius for translations: largest translation of any vertex in one step,
    /// as a fraction of the longest rod.
    pub max_translation_step: f64,
    /// Maximum number of rejected trial steps within one iteration (each rejection
    /// raises the damping and shrinks the trust radius).
    pub max_line_search_steps: usize,
    /// Smallest non-zero Levenberg–Marquardt damping, relative to each unknown's own
    /// Hessian diagonal (per-unknown scaling: positions, rotations and joints each keep
    /// their own stiffness scale).
    pub min_damping: f64,
    /// Largest damping before the iteration gives up (the step would be a vanishing
    /// scaled-gradient step).
    pub max_damping: f64,
    /// Factor by which the damping grows after a rejected step or a failed
    /// factorisation.
    pub damping_increase: f64,
    /// Factor by which the damping shrinks after a very successful step (down to 0,
    /// the pure Newton step).
    pub damping_decrease: f64,
    /// [`SolverSettings::damping_decrease`] of a step with contact rows. There a long
    /// step mostly fails because the contacts change along it (a hose sliding over the
    /// scene), not because the energy's model is poor, and a damping cut by 8 after
    /// every accurate step alternates between accurate short steps and long rejected
    /// ones; by 3 (the smallest factor of Nielsen's update) it settles in between.
    /// Measured on the drop family of `tests/validation/drop.rs` (with
    /// [`SolverSettings::follow_on_contact`]): median 30 → 23 iterations, mean 40 → 35.
    pub contact_damping_decrease: f64,
    /// A trial step is accepted when the achieved decrease of the merit function is at
    /// least this fraction of the decrease predicted by the quadratic model.
    pub acceptance_ratio: f64,
    /// Above this ratio of achieved to predicted decrease the model is trusted: the
    /// damping shrinks and the trust radius grows back.
    pub trust_ratio: f64,
    /// Number of iterations without a reduction of the best residual by
    /// [`SolverSettings::stagnation_reduction`] after which the solve stops as
    /// stagnated (reported, never as converged).
    pub stagnation_iterations: usize,
    /// Required reduction factor of the best residual within
    /// [`SolverSettings::stagnation_iterations`].
    pub stagnation_reduction: f64,
    /// Start rods of more than 64 segments from the solution of a coarsened copy of the
    /// system (nested iteration). Turn off when warm-starting from a nearby solution.
    pub nested_iteration: bool,
    /// Nested iteration: the iteration budget of the coarse level (it only proposes a
    /// start, so a hard coarse problem must not cost more than it saves).
    pub coarse_max_iterations: usize,
    /// When a direct solve does not converge, ramp gravity and the dead end loads from
    /// zero with an adaptive step (first 1/8, doubled after an easy step, quartered
    /// after a failed one), each step warm-started, and report that result instead.
    pub load_continuation: bool,
    /// When the direct solve and load continuation fail from a start that holds its
    /// clamped or pinned ends (or fixed bodies) away from the supports — a warm start
    /// from another design — move the supports from there to their place with the same
    /// adaptive ramp, each step warm-started, and report that result instead.
    pub support_continuation: bool,
    /// Solve a system with a rod far stiffer in stretch and shear than in bending at
    /// the scale of its edges (`C·h²/EI` above 1e4) first with that stiffness capped,
    /// then raise the cap step by step, each step warm-started (see
    /// [`crate::stiffness`]). Not used with contact constraints.
    pub stiffness_continuation: bool,
    /// When a solve converges to an unstable equilibrium (a straight rod beyond
    /// buckling, reached from a perfectly straight start), perturb it along its
    /// direction of most negative curvature and solve again, returning the stable branch
    /// a real hose takes. Turn off to examine a given unstable state.
    pub escape_saddles: bool,
    /// Mixed Newton (Magisano, Leonetti & Garcea 2017): the Hessian's stress terms of
    /// every edge use the force predicted by the linearised last step, not the force of
    /// the strain at the new iterate, which a step turning a stiff rod's frames
    /// inflates at second order (see `strand_system::Model::evaluate_mixed`). Same
    /// equilibria, fewer iterations on stiff rods.
    pub mixed_newton: bool,
    /// Add the curvature of the contact constraints held with a positive force to the
    /// model's Hessian (the Lagrangian's `−λ∇²g`: across a ridge, a mesh vertex or
    /// another rod the gap is curved, about `λ/r`, which a limp rod's own stiffness
    /// does not see). Default on: with [`SolverSettings::active_row_penalty`], the drop
    /// family of `tests/validation/drop.rs` (median 49 iterations without either)
    /// takes 41 (alone 38, but one case 49 → 147); with this round's other contact
    /// changes (the path-sampled advancement, the halved trust-region shrink),
    /// `hose_in_groove.ron` takes 11 iterations instead of 51 and
    /// `cooler_hose_contact.ron` 12 instead of 14.
    pub constraint_curvature: bool,
    /// Add the augmented-Lagrangian term `½ ρ (gap + a·d)²` of every row held with a
    /// positive force in the last step to the SQP model, `ρ` the rod's own stiffness
    /// along the row: the step and forces are unchanged while the active set holds, but
    /// the model is positive definite wherever the equilibrium is stable on the
    /// contacts' tangent space (a hose draped over a pipe), so Newton needs no damping.
    /// Default on: the grooves and corner of `tests/validation/groove.rs` converge in 2
    /// iterations (5–6 before this round); without it the curvature costs two drop
    /// cases 169 and 1205 iterations.
    pub active_row_penalty: bool,
    /// With [`SolverSettings::active_row_penalty`]: a row the last QP held that is open
    /// at the iterate by more than the gap its force opens in the rod's own stiffness
    /// (`λ/ρ`, m) keeps the penalty's curvature but is no longer pulled shut (the pull
    /// left out is added back to its multiplier, so the step and forces of a row that
    /// stays held are unchanged). Cables creeping along a 60° groove converge: the
    /// everyday cases `everyday_s3_027` in 208 iterations instead of 429 (exit 3 with
    /// the default budget of 200) and `everyday_s9_035` in 150 instead of stopping at
    /// 4.3e-7 N; the drop family's total falls from 419 to 391 iterations and its
    /// hardest case from 95 to 87, but its median rises from 23 to 27 (issue 10 asks
    /// for ≤ 25), so it is off by default. Turn it on when a hose sliding along a
    /// groove ends `max_iterations` or stagnates.
    pub release_open_rows: bool,
    /// With contact, [`SolverSettings::active_row_penalty`] and without
    /// [`SolverSettings::release_open_rows`]: when the direct attempt ends unconverged
    /// (`max_iterations`, a failed line search; not a stall at the round-off floor),
    /// iterate once more from where it stopped with `release_open_rows` on, before any
    /// continuation (counted as one continuation step). A cable creeping along a 60°
    /// groove under the rows' pull then converges where it ran out of budget
    /// (`everyday_s39_013`: 3.2 N after 439 iterations, now converged), while the
    /// cases that converge directly keep the default's path. A coarse level of nested
    /// iteration, which only proposes a start within its own budget, does not retry.
    /// The direct attempt also ends early where it creeps ([`crate::Termination::Creeping`]:
    /// [`SolverSettings::stagnation_iterations`] exact steps in a row that still needed
    /// damping, the residual not falling by [`SolverSettings::stagnation_reduction`]),
    /// and resumes with the rest of its budget should the retry fail
    /// (`everyday_s74_001`: 274 → 127 iterations).
    pub release_retry: bool,
    /// When the first trial of a step with contact rows is rejected, try it once more
    /// projected back onto the rows held (the rows' second-order correction: a curved
    /// gap is violated at second order by a step that satisfied its linearisation, and
    /// the exact penalty would reject the step for it). Default on: drop case 10 of
    /// `tests/validation/drop.rs` converges in 105 iterations instead of 278 (with
    /// continuation), the family's mean 60 → 46.
    pub constraint_correction: bool,
    /// Let the positions of a trial step with contact rows follow its frames (the
    /// positions-only Newton step, every rotation held, constrained by the trial's
    /// rows: those held with a force closed, the others kept open), when the step
    /// turns a stiff rod's frames beyond a tenth of its valley turn or the energy
    /// model mispredicted it; kept when it lowers the merit. Without rows this is
    /// always done. Default on: the drop family of `tests/validation/drop.rs` takes a
    /// median of 30 iterations instead of 32 (mean 40 instead of 44; cases 9 and 10
    /// 76 → 45 and 84 → 50), whose long steps were mispredicted by ratios of −1 to −50.
    pub follow_on_contact: bool,
    /// Escape only from saddles whose most negative curvature is at least this
    /// fraction of the unknowns' own stiffness scale (the smallest shift `σ` that makes
    /// `H + σD` positive definite, `D` the damping scale); 0 escapes from every saddle.
    /// Stiffness continuation steps use [`SolverSettings::stiffness_step_escape_shift`].
    pub escape_min_shift: f64,
    /// Largest number of continuation steps (accepted and rejected together).
    pub max_continuation_steps: usize,
    /// Load continuation: the first load increment, as a fraction of the full load.
    pub continuation_first_step: f64,
    /// Load continuation: the smallest load increment before the ramp gives up.
    pub continuation_smallest_step: f64,
    /// Load continuation: a step that converged in at most this many iterations
    /// doubles the next increment.
    pub continuation_easy_iterations: usize,
    /// Load continuation: the iteration budget of one load step (a failing step costs
    /// little before it is retried at a quarter of its size).
    pub continuation_step_iterations: usize,
    /// Stiffness continuation: `C·h²/EI` (strain stiffness × shortest edge² / softest
    /// bending stiffness) above which a system is solved by stiffness continuation.
    pub stiffness_threshold: f64,
    /// Stiffness continuation: `C·h²/EI` of the softened system it starts from.
    pub stiffness_soft_ratio: f64,
    /// Stiffness continuation: the cap on the strain stiffnesses is at least this
    /// multiple of the system's load (weight plus dead end forces, N), so that the
    /// softened rods stretch by at most about its inverse.
    pub stiffness_load_ratio: f64,
    /// Stiffness continuation: when the load floor
    /// ([`SolverSettings::stiffness_load_ratio`]) rather than the bending sets the cap
    /// (a limp cable under a load), first solve the system softened to
    /// [`SolverSettings::stiffness_soft_ratio`] with every load scaled down to where
    /// the floor meets that cap (the stretch bound is kept, and a limp cable's shape
    /// does not depend on the size of its load), and start the softened start from it
    /// (see `strand_solve::stiffness`). Default on.
    pub stiffness_limp_start: bool,
    /// Stiffness continuation: the first growth factor of the cap.
    pub stiffness_first_growth: f64,
    /// Stiffness continuation: the largest growth factor of the cap per step (the
    /// factor is squared after an easy step).
    pub stiffness_max_growth: f64,
    /// Stiffness continuation: the smallest growth factor (square-rooted after a
    /// failed step) before the continuation gives up.
    pub stiffness_min_growth: f64,
    /// Stiffness continuation: tolerance of the intermediate steps relative to the
    /// system's force scale (loads plus `EI/L²` of every rod); the final solve of the
    /// true system meets `tolerance_n`.
    pub stiffness_step_tolerance: f64,
    /// Stiffness continuation: the tolerance of an intermediate step is at least this
    /// multiple of its own round-off floor (which grows with the capped stiffness): an
    /// intermediate step only has to bring the next one into its basin, and
    /// iterations spent at the round-off floor of a step that is not the final
    /// one buy nothing.
    pub stiffness_step_floor_multiple: f64,
    /// Stiffness continuation: a step that converged in at most this many iterations
    /// squares the growth factor.
    pub stiffness_easy_iterations: usize,
    /// Stiffness continuation: the iteration budget of one stiffening step.
    pub stiffness_step_iterations: usize,
    /// Stiffness continuation: the [`SolverSettings::escape_min_shift`] of every
    /// stiffening step. A softened rod may prefer compression to buckling, so a ramp
    /// can follow the straight branch past its buckling load: a step that lands on a
    /// clearly unstable state (a straight rod far beyond buckling) is perturbed off it,
    /// while the nearly neutral directions of a limp cable's slack part are left to
    /// the final solve.
    pub stiffness_step_escape_shift: f64,
    /// Inequality constraints (contact gaps in m, joint limits in rad or m): a converged
    /// state violates none by more than this, and every constraint that carries a force
    /// is closed to within it.
    pub constraint_tolerance: f64,
    /// Stability classification: a generalised eigenvalue of the reduced Hessian
    /// relative to its diagonal, `|λ| ≤ neutral_tolerance`, is a neutral (zero)
    /// direction; below `−neutral_tolerance` the equilibrium is unstable.
    pub neutral_tolerance: f64,
    /// Keep the Hessian at a converged equilibrium with the solution
    /// ([`crate::Solution::hessian`]), for sensitivities that then do not evaluate it
    /// again. Off by default: it holds one number per entry of the Hessian's pattern
    /// for as long as the solution is kept.
    pub keep_hessian: bool,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            tolerance_n: 1e-9,
            max_iterations: 200,
            max_rotation_step_rad: 0.5,
            max_translation_step: 0.25,
            max_line_search_steps: 40,
            min_damping: 1e-12,
            max_damping: 1e12,
            damping_increase: 8.0,
            damping_decrease: 8.0,
            contact_damping_decrease: 3.0,
            acceptance_ratio: 1e-4,
            trust_ratio: 0.5,
            stagnation_iterations: 12,
            stagnation_reduction: 0.5,
            nested_iteration: true,
            coarse_max_iterations: 40,
            load_continuation: true,
            support_continuation: true,
            stiffness_continuation: true,
            escape_saddles: true,
            mixed_newton: true,
            constraint_curvature: true,
            active_row_penalty: true,
            release_open_rows: false,
            release_retry: true,
            constraint_correction: true,
            follow_on_contact: true,
            escape_min_shift: 0.0,
            max_continuation_steps: 64,
            continuation_first_step: 0.125,
            continuation_smallest_step: 1.0 / 4096.0,
            continuation_easy_iterations: 12,
            continuation_step_iterations: 40,
            stiffness_threshold: 1e3,
            stiffness_soft_ratio: 3.0,
            stiffness_load_ratio: 30.0,
            stiffness_limp_start: true,
            stiffness_first_growth: 1e3,
            stiffness_max_growth: 1e4,
            stiffness_min_growth: 1.5,
            stiffness_step_tolerance: 1e-6,
            stiffness_step_floor_multiple: 100.0,
            stiffness_easy_iterations: 6,
            stiffness_step_iterations: 40,
            stiffness_step_escape_shift: 1e-3,
            constraint_tolerance: 1e-9,
            neutral_tolerance: 1e-11,
            keep_hessian: false,
        }
    }
}

/// An invalid setting.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("solver setting '{field}' = {value}: {requirement}")]
pub struct SettingsError {
    /// The setting's name as in the case file.
    pub field: &'static str,
    /// The given value.
    pub value: f64,
    /// What it must satisfy.
    pub requirement: &'static str,
}

impl SettingsError {
    /// `Ok` when `value` is finite and > 0, else the error of setting `field`.
    pub fn require_positive(field: &'static str, value: f64) -> Result<(), SettingsError> {
        if value.is_finite() && value > 0.0 {
            Ok(())
        } else {
            Err(SettingsError {
                field,
                value,
                requirement: "must be > 0",
            })
        }
    }
}

impl SolverSettings {
    /// Checks every setting.
    pub fn validate(&self) -> Result<(), SettingsError> {
        let check = |field, value: f64, ok: bool, requirement| {
            if value.is_finite() && ok {
                Ok(())
            } else {
                Err(SettingsError {
                    field,
                    value,
                    requirement,
                })
            }
        };
        let positive = |field, value: f64| check(field, value, value > 0.0, "must be > 0");
        positive("tolerance_n", self.tolerance_n)?;
        positive("max_rotation_step_rad", self.max_rotation_step_rad)?;
        positive("max_translation_step", self.max_translation_step)?;
        positive("constraint_tolerance", self.constraint_tolerance)?;
        positive("min_damping", self.min_damping)?;
        positive("neutral_tolerance", self.neutral_tolerance)?;
        positive("stiffness_threshold", self.stiffness_threshold)?;
        positive("stiffness_soft_ratio", self.stiffness_soft_ratio)?;
        positive("stiffness_load_ratio", self.stiffness_load_ratio)?;
        positive("stiffness_step_tolerance", self.stiffness_step_tolerance)?;
        positive(
            "stiffness_step_floor_multiple",
            self.stiffness_step_floor_multiple,
        )?;
        let non_negative = |field, value: f64| check(field, value, value >= 0.0, "must be >= 0");
        non_negative("escape_min_shift", self.escape_min_shift)?;
        non_negative(
            "stiffness_step_escape_shift",
            self.stiffness_step_escape_shift,
        )?;
        check(
            "continuation_first_step",
            self.continuation_first_step,
            self.continuation_first_step > 0.0 && self.continuation_first_step <= 1.0,
            "must be in (0, 1]",
        )?;
        check(
            "continuation_smallest_step",
            self.continuation_smallest_step,
            self.continuation_smallest_step > 0.0
                && self.continuation_smallest_step <= self.continuation_first_step,
            "must be > 0 and <= continuation_first_step",
        )?;
        check(
            "stiffness_min_growth",
            self.stiffness_min_growth,
            self.stiffness_min_growth > 1.0,
            "must be > 1",
        )?;
        check(
            "stiffness_first_growth",
            self.stiffness_first_growth,
            self.stiffness_first_growth >= self.stiffness_min_growth,
            "must be >= stiffness_min_growth",
        )?;
        check(
            "stiffness_max_growth",
            self.stiffness_max_growth,
            self.stiffness_max_growth >= self.stiffness_first_growth,
            "must be >= stiffness_first_growth",
        )?;
        check(
            "max_damping",
            self.max_damping,
            self.max_damping > self.min_damping,
            "must be > min_damping",
        )?;
        for (field, value) in [
            ("damping_increase", self.damping_increase),
            ("damping_decrease", self.damping_decrease),
            ("contact_damping_decrease", self.contact_damping_decrease),
        ] {
            check(field, value, value > 1.0, "must be > 1")?;
        }
        check(
            "acceptance_ratio",
            self.acceptance_ratio,
            self.acceptance_ratio > 0.0 && self.acceptance_ratio < self.trust_ratio,
            "must be > 0 and < trust_ratio",
        )?;
        check(
            "trust_ratio",
            self.trust_ratio,
            self.trust_ratio < 1.0,
            "must be < 1",
        )?;
        check(
            "stagnation_reduction",
            self.stagnation_reduction,
            self.stagnation_reduction > 0.0 && self.stagnation_reduction < 1.0,
            "must be in (0, 1)",
        )?;
        // Counts: at least one, and bounded so that a typo cannot make a solve run
        // for hours.
        for (field, value, max) in [
            ("max_iterations", self.max_iterations, 100_000),
            ("max_line_search_steps", self.max_line_search_steps, 200),
            ("coarse_max_iterations", self.coarse_max_iterations, 100_000),
            ("stagnation_iterations", self.stagnation_iterations, 100_000),
            (
                "max_continuation_steps",
                self.max_continuation_steps,
                10_000,
            ),
            (
                "continuation_easy_iterations",
                self.continuation_easy_iterations,
                100_000,
            ),
            (
                "continuation_step_iterations",
                self.continuation_step_iterations,
                100_000,
            ),
            (
                "stiffness_easy_iterations",
                self.stiffness_easy_iterations,
                100_000,
            ),
            (
                "stiffness_step_iterations",
                self.stiffness_step_iterations,
                100_000,
            ),
        ] {
            if value == 0 || value > max {
                return Err(SettingsError {
                    field,
                    value: value as f64,
                    requirement: match max {
                        200 => "must be in 1..=200",
                        10_000 => "must be in 1..=10000",
                        _ => "must be in 1..=100000",
                    },
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_every_bad_value_names_its_field() {
        assert!(SolverSettings::default().validate().is_ok());
        let cases: Vec<(SolverSettings, &str)> = vec![
            (
                SolverSettings {
                    tolerance_n: f64::NAN,
                    ..Default::default()
                },
                "tolerance_n",
            ),
            (
                SolverSettings {
                    stiffness_max_growth: 10.0,
                    ..Default::default()
                },
                "stiffness_max_growth",
            ),
            (
                SolverSettings {
                    stiffness_min_growth: 1.0,
                    ..Default::default()
                },
                "stiffness_min_growth",
            ),
            (
                SolverSettings {
                    continuation_smallest_step: 0.5,
                    ..Default::default()
                },
                "continuation_smallest_step",
            ),
            (
                SolverSettings {
                    stiffness_step_iterations: 0,
                    ..Default::default()
                },
                "stiffness_step_iterations",
            ),
            (
                SolverSettings {
                    stiffness_soft_ratio: -3.0,
                    ..Default::default()
                },
                "stiffness_soft_ratio",
            ),
            (
                SolverSettings {
                    max_line_search_steps: 1_000_000_000,
                    ..Default::default()
                },
                "max_line_search_steps",
            ),
            (
                SolverSettings {
                    max_damping: 1e-13,
                    ..Default::default()
                },
                "max_damping",
            ),
            (
                SolverSettings {
                    acceptance_ratio: 0.9,
                    ..Default::default()
                },
                "acceptance_ratio",
            ),
            (
                SolverSettings {
                    max_iterations: 0,
                    ..Default::default()
                },
                "max_iterations",
            ),
        ];
        for (settings, field) in cases {
            assert_eq!(settings.validate().unwrap_err().field, field);
        }
    }
}
