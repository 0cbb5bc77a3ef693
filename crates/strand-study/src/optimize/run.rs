//! The trust-region SQP loop over the design variables.
//!
//! Each iteration linearises the objective's pieces and the constraint rows at the
//! current point with their exact gradients, solves the subproblem ([`super::step`])
//! inside the trust region, and solves the equilibrium at the trial point (warm, along
//! the first-order path). The trial is accepted when the merit (normalised objective
//! plus ρ times the normalised violation) falls by at least a fraction of the model's
//! prediction; the trust region grows after good steps and shrinks after bad ones.
//! The curvature model is a damped BFGS update of the Lagrangian's Hessian (the
//! pieces' weights and the rows' multipliers from the subproblem).
//!
//! Non-smooth places — a peak whose arg-max jumps along the rod, a contact or joint
//! stop that opens or closes — are where the gradient model fails: the step is
//! rejected, the trust region shrinks, and the history says why. When the region
//! collapses without meeting the convergence test, the run stops as `non_smooth`
//! (not converged) at the best point found.

use nalgebra::{DMatrix, DVector};
use strand_case::Case;

use super::evaluate::{Evaluation, Evaluator};
use super::pieces::{
    Piece, Row, check_names, constraint_rows, energy_output, objective_pieces, supports,
};
use super::problem::Problem;
use super::problem::unit_of;
use super::step::{Affine, Step, Subproblem};
use super::{
    OptimizeError, OptimizeSettings, Optimum, OptimumConstraint, OptimumIterate, Termination,
};

/// Largest penalty ρ the merit takes.
const MAX_PENALTY: f64 = 1e8;

/// Fraction of a variable's bounds' width within which a trial point is snapped onto
/// the bound (the interior-point subproblem ends a hair short of it) and the final
/// point counts as on it. At 1e-7 the cooler hose's `--minimize peak_moment` over
/// hose 2's 150–300 mm ended 1.9e-5 mm (1.3e-7 of the width) short of 300 mm and
/// reported no bound active, although the optimum sits on it.
const BOUND_SNAP: f64 = 1e-6;

/// The normalisation of a run: the objective's scale and the variables' widths.
struct Scales {
    objective: f64,
    widths: Vec<f64>,
    penalty: f64,
}

impl Scales {
    fn pieces(&self, pieces: &[Piece]) -> Vec<Affine> {
        pieces
            .iter()
            .map(|p| Affine {
                value: p.value / self.objective,
                gradient: p
                    .gradient
                    .iter()
                    .zip(&self.widths)
                    .map(|(g, w)| g * w / self.objective)
                    .collect(),
            })
            .collect()
    }

    fn rows(&self, rows: &[Row]) -> Vec<Affine> {
        rows.iter()
            .map(|r| Affine {
                value: r.piece.value / r.scale,
                gradient: r
                    .piece
                    .gradient
                    .iter()
                    .zip(&self.widths)
                    .map(|(g, w)| g * w / r.scale)
                    .collect(),
            })
            .collect()
    }

    /// The merit: the largest normalised piece plus ρ times the normalised violation.
    fn merit(&self, pieces: &[Piece], rows: &[Row]) -> f64 {
        objective_value(pieces) / self.objective + self.penalty * violation(rows)
    }
}

/// The objective: the largest piece.
fn objective_value(pieces: &[Piece]) -> f64 {
    pieces
        .iter()
        .map(|p| p.value)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The summed normalised violation of the rows.
fn violation(rows: &[Row]) -> f64 {
    rows.iter()
        .map(|r| (-r.piece.value / r.scale).max(0.0))
        .sum()
}

/// The largest normalised violation.
fn worst(rows: &[Row]) -> f64 {
    rows.iter()
        .map(|r| (-r.piece.value / r.scale).max(0.0))
        .fold(0.0, f64::max)
}

/// The linearisation at a point.
struct Linear {
    pieces: Vec<Piece>,
    rows: Vec<Row>,
}

/// The Lagrangian's gradient (normalised, scaled variables) at `at` with the weights
/// and multipliers of `step` on the pieces and rows labelled as in `reference`.
fn lagrangian_gradient(scales: &Scales, reference: &Linear, at: &Linear, step: &Step) -> Vec<f64> {
    let n = scales.widths.len();
    let mut g = vec![0.0; n];
    let pa = scales.pieces(&at.pieces);
    let ra = scales.rows(&at.rows);
    for (p, w) in reference.pieces.iter().zip(&step.weights) {
        if let Some(k) = at.pieces.iter().position(|q| q.label == p.label) {
            for j in 0..n {
                g[j] += w * pa[k].gradient[j];
            }
        }
    }
    for (r, m) in reference.rows.iter().zip(&step.multipliers) {
        if let Some(k) = at.rows.iter().position(|q| q.piece.label == r.piece.label) {
            for j in 0..n {
                g[j] -= m * ra[k].gradient[j];
            }
        }
    }
    g
}

/// Damped BFGS (Powell): `B` stays positive definite.
fn bfgs(b: &mut DMatrix<f64>, s: &[f64], y: &[f64]) {
    let s = DVector::from_column_slice(s);
    let y = DVector::from_column_slice(y);
    let bs = &*b * &s;
    let sbs = s.dot(&bs);
    if sbs.is_nan() || sbs <= 0.0 {
        return;
    }
    let sy = s.dot(&y);
    let theta = if sy >= 0.2 * sbs {
        1.0
    } else {
        0.8 * sbs / (sbs - sy)
    };
    let r = &y * theta + &bs * (1.0 - theta);
    let sr = s.dot(&r);
    if sr.is_nan() || sr <= 0.0 {
        return;
    }
    *b += &r * r.transpose() / sr - &bs * bs.transpose() / sbs;
}

/// The reasons the gradient model may fail between `from` and `to`: one-sided
/// derivatives of pieces or rows near the max, contacts and stops that switched.
fn switches(from: &Evaluation, to: &Evaluation, lin: &Linear) -> Vec<String> {
    let mut out = Vec::new();
    let top = objective_value(&lin.pieces);
    for p in &lin.pieces {
        if p.one_sided && p.value >= top - 1e-3 * top.abs() {
            out.push(format!("the arg-max of {} moves", p.label));
        }
    }
    for r in &lin.rows {
        if r.piece.one_sided && r.piece.value <= 1e-3 * r.scale {
            out.push(format!("the arg-min of {} moves", r.piece.label));
        }
    }
    let active = |e: &Evaluation| {
        let mut keys: Vec<String> = e
            .solution
            .constraints
            .iter()
            .filter(|(_, l)| *l > 0.0)
            .map(|(r, _)| format!("{:?}", r.key))
            .collect();
        keys.sort();
        keys
    };
    let (a, b) = (active(from), active(to));
    if a != b {
        let closed = b.iter().filter(|k| !a.contains(k)).count();
        let opened = a.iter().filter(|k| !b.contains(k)).count();
        out.push(format!(
            "the active contacts/stops change ({closed} close, {opened} open)"
        ));
    }
    out
}

/// Finds the best design of `problem` for `case`; `progress` sees every iterate.
pub fn optimize(
    case: &Case,
    problem: &Problem,
    settings: &OptimizeSettings,
    progress: &mut dyn FnMut(&OptimumIterate),
) -> Result<Optimum, OptimizeError> {
    settings.validate()?;
    let n = problem.variables.len();
    if n == 0 {
        return Err(OptimizeError::input(
            "--vary",
            "",
            "no design variable",
            "give at least one --vary NAME=LO..HI",
        ));
    }
    let base_built = case.build(None)?;
    check_names(problem, &base_built)?;
    drop(base_built);
    let supports = supports(case);
    let mut evaluator = Evaluator::new(
        case,
        problem
            .variables
            .iter()
            .map(|v| v.parameter.clone())
            .collect(),
        settings.sensitivity.clone(),
        energy_output(problem),
    );
    let (lower, upper): (Vec<f64>, Vec<f64>) =
        problem.variables.iter().map(|v| (v.lower, v.upper)).unzip();
    let start: Vec<f64> = (0..n).map(|j| 0.0f64.clamp(lower[j], upper[j])).collect();
    let mut current = evaluator
        .evaluate(&start, None)?
        .map_err(OptimizeError::Start)?;
    let contact_n = current
        .table
        .outputs
        .iter()
        .filter(|o| o.name.contains(".contact_force_N."))
        .map(|o| o.value)
        .sum::<f64>()
        .max(1.0);
    let linearise = |e: &Evaluation| -> Result<Linear, OptimizeError> {
        Ok(Linear {
            pieces: objective_pieces(&problem.objective, e, &supports)?,
            rows: constraint_rows(problem, e, contact_n)?,
        })
    };
    let mut lin = linearise(&current)?;
    let top = objective_value(&lin.pieces).abs();
    let mut scales = Scales {
        objective: if top > 0.0 { top } else { 1.0 },
        widths: problem.variables.iter().map(|v| v.width()).collect(),
        penalty: settings.penalty,
    };
    let values = |x: &[f64]| -> Vec<f64> {
        problem
            .variables
            .iter()
            .zip(x)
            .map(|(v, o)| v.value(*o))
            .collect()
    };
    let mut radius = settings.initial_radius;
    let mut curvature = DMatrix::identity(n, n) * settings.initial_curvature;
    let mut history = vec![OptimumIterate {
        iteration: 0,
        solves: evaluator.solves,
        values: values(&current.offsets),
        objective: Some(objective_value(&lin.pieces)),
        violation: Some(worst(&lin.rows)),
        radius,
        ratio: None,
        accepted: true,
        note: "start (the case, within the bounds)".into(),
    }];
    progress(&history[0]);
    let mut non_smooth: Vec<String> = Vec::new();
    let mut iterations = 0;
    let subproblem_at = |lin: &Linear,
                         scales: &Scales,
                         radius: f64,
                         curvature: &DMatrix<f64>,
                         x: &[f64]|
     -> Result<Step, OptimizeError> {
        let pa = scales.pieces(&lin.pieces);
        let ra = scales.rows(&lin.rows);
        let lo: Vec<f64> = (0..n)
            .map(|j| (-radius).max((lower[j] - x[j]) / scales.widths[j]).min(0.0))
            .collect();
        let hi: Vec<f64> = (0..n)
            .map(|j| radius.min((upper[j] - x[j]) / scales.widths[j]).max(0.0))
            .collect();
        Subproblem {
            pieces: &pa,
            rows: &ra,
            curvature,
            lower: &lo,
            upper: &hi,
            penalty: scales.penalty,
        }
        .solve()
    };
    let termination = loop {
        if iterations >= settings.max_iterations {
            break Termination::MaxIterations;
        }
        if evaluator.solves >= settings.max_solves {
            break Termination::MaxSolves;
        }
        let mut step = subproblem_at(&lin, &scales, radius, &curvature, &current.offsets)?;
        // Raise the penalty while the subproblem prefers violating a row it could meet.
        while step.multipliers.iter().any(|&m| m >= 0.99 * scales.penalty)
            && scales.penalty < MAX_PENALTY
        {
            let before = step.s.clone();
            scales.penalty *= 10.0;
            step = subproblem_at(&lin, &scales, radius, &curvature, &current.offsets)?;
            if step.s == before {
                break;
            }
        }
        let merit = scales.merit(&lin.pieces, &lin.rows);
        let predicted = merit - step.model;
        let size = step.s.iter().fold(0.0f64, |m, s| m.max(s.abs()));
        if size <= settings.step_tolerance || predicted <= 1e-12 * merit.abs().max(1.0) {
            break if worst(&lin.rows) <= settings.feasibility_tolerance {
                Termination::Converged
            } else {
                Termination::Infeasible
            };
        }
        iterations += 1;
        // Onto a bound the interior-point step ends a hair short of: snap.
        let trial_x: Vec<f64> = (0..n)
            .map(|j| {
                let x =
                    (current.offsets[j] + step.s[j] * scales.widths[j]).clamp(lower[j], upper[j]);
                let near = BOUND_SNAP * scales.widths[j];
                if x - lower[j] <= near {
                    lower[j]
                } else if upper[j] - x <= near {
                    upper[j]
                } else {
                    x
                }
            })
            .collect();
        let mut record = OptimumIterate {
            iteration: iterations,
            solves: 0,
            values: values(&trial_x),
            objective: None,
            violation: None,
            radius,
            ratio: None,
            accepted: false,
            note: String::new(),
        };
        match evaluator.evaluate(&trial_x, Some(&current))? {
            Err(why) => {
                radius = 0.25 * size;
                record.note = format!("rejected: {why}");
            }
            Ok(trial) => {
                let tlin = linearise(&trial)?;
                let tmerit = scales.merit(&tlin.pieces, &tlin.rows);
                let ratio = (merit - tmerit) / predicted;
                record.objective = Some(objective_value(&tlin.pieces));
                record.violation = Some(worst(&tlin.rows));
                record.ratio = ratio.is_finite().then_some(ratio);
                let events = switches(&current, &trial, &tlin);
                if ratio >= settings.accept_ratio {
                    let g0 = lagrangian_gradient(&scales, &lin, &lin, &step);
                    let g1 = lagrangian_gradient(&scales, &lin, &tlin, &step);
                    let y: Vec<f64> = g1.iter().zip(&g0).map(|(a, b)| a - b).collect();
                    let s: Vec<f64> = (0..n)
                        .map(|j| (trial_x[j] - current.offsets[j]) / scales.widths[j])
                        .collect();
                    bfgs(&mut curvature, &s, &y);
                    if ratio > 0.75 && size >= 0.99 * radius {
                        radius = (2.0 * radius).min(settings.max_radius);
                    }
                    record.accepted = true;
                    record.note = if events.is_empty() {
                        "accepted".into()
                    } else {
                        format!("accepted ({})", events.join("; "))
                    };
                    current = trial;
                    lin = tlin;
                } else {
                    radius = 0.25 * size;
                    record.note = if events.is_empty() {
                        "rejected: the gradient model overestimates the gain".into()
                    } else {
                        let why = format!("non-smooth: {}", events.join("; "));
                        non_smooth.push(format!(
                            "iteration {iterations}: {why}: the step is rejected and the trust region shrinks"
                        ));
                        format!("rejected ({why})")
                    };
                }
            }
        }
        record.solves = evaluator.solves;
        record.radius = radius;
        progress(&record);
        history.push(record);
        if radius < settings.step_tolerance {
            // Collapsed with a constraint still violated: no feasible point was found
            // (whether the gradients also jumped is in `non_smooth`).
            break if worst(&lin.rows) > settings.feasibility_tolerance {
                Termination::Infeasible
            } else {
                Termination::NonSmooth
            };
        }
    };
    // The multipliers at the final point (a zero-size step there when converged).
    let step = subproblem_at(
        &lin,
        &scales,
        radius.max(settings.step_tolerance),
        &curvature,
        &current.offsets,
    )?;
    let objective_unit = problem.objective.unit();
    let mut constraints: Vec<OptimumConstraint> = lin
        .rows
        .iter()
        .zip(&step.multipliers)
        .map(|(r, &m)| {
            let limit = &problem.limits[r.limit];
            let active = m > 1e-6 || r.piece.value.abs() <= settings.active_tolerance * r.scale;
            // An inactive row's multiplier is the interior-point method's residue.
            let multiplier = if active {
                m * scales.objective / r.scale
            } else {
                0.0
            };
            OptimumConstraint {
                name: limit.text.clone(),
                kind: "constraint".into(),
                output: r.piece.label.clone(),
                value: r.output,
                bound: r.bound,
                satisfied: r.piece.value >= -settings.feasibility_tolerance * r.scale,
                active,
                multiplier,
                d_objective_d_bound: if limit.at_least {
                    multiplier
                } else {
                    -multiplier
                },
                multiplier_unit: format!("{objective_unit}/{}", unit_of(&r.piece.label)),
                in_contact: r.in_contact,
            }
        })
        .collect();
    for (j, v) in problem.variables.iter().enumerate() {
        let x = current.offsets[j];
        let near = BOUND_SNAP * v.width();
        let (zl, zu) = step.bound_multipliers[j];
        let upper = if x <= v.lower + near {
            false
        } else if x >= v.upper - near {
            true
        } else {
            continue;
        };
        let bound = v.value(if upper { v.upper } else { v.lower });
        // Per unit of the variable beyond its bound, the objective would fall by this.
        let multiplier = if upper { zu } else { zl } * scales.objective / v.width();
        constraints.push(OptimumConstraint {
            name: format!(
                "{} {} {bound}{}",
                v.name,
                if upper { "<=" } else { ">=" },
                v.unit
            ),
            kind: if upper { "upper_bound" } else { "lower_bound" }.into(),
            output: String::new(),
            value: bound,
            bound,
            satisfied: true,
            active: true,
            multiplier,
            d_objective_d_bound: if upper { -multiplier } else { multiplier },
            multiplier_unit: format!("{objective_unit}/{}", v.unit),
            in_contact: false,
        });
    }
    let top = objective_value(&lin.pieces);
    let attained_by = lin
        .pieces
        .iter()
        .zip(&step.weights)
        .filter(|(p, w)| **w > 1e-3 || p.value >= top - 1e-6 * top.abs())
        .map(|(p, _)| p.label.clone())
        .collect();
    let changes = evaluator.design(&current.offsets).changes(&vec![0.0; n]);
    let message = match termination {
        Termination::Converged => format!(
            "converged: the subproblem's step is below {} of the bounds' widths at a feasible point",
            settings.step_tolerance
        ),
        Termination::Infeasible => {
            "not converged: no feasible point was found (the constraint violation cannot be reduced further within the bounds)".into()
        }
        Termination::NonSmooth => format!(
            "not converged: the trust region collapsed (below {} of the widths) because the gradient model does not predict the change{}; the best point found is reported",
            settings.step_tolerance,
            if non_smooth.is_empty() {
                String::new()
            } else {
                " (non-smooth: see non_smooth)".to_string()
            }
        ),
        Termination::MaxIterations => format!(
            "not converged: {} iterations without meeting the convergence test",
            settings.max_iterations
        ),
        Termination::MaxSolves => format!(
            "not converged: {} equilibrium solves without meeting the convergence test",
            settings.max_solves
        ),
    };
    Ok(Optimum {
        converged: termination == Termination::Converged,
        termination,
        message,
        offsets: current.offsets.clone(),
        values: values(&current.offsets),
        objective: top,
        attained_by,
        constraints,
        outputs: current.table.outputs.clone(),
        solution: current.solution.clone(),
        solves: evaluator.solves,
        iterations,
        newton_iterations: evaluator.iterations,
        residual_n: current.solution.report.residual.combined_n,
        non_smooth,
        history,
        changes,
    })
}
