//! The trust-region subproblem: in the variables scaled by their bounds' widths
//! (`s_j = Δx_j / width_j`), the objective normalised by its starting size and every
//! constraint row by its bound,
//!
//! ```text
//!   min  t + ½ sᵀ B s + ρ Σ e_k
//!   s.t. f_i + g_iᵀ s ≤ t            (one row per objective piece: the epigraph of the max)
//!        c_k + a_kᵀ s + e_k ≥ 0,  e_k ≥ 0   (constraints, elastic: always feasible)
//!        lo_j ≤ s_j ≤ hi_j           (the bounds intersected with the trust region)
//! ```
//!
//! solved by clarabel (`A y + z = b, z ≥ 0`); its duals are the pieces' weights
//! (summing to 1), the constraints' multipliers and the bounds'.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus};
use nalgebra::DMatrix;

use super::OptimizeError;

/// An affine model `value + gradientᵀ s` (normalised, per scaled variable).
#[derive(Clone, Debug, PartialEq)]
pub struct Affine {
    /// Value at `s = 0`.
    pub value: f64,
    /// Gradient per scaled variable.
    pub gradient: Vec<f64>,
}

impl Affine {
    /// The value at `s`.
    pub fn at(&self, s: &[f64]) -> f64 {
        self.value + self.gradient.iter().zip(s).map(|(g, x)| g * x).sum::<f64>()
    }
}

/// The subproblem at one point.
pub struct Subproblem<'a> {
    /// Objective pieces.
    pub pieces: &'a [Affine],
    /// Constraint rows (`≥ 0` when satisfied).
    pub rows: &'a [Affine],
    /// The curvature model `B` (positive semidefinite, scaled variables).
    pub curvature: &'a DMatrix<f64>,
    /// Lower step bounds (≤ 0).
    pub lower: &'a [f64],
    /// Upper step bounds (≥ 0).
    pub upper: &'a [f64],
    /// The penalty `ρ` on constraint violation.
    pub penalty: f64,
}

/// The subproblem's solution.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// The step in scaled variables.
    pub s: Vec<f64>,
    /// The model's value `max_i (f_i + g_iᵀ s) + ½ sᵀ B s + ρ Σ max(0, −c_k − a_kᵀ s)`.
    pub model: f64,
    /// The pieces' weights (≥ 0, summing to 1).
    pub weights: Vec<f64>,
    /// The rows' multipliers (≥ 0, ≤ ρ).
    pub multipliers: Vec<f64>,
    /// The multipliers of the lower and upper step bounds per variable.
    pub bound_multipliers: Vec<(f64, f64)>,
}

impl Subproblem<'_> {
    /// The model's value at `s` (the merit's model).
    pub fn model(&self, s: &[f64]) -> f64 {
        let top = self
            .pieces
            .iter()
            .map(|p| p.at(s))
            .fold(f64::NEG_INFINITY, f64::max);
        let bs = self.curvature * nalgebra::DVector::from_column_slice(s);
        let quad = 0.5 * s.iter().zip(bs.iter()).map(|(a, b)| a * b).sum::<f64>();
        let violation: f64 = self.rows.iter().map(|r| (-r.at(s)).max(0.0)).sum();
        top + quad + self.penalty * violation
    }

    /// Solves the subproblem.
    pub fn solve(&self) -> Result<Step, OptimizeError> {
        let n = self.lower.len();
        let (np, m) = (self.pieces.len(), self.rows.len());
        // Unknowns: s (n), t, e (m).
        let dim = n + 1 + m;
        let t = n;
        let mut p_entries = Vec::new();
        for c in 0..n {
            for r in 0..=c {
                let v = 0.5 * (self.curvature[(r, c)] + self.curvature[(c, r)]);
                if v != 0.0 {
                    p_entries.push((r, c, v));
                }
            }
        }
        let mut a_entries = Vec::new();
        let mut b = Vec::new();
        let mut row = 0;
        for p in self.pieces {
            for (j, g) in p.gradient.iter().enumerate() {
                a_entries.push((row, j, *g));
            }
            a_entries.push((row, t, -1.0));
            b.push(-p.value);
            row += 1;
        }
        for (k, r) in self.rows.iter().enumerate() {
            for (j, g) in r.gradient.iter().enumerate() {
                a_entries.push((row, j, -g));
            }
            a_entries.push((row, n + 1 + k, -1.0));
            b.push(r.value);
            row += 1;
        }
        for k in 0..m {
            a_entries.push((row, n + 1 + k, -1.0));
            b.push(0.0);
            row += 1;
        }
        for j in 0..n {
            a_entries.push((row, j, -1.0));
            b.push(-self.lower[j]);
            a_entries.push((row + 1, j, 1.0));
            b.push(self.upper[j]);
            row += 2;
        }
        let mut q = vec![0.0; dim];
        q[t] = 1.0;
        for k in 0..m {
            q[n + 1 + k] = self.penalty;
        }
        let p = csc(dim, dim, p_entries);
        let a = csc(row, dim, a_entries);
        let cones = [NonnegativeConeT(row)];
        let settings = DefaultSettings::<f64> {
            verbose: false,
            ..Default::default()
        };
        let mut solver = DefaultSolver::new(&p, &q, &a, &b, &cones, settings)
            .map_err(|e| OptimizeError::Subproblem(format!("set-up: {e:?}")))?;
        solver.solve();
        match solver.solution.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => {}
            status => return Err(OptimizeError::Subproblem(format!("{status:?}"))),
        }
        let x = &solver.solution.x;
        let z: Vec<f64> = solver.solution.z.iter().map(|v| v.max(0.0)).collect();
        let s: Vec<f64> = (0..n)
            .map(|j| x[j].clamp(self.lower[j], self.upper[j]))
            .collect();
        let base = np + 2 * m;
        Ok(Step {
            model: self.model(&s),
            weights: z[..np].to_vec(),
            multipliers: z[np..np + m].to_vec(),
            bound_multipliers: (0..n)
                .map(|j| (z[base + 2 * j], z[base + 2 * j + 1]))
                .collect(),
            s,
        })
    }
}

/// A compressed-column matrix from `(row, column, value)` entries (duplicates summed).
fn csc(rows: usize, cols: usize, mut entries: Vec<(usize, usize, f64)>) -> CscMatrix<f64> {
    entries.sort_by_key(|&(r, c, _)| (c, r));
    let mut col_ptr = vec![0; cols + 1];
    let mut row_idx: Vec<usize> = Vec::with_capacity(entries.len());
    let mut values: Vec<f64> = Vec::with_capacity(entries.len());
    let mut last: Option<(usize, usize)> = None;
    for (r, c, v) in entries {
        if last == Some((r, c)) {
            *values.last_mut().expect("an entry") += v;
            continue;
        }
        row_idx.push(r);
        values.push(v);
        col_ptr[c + 1] += 1;
        last = Some((r, c));
    }
    for c in 0..cols {
        col_ptr[c + 1] += col_ptr[c];
    }
    CscMatrix::new(rows, cols, col_ptr, row_idx, values)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// min max(x, 1 − x) over [0, 1] from 0 with a unit trust region: the kink at 1/2
    /// with equal weights.
    #[test]
    fn the_epigraph_finds_the_kink_of_a_min_max() {
        let pieces = [
            Affine {
                value: 0.0,
                gradient: vec![1.0],
            },
            Affine {
                value: 1.0,
                gradient: vec![-1.0],
            },
        ];
        let b = DMatrix::zeros(1, 1);
        let step = Subproblem {
            pieces: &pieces,
            rows: &[],
            curvature: &b,
            lower: &[0.0],
            upper: &[1.0],
            penalty: 10.0,
        }
        .solve()
        .unwrap();
        assert!((step.s[0] - 0.5).abs() < 1e-7, "{step:?}");
        assert!((step.model - 0.5).abs() < 1e-7);
        assert!((step.weights[0] - 0.5).abs() < 1e-6 && (step.weights[1] - 0.5).abs() < 1e-6);
    }

    /// min ½ (s − 2)² written as piece −2 s with B = 1, subject to s ≤ 1 as a row
    /// 1 − s ≥ 0: the bound is active with multiplier 1 (= −d objective / d s at 1).
    #[test]
    fn an_active_row_carries_the_objective_slope() {
        let pieces = [Affine {
            value: 0.0,
            gradient: vec![-2.0],
        }];
        let rows = [Affine {
            value: 1.0,
            gradient: vec![-1.0],
        }];
        let b = DMatrix::from_element(1, 1, 1.0);
        let step = Subproblem {
            pieces: &pieces,
            rows: &rows,
            curvature: &b,
            lower: &[-5.0],
            upper: &[5.0],
            penalty: 10.0,
        }
        .solve()
        .unwrap();
        assert!((step.s[0] - 1.0).abs() < 1e-6, "{step:?}");
        assert!((step.multipliers[0] - 1.0).abs() < 1e-6, "{step:?}");
    }

    /// A row that cannot be met inside the trust region is violated as little as the
    /// region allows (elastic), not reported infeasible.
    #[test]
    fn an_unreachable_row_is_met_as_far_as_the_trust_region_allows() {
        let pieces = [Affine {
            value: 0.0,
            gradient: vec![0.1],
        }];
        let rows = [Affine {
            value: -3.0,
            gradient: vec![1.0],
        }];
        let b = DMatrix::zeros(1, 1);
        let step = Subproblem {
            pieces: &pieces,
            rows: &rows,
            curvature: &b,
            lower: &[-1.0],
            upper: &[1.0],
            penalty: 10.0,
        }
        .solve()
        .unwrap();
        assert!((step.s[0] - 1.0).abs() < 1e-6, "{step:?}");
        assert!((step.model - (0.1 + 10.0 * 2.0)).abs() < 1e-5);
    }
}
