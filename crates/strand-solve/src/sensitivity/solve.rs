//! The state and multiplier derivatives of every parameter.

use strand_system::{Model, SystemState};

use super::kkt::{self, Kkt, Point, RowsAt};
use super::schur::KktFactor;
use super::{Design, Designed, ModelLine, SensitivityError, SensitivitySettings};
use crate::Solution;
use crate::constraints::{Constraints, RowKey};
use crate::gauge::Gauge;

/// The derivative of the equilibrium with respect to one parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterSensitivity {
    /// `dδ/dp`: the change of every unknown in the solver's chart at the base state
    /// (m for positions, rad for rotations and revolute joints) per unit of the
    /// parameter. Held vertices follow their supports and are not part of it.
    pub state: Vec<f64>,
    /// `dμ/dp` of every active row, in the order of [`Sensitivities::active`] (N or
    /// N·m per unit of the parameter).
    pub multipliers: Vec<f64>,
    /// The difference step of `∂Φ/∂p`, in the parameter's unit.
    pub step: f64,
    /// The difference step of the outputs along the first-order path, in the
    /// parameter's unit.
    pub output_step: f64,
    /// Residual of the linearised KKT conditions left by the derivative, relative to
    /// the size of their terms (the derivative's own accuracy check).
    pub kkt_residual: f64,
    /// Refinement steps taken against the exact directional derivative.
    pub refinements: usize,
    /// Elements the right-hand side `∂Φ/∂p` evaluated in each design of its
    /// differences, summed over the differences (two with Richardson extrapolation):
    /// those the parameter changes ([`SensitivitySettings::element_differences`]), or
    /// every element of the model per difference.
    pub rhs_elements: usize,
    /// Designs built ([`Design::build`]) for the right-hand side: none where it is
    /// the closed-form derivative along the model's line
    /// ([`SensitivitySettings::exact_right_hand_sides`]), else two per difference.
    pub rhs_designs: usize,
    /// Evaluations of the constraint rows near the active ones for the closed-form
    /// right-hand side's rows part: none where the line moves nothing the active rows
    /// read ([`crate::Constraints::rows_may_differ`]), else two per difference.
    pub rhs_row_evaluations: usize,
}

/// One parameter's right-hand side and its work.
struct RightHandSide {
    rhs: Kkt,
    /// [`ParameterSensitivity::rhs_elements`].
    elements: usize,
    /// [`ParameterSensitivity::rhs_designs`].
    designs: usize,
    /// [`ParameterSensitivity::rhs_row_evaluations`].
    row_evaluations: usize,
}

/// Two copies of the base model and state, moved in place to `±h` along one
/// parameter's line after another for the closed-form right-hand sides.
struct Scratch {
    plus: Model,
    minus: Model,
    plus_state: SystemState,
    minus_state: SystemState,
}

impl Scratch {
    /// Moves the copies to `±t` along `line` (the models' real numbers, and `base`
    /// with the supports of each placed); `t = 0` moves them back.
    fn move_to(
        &mut self,
        line: &ModelLine<'_>,
        base: &SystemState,
        t: f64,
    ) -> Result<(), strand_system::SystemError> {
        let moved = &line.moved;
        let at = |t: f64| move |k: usize| line.reals[k] + t * line.direction[k];
        self.plus.set_reals_changed(moved, &at(t))?;
        self.minus.set_reals_changed(moved, &at(-t))?;
        if t != 0.0 {
            self.plus_state.clone_from(base);
            self.minus_state.clone_from(base);
            self.plus.enforce_supports(&mut self.plus_state);
            self.minus.enforce_supports(&mut self.minus_state);
        }
        Ok(())
    }
}

/// Why a row is flagged: the active set is about to change there, so derivatives
/// that depend on it hold on one side only.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Flag {
    /// An active row whose multiplier is near zero: it may open.
    MultiplierNearZero,
    /// An open row whose gap is near zero: it may close.
    GapNearZero,
}

/// A row near a change of the active set.
#[derive(Clone, Debug, PartialEq)]
pub struct FlaggedRow {
    /// The row.
    pub key: RowKey,
    /// Its value (m or rad).
    pub value: f64,
    /// Its multiplier (N or N·m).
    pub multiplier: f64,
    /// Why it is flagged.
    pub flag: Flag,
}

/// Sensitivities of an equilibrium with respect to every parameter of a [`Design`].
#[derive(Clone, Debug)]
pub struct Sensitivities {
    /// The active rows (multiplier > 0 at the base equilibrium), which stay active.
    pub active: Vec<RowKey>,
    /// Their multipliers at the base equilibrium (N or N·m).
    pub multipliers: Vec<f64>,
    /// Rows near a change of the active set.
    pub flagged: Vec<FlaggedRow>,
    /// Whether some active rows are linearly dependent (their multipliers' split, not
    /// their sum, is then a minimum-norm choice).
    pub dependent_rows: bool,
    /// Whether the energy Hessian alone is indefinite at the equilibrium, which its
    /// active rows hold (stable on the directions they leave free): the derivatives
    /// were solved with the factor of `H + ρ AᵀA`, the same linearised KKT system.
    pub held_by_active_rows: bool,
    /// Whether the solver's Hessian at the equilibrium was used
    /// ([`crate::Solution::hessian`]): none was evaluated here.
    pub reused_hessian: bool,
    /// One entry per parameter.
    pub parameters: Vec<ParameterSensitivity>,
    gauge: Gauge,
    /// Per unknown, whether an active row's gradient touches it: the rows a residual
    /// reads are found by searching near them ([`crate::Constraints::rows_touching`]).
    active_unknowns: Vec<bool>,
    /// Whether an active row is curved ([`crate::constraints::Row::curvature`]): the
    /// first solves then leave out a term of the Jacobian.
    curved_rows: bool,
    /// Whether every active row is flat in the unknowns (no curvature, and a gradient
    /// on free vertices' positions only, whose chart is linear): its second
    /// derivative is zero, and the refinement checks need not difference the rows.
    flat_rows: bool,
}

impl Sensitivities {
    /// Differentiates the converged `solution` of `design` (at zero offsets) with
    /// respect to every parameter.
    ///
    /// Costs one factorisation of the Hessian at the equilibrium (evaluated there unless
    /// the solver handed it on, [`crate::Solution::hessian`]), one solve per active
    /// row, and per parameter its right-hand side (in closed form along the model's
    /// line: one evaluation of each element it changes, no design built; else two
    /// builds and the changed elements' gradients per difference), one solve and one
    /// refinement check (`H v` for eight parameters at a time).
    pub fn compute<D: Design>(
        design: &D,
        solution: &Solution,
        settings: &SensitivitySettings,
    ) -> Result<Self, SensitivityError> {
        settings.validate()?;
        if !solution.report.converged {
            return Err(SensitivityError::NotConverged {
                residual_n: solution.report.residual.combined_n,
            });
        }
        let count = design.parameter_count();
        let base = design
            .build(&vec![0.0; count])
            .map_err(|e| SensitivityError::Design {
                parameter: 0,
                source: Box::new(e),
            })?;
        let model = base.model();
        let gauge = Gauge::of(model);
        let largest = solution
            .constraints
            .iter()
            .map(|(_, l)| *l)
            .fold(1.0f64, f64::max);
        let mut active = Vec::new();
        let mut multipliers = Vec::new();
        let mut active_rows = Vec::new();
        let mut flagged = Vec::new();
        for (row, lambda) in &solution.constraints {
            if *lambda > 0.0 {
                active.push(row.key);
                multipliers.push(*lambda);
                active_rows.push(row);
                if *lambda <= settings.near_zero_multiplier * largest {
                    flagged.push(FlaggedRow {
                        key: row.key,
                        value: row.value,
                        multiplier: *lambda,
                        flag: Flag::MultiplierNearZero,
                    });
                }
            } else if row.value <= settings.near_zero_gap {
                flagged.push(FlaggedRow {
                    key: row.key,
                    value: row.value,
                    multiplier: *lambda,
                    flag: Flag::GapNearZero,
                });
            }
        }
        // The solver's own Hessian at the equilibrium where it handed it on (with the
        // analysis of this model's pattern: the same model), else evaluated here.
        let same_model = solution
            .analysis
            .as_ref()
            .is_some_and(|a| a.is_of(model.pattern()));
        let kept = solution
            .hessian
            .as_deref()
            .filter(|h| same_model && h.len() == model.pattern().nnz());
        let evaluated;
        let hessian = match kept {
            Some(hessian) => hessian,
            None => {
                let mut eval = model.new_evaluation();
                model.evaluate(&solution.state, &mut eval, true);
                evaluated = eval.hessian;
                &evaluated[..]
            }
        };
        let mut active_unknowns = vec![false; model.dofs().len()];
        for row in &active_rows {
            for &(k, _) in &row.gradient {
                active_unknowns[k] = true;
            }
        }
        let mut factor = KktFactor::new(
            model,
            hessian,
            &gauge,
            &active_rows,
            solution.analysis.as_ref(),
        )?;
        let mut this = Self {
            active,
            multipliers,
            flagged,
            dependent_rows: factor.dependent,
            held_by_active_rows: factor.augmented(),
            reused_hessian: kept.is_some(),
            parameters: Vec::with_capacity(count),
            gauge,
            active_unknowns,
            curved_rows: active_rows.iter().any(|row| row.curvature.is_some()),
            flat_rows: flat_rows(model, &active_rows),
        };
        // Every right-hand side, then every first solve in one pass through the factor,
        // then their refinement checks' `H v` in one pass over the Hessian for eight
        // parameters at a time.
        let mut scratch = None;
        let mut sides = Vec::with_capacity(count);
        for j in 0..count {
            sides.push(this.right_hand_side_of(
                design,
                (model, base.constraints()),
                &solution.state,
                j,
                &mut scratch,
                settings,
            )?);
        }
        let right_hand_sides: Vec<&Kkt> = sides.iter().map(|side| &side.rhs).collect();
        let first = factor.solve_all(&right_hand_sides);
        let states: Vec<Vec<f64>> = first.iter().map(|(v, _)| v.clone()).collect();
        let products = factor.hessian_products(&states);
        for (j, ((side, (v, w)), hv)) in sides.into_iter().zip(first).zip(products).enumerate() {
            let p = this.parameter(
                design,
                &base,
                model,
                &solution.state,
                j,
                &mut factor,
                side,
                (v, w, hv),
                settings,
            )?;
            this.parameters.push(p);
        }
        Ok(this)
    }

    /// The right-hand side `∂Φ/∂p_j`: in closed form along the model's line
    /// ([`SensitivitySettings::exact_right_hand_sides`]; the active rows' part by their
    /// differences at the model moved along it, zero where it moves nothing they
    /// read), else by differences of designs built at `±h` (and `±2h`). `base` is the
    /// base design's model and constraints.
    fn right_hand_side_of<D: Design>(
        &self,
        design: &D,
        base: (&Model, Option<&dyn Constraints>),
        state: &SystemState,
        j: usize,
        scratch: &mut Option<Scratch>,
        settings: &SensitivitySettings,
    ) -> Result<RightHandSide, SensitivityError> {
        let model = base.0;
        let h = settings.relative_step * design.step(j);
        let n = model.dofs().len();
        let richardson = settings.richardson && !design.enters_linearly(j);
        let exact = if settings.exact_right_hand_sides {
            let line = design.model_line(j).map_err(|e| SensitivityError::Design {
                parameter: j,
                source: Box::new(e),
            })?;
            match line {
                Some(line) => {
                    let steps: &[f64] = if richardson { &[h, 2.0 * h] } else { &[h] };
                    self.exact_right_hand_side(base, state, &line, j, steps, scratch)?
                }
                None => None,
            }
        } else {
            None
        };
        Ok(match exact {
            Some(side) => side,
            None => {
                let (rhs, elements) = self.right_hand_side(
                    design,
                    state,
                    j,
                    h,
                    n,
                    richardson,
                    settings.element_differences,
                )?;
                RightHandSide {
                    rhs,
                    elements,
                    designs: if richardson { 4 } else { 2 },
                    row_evaluations: 0,
                }
            }
        })
    }

    /// The derivative with respect to parameter `j` from its right-hand side `side`
    /// and its first solve `(v, w)` with `H v` (`first`): refinement against the
    /// directional derivative.
    #[allow(clippy::too_many_arguments)]
    fn parameter<D: Design>(
        &self,
        design: &D,
        base_built: &D::Built,
        model: &Model,
        base: &SystemState,
        j: usize,
        factor: &mut KktFactor,
        side: RightHandSide,
        first: (Vec<f64>, Vec<f64>, Vec<f64>),
        settings: &SensitivitySettings,
    ) -> Result<ParameterSensitivity, SensitivityError> {
        let h = settings.relative_step * design.step(j);
        let RightHandSide {
            rhs,
            elements: rhs_elements,
            designs: rhs_designs,
            row_evaluations: rhs_row_evaluations,
        } = side;
        let (mut v, mut w, first_hv) = first;
        let mut first_hv = Some(first_hv);
        let mut best = (v.clone(), w.clone(), f64::INFINITY);
        let mut refinements = 0;
        for step in 0..=settings.max_refinements {
            let hv = first_hv
                .take()
                .unwrap_or_else(|| factor.hessian_product(&v));
            let (res, hv) = self.linear_residual(base_built, base, j, factor, &rhs, &v, &w, hv)?;
            let relative = relative_size(model, &res, &rhs, &v, &hv);
            if relative < best.2 {
                best = (v.clone(), w.clone(), relative);
                refinements = step;
            } else {
                break; // round-off reached
            }
            // The first solve is of the exact Jacobian unless an active row is curved
            // (its curvature left out): then refine down to round-off (the
            // tolerance's documentation).
            let tolerance = if self.curved_rows {
                0.0
            } else {
                settings.refinement_tolerance
            };
            if relative <= tolerance || step == settings.max_refinements {
                break;
            }
            let (dv, dw) = factor.solve(&res);
            v.iter_mut().zip(&dv).for_each(|(a, b)| *a += b);
            w.iter_mut().zip(&dw).for_each(|(a, b)| *a += b);
        }
        let (state, multipliers, kkt_residual) = best;
        Ok(ParameterSensitivity {
            state,
            multipliers,
            step: h,
            output_step: settings.output_relative_step * design.step(j),
            kkt_residual,
            refinements,
            rhs_elements,
            rhs_designs,
            rhs_row_evaluations,
        })
    }

    /// `∂Φ/∂p_j` in closed form along the model's line: the base model and state
    /// moved in place to `±h` along it (the scratch copies, moved back afterwards)
    /// give each changed element's change of reference data and held vertices,
    /// [`Model::gradient_derivative`] the rest; the active rows' part
    /// ([`Sensitivities::rows_part`]) by the differences of steps `steps`. Also returns
    /// the elements evaluated; `None` where the line moves what the closed forms do
    /// not carry (the caller then takes the differences of built designs).
    fn exact_right_hand_side(
        &self,
        base: (&Model, Option<&dyn Constraints>),
        state: &SystemState,
        line: &ModelLine<'_>,
        j: usize,
        steps: &[f64],
        scratch: &mut Option<Scratch>,
    ) -> Result<Option<RightHandSide>, SensitivityError> {
        let model = base.0;
        if line.reals.len() != line.direction.len() {
            return Ok(None);
        }
        let scratch = scratch.get_or_insert_with(|| Scratch {
            plus: model.clone(),
            minus: model.clone(),
            plus_state: state.clone(),
            minus_state: state.clone(),
        });
        let failed = |e: strand_system::SystemError| SensitivityError::Design {
            parameter: j,
            source: Box::new(e),
        };
        let h = steps[0];
        scratch.move_to(line, state, h).map_err(failed)?;
        let derivative = model.gradient_derivative(
            state,
            (&scratch.plus, &scratch.plus_state),
            (&scratch.minus, &scratch.minus_state),
            h,
        );
        let rows = match &derivative {
            Some(_) if !self.active.is_empty() => {
                Some(self.rows_part(base, state, line, j, steps, scratch))
            }
            _ => None,
        };
        scratch.move_to(line, state, 0.0).map_err(failed)?;
        let Some(d) = derivative else {
            return Ok(None);
        };
        let mut gradient = d.gradient;
        let (gaps, row_evaluations) = match rows.transpose()? {
            Some((part, evaluations)) => {
                gradient
                    .iter_mut()
                    .zip(&part.gradient)
                    .for_each(|(g, r)| *g += r);
                (part.gaps, evaluations)
            }
            None => (vec![0.0; self.active.len()], 0),
        };
        self.gauge.fix_vector(&mut gradient);
        Ok(Some(RightHandSide {
            rhs: Kkt { gradient, gaps },
            elements: d.elements,
            designs: 0,
            row_evaluations,
        }))
    }

    /// The active rows' part of `∂Φ/∂p_j` along the model's line, `scratch` moved to
    /// `±steps[0]`: `−Σ μ_i ∂a_i/∂p` and `∂c_i/∂p` at the base's unknowns. Zero where
    /// neither side moves anything the rows read (joint stops, and
    /// [`Constraints::rows_may_differ`]); else the rows near the active ones of the
    /// base's constraints (the line's contract: the constraints do not move) at each
    /// side, differenced at every step of `steps` (extrapolated where two). Also
    /// returns the evaluations of rows it took.
    fn rows_part(
        &self,
        base: (&Model, Option<&dyn Constraints>),
        state: &SystemState,
        line: &ModelLine<'_>,
        j: usize,
        steps: &[f64],
        scratch: &mut Scratch,
    ) -> Result<(Kkt, usize), SensitivityError> {
        let (model, constraints) = base;
        let n = model.dofs().len();
        let moves = |moved: &Model, moved_state: &SystemState| {
            let stops = |m: &Model| {
                m.system()
                    .clips
                    .iter()
                    .map(|c| c.limits)
                    .collect::<Vec<_>>()
            };
            stops(model) != stops(moved)
                || constraints.is_some_and(|c| {
                    c.rows_may_differ(model, state, (moved, moved_state), &self.active_unknowns)
                })
        };
        if !moves(&scratch.plus, &scratch.plus_state)
            && !moves(&scratch.minus, &scratch.minus_state)
        {
            return Ok((
                Kkt {
                    gradient: vec![0.0; n],
                    gaps: vec![0.0; self.active.len()],
                },
                0,
            ));
        }
        let mut differences = Vec::with_capacity(steps.len());
        for (k, &step) in steps.iter().enumerate() {
            if k > 0 {
                scratch
                    .move_to(line, state, step)
                    .map_err(|e| SensitivityError::Design {
                        parameter: j,
                        source: Box::new(e),
                    })?;
            }
            let touching = Some(&self.active_unknowns[..]);
            let plus = kkt::rows_at(&scratch.plus, constraints, &scratch.plus_state, j, touching)?;
            let minus = kkt::rows_at(
                &scratch.minus,
                constraints,
                &scratch.minus_state,
                j,
                touching,
            )?;
            let difference = kkt::rows_difference(
                (&plus, &minus),
                &self.active,
                &self.multipliers,
                vec![0.0; n],
                j,
            )?;
            differences.push(difference.divided(2.0 * step));
        }
        let evaluations = 2 * steps.len();
        Ok((
            match differences.as_slice() {
                [fine, coarse] => Kkt::richardson(fine, coarse),
                _ => differences.swap_remove(0),
            },
            evaluations,
        ))
    }

    /// The residual `J·(v, w) + rhs` of the linearised KKT system with the exact
    /// Jacobian: `H v − Aᵀ w − Σ μ_i ∇²c_i v + rhs_g` and `A v + rhs_c`, `H v`
    /// (the size of the force terms, [`relative_size`]; given as `hv`). Only the
    /// curvature of the active rows (zero for a flat contact or a joint stop) is taken
    /// by a difference, of the rows' gradients alone along `v` (no energy gradient, so
    /// no round-off of the stiff axial terms).
    #[allow(clippy::too_many_arguments)]
    fn linear_residual<B: Designed>(
        &self,
        built: &B,
        base: &SystemState,
        j: usize,
        factor: &KktFactor,
        rhs: &Kkt,
        v: &[f64],
        w: &[f64],
        hv: Vec<f64>,
    ) -> Result<(Kkt, Vec<f64>), SensitivityError> {
        let mut gradient = hv.clone();
        for ((g, aw), r) in gradient
            .iter_mut()
            .zip(factor.transpose_product(w))
            .zip(&rhs.gradient)
        {
            *g += r - aw;
        }
        let gaps: Vec<f64> = factor
            .row_product(v)
            .iter()
            .zip(&rhs.gaps)
            .map(|(a, c)| a + c)
            .collect();
        if !self.active.is_empty() && !self.flat_rows {
            let model = built.model();
            let size = model.step_size(v);
            let largest = size.0.max(size.1);
            if largest > 0.0 {
                let t = CURVATURE_STEP / largest;
                let mut sides = Vec::with_capacity(2);
                for sign in [1.0, -1.0] {
                    let delta: Vec<f64> = v.iter().map(|x| sign * t * x).collect();
                    let state = model.retract(base, &delta);
                    let rows = kkt::rows_at(
                        model,
                        built.constraints(),
                        &state,
                        j,
                        Some(&self.active_unknowns),
                    )?;
                    let mut force = vec![0.0; v.len()];
                    for (&key, &m) in self.active.iter().zip(&self.multipliers) {
                        let row = rows
                            .iter()
                            .find(|r| r.key == key)
                            .ok_or(SensitivityError::RowLost { parameter: j, key })?;
                        for &(k, a) in &row.gradient {
                            force[k] += m * a;
                        }
                    }
                    model.pull_back_gradient(&delta, 1.0, &mut force);
                    self.gauge.fix_vector(&mut force);
                    sides.push(force);
                }
                for (g, (a, b)) in gradient.iter_mut().zip(sides[0].iter().zip(&sides[1])) {
                    *g -= (a - b) / (2.0 * t);
                }
            }
        }
        Ok((Kkt { gradient, gaps }, hv))
    }

    /// `∂Φ/∂p_j` by central differences of steps `h` and `2h`, extrapolated
    /// (Richardson: `(4 D(h) − D(2h)) / 3`, error `O(h⁴)`), so that `h` can be large
    /// enough for the round-off of the gradient (`ε` times the axial stiffness) not to
    /// matter; without `richardson`, `D(h)` alone (error `O(h²)`). Each difference
    /// evaluates only the elements the parameter changes
    /// ([`SensitivitySettings::element_differences`]; otherwise both sides' whole
    /// gradients). Also returns the elements evaluated, summed over the differences.
    #[allow(clippy::too_many_arguments)]
    fn right_hand_side<D: Design>(
        &self,
        design: &D,
        base: &SystemState,
        j: usize,
        h: f64,
        n: usize,
        richardson: bool,
        element_differences: bool,
    ) -> Result<(Kkt, usize), SensitivityError> {
        let steps: &[f64] = if richardson { &[h, 2.0 * h] } else { &[h] };
        let zero_v = vec![0.0; n];
        let zero_w = vec![0.0; self.active.len()];
        let mut differences = Vec::with_capacity(2);
        let mut elements = 0;
        for &step in steps {
            let rows = RowsAt::Touching(&self.active_unknowns);
            let (plus, _, mu) = self.path(design, base, j, step, &zero_v, &zero_w, rows)?;
            let (minus, _, _) = self.path(design, base, j, -step, &zero_v, &zero_w, rows)?;
            let difference = if element_differences {
                let (d, count) =
                    kkt::residual_difference(&plus, &minus, &self.active, &mu, &self.gauge, j)?;
                elements += count;
                d
            } else {
                let side = |point: &Point<D::Built>| {
                    kkt::residual(point, &self.active, &mu, &zero_v, &self.gauge, j)
                };
                let (a, b) = (side(&plus)?, side(&minus)?);
                elements += plus.built.model().element_count();
                Kkt::subtract(&a, &b)
            };
            differences.push(difference.divided(2.0 * step));
        }
        Ok((
            match differences.as_slice() {
                [fine, coarse] => Kkt::richardson(fine, coarse),
                _ => differences.swap_remove(0),
            },
            elements,
        ))
    }

    /// The point `(p + t e_j, x ⊕ t v, μ + t w)` of the first-order path.
    #[allow(clippy::type_complexity)]
    pub(crate) fn path<D: Design>(
        &self,
        design: &D,
        base: &SystemState,
        j: usize,
        t: f64,
        v: &[f64],
        w: &[f64],
        rows: RowsAt<'_>,
    ) -> Result<(Point<D::Built>, Vec<f64>, Vec<f64>), SensitivityError> {
        let mut offsets = vec![0.0; design.parameter_count()];
        offsets[j] = t;
        let delta: Vec<f64> = v.iter().map(|x| t * x).collect();
        let mu: Vec<f64> = self
            .multipliers
            .iter()
            .zip(w)
            .map(|(l, x)| l + t * x)
            .collect();
        let point = kkt::point(design, j, &offsets, base, &delta, rows)?;
        Ok((point, delta, mu))
    }
}

/// Whether every row of `rows` has no curvature and a gradient on the positions of
/// free vertices only (whose unknowns are the positions themselves): a row linear in
/// the unknowns, as a contact on a face's inside (`Row::curvature` is `None` only
/// where the solver takes the gap as flat).
fn flat_rows(model: &Model, rows: &[&crate::constraints::Row]) -> bool {
    let dofs = model.dofs();
    let mut position = vec![false; dofs.len()];
    for (r, spec) in model.system().rods.iter().enumerate() {
        for j in 0..=spec.rod.segments() {
            if let Some(block) = dofs.vertex(r, j) {
                position[3 * block..3 * block + 3].fill(true);
            }
        }
    }
    rows.iter()
        .all(|row| row.curvature.is_none() && row.gradient.iter().all(|&(k, _)| position[k]))
}

/// Largest translation (m) or rotation (rad) of the difference step of the rows'
/// curvature: their gradients (unit normals) are exact to round-off, so a small step
/// keeps the truncation error negligible.
const CURVATURE_STEP: f64 = 1e-7;

/// Size of the residual `res = J·(v, w) + rhs` relative to its terms: the larger of
/// the force part (combined measure, N; against the right-hand side and `H v`) and
/// the row part (m, rad); `v` the state's change.
fn relative_size(model: &Model, res: &Kkt, rhs: &Kkt, v: &[f64], hv: &[f64]) -> f64 {
    let combined = |g: &[f64]| model.residual(g).combined_n;
    let scale_g = combined(&rhs.gradient).max(combined(hv));
    let force = if scale_g > 0.0 {
        combined(&res.gradient) / scale_g
    } else {
        0.0
    };
    let inf = |x: &[f64]| x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let lhs_c: Vec<f64> = res.gaps.iter().zip(&rhs.gaps).map(|(r, b)| r - b).collect();
    // The rows' residual in m (rad) per unit, against the rows' terms and the size of
    // the state's change itself (a row the parameter does not move has no terms).
    let scale_c = inf(&rhs.gaps).max(inf(&lhs_c)).max(inf(v));
    let gap = if scale_c > 0.0 {
        inf(&res.gaps) / scale_c
    } else {
        0.0
    };
    force.max(gap)
}
