//! Derivatives of outputs (reactions, peaks, clearances, poses, contact forces) by
//! the chain rule along the first-order path of the equilibrium.

use super::kkt::RowsAt;
use super::{Design, Sensitivities, SensitivityError};
use crate::Solution;
use crate::constraints::RowKey;

/// One output value, with where a peak or minimum is attained (`arg`: any index that
/// changes when the location jumps, e.g. the vertex of a peak; 0 for a smooth output).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// The value, in the output's unit.
    pub value: f64,
    /// Where it is attained.
    pub arg: usize,
}

/// The derivative of one output with respect to one parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutputDerivative {
    /// The output's unit per parameter unit.
    pub derivative: f64,
    /// Whether the arg-max/arg-min differs between the base and a side of the
    /// difference: the derivative is then one-sided.
    pub one_sided: bool,
}

impl Sensitivities {
    /// The design and an equilibrium-to-first-order at `p + t e_j`: the base state
    /// moved by `t · dδ/dp_j`, the active multipliers by `t · dμ/dp_j`; its
    /// constraints are as `rows` says. Its report is the base solution's.
    pub fn path_point<D: Design>(
        &self,
        design: &D,
        base: &Solution,
        parameter: usize,
        t: f64,
        rows: PathRows,
    ) -> Result<(D::Built, Solution), SensitivityError> {
        let p = &self.parameters[parameter];
        let evaluated = match rows {
            PathRows::All => RowsAt::Evaluated,
            PathRows::Active => RowsAt::Skipped,
        };
        let (point, _, mu) = self.path(
            design,
            &base.state,
            parameter,
            t,
            &p.state,
            &p.multipliers,
            evaluated,
        )?;
        // The moved multipliers by key, looked up by bisection (not a scan of the
        // active rows per row: thousands of each on a long cable lying on a floor).
        let mut by_key: Vec<(RowKey, f64)> = self
            .active
            .iter()
            .copied()
            .zip(mu.iter().copied())
            .collect();
        by_key.sort_by_key(|(k, _)| *k);
        let force = |key: &RowKey| {
            by_key
                .binary_search_by_key(key, |(k, _)| *k)
                .ok()
                .map(|i| by_key[i].1)
        };
        let constraints = match rows {
            PathRows::All => point
                .rows
                .iter()
                .map(|row| (row.clone(), force(&row.key).unwrap_or(0.0)))
                .collect(),
            PathRows::Active => base
                .constraints
                .iter()
                .filter_map(|(row, _)| Some((row.clone(), force(&row.key)?)))
                .collect(),
        };
        let solution = Solution {
            state: point.state,
            report: base.report.clone(),
            constraints,
            analysis: base.analysis.clone(),
            // A point along the path, not the equilibrium the Hessian is of.
            hessian: None,
        };
        Ok((point.built, solution))
    }

    /// The derivatives of the outputs that `outputs` computes from a design and a
    /// solution, with respect to parameter `parameter`: [`Sensitivities::derivative_at`]
    /// with the same evaluation at every point of the path (its constraints as `rows`
    /// says).
    pub fn derivative<D: Design>(
        &self,
        design: &D,
        base: &Solution,
        parameter: usize,
        rows: PathRows,
        mut outputs: impl FnMut(&D::Built, &Solution) -> Vec<Sample>,
    ) -> Result<Vec<OutputDerivative>, SensitivityError> {
        self.derivative_at(design, base, parameter, rows, |built, at, _| {
            outputs(built, at)
        })
    }

    /// The derivatives of the outputs that `outputs` computes from a design, a
    /// solution and the [`PathPlace`] of the point (its constraints as `rows` says:
    /// [`PathRows`]), with respect to parameter `parameter`, by the chain rule along
    /// the first-order path: central differences
    /// of steps `h` and `2h`, extrapolated (error `O(h⁴)`), at up to three steps `h`,
    /// `h/10`, `h/100` (`h` the parameter's
    /// [`super::ParameterSensitivity::output_step`]). Per output, the largest step is
    /// taken whose result the next smaller one confirms (to [`STEP_AGREEMENT`]);
    /// otherwise the middle step when the smallest agrees with it better than with the
    /// largest (the output is nonlinear at the scale of `h`: a rod near a limit
    /// point), else the largest (the smaller steps see round-off of reactions summed
    /// from stiff forces). The smallest step is evaluated only when some output's
    /// largest step is not confirmed by the middle one (the choice is then the same as
    /// with all three). One-sided where an output's arg at a point differs from its
    /// arg at the base; `outputs` may report the base's arg everywhere except at the
    /// [`PathPlace::Outermost`] points (`±2h` of the largest step), where a jump of
    /// the arg-max within the steps shows. `outputs` must return the same number of
    /// samples at every point.
    pub fn derivative_at<D: Design>(
        &self,
        design: &D,
        base: &Solution,
        parameter: usize,
        rows: PathRows,
        mut outputs: impl FnMut(&D::Built, &Solution, PathPlace) -> Vec<Sample>,
    ) -> Result<Vec<OutputDerivative>, SensitivityError> {
        self.derivative_along(parameter, |t, place| {
            let (built, at) = self.path_point(design, base, parameter, t, rows)?;
            Ok(outputs(&built, &at, place))
        })
    }

    /// [`Sensitivities::derivative_at`] with the outputs at the point `t` of the
    /// first-order path of parameter `parameter` (in the parameter's unit; `t = 0` is
    /// the base, [`PathPlace::Base`]) computed by `outputs`: the same steps, the same
    /// choice among them and the same one-sided marks, for a caller that evaluates the
    /// outputs at a point without building the design there (e.g. from the few
    /// elements each output reads).
    pub fn derivative_along<E>(
        &self,
        parameter: usize,
        mut outputs: impl FnMut(f64, PathPlace) -> Result<Vec<Sample>, E>,
    ) -> Result<Vec<OutputDerivative>, E> {
        let centre = outputs(0.0, PathPlace::Base)?;
        let count = centre.len();
        let mut rung = |k: i32| -> Result<Vec<OutputDerivative>, E> {
            let h = self.parameters[parameter].output_step * 0.1f64.powi(k);
            let mut samples = Vec::with_capacity(4);
            for t in [h, -h, 2.0 * h, -2.0 * h] {
                let place = if k == 0 && t.abs() > 1.5 * h {
                    PathPlace::Outermost
                } else {
                    PathPlace::Inner
                };
                samples.push(outputs(t, place)?);
            }
            Ok((0..count)
                .map(|j| {
                    let value = |i: usize| samples[i].get(j).map_or(f64::NAN, |s| s.value);
                    let fine = (value(0) - value(1)) / (2.0 * h);
                    let coarse = (value(2) - value(3)) / (4.0 * h);
                    OutputDerivative {
                        derivative: (4.0 * fine - coarse) / 3.0,
                        one_sided: samples
                            .iter()
                            .any(|s| s.get(j).is_none_or(|s| s.arg != centre[j].arg)),
                    }
                })
                .collect())
        };
        let apart = |a: OutputDerivative, b: OutputDerivative| (a.derivative - b.derivative).abs();
        let confirmed = |large: OutputDerivative, middle: OutputDerivative| {
            apart(large, middle) <= STEP_AGREEMENT * middle.derivative.abs()
        };
        let (large, middle) = (rung(0)?, rung(1)?);
        let small = if large.iter().zip(&middle).all(|(l, m)| confirmed(*l, *m)) {
            None
        } else {
            Some(rung(2)?)
        };
        Ok((0..count)
            .map(|j| {
                let (large, middle) = (large[j], middle[j]);
                let small = small.as_ref().map(|s| s[j]);
                let chosen = match small {
                    _ if confirmed(large, middle) => large,
                    Some(small) if apart(middle, small) < apart(large, middle) => middle,
                    _ => large,
                };
                OutputDerivative {
                    derivative: chosen.derivative,
                    one_sided: large.one_sided
                        || middle.one_sided
                        || small.is_some_and(|s| s.one_sided),
                }
            })
            .collect())
    }
}

/// The constraints of a point of the first-order path
/// ([`Sensitivities::path_point`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathRows {
    /// Every joint-limit and contact row evaluated at the point, each with its
    /// multiplier moved along the path (zero unless active at the base).
    All,
    /// Only the base's active rows, with their multipliers moved along the path
    /// (their values are the base's): enough for what takes a pair's force by its
    /// key ([`crate::contact::Contact::forces`]: a contact at the point carries its
    /// multiplier when its key is active, none otherwise, as with
    /// [`PathRows::All`]), without evaluating the rows at every point.
    Active,
}

/// Where on the first-order path [`Sensitivities::derivative_at`] evaluates the
/// outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathPlace {
    /// The base equilibrium (`t = 0`).
    Base,
    /// The outermost points, `t = ±2h` of the largest step: where a jump of an
    /// arg-max or arg-min within the steps is looked for.
    Outermost,
    /// Every other point (its args may be reported as the base's).
    Inner,
}

/// Relative agreement of two steps' derivatives that confirms the larger step.
pub const STEP_AGREEMENT: f64 = 1e-6;
