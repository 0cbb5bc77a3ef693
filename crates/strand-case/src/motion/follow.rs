//! Quasi-static path following along a motion: from the case's own pose (parameter 0)
//! up to the largest and down to the smallest requested value, each step
//! warm-started from the last equilibrium with a predictor ([`Predictor`]; the secant
//! and its blend with the tangent are
//! [`strand_solve::continuation::predictor::extrapolate`]), the step halved
//! when a solve fails or the state jumps, and grown again on easy steps.
//!
//! A jump that persists down to the smallest step is a snap-through (the equilibrium
//! branch ended and the hose jumped to another one): it is reported as a
//! [`MotionEvent::SnapThrough`], never taken silently. A step that still fails at the
//! smallest step ends that direction of the motion ([`FollowEnd::failed`]).

use strand_solve::{Solution, SolveError, SolverSettings};
use strand_system::SystemState;

use crate::error::CaseError;
use crate::{BuiltCase, Case};
use strand_solve::continuation::predictor::extrapolate;

/// Settings of the path following.
#[derive(Clone, Debug, PartialEq)]
pub struct FollowSettings {
    /// The smallest step, as a fraction of the requested step (default 1/64).
    pub smallest_fraction: f64,
    /// A step whose largest vertex displacement per parameter unit exceeds this
    /// multiple of the previous step's is suspected of a jump and retried at half
    /// size (default 4).
    pub jump_ratio: f64,
    /// A step suspected of a jump at the smallest step is a snap-through only if its
    /// largest vertex displacement also exceeds this, m (default 1e-3).
    pub jump_floor_m: f64,
    /// Steps that take at most this many Newton iterations double the next step,
    /// up to the requested step (default 3).
    pub easy_iterations: usize,
    /// The first step of each direction, as a fraction of the requested step (default
    /// 1/8): small, so that the rate a jump is measured against is known early.
    pub first_fraction: f64,
    /// Whether a step whose last state starts inside a moving mesh is retried with the
    /// hose near the moving meshes carried along with them (default;
    /// [`super::carry`]).
    pub carry: bool,
    /// Where each step starts (default [`Predictor::Secant`]: on the engine roll the
    /// tangent saves a quarter of the Newton iterations but costs more than they do).
    pub predictor: Predictor,
}

/// Where a step of the path following starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Predictor {
    /// The last equilibrium.
    Last,
    /// The secant extrapolation of the last two equilibria (the last one alone on the
    /// first step of a direction).
    Secant,
    /// The exact tangent of the path at the last equilibrium
    /// ([`strand_solve::sensitivity`], the motion parameter as the design parameter),
    /// combined with the previous equilibrium into a second-order prediction (the
    /// tangent's prediction extrapolated beyond the secant's by the step ratio: the
    /// errors of the secant, `(Δ² + Δh) x''/2`, and of the tangent, `Δ² x''/2`,
    /// cancel); the secant where the tangent cannot be computed (an unstable state, an
    /// active contact about to open).
    Tangent,
}

impl Default for FollowSettings {
    fn default() -> Self {
        Self {
            smallest_fraction: 1.0 / 64.0,
            jump_ratio: 4.0,
            jump_floor_m: 1e-3,
            easy_iterations: 3,
            first_fraction: 1.0 / 8.0,
            carry: true,
            predictor: Predictor::Secant,
        }
    }
}

/// Something that happened between two steps of a motion.
#[derive(Clone, Debug, PartialEq)]
pub enum MotionEvent {
    /// The state jumped between parameters `from` and `to` (at the smallest step): the
    /// largest vertex displacement was `jump_m`, m.
    SnapThrough {
        /// Last value before the jump.
        from: f64,
        /// First value after it.
        to: f64,
        /// Largest vertex displacement of the jump, m.
        jump_m: f64,
    },
    /// The equilibrium stopped being stable at `at` (directions of negative
    /// curvature).
    StabilityLost {
        /// Parameter value.
        at: f64,
        /// Directions of negative curvature.
        negative_directions: usize,
    },
    /// The equilibrium became stable again at `at`.
    StabilityRegained {
        /// Parameter value.
        at: f64,
    },
}

/// One requested pose, solved.
#[derive(Clone, Debug)]
pub struct MotionStep {
    /// Parameter value, in the motion's unit.
    pub value: f64,
    /// The case built at this pose.
    pub built: BuiltCase,
    /// Its solution.
    pub solution: Solution,
    /// Whether the solve was warm-started from a neighbouring pose (all but the
    /// case's own pose).
    pub warm: bool,
    /// Solves (accepted and rejected) taken since the previous requested pose.
    pub solves: usize,
    /// Newton iterations of those solves.
    pub iterations: usize,
    /// Of those solves, how many started from the tangent prediction.
    pub tangent_starts: usize,
    /// Events found since the previous requested pose.
    pub events: Vec<MotionEvent>,
}

/// Why a direction of the motion ended early.
#[derive(Clone, Debug, PartialEq)]
pub struct StepOutcome {
    /// The last value reached (solved).
    pub reached: f64,
    /// The value that could not be solved.
    pub value: f64,
    /// Why.
    pub reason: String,
}

/// How the path following ended.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FollowEnd {
    /// The directions that ended early (at most one per direction).
    pub failed: Vec<StepOutcome>,
    /// Where the time went (wall clock, s), over the whole path following.
    pub times: PhaseTimes,
}

/// Wall-clock time (s) spent in each phase of the path following.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhaseTimes {
    /// Building the case at each pose (warm builds: no guesses).
    pub build_s: f64,
    /// Solving (predictors included).
    pub solve_s: f64,
    /// Computing the path's tangents ([`Predictor::Tangent`]).
    pub tangent_s: f64,
}

/// Accumulates [`PhaseTimes`] through shared references.
#[derive(Default)]
struct Clock {
    build: std::cell::Cell<f64>,
    solve: std::cell::Cell<f64>,
    tangent: std::cell::Cell<f64>,
}

impl Clock {
    /// Runs `f`, adding its wall time to `slot`.
    fn time<T>(slot: &std::cell::Cell<f64>, f: impl FnOnce() -> T) -> T {
        let started = std::time::Instant::now();
        let out = f();
        slot.set(slot.get() + started.elapsed().as_secs_f64());
        out
    }

    fn totals(&self) -> PhaseTimes {
        PhaseTimes {
            build_s: self.build.get(),
            solve_s: self.solve.get(),
            tangent_s: self.tangent.get(),
        }
    }
}

/// Largest distance between corresponding vertices of two states of one model, m.
pub fn jump_m(a: &SystemState, b: &SystemState) -> f64 {
    a.rods
        .iter()
        .zip(&b.rods)
        .flat_map(|(p, q)| p.positions.iter().zip(&q.positions))
        .map(|(x, y)| (x - y).norm())
        .fold(0.0, f64::max)
}

/// A solved point of the path.
struct Point {
    value: f64,
    state: SystemState,
    stable: bool,
    /// The path's tangent there (solver chart at `state`, per parameter unit), if
    /// computed.
    tangent: Option<Vec<f64>>,
}

/// Follows motion `motion` of `case` through `values` (the motion's unit, any order):
/// the case's pose is solved cold, then each direction is followed outwards from it.
/// `on_step` gets every requested value in the order solved: 0 first if requested,
/// then upwards, then downwards. Every requested pose is built (and checked) before
/// any solve, so a value outside the keyframes or a pose the case cannot be built at
/// is an error before anything is solved.
pub fn follow(
    case: &Case,
    motion: &str,
    values: &[f64],
    step: f64,
    segments: Option<usize>,
    settings: &FollowSettings,
    on_step: &mut dyn FnMut(MotionStep),
) -> Result<FollowEnd, CaseError> {
    let clock = Clock::default();
    let mut built: Vec<(f64, BuiltCase)> = Vec::with_capacity(values.len() + 1);
    let base = Clock::time(&clock.build, || case.build_motion(motion, 0.0, segments))?;
    let unit = case.motion(motion)?.unit;
    for &v in values {
        // Warm builds: the guess is never used (each pose starts from its neighbour).
        let b = Clock::time(&clock.build, || {
            case.build_motion_from(motion, v, segments, &base.initial)
        })?;
        built.push((v, b));
    }
    let cold = Clock::time(&clock.solve, || {
        base.solve_from(base.initial.clone(), &base.settings)
    })
    .map_err(|e| solve_error(&base, e))?;
    let mut end = FollowEnd::default();
    if !cold.report.converged {
        end.failed.push(StepOutcome {
            reached: f64::NAN,
            value: 0.0,
            reason: format!(
                "the case's own pose did not converge ({:?}, residual {:.3e} N after {} iterations)",
                cold.report.termination, cold.report.residual.combined_n, cold.report.iterations
            ),
        });
        end.times = clock.totals();
        return Ok(end);
    }
    let tangent_at = |value: f64, solution: &Solution| match settings.predictor {
        Predictor::Tangent => Clock::time(&clock.tangent, || {
            super::tangent::tangent(case, motion, &unit, value, segments, solution)
        }),
        _ => None,
    };
    let start = Point {
        value: 0.0,
        state: cold.state.clone(),
        stable: cold.report.stable,
        tangent: tangent_at(0.0, &cold),
    };
    let mut upward: Vec<(f64, BuiltCase)> = Vec::new();
    let mut downward: Vec<(f64, BuiltCase)> = Vec::new();
    for (v, b) in built {
        if v == 0.0 {
            on_step(MotionStep {
                value: 0.0,
                built: b,
                solution: cold.clone(),
                warm: false,
                solves: 1,
                iterations: cold.report.iterations,
                tangent_starts: 0,
                events: Vec::new(),
            });
        } else if v > 0.0 {
            upward.push((v, b));
        } else {
            downward.push((v, b));
        }
    }
    upward.sort_by(|a, b| a.0.total_cmp(&b.0));
    downward.sort_by(|a, b| b.0.total_cmp(&a.0));
    let step = step.abs();
    for (targets, direction) in [(upward, 1.0), (downward, -1.0)] {
        let mut branch = Branch {
            case,
            motion,
            segments,
            settings,
            largest: step,
            smallest: step * settings.smallest_fraction,
            previous: None,
            rate_m: None,
            tangent_at: &tangent_at,
            clock: &clock,
        };
        let last = Point {
            value: start.value,
            state: start.state.clone(),
            stable: start.stable,
            tangent: start.tangent.clone(),
        };
        if let Some(failed) = branch.run(last, targets, direction, on_step)? {
            end.failed.push(failed);
        }
    }
    end.times = clock.totals();
    Ok(end)
}

fn solve_error(built: &BuiltCase, e: strand_solve::SolveError) -> CaseError {
    CaseError::Invalid {
        origin: built.origin.clone(),
        item: "motion".to_string(),
        message: format!("the solver could not start: {e}"),
        hint: "check the case with `strand check`".to_string(),
    }
}

/// One direction of the path following.
struct Branch<'a> {
    case: &'a Case,
    motion: &'a str,
    segments: Option<usize>,
    settings: &'a FollowSettings,
    largest: f64,
    smallest: f64,
    /// The point before the last one, for the predictor.
    previous: Option<Point>,
    /// Largest vertex displacement per parameter unit of the last accepted step, m.
    rate_m: Option<f64>,
    /// The path's tangent at a converged pose, if the predictor uses it.
    tangent_at: &'a dyn Fn(f64, &Solution) -> Option<Vec<f64>>,
    clock: &'a Clock,
}

/// A solve of one attempted step, and whether it started from the tangent.
struct Attempt {
    solution: Solution,
    from_tangent: bool,
}

impl Branch<'_> {
    /// One solve of the case built at `value`, warm-started from `last` with the
    /// predictor. A start inside an obstacle (the predictor pushed a resting hose into
    /// it, or a moving part moved into the hose) is retried from the last state, then
    /// from the last state with the hose near the moving meshes carried along
    /// ([`super::carry::carry`]); `Err(reason)` if that starts inside too.
    fn attempt(
        &self,
        built: &BuiltCase,
        last: &Point,
        value: f64,
    ) -> Result<Result<Attempt, String>, CaseError> {
        let change = value - last.value;
        let secant = self
            .previous
            .as_ref()
            .filter(|_| self.settings.predictor != Predictor::Last)
            .map(|p| {
                (
                    extrapolate(
                        &[last.state.clone(), p.state.clone()],
                        &[last.value, p.value],
                        value,
                    ),
                    p,
                )
            });
        let tangent = last
            .tangent
            .as_ref()
            .filter(|_| self.settings.predictor == Predictor::Tangent)
            .map(|t| super::tangent::along(&built.model, &last.state, t, change));
        let (predicted, from_tangent) = match (secant, tangent) {
            (Some((secant, p)), Some(tangent)) => (
                // The tangent's prediction one secant ratio beyond the secant's.
                Some(extrapolate(
                    &[tangent, secant],
                    &[1.0, 0.0],
                    1.0 + change / (last.value - p.value),
                )),
                true,
            ),
            (None, Some(tangent)) => (Some(tangent), true),
            (Some((secant, _)), None) => (Some(secant), false),
            (None, None) => (None, false),
        };
        let settings = SolverSettings {
            nested_iteration: false,
            load_continuation: false,
            support_continuation: false,
            max_iterations: built
                .settings
                .max_iterations
                .min(built.settings.continuation_step_iterations),
            ..built.settings.clone()
        };
        let mut inside = String::new();
        let carried = || {
            super::carry::carry(
                self.case,
                self.motion,
                built,
                &last.state,
                last.value,
                value,
            )
        };
        let starts = [
            predicted.map(|p| (p, from_tangent)),
            Some((last.state.clone(), false)),
        ];
        for (k, start) in starts.into_iter().enumerate() {
            let Some((start, from_tangent)) = start else {
                continue;
            };
            let solve =
                |start| Clock::time(&self.clock.solve, || built.solve_from(start, &settings));
            let mut solved = solve(start);
            if k == 1
                && self.settings.carry
                && matches!(solved, Err(SolveError::StartsInside(_)))
                && let Some(carried) = carried()
            {
                solved = solve(carried);
            }
            match solved {
                Ok(solution) => {
                    return Ok(Ok(Attempt {
                        solution,
                        from_tangent,
                    }));
                }
                Err(SolveError::StartsInside(e)) => inside = e.to_string(),
                Err(e) => return Err(solve_error(built, e)),
            }
        }
        Ok(Err(inside))
    }

    fn run(
        &mut self,
        mut last: Point,
        targets: Vec<(f64, BuiltCase)>,
        direction: f64,
        on_step: &mut dyn FnMut(MotionStep),
    ) -> Result<Option<StepOutcome>, CaseError> {
        let mut h = (self.largest * self.settings.first_fraction).max(self.smallest);
        for (target, target_built) in targets {
            let (mut solves, mut iterations, mut events) = (0, 0, Vec::new());
            let mut tangent_starts = 0;
            loop {
                let remaining = (target - last.value) * direction;
                let reaches = h >= remaining * (1.0 - 1e-9);
                let value = if reaches {
                    target
                } else {
                    last.value + direction * h
                };
                let built = if reaches {
                    target_built.clone()
                } else {
                    Clock::time(&self.clock.build, || {
                        self.case
                            .build_motion_from(self.motion, value, self.segments, &last.state)
                    })?
                };
                let attempt = self.attempt(&built, &last, value)?;
                let solution = match attempt {
                    Ok(attempt) => {
                        tangent_starts += usize::from(attempt.from_tangent);
                        attempt.solution
                    }
                    Err(inside) => {
                        solves += 1;
                        let size = (value - last.value).abs();
                        if size <= self.smallest * (1.0 + 1e-9) {
                            return Ok(Some(StepOutcome {
                                reached: last.value,
                                value,
                                reason: format!(
                                    "the hoses of the last pose start inside an obstacle at {value} even with the smallest step ({}): {inside}",
                                    self.smallest
                                ),
                            }));
                        }
                        h = (size * 0.5).max(self.smallest);
                        continue;
                    }
                };
                solves += 1;
                iterations += solution.report.iterations;
                let size = (value - last.value).abs();
                let at_smallest = size <= self.smallest * (1.0 + 1e-9);
                // At the smallest step, a state that cannot be followed may have
                // lost its branch (a fold): solve with every aid of the solver (its
                // own continuation, the full iteration budget) to find where the
                // hoses go.
                let solution = if !solution.report.converged && at_smallest {
                    let full = Clock::time(&self.clock.solve, || {
                        built.solve_from(last.state.clone(), &built.settings)
                    });
                    match full {
                        Ok(s) => {
                            solves += 1;
                            iterations += s.report.iterations;
                            s
                        }
                        Err(_) => solution,
                    }
                } else {
                    solution
                };
                if !solution.report.converged {
                    if at_smallest {
                        return Ok(Some(StepOutcome {
                            reached: last.value,
                            value,
                            reason: format!(
                                "no equilibrium found at {value} even with the smallest step ({}): {:?}, residual {:.3e} N after {} iterations",
                                self.smallest,
                                solution.report.termination,
                                solution.report.residual.combined_n,
                                solution.report.iterations
                            ),
                        }));
                    }
                    h = (size * 0.5).max(self.smallest);
                    continue;
                }
                let moved = jump_m(&last.state, &solution.state);
                let rate = moved / size;
                let suspicious = moved > self.settings.jump_floor_m
                    && match self.rate_m {
                        Some(r) => rate > self.settings.jump_ratio * r,
                        // No rate yet: a smooth path moves about half as far in half
                        // the step; a jump does not.
                        None if !at_smallest => {
                            let half = last.value + 0.5 * (value - last.value);
                            let built = Clock::time(&self.clock.build, || {
                                self.case.build_motion_from(
                                    self.motion,
                                    half,
                                    self.segments,
                                    &last.state,
                                )
                            })?;
                            solves += 1;
                            match self.attempt(&built, &last, half)? {
                                Ok(a) if a.solution.report.converged => {
                                    iterations += a.solution.report.iterations;
                                    tangent_starts += usize::from(a.from_tangent);
                                    jump_m(&last.state, &a.solution.state) > 0.75 * moved
                                }
                                _ => true,
                            }
                        }
                        None => true,
                    };
                if suspicious && !at_smallest {
                    h = (size * 0.5).max(self.smallest);
                    continue;
                }
                let stable = solution.report.stable;
                if last.stable && !stable {
                    events.push(MotionEvent::StabilityLost {
                        at: value,
                        negative_directions: solution.report.negative_directions,
                    });
                } else if !last.stable && stable {
                    events.push(MotionEvent::StabilityRegained { at: value });
                }
                let point = Point {
                    value,
                    state: solution.state.clone(),
                    stable,
                    tangent: (self.tangent_at)(value, &solution),
                };
                let before = std::mem::replace(&mut last, point);
                if suspicious {
                    events.push(MotionEvent::SnapThrough {
                        from: before.value,
                        to: value,
                        jump_m: moved,
                    });
                    // The branch after the jump measures its own rate and secant.
                    self.rate_m = None;
                    self.previous = None;
                } else {
                    self.rate_m = Some(rate);
                    self.previous = Some(before);
                }
                h = if solution.report.iterations <= self.settings.easy_iterations {
                    (size * 2.0).min(self.largest)
                } else {
                    size
                };
                if reaches {
                    on_step(MotionStep {
                        value,
                        built,
                        solution,
                        warm: true,
                        solves,
                        iterations,
                        tangent_starts,
                        events,
                    });
                    break;
                }
            }
        }
        Ok(None)
    }
}
