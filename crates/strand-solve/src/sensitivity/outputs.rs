//! Derivatives of outputs (reactions, peaks, clearances, poses, contact forces) by
//! the chain rule along the first-order path of the equilibrium.

use super::{Design, Sensitivities, SensitivityError};
use crate::Solution;

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
    /// Whether the arg-max/arg-min differs on the two sides of the parameter: the
    /// derivative is then one-sided (the central value averages the two sides).
    pub one_sided: bool,
}

impl Sensitivities {
    /// The design and an equilibrium-to-first-order at `p + t e_j`: the base state
    /// moved by `t · dδ/dp_j`, the active multipliers by `t · dμ/dp_j` (every other
    /// row at zero force). Its report is the base solution's.
    pub fn path_point<D: Design>(
        &self,
        design: &D,
        base: &Solution,
        parameter: usize,
        t: f64,
    ) -> Result<(D::Built, Solution), SensitivityError> {
        let p = &self.parameters[parameter];
        let (point, _, mu) =
            self.path(design, &base.state, parameter, t, &p.state, &p.multipliers)?;
        let constraints = point
            .rows
            .iter()
            .map(|row| {
                let force = self
                    .active
                    .iter()
                    .position(|k| *k == row.key)
                    .map_or(0.0, |i| mu[i]);
                (row.clone(), force)
            })
            .collect();
        let solution = Solution {
            state: point.state,
            report: base.report.clone(),
            constraints,
        };
        Ok((point.built, solution))
    }

    /// The derivatives of the outputs that `outputs` computes from a design and a
    /// solution, with respect to parameter `parameter`: central differences of steps
    /// `h` and `2h` along the first-order path, extrapolated (error `O(h⁴)`),
    /// one-sided where an output's arg differs on the two sides. `outputs` must return
    /// the same number of samples at every point.
    pub fn derivative<D: Design>(
        &self,
        design: &D,
        base: &Solution,
        parameter: usize,
        mut outputs: impl FnMut(&D::Built, &Solution) -> Vec<Sample>,
    ) -> Result<Vec<OutputDerivative>, SensitivityError> {
        let h = self.parameters[parameter].step;
        let mut samples = Vec::with_capacity(4);
        for t in [h, -h, 2.0 * h, -2.0 * h] {
            let (built, solution) = self.path_point(design, base, parameter, t)?;
            samples.push(outputs(&built, &solution));
        }
        let count = samples.iter().map(Vec::len).min().unwrap_or(0);
        Ok((0..count)
            .map(|k| {
                let fine = (samples[0][k].value - samples[1][k].value) / (2.0 * h);
                let coarse = (samples[2][k].value - samples[3][k].value) / (4.0 * h);
                OutputDerivative {
                    derivative: (4.0 * fine - coarse) / 3.0,
                    one_sided: samples[0][k].arg != samples[1][k].arg,
                }
            })
            .collect())
    }
}
