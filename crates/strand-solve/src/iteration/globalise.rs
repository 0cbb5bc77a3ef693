//! Globalisation and acceptance of a Newton/SQP step: the trust region in physical
//! units, the ratio of achieved to predicted decrease of the merit function, the
//! second-order correction and the positions-only correction of mispredicted trials,
//! the extension of exact steps and the steps along a direction of negative curvature.

use strand_system::SystemState;

use super::{Iteration, violation_of};
use crate::constraints::{FarVertex, Row, RowKey};
use crate::linear::symmetric_product;
use crate::report::Termination;

/// Fraction of [`Iteration`]'s `valley_turn` beyond which a trial's positions follow
/// its frames (at a tenth, the axial strain it induces costs 1e-4 of the bending).
const FOLLOW_TURN: f64 = 0.1;

/// Relative size of energy differences treated as round-off: below it, a step is
/// accepted when it reduces the residual. The energy is a sum of terms (strain, weight,
/// loads) much larger than itself: measured, a converged clipped hose (0.04 J) shows
/// differences of 5e-13 J along a Newton step of 7e-9 m.
pub(super) const ENERGY_NOISE: f64 = 1e-10;

/// Fraction of a rejected trial's length the trust region shrinks to.
const REJECTED_SHRINK: f64 = 0.25;

/// [`REJECTED_SHRINK`] of an iteration with contact rows: there a rejection mostly
/// means the contact set changed along the step (a vertex reaching or leaving a
/// face), which a shorter step does not model better, so it is halved only (measured
/// on the drop family of `tests/validation/drop.rs`: median 40 → 32 iterations, one
/// case 1085 → 274).
const REJECTED_SHRINK_CONTACT: f64 = 0.5;

/// Lengths tried along a direction of negative curvature (each a quarter of the last).
const NEGATIVE_CURVATURE_TRIALS: usize = 5;

/// [`NEGATIVE_CURVATURE_TRIALS`] with contact rows, where a trial whose energy beats
/// the best also collects its rows and the conservative advancement (a 3247-segment
/// cable on a floor: about 0.2 G instructions each, five of them a sixth of its solve,
/// none taken). On the cable over a rim that needs them the first or second length is
/// taken.
const NEGATIVE_CURVATURE_TRIALS_WITH_ROWS: usize = 2;

impl Iteration<'_> {
    /// Globalisation and acceptance: tries the step scaled into the trust region,
    /// shrinking the region on rejection; adapts the damping and the region to the
    /// ratio of achieved to predicted decrease.
    pub(super) fn globalise(&mut self, residual: f64) -> Result<(), Termination> {
        let settings = self.settings;
        let (rotation, translation) = self.model.step_size(&self.work.step);
        let max_translation = self.max_translation;
        let advance = self.advancement(translation);
        // The multiple of the step that fits into a trust region of `radius`.
        let reach = move |radius: f64| {
            (radius * settings.max_rotation_step_rad / rotation.max(1e-300)).min(radius * advance)
        };
        let fits = move |radius: f64| reach(radius).min(1.0);
        // Whether the translation limits (conservative advancement towards the
        // constraints, the settings' largest move), not the trust region's rotation
        // limit, set the length of the first trial: a step cut there says nothing
        // about the quality of the model, so an accurate one still lowers the damping.
        let advance_bound =
            advance < 1.0 && advance <= settings.max_rotation_step_rad / rotation.max(1e-300);
        // Quadratic model along the step: m(t) = t·gᵀd + ½t²·dᵀHd (undamped H).
        let slope: f64 = self
            .work
            .step
            .iter()
            .zip(&self.work.eval.gradient)
            .map(|(s, g)| s * g)
            .sum();
        let newton_step = self.rows.is_empty() && self.work.model_gradient.is_none();
        let curvature =
            self.work
                .step_curvature(self.model.pattern(), newton_step, self.damping, slope);
        let violation = violation_of(&self.rows);
        let merit = self.work.eval.energy + self.merit_weight * violation;
        // A damped step well inside the trust region (a quarter of it or less) is
        // short because of the damping: only then look for negative curvature.
        let room = reach(self.radius);
        let negative = if room >= 4.0 {
            self.negative_curvature()
        } else {
            None
        };

        let mut trial = self.state.clone();
        let mut trial_rows: Vec<Row> = Vec::new();
        let mut trial_far: Vec<FarVertex> = Vec::new();
        let mut t = fits(self.radius);
        if self.work.model_gradient.is_some()
            && -(t * slope + 0.5 * t * t * curvature) + self.merit_weight * violation * t <= 0.0
        {
            // The augmented model's step goes uphill in the merit: no shorter trial
            // of it can be accepted (every ratio would be 0); step with the plain
            // model instead (`run`).
            if self.trace {
                eprintln!(
                    "strand-solve: iteration {:3}: the augmented model's step ascends; plain step",
                    self.report.iterations
                );
            }
            self.ascent = true;
            return Err(Termination::LineSearchFailed);
        }
        // The second-order correction of the first trial (at `first_t`), once computed:
        // shorter trials follow the parabola `t·d + (t/first_t)²·c`.
        let first_t = t;
        let mut correction: Option<Vec<f64>> = None;
        // Whether a positions-only correction overwrote this iteration's factor.
        let mut factor_lost = false;
        let mut attempt = 0;
        while attempt <= settings.max_line_search_steps {
            let full = attempt == 0;
            self.step_at_limit = full && advance_bound;
            // The quadratic model's decrease along the trial's step (energy only).
            let mut model_decrease = -(t * slope + 0.5 * t * t * curvature);
            if let Some(c) = &correction {
                let bent = curved_step(&self.work.step, t, c, (t / first_t).powi(2));
                model_decrease = -self.quadratic_model(&bent);
                self.model.retract_into(&self.state, &bent, 1.0, &mut trial);
            } else {
                self.model
                    .retract_into(&self.state, &self.work.step, t, &mut trial);
            }
            // Whether `work.trial_eval` holds the trial's energy and gradient (its
            // Hessian is assembled only when a correction or the next iteration needs
            // it: `has_hessian`).
            let mut evaluated = full;
            // A stiff rod's positions follow a large turn of its frames (below), and
            // that correction needs the trial's Hessian; so does the next iteration,
            // unless mixed Newton evaluates it again with the predicted stresses.
            let turned = self.stiff && t * rotation > FOLLOW_TURN * self.valley_turn;
            let mixed = settings.mixed_newton && self.stiff;
            let mut energy = if full {
                let with_hessian = !mixed || (turned && self.rows.is_empty());
                self.model
                    .evaluate(&trial, &mut self.work.trial_eval, with_hessian);
                self.work.trial_eval.energy
            } else {
                self.model.energy(&trial)
            };
            // A stiff rod's positions follow its frames when the turn is large
            // enough to strain it at second order (the positions moved along
            // straight lines), or when the model mispredicted the step.
            // Not judged in the round-off regime, where both the model's decrease and
            // the energy's are noise (a correction there only changes the energy in its
            // tenth digit and costs two Hessians and a factorisation).
            let surprising = self.work.eval.energy - energy < settings.trust_ratio * model_decrease
                && !within_noise(self.work.eval.energy, energy, model_decrease);
            if self.rows.is_empty() {
                if full && surprising {
                    // The second-order correction: the remainder of the gradient at the
                    // trial beyond the model, solved with this iteration's factor.
                    if let Some((bent, c)) = self.second_order_correction(t) {
                        let bent_energy = self.model.energy(&bent);
                        if self.trace {
                            eprintln!(
                                "strand-solve:   second-order correction: energy {bent_energy:.9e} J (straight trial {energy:.9e} J)"
                            );
                        }
                        if bent_energy < energy {
                            model_decrease =
                                -self.quadratic_model(&curved_step(&self.work.step, t, &c, 1.0));
                            trial = bent;
                            energy = bent_energy;
                            evaluated = false;
                            correction = Some(c);
                        }
                    }
                }
                if surprising || turned {
                    energy = self.follow(&mut trial, &mut evaluated);
                }
            } else if settings.follow_on_contact && (surprising || turned) {
                // The same with contact rows: the positions follow under the rows.
                energy = self.follow_on_rows(&mut trial, &mut evaluated);
                factor_lost = true;
            }
            let admissible = self.collect_rows(&trial, &mut trial_rows, &mut trial_far);
            let trial_merit = if admissible {
                energy + self.merit_weight * violation_of(&trial_rows)
            } else {
                f64::INFINITY
            };
            // The linearised rows close the violation in proportion to t.
            let predicted = model_decrease + self.merit_weight * violation * t;
            let achieved = merit - trial_merit;
            let noise = ENERGY_NOISE * self.work.eval.energy.abs().max(energy.abs()).max(1e-12);
            let mut accepted = trial_merit.is_finite()
                && predicted > 0.0
                && achieved >= settings.acceptance_ratio * predicted;
            let ratio = if predicted > 0.0 {
                achieved / predicted
            } else {
                0.0
            };
            // Round-off regime: merit differences are noise; accept a step that
            // reduces the residual.
            if !accepted
                && trial_merit.is_finite()
                && achieved.abs() <= noise
                && predicted.abs() <= noise
            {
                if !evaluated {
                    self.model
                        .evaluate(&trial, &mut self.work.trial_eval, false);
                }
                let (trial_residual, _) = self.kkt(&trial_rows, &self.work.trial_eval.gradient);
                accepted = trial_residual.combined_n < residual;
                if accepted {
                    if !self.work.trial_eval.has_hessian {
                        self.model.evaluate(&trial, &mut self.work.trial_eval, true);
                    }
                    self.accept(trial, trial_rows, trial_far, t, 1.0, None);
                    return Ok(());
                }
            }
            if self.trace {
                eprintln!(
                    "strand-solve: iteration {:3} trial {attempt}: residual {residual:.3e} N, energy {:.9e} J, damping {:.1e}, radius {:.2e}, t {t:.2e}, ratio {ratio:.3}, rotation {rotation:.2e} rad, translation {translation:.2e} m, advance {advance:.2e}, rows {}",
                    self.report.iterations,
                    self.work.eval.energy,
                    self.damping,
                    self.radius,
                    self.rows.len()
                );
            }
            if full
                && !accepted
                && !self.rows.is_empty()
                && trial_merit.is_finite()
                && predicted > 0.0
                && settings.constraint_correction
                && (!factor_lost || self.refactor())
                && let Some((corrected, corrected_rows, corrected_far, corrected_energy)) =
                    self.constraint_correction(&trial, &trial_rows, t)
            {
                // The rows' second-order correction: the trial projected back onto the
                // rows held (and any it violates), in the metric of this iteration's
                // factor. A curved gap (a hose sliding over a ridge or a pipe) is
                // violated at second order by a step that satisfied its linearisation,
                // and the exact penalty rejects the step for it (the Maratos effect).
                let corrected_merit =
                    corrected_energy + self.merit_weight * violation_of(&corrected_rows);
                let corrected_achieved = merit - corrected_merit;
                if self.trace {
                    eprintln!(
                        "strand-solve:   constraint correction: merit {corrected_merit:.9e} J (trial {trial_merit:.9e} J, from {merit:.9e} J)"
                    );
                }
                if corrected_achieved >= settings.acceptance_ratio * predicted {
                    self.model
                        .evaluate(&corrected, &mut self.work.trial_eval, true);
                    self.accept(
                        corrected,
                        corrected_rows,
                        corrected_far,
                        t,
                        corrected_achieved / predicted,
                        None,
                    );
                    return Ok(());
                }
            }
            if full && let Some(v) = &negative {
                // Along a direction of negative curvature the damped step is short;
                // the step plus that direction, scaled to the trust region, often
                // falls much further (the trust-region step of the indefinite case).
                let (v_rotation, v_translation) = self.model.step_size(v);
                let reach = (self.radius * settings.max_rotation_step_rad / v_rotation.max(1e-300))
                    .min(self.radius * max_translation / v_translation.max(1e-300));
                let descent: f64 = v
                    .iter()
                    .zip(&self.work.eval.gradient)
                    .map(|(a, g)| a * g)
                    .sum();
                let sense = if descent > 0.0 { -1.0 } else { 1.0 };
                let best_so_far = if accepted { trial_merit } else { merit };
                // From the whole region down: the turn along `v` strains a rod held at
                // both ends at second order, so its useful length is not known.
                let mut length = reach;
                let trials = if self.rows.is_empty() {
                    NEGATIVE_CURVATURE_TRIALS
                } else {
                    NEGATIVE_CURVATURE_TRIALS_WITH_ROWS
                };
                for _ in 0..trials {
                    let combined: Vec<f64> = self
                        .work
                        .step
                        .iter()
                        .zip(v)
                        .map(|(d, vi)| t * d + sense * length * vi)
                        .collect();
                    let mut bent = self.model.retract(&self.state, &combined);
                    // A large turn moved the positions along straight lines: let them
                    // follow the frames (the axial strain of a stiff rod would reject
                    // it). The trial's evaluation is kept aside meanwhile.
                    std::mem::swap(&mut self.work.trial_eval, &mut self.work.spare_eval);
                    let mut bent_evaluated = false;
                    let bent_energy = if self.stiff {
                        self.follow(&mut bent, &mut bent_evaluated)
                    } else {
                        self.model.energy(&bent)
                    };
                    std::mem::swap(&mut self.work.trial_eval, &mut self.work.spare_eval);
                    // With rows: the merit at the trial's own rows, and only a trial
                    // the conservative advancement reaches (no edge through a mesh on
                    // the way). Neither is needed when the energy alone does not beat
                    // the best (the merit is never below it).
                    let (mut bent_rows, mut bent_far) = (Vec::new(), Vec::new());
                    let bent_merit = if self.rows.is_empty() {
                        bent_energy
                    } else if bent_energy.partial_cmp(&best_so_far)
                        != Some(std::cmp::Ordering::Less)
                    {
                        f64::INFINITY
                    } else if self.constraints.is_some_and(|c| {
                        c.advancement(self.model, &self.state, &bent)
                            .is_ok_and(|a| a >= 1.0)
                    }) && self.collect_rows(&bent, &mut bent_rows, &mut bent_far)
                    {
                        bent_energy + self.merit_weight * violation_of(&bent_rows)
                    } else {
                        f64::INFINITY
                    };
                    if self.trace {
                        eprintln!(
                            "strand-solve:   negative-curvature trial: merit {bent_merit:.9e} J, length {length:.2e} (reach {reach:.2e})"
                        );
                    }
                    if bent_merit.is_finite() && bent_merit < best_so_far {
                        self.model.evaluate(&bent, &mut self.work.trial_eval, true);
                        let ratio = if predicted > 0.0 {
                            (merit - bent_merit) / predicted
                        } else {
                            1.0
                        };
                        self.accept(
                            bent,
                            bent_rows,
                            bent_far,
                            t,
                            ratio.min(1.0),
                            Some(&combined),
                        );
                        return Ok(());
                    }
                    length *= 0.25;
                }
            }
            if accepted {
                let short = self.damping > 0.0;
                if full && short && t >= 1.0 && ratio > 0.9 && room >= 2.0 && self.rows.is_empty() {
                    // The model is exact and the step well inside the region (a damped
                    // step along negative curvature): extend it while the energy falls.
                    // An undamped step on a positive definite Hessian already ends at
                    // the model's minimum along it (the model at twice the step is back
                    // at the current energy), so it is not tried.
                    let (mut best_t, mut best_energy) = (t, trial_merit);
                    let mut longer = trial.clone();
                    let mut scale = 2.0;
                    while scale <= room {
                        self.model
                            .retract_into(&self.state, &self.work.step, scale, &mut longer);
                        let energy = if self.stiff {
                            std::mem::swap(&mut self.work.trial_eval, &mut self.work.spare_eval);
                            let mut e = false;
                            let energy = self.follow(&mut longer, &mut e);
                            std::mem::swap(&mut self.work.trial_eval, &mut self.work.spare_eval);
                            energy
                        } else {
                            self.model.energy(&longer)
                        };
                        if energy.partial_cmp(&best_energy) != Some(std::cmp::Ordering::Less) {
                            break;
                        }
                        (best_t, best_energy) = (scale, energy);
                        scale *= 2.0;
                    }
                    if self.trace {
                        eprintln!("strand-solve:   extended to t {best_t:.2e} (room {room:.2e})");
                    }
                    if best_t > t {
                        t = best_t;
                        self.model
                            .retract_into(&self.state, &self.work.step, best_t, &mut trial);
                        let mut e = false;
                        if self.stiff {
                            self.follow(&mut trial, &mut e);
                        }
                        self.model.evaluate(&trial, &mut self.work.trial_eval, true);
                        self.collect_rows(&trial, &mut trial_rows, &mut trial_far);
                    }
                }
                // With mixed Newton, `accept` evaluates the trial itself (with the
                // predicted stresses); otherwise its Hessian is the next iteration's.
                let has_hessian = evaluated && self.work.trial_eval.has_hessian;
                if !(mixed || has_hessian) {
                    self.model.evaluate(&trial, &mut self.work.trial_eval, true);
                }
                let taken = match &correction {
                    Some(c) => curved_step(&self.work.step, t, c, (t / first_t).powi(2)),
                    None => self.work.step.iter().map(|d| t * d).collect(),
                };
                self.accept(trial, trial_rows, trial_far, t, ratio, Some(&taken));
                return Ok(());
            }
            // Rejected: shrink the region (to at most a fraction of the tried step).
            let contact = self
                .rows
                .iter()
                .any(|r| matches!(r.key, RowKey::Contact(_)));
            let shrink = if contact {
                REJECTED_SHRINK_CONTACT
            } else {
                REJECTED_SHRINK
            };
            let next = after_rejection(
                Region {
                    radius: self.radius,
                    t,
                    attempt,
                },
                reach,
                shrink,
                !full,
                settings.max_line_search_steps,
            );
            (self.radius, t, attempt) = (next.radius, next.t, next.attempt);
        }
        Err(Termination::LineSearchFailed)
    }

    /// The second-order correction of the trial `retract(state, t·step)` (whose
    /// gradient is in `work.trial_eval`): `c = −K⁻¹ (ĝ(t·d) − g − t·H d)` with this
    /// iteration's factor `K`, `ĝ` the trial's gradient pulled back to the current
    /// chart. It bends the step along a curved valley (a rod turning as a whole moves
    /// its vertices on circles, not on the tangent lines of the linear step). Returns
    /// the corrected trial and `c`; `None` when `c` is larger than the step itself (the
    /// expansion does not hold).
    fn second_order_correction(&mut self, t: f64) -> Option<(SystemState, Vec<f64>)> {
        let work = &mut *self.work;
        // `work.product` may hold the product with a direction of negative curvature.
        symmetric_product(
            self.model.pattern(),
            &work.eval.hessian,
            &work.step,
            &mut work.product,
        );
        work.rhs.copy_from_slice(&work.trial_eval.gradient);
        self.model.pull_back_gradient(&work.step, t, &mut work.rhs);
        for ((r, g), hd) in work
            .rhs
            .iter_mut()
            .zip(&work.eval.gradient)
            .zip(&work.product)
        {
            *r -= g + t * hd;
        }
        work.gauge.fix_vector(&mut work.rhs);
        work.cholesky.solve_in_place(&mut work.rhs);
        let c: Vec<f64> = work.rhs.iter().map(|r| -r).collect();
        let (c_rotation, c_translation) = self.model.step_size(&c);
        let (rotation, translation) = self.model.step_size(&work.step);
        if c_rotation > t * rotation && c_translation > t * translation {
            return None;
        }
        let bent = curved_step(&work.step, t, &c, 1.0);
        Some((self.model.retract(&self.state, &bent), c))
    }

    /// The rows' second-order correction of a rejected `trial` (at `t` times the step)
    /// with its `rows`: the least change `c` in the metric of this iteration's factor
    /// `K` that closes the rows held in this step (and every row violated at the trial)
    /// to first order at the trial, `min ½ cᵀKc s.t. value_i + a_i·c ≥ 0` (the exact
    /// step of [`crate::sqp`] with a zero gradient). Returns the corrected state, its
    /// rows and its energy; `None` when there is nothing to correct, the correction is
    /// not smaller than the step, or the corrected state is not admissible.
    fn constraint_correction(
        &mut self,
        trial: &SystemState,
        rows: &[Row],
        t: f64,
    ) -> Option<(SystemState, Vec<Row>, Vec<FarVertex>, f64)> {
        let held: Vec<usize> = (0..rows.len())
            .filter(|&i| self.multiplier(rows[i].key) > 0.0 || rows[i].value < 0.0)
            .collect();
        if held.is_empty() {
            return None;
        }
        let zero = vec![0.0; self.work.step.len()];
        let corrected = crate::sqp::exact_step_of_independent_rows(
            &mut self.work.cholesky,
            rows,
            &held,
            &zero,
        )?;
        let c = corrected.step;
        let (c_rotation, c_translation) = self.model.step_size(&c);
        let (rotation, translation) = self.model.step_size(&self.work.step);
        if c_rotation > t * rotation && c_translation > t * translation {
            return None;
        }
        let state = self.model.retract(trial, &c);
        let (mut state_rows, mut state_far) = (Vec::new(), Vec::new());
        if !self.collect_rows(&state, &mut state_rows, &mut state_far) {
            return None;
        }
        let energy = self.model.energy(&state);
        Some((state, state_rows, state_far, energy))
    }

    /// The quadratic model `gᵀp + ½ pᵀHp` (J) of the energy change along `p`.
    fn quadratic_model(&self, p: &[f64]) -> f64 {
        let mut product = vec![0.0; p.len()];
        symmetric_product(
            self.model.pattern(),
            &self.work.eval.hessian,
            p,
            &mut product,
        );
        p.iter()
            .zip(&self.work.eval.gradient)
            .zip(&product)
            .map(|((p, g), hp)| p * g + 0.5 * p * hp)
            .sum()
    }

    /// The multiple of the step allowed by the translation limits: the settings' limit
    /// on the largest vertex move (`translation`, m, at the full step) and the
    /// conservative advancement of the constraints (the clearance of every moving
    /// edge); the blind limit where the clearance cannot be measured.
    fn advancement(&self, translation: f64) -> f64 {
        let settings_limit = self.free_translation / translation.max(1e-300);
        let Some(constraints) = self.constraints else {
            return settings_limit;
        };
        let target = self.model.retract(&self.state, &self.work.step);
        match constraints.advancement(self.model, &self.state, &target) {
            Ok(advance) => settings_limit.min(advance),
            Err(_) => self.max_translation / translation.max(1e-300),
        }
    }

    /// Lets the positions of `trial` follow its frames: replaces it by the positions-only
    /// correction ([`Iteration::relax_positions`]) when that lowers the energy. Returns
    /// the energy of `trial`; `evaluated` says whether `work.trial_eval` holds its
    /// energy and gradient (on entry and on return; the Hessian, which the correction
    /// needs, is assembled here if missing, and not for a relaxed trial).
    fn follow(&mut self, trial: &mut SystemState, evaluated: &mut bool) -> f64 {
        if !*evaluated || !self.work.trial_eval.has_hessian {
            self.model.evaluate(trial, &mut self.work.trial_eval, true);
            *evaluated = true;
        }
        let energy = self.work.trial_eval.energy;
        if let Some(relaxed) = self.relax_positions(trial) {
            let relaxed_energy = self.model.energy(&relaxed);
            if relaxed_energy < energy {
                *trial = relaxed;
                self.model.evaluate(trial, &mut self.work.trial_eval, false);
                return self.work.trial_eval.energy;
            }
        }
        energy
    }

    /// Positions-only correction: at fixed frames the rod energy is quadratic in the
    /// positions (strains are linear in them), so one Newton step on the positions
    /// alone, with the Hessian at `trial` (`work.trial_eval`), removes the axial and
    /// shear strain that a finite rotation of the frames induced. `None` when that
    /// block is not positive definite (a body or clip couples positions to rotations).
    /// Overwrites the factor of this iteration (the step is already computed).
    fn relax_positions(&mut self, trial: &SystemState) -> Option<SystemState> {
        if !self.work.positions_only_step(self.model.pattern()) {
            return None;
        }
        Some(self.model.retract(trial, &self.work.rhs))
    }

    /// Moves to an accepted trial and adapts damping and trust radius. `taken` is the
    /// chart step from the current state whose linearisation predicts the trial's edge
    /// stresses (mixed Newton; `None`: the trial's own stresses).
    fn accept(
        &mut self,
        trial: SystemState,
        rows: Vec<Row>,
        far: Vec<FarVertex>,
        t: f64,
        ratio: f64,
        taken: Option<&[f64]>,
    ) {
        let settings = self.settings;
        let stresses = match taken {
            Some(step) if settings.mixed_newton && self.stiff => {
                let linear = self.model.retract(&self.state, step);
                Some(self.model.linearised_edge_stresses(&self.state, &linear))
            }
            _ => None,
        };
        self.state = trial;
        self.rows = rows;
        self.far = far;
        std::mem::swap(&mut self.work.eval, &mut self.work.trial_eval);
        match &stresses {
            Some(stresses) => self
                .model
                .evaluate_mixed(&self.state, &mut self.work.eval, stresses),
            None => assert!(self.work.eval.has_hessian, "accepted without a Hessian"),
        }
        self.mixed_hessian = stresses.is_some();
        let full_step = t >= 1.0 || self.step_at_limit;
        self.try_undamped =
            full_step && (super::EXACT_RATIO..=1.0 / super::EXACT_RATIO).contains(&ratio);
        if ratio >= settings.trust_ratio {
            self.radius = (self.radius * 2.0).min(1.0);
            if full_step {
                let contact = self
                    .rows
                    .iter()
                    .any(|r| matches!(r.key, RowKey::Contact(_)));
                self.damping /= if contact {
                    settings.contact_damping_decrease
                } else {
                    settings.damping_decrease
                };
                if self.damping < settings.min_damping {
                    self.damping = 0.0;
                }
            }
        } else {
            self.damping = (self.damping * settings.damping_increase).max(settings.min_damping);
        }
    }
}

/// `t·step + w·correction`: a point on the parabola of a corrected step.
fn curved_step(step: &[f64], t: f64, correction: &[f64], w: f64) -> Vec<f64> {
    step.iter()
        .zip(correction)
        .map(|(d, c)| t * d + w * c)
        .collect()
}

/// Whether the energy change from `before` to `after` (J) and the model's predicted
/// decrease `predicted` (J) are both round-off ([`ENERGY_NOISE`] of the energy).
fn within_noise(before: f64, after: f64, predicted: f64) -> bool {
    let noise = ENERGY_NOISE * before.abs().max(after.abs()).max(1e-12);
    (before - after).abs() <= noise && predicted.abs() <= noise
}

/// The trust region's `radius`, the trial's multiple `t` of the step and the attempt
/// counter of a line search.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Region {
    radius: f64,
    t: f64,
    attempt: usize,
}

/// The region and next trial after the trial at `region.t` was rejected, for a step of
/// which `reach(radius)` times fit into a region of `radius`: the region shrinks to `shrink`
/// of itself, and to at most `shrink` of the radius the tried step fits; the next trial
/// is the multiple of the step that fits (at most 1).
///
/// A trial after the first is decided on its energy alone (no corrections), so with
/// `repeats_rejected` one the region did not shorten — a step much shorter than the
/// region stays whole while the region halves — would be the rejected trial again: the
/// region shrinks on without evaluating it, each shrink counted as an attempt (up to
/// `max_attempt`), so the attempts, the region and the next trial are those of
/// evaluating it. On the 94,500-facet drum one iteration evaluated one trial 17 times
/// while the region halved from 1 to 1e-5.
fn after_rejection(
    region: Region,
    reach: impl Fn(f64) -> f64,
    shrink: f64,
    repeats_rejected: bool,
    max_attempt: usize,
) -> Region {
    let fits = |radius: f64| reach(radius).min(1.0);
    let step = |r: Region| {
        let radius = (r.radius * shrink).min(shrink * r.t / fits(1.0).max(1e-300));
        Region {
            radius,
            t: fits(radius),
            attempt: r.attempt + 1,
        }
    };
    let mut next = step(region);
    while repeats_rejected && next.t == region.t && next.attempt <= max_attempt {
        next = step(next);
    }
    next
}

#[cfg(test)]
mod tests {
    use super::{Region, after_rejection};

    /// The old rule, one rejected evaluation per attempt.
    fn evaluating_every_attempt(mut region: Region, unit_reach: f64, shrink: f64) -> Region {
        let tried = region.t;
        while region.t == tried {
            region = after_rejection(region, |r| r * unit_reach, shrink, false, usize::MAX);
        }
        region
    }

    #[test]
    fn a_repeated_rejected_trial_is_skipped_with_the_region_and_attempts_of_evaluating_it() {
        // A step 1e5 times shorter than the unit region: t stays 1 while the region
        // halves from 1 to below 1e-5 (17 halvings), then the trial shortens.
        let start = Region {
            radius: 1.0,
            t: 1.0,
            attempt: 1,
        };
        let skipped = after_rejection(start, |r| r * 1e5, 0.5, true, 40);
        let evaluated = evaluating_every_attempt(start, 1e5, 0.5);
        assert_eq!(skipped, evaluated);
        assert!(skipped.t < 1.0, "{skipped:?}");
        assert_eq!(skipped.attempt, 1 + 17, "{skipped:?}");
        // After the first trial (full evaluation, corrections) nothing is skipped: the
        // same `t` is evaluated again on its energy alone.
        let once = after_rejection(start, |r| r * 1e5, 0.5, false, 40);
        assert_eq!((once.t, once.attempt), (1.0, 2));
        // A step that fills the region shortens at once: the rules agree.
        let filling = Region {
            radius: 1.0,
            t: 1.0,
            attempt: 1,
        };
        assert_eq!(
            after_rejection(filling, |r| r, 0.25, true, 40),
            after_rejection(filling, |r| r, 0.25, false, 40)
        );
        // The attempts stop at the limit, as evaluating them would.
        let limited = after_rejection(start, |r| r * 1e5, 0.5, true, 5);
        assert_eq!((limited.t, limited.attempt), (1.0, 6));
    }
}
