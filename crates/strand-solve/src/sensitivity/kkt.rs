//! The KKT residual `Φ(δ, μ, p)` of a design at a point near the base equilibrium.

use strand_system::{Evaluation, Model, SystemState};

use super::{Design, Designed, SensitivityError};
use crate::constraints::{Row, RowKey, limit_rows};
use crate::gauge::Gauge;

/// `Φ` at one point: the Lagrangian gradient in the base chart (N, N·m; the gauge
/// entries zeroed) and the active rows' values (m, rad).
#[derive(Clone, Debug)]
pub(crate) struct Kkt {
    /// `g − Σ μ_i a_i`, pulled back into the chart of the base state.
    pub gradient: Vec<f64>,
    /// The active rows' values, in the order of the active keys.
    pub gaps: Vec<f64>,
}

impl Kkt {
    /// `(4 fine − coarse) / 3`: Richardson extrapolation of central differences of
    /// steps `h` (`fine`) and `2h` (`coarse`).
    pub(crate) fn richardson(fine: &Kkt, coarse: &Kkt) -> Kkt {
        let combine = |x: &[f64], y: &[f64]| -> Vec<f64> {
            x.iter().zip(y).map(|(a, b)| (4.0 * a - b) / 3.0).collect()
        };
        Kkt {
            gradient: combine(&fine.gradient, &coarse.gradient),
            gaps: combine(&fine.gaps, &coarse.gaps),
        }
    }

    /// `a − b`, entry by entry.
    pub(crate) fn subtract(a: &Kkt, b: &Kkt) -> Kkt {
        let diff =
            |x: &[f64], y: &[f64]| -> Vec<f64> { x.iter().zip(y).map(|(x, y)| x - y).collect() };
        Kkt {
            gradient: diff(&a.gradient, &b.gradient),
            gaps: diff(&a.gaps, &b.gaps),
        }
    }

    /// Every entry divided by `divisor`.
    pub(crate) fn divided(mut self, divisor: f64) -> Kkt {
        self.gradient
            .iter_mut()
            .chain(&mut self.gaps)
            .for_each(|x| *x /= divisor);
        self
    }
}

/// A point of the first-order path: the design at `offsets`, the base state moved by
/// `delta` in its chart (held vertices on the design's supports), and the rows there
/// (where asked for).
pub(crate) struct Point<B> {
    pub built: B,
    pub state: SystemState,
    pub rows: Vec<Row>,
}

/// Which rows a [`Point`] evaluates at its state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum RowsAt<'a> {
    /// Every joint-limit and contact row at the point.
    Evaluated,
    /// At least those whose gradients touch only flagged unknowns (the active rows', for
    /// a residual `Φ`, which reads only them: [`Constraints::rows_touching`]).
    Touching(&'a [bool]),
    /// None (the outputs at a point read only its state).
    Skipped,
}

/// Builds the design at `offsets` and moves `base` by `delta` on it.
pub(crate) fn point<D: Design>(
    design: &D,
    parameter: usize,
    offsets: &[f64],
    base: &SystemState,
    delta: &[f64],
    rows: RowsAt<'_>,
) -> Result<Point<D::Built>, SensitivityError> {
    let built = design
        .build(offsets)
        .map_err(|e| SensitivityError::Design {
            parameter,
            source: Box::new(e),
        })?;
    let model = built.model();
    let expected = delta.len();
    if model.dofs().len() != expected {
        return Err(SensitivityError::Shape {
            parameter,
            given: model.dofs().len(),
            expected,
        });
    }
    let mut start = base.clone();
    model.enforce_supports(&mut start);
    // A point of the right-hand side `∂Φ/∂p` keeps the state (no retraction: the
    // supports are placed above, and a zero step moves nothing else).
    let state = if delta.iter().all(|d| *d == 0.0) {
        start
    } else {
        model.retract(&start, delta)
    };
    let rows = match rows {
        RowsAt::Evaluated => rows_at(model, built.constraints(), &state, parameter, None)?,
        RowsAt::Touching(unknowns) => rows_at(
            model,
            built.constraints(),
            &state,
            parameter,
            Some(unknowns),
        )?,
        RowsAt::Skipped => Vec::new(),
    };
    Ok(Point { built, state, rows })
}

/// Joint-limit and contact rows of `state`: every one, or at least those whose
/// gradients touch only unknowns that `touching` flags.
pub(crate) fn rows_at(
    model: &Model,
    constraints: Option<&dyn crate::Constraints>,
    state: &SystemState,
    parameter: usize,
    touching: Option<&[bool]>,
) -> Result<Vec<Row>, SensitivityError> {
    let mut rows = Vec::new();
    limit_rows(model, state, &mut rows);
    if let Some(c) = constraints {
        match touching {
            Some(unknowns) => c.rows_touching(model, state, unknowns, &mut rows),
            None => c.rows(model, state, &mut rows),
        }
        .map_err(|source| SensitivityError::Constraint {
            parameter,
            source: Box::new(source),
        })?;
    }
    Ok(rows)
}

/// `Φ` at `point` with multipliers `mu` on the `active` keys; `delta` is the chart
/// increment the point was made with (for the pull-back).
pub(crate) fn residual<B: Designed>(
    point: &Point<B>,
    active: &[RowKey],
    mu: &[f64],
    delta: &[f64],
    gauge: &Gauge,
    parameter: usize,
) -> Result<Kkt, SensitivityError> {
    let model = point.built.model();
    let mut eval = gradient_only(model);
    model.evaluate(&point.state, &mut eval, false);
    let mut gradient = eval.gradient;
    let mut gaps = Vec::with_capacity(active.len());
    for (&key, &m) in active.iter().zip(mu) {
        let row = point
            .rows
            .iter()
            .find(|r| r.key == key)
            .ok_or(SensitivityError::RowLost { parameter, key })?;
        for &(k, a) in &row.gradient {
            gradient[k] -= m * a;
        }
        gaps.push(row.value);
    }
    if delta.iter().any(|d| *d != 0.0) {
        model.pull_back_gradient(delta, 1.0, &mut gradient);
    }
    gauge.fix_vector(&mut gradient);
    Ok(Kkt { gradient, gaps })
}

/// `Φ(plus) − Φ(minus)` at two points of the right-hand side (no chart increment:
/// both keep the base state's unknowns) with the same multipliers `mu` on the
/// `active` keys: the energy gradients' difference over the elements whose inputs
/// differ between the two designs ([`Model::gradient_difference`]), the active rows'
/// gradients and values as in [`residual`]. Also returns the elements evaluated in
/// each design.
pub(crate) fn residual_difference<B: Designed>(
    plus: &Point<B>,
    minus: &Point<B>,
    active: &[RowKey],
    mu: &[f64],
    gauge: &Gauge,
    parameter: usize,
) -> Result<(Kkt, usize), SensitivityError> {
    let difference =
        plus.built
            .model()
            .gradient_difference(&plus.state, minus.built.model(), &minus.state);
    let mut kkt = rows_difference(
        (&plus.rows, &minus.rows),
        active,
        mu,
        difference.gradient,
        parameter,
    )?;
    gauge.fix_vector(&mut kkt.gradient);
    Ok((kkt, difference.elements))
}

/// The active rows' part of `Φ(plus) − Φ(minus)` added to `gradient` (the energy
/// gradients' difference, or zeros): `−Σ μ_i (a_i⁺ − a_i⁻)` and `c_i⁺ − c_i⁻` of the
/// `active` keys with multipliers `mu`, from the rows at the two points.
pub(crate) fn rows_difference(
    (plus, minus): (&[Row], &[Row]),
    active: &[RowKey],
    mu: &[f64],
    mut gradient: Vec<f64>,
    parameter: usize,
) -> Result<Kkt, SensitivityError> {
    fn find(rows: &[Row], key: RowKey, parameter: usize) -> Result<&Row, SensitivityError> {
        rows.iter()
            .find(|r| r.key == key)
            .ok_or(SensitivityError::RowLost { parameter, key })
    }
    let mut gaps = Vec::with_capacity(active.len());
    for (&key, &m) in active.iter().zip(mu) {
        let (a, b) = (find(plus, key, parameter)?, find(minus, key, parameter)?);
        for &(k, g) in &a.gradient {
            gradient[k] -= m * g;
        }
        for &(k, g) in &b.gradient {
            gradient[k] += m * g;
        }
        gaps.push(a.value - b.value);
    }
    Ok(Kkt { gradient, gaps })
}

/// An [`Evaluation`] for the gradient alone: no storage for the Hessian's values
/// (an evaluation without the Hessian does not touch them), so that each of the
/// right-hand side's gradients does not allocate and zero the Hessian's pattern.
pub(crate) fn gradient_only(model: &Model) -> Evaluation {
    Evaluation {
        energy: 0.0,
        gradient: vec![0.0; model.dofs().len()],
        hessian: Vec::new(),
        has_hessian: false,
    }
}
