//! Gragg–Bulirsch–Stoer (GBS) extrapolation integrator with a fixed step grid.
//!
//! Each macro step of length `H` runs Gragg's modified midpoint rule with
//! `n_j = 2, 4, 6, …, 2·levels` sub-steps and extrapolates the results to
//! `h → 0` with the Aitken–Neville scheme in `h²`.  With `levels = k` the
//! local error is `O(H^(2k+1))`, i.e. the method has order `2k`.  The
//! default (`levels = 8`, 64 macro steps per interval) is a 16th-order
//! method; on the smooth problems of this crate it reaches round-off level
//! (≈ 1e-15 relative) accuracy.
//!
//! The integrator is deliberately simple and self-contained (no step-size
//! control) so that the references do not depend on any other code.

/// Fixed-grid Gragg–Bulirsch–Stoer integrator for `y' = f(s, y)`,
/// `y ∈ ℝᴺ` (the independent variable `s` carries whatever unit the
/// problem uses, typically metres of reference arc length).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Gbs {
    /// Number of equal macro steps used by [`Gbs::integrate`] and
    /// [`Gbs::integrate_grid`] to cover an interval (dimensionless).
    pub steps: usize,
    /// Number of extrapolation levels `k` (dimensionless); the method has
    /// order `2k`.
    pub levels: usize,
}

impl Default for Gbs {
    /// 64 macro steps, 8 levels (order 16).
    fn default() -> Self {
        Self {
            steps: 64,
            levels: 8,
        }
    }
}

/// `a + c·b` component-wise.
fn axpy<const N: usize>(a: &[f64; N], c: f64, b: &[f64; N]) -> [f64; N] {
    std::array::from_fn(|i| a[i] + c * b[i])
}

impl Gbs {
    /// Creates an integrator with `steps` macro steps per interval and
    /// `levels` extrapolation levels (order `2·levels`).
    ///
    /// # Panics
    /// If `steps == 0` or `levels == 0`.
    pub fn new(steps: usize, levels: usize) -> Self {
        assert!(
            steps > 0 && levels > 0,
            "Gbs needs steps > 0 and levels > 0"
        );
        Self { steps, levels }
    }

    /// Gragg's modified midpoint rule with `n` (even) sub-steps over
    /// `[s0, s0 + big_h]`, including the final smoothing step.  Works with
    /// the increment `u = z − y0` (small, `O(H)`) to limit round-off, and
    /// returns the increment `y(s0 + H) − y0`.
    fn midpoint<const N: usize, F>(f: &F, s0: f64, y0: &[f64; N], big_h: f64, n: usize) -> [f64; N]
    where
        F: Fn(f64, &[f64; N]) -> [f64; N],
    {
        let h = big_h / n as f64;
        let eval = |s: f64, u: &[f64; N]| f(s, &std::array::from_fn(|i| y0[i] + u[i]));
        let mut u_prev = [0.0; N];
        let mut u = axpy(&u_prev, h, &f(s0, y0));
        for m in 1..n {
            let u_next = axpy(&u_prev, 2.0 * h, &eval(s0 + m as f64 * h, &u));
            u_prev = u;
            u = u_next;
        }
        let fu = eval(s0 + big_h, &u);
        std::array::from_fn(|i| 0.5 * (u[i] + u_prev[i] + h * fu[i]))
    }

    /// Extrapolated increment `y(s0 + h) − y(s0)` of one step.
    fn increment<const N: usize, F>(&self, f: &F, s0: f64, y0: &[f64; N], h: f64) -> [f64; N]
    where
        F: Fn(f64, &[f64; N]) -> [f64; N],
    {
        let seq = |j: usize| 2 * (j + 1);
        // `row` holds T[j-1][0..j] of the Aitken–Neville tableau.
        let mut row: Vec<[f64; N]> = Vec::with_capacity(self.levels);
        for j in 0..self.levels {
            let mut new_row = Vec::with_capacity(j + 1);
            new_row.push(Self::midpoint(f, s0, y0, h, seq(j)));
            for k in 1..=j {
                let ratio = seq(j) as f64 / seq(j - k) as f64;
                let denom = ratio * ratio - 1.0;
                let t_hi = new_row[k - 1];
                let t_lo = row[k - 1];
                new_row.push(std::array::from_fn(|i| {
                    t_hi[i] + (t_hi[i] - t_lo[i]) / denom
                }));
            }
            row = new_row;
        }
        row[self.levels - 1]
    }

    /// One extrapolated step from `(s0, y0)` to `s0 + h`.
    pub fn step<const N: usize, F>(&self, f: &F, s0: f64, y0: &[f64; N], h: f64) -> [f64; N]
    where
        F: Fn(f64, &[f64; N]) -> [f64; N],
    {
        if h == 0.0 {
            return *y0;
        }
        let du = self.increment(f, s0, y0, h);
        std::array::from_fn(|i| y0[i] + du[i])
    }

    /// Integrates from `(s0, y0)` to `s1` with [`Gbs::steps`] equal macro
    /// steps and returns `y(s1)`.
    pub fn integrate<const N: usize, F>(&self, f: &F, s0: f64, s1: f64, y0: &[f64; N]) -> [f64; N]
    where
        F: Fn(f64, &[f64; N]) -> [f64; N],
    {
        let (_, states) = self.run(f, s0, s1, y0, false);
        states[0]
    }

    /// Like [`Gbs::integrate`] but returns all `steps + 1` grid nodes
    /// `s_k = s0 + k (s1 - s0)/steps` and the states `y(s_k)`.
    pub fn integrate_grid<const N: usize, F>(
        &self,
        f: &F,
        s0: f64,
        s1: f64,
        y0: &[f64; N],
    ) -> (Vec<f64>, Vec<[f64; N]>)
    where
        F: Fn(f64, &[f64; N]) -> [f64; N],
    {
        self.run(f, s0, s1, y0, true)
    }

    /// Macro-step loop with Kahan-compensated accumulation of the
    /// increments.  Returns either all nodes (`keep_all`) or only the last.
    fn run<const N: usize, F>(
        &self,
        f: &F,
        s0: f64,
        s1: f64,
        y0: &[f64; N],
        keep_all: bool,
    ) -> (Vec<f64>, Vec<[f64; N]>)
    where
        F: Fn(f64, &[f64; N]) -> [f64; N],
    {
        let h = (s1 - s0) / self.steps as f64;
        let node = |k: usize| {
            if k == self.steps {
                s1
            } else {
                s0 + k as f64 * h
            }
        };
        let mut y = *y0;
        let mut comp = [0.0; N];
        let (mut nodes, mut states) = (vec![s0], vec![*y0]);
        for k in 0..self.steps {
            let du = self.increment(f, node(k), &y, node(k + 1) - node(k));
            for i in 0..N {
                let add = du[i] - comp[i];
                let sum = y[i] + add;
                comp[i] = (sum - y[i]) - add;
                y[i] = sum;
            }
            if keep_all {
                nodes.push(node(k + 1));
                states.push(y);
            }
        }
        if !keep_all {
            (nodes, states) = (vec![s1], vec![y]);
        }
        (nodes, states)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn harmonic_oscillator_is_exact_to_round_off() {
        // y'' = -y, y(0) = 0, y'(0) = 1  =>  y = sin s.
        let f = |_s: f64, y: &[f64; 2]| [y[1], -y[0]];
        let y = Gbs::default().integrate(&f, 0.0, 10.0, &[0.0, 1.0]);
        assert!((y[0] - 10f64.sin()).abs() < 1e-13, "{}", y[0] - 10f64.sin());
        assert!((y[1] - 10f64.cos()).abs() < 1e-13);
    }

    #[test]
    fn non_autonomous_quadrature() {
        // y' = cos(s) e^{sin s}  =>  y = e^{sin s} - 1.
        let f = |s: f64, _y: &[f64; 1]| [s.cos() * s.sin().exp()];
        let y = Gbs::new(16, 6).integrate(&f, 0.0, 3.0, &[0.0]);
        let exact = 3f64.sin().exp() - 1.0;
        assert!((y[0] - exact).abs() < 1e-14);
    }

    #[test]
    fn order_is_two_times_levels() {
        // With 2 levels (order 4) halving the step should reduce the
        // error by ≈ 2⁴ = 16.
        let f = |_s: f64, y: &[f64; 1]| [y[0]];
        let err =
            |steps| (Gbs::new(steps, 2).integrate(&f, 0.0, 1.0, &[1.0])[0] - 1f64.exp()).abs();
        let ratio = err(8) / err(16);
        assert!((ratio - 16.0).abs() < 1.0, "ratio {ratio}");
    }
}
