//! The heavy cantilever: a planar Reissner rod (extensible, shearable) clamped at
//! `s = 0` and free at `s = L`, under its own weight — a uniform load `q` per
//! *reference* length — and an optional dead tip force, with large deflections.
//!
//! # Model
//!
//! Same kinematics and constitutive law as [`super::reissner_planar`]: director angle
//! `θ(s)`, `t = (cos θ, sin θ)`, `d = (−sin θ, cos θ)`, material force components
//! `N = n·t`, `Q = n·d`, stretch `ν = 1 + N/EA`, shear `γ = Q/GA`, bending moment
//! `m = EI θ'`. Here `x` is horizontal and `y` points up; the load acts along `−y`.
//!
//! The internal force (exerted by the part beyond `s` on the part before `s`) follows
//! from the equilibrium of `[s, L]` and is known in closed form:
//!
//! ```text
//! n(s) = P + (0, −q (L − s)),
//! ```
//!
//! with `P` the dead tip force (N). The remaining equations are
//!
//! ```text
//! x' = ν cos θ − γ sin θ,   y' = ν sin θ + γ cos θ,   θ' = m/EI,   m' = −(ν Q − γ N),
//! ```
//!
//! with `r(0) = 0`, `θ(0) = θ₀` (the clamp angle) and the free-end condition `m(L) = 0`.
//! The boundary value problem is solved by shooting on the clamp moment `m(0)`; the
//! derivative `∂m(L)/∂m(0)` comes from the variational equations integrated alongside
//! (`δθ' = δm/EI`, `δm' = −∂(νQ − γN)/∂θ · δθ` with
//! `∂(νQ − γN)/∂θ = −N + (Q² − N²)(1/EA − 1/GA)`). Large loads are reached by
//! continuation in `q` (each step started from the previous clamp moment).
//!
//! The support at the clamp exerts the force `−n(0)` and the moment `−m(0)` on the rod.
//!
//! # Accuracy
//!
//! The ODE is integrated with the 16th-order [`Gbs`] method (64 macro steps; halving
//! the step changes the tip by < 1e-13 m at `qL³/EI = 50`), and Newton is converged
//! until `|m(L)| ≤ 1e-13 EI/L`. The self-checks compare with the linear theory at a
//! small load (Timoshenko beam: tip deflection `qL⁴/8EI + qL²/2GA`) and verify the
//! global moment balance `m(0) = −q ∫ (x(s) − x(0)) ds` (+ the tip force's moment) by
//! an independent quadrature.

use super::ode::Gbs;

/// A planar heavy cantilever.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeavyCantilever {
    /// Reference length `L` (m).
    pub length: f64,
    /// Bending stiffness `EI` (N·m²).
    pub ei: f64,
    /// Shear stiffness `GA` (N); `f64::INFINITY` for an unshearable rod.
    pub ga: f64,
    /// Axial stiffness `EA` (N); `f64::INFINITY` for an inextensible rod.
    pub ea: f64,
    /// Load per reference length `q` (N/m), acting along `−y`.
    pub load: f64,
    /// Dead tip force `P = (Pₓ, P_y)` (N).
    pub tip_force: [f64; 2],
    /// Clamp angle `θ₀` (rad) from `+x`.
    pub clamp_angle: f64,
}

/// The solution of a [`HeavyCantilever`].
#[derive(Clone, Debug)]
pub struct HeavySolution {
    /// The problem.
    pub problem: HeavyCantilever,
    /// Internal moment at the clamp `m(0)` (N·m); the clamp exerts `−m(0)` on the rod.
    pub clamp_moment: f64,
    /// Tip position `r(L)` (m).
    pub tip: [f64; 2],
    /// Tip angle `θ(L)` (rad).
    pub tip_angle: f64,
    /// Residual `m(L)` (N·m).
    pub tip_moment: f64,
    nodes: Vec<f64>,
    states: Vec<[f64; 4]>,
    integrator: Gbs,
}

impl HeavyCantilever {
    /// Internal force `n(s)` (N).
    pub fn force(&self, s: f64) -> [f64; 2] {
        [
            self.tip_force[0],
            self.tip_force[1] - self.load * (self.length - s),
        ]
    }

    /// Right-hand side for `y = [x, y, θ, m, δθ, δm]` (state and its derivative with
    /// respect to the clamp moment).
    fn rhs(&self, s: f64, y: &[f64; 6]) -> [f64; 6] {
        let [fx, fy] = self.force(s);
        let (sn, cs) = y[2].sin_cos();
        let n = fx * cs + fy * sn;
        let q = -fx * sn + fy * cs;
        let (nu, gamma) = (1.0 + n / self.ea, q / self.ga);
        let dg = -n + (q * q - n * n) * (1.0 / self.ea - 1.0 / self.ga);
        [
            nu * cs - gamma * sn,
            nu * sn + gamma * cs,
            y[3] / self.ei,
            -(nu * q - gamma * n),
            y[5] / self.ei,
            -dg * y[4],
        ]
    }

    fn shoot(&self, m0: f64, integ: &Gbs) -> [f64; 6] {
        let f = |s: f64, y: &[f64; 6]| self.rhs(s, y);
        integ.integrate(
            &f,
            0.0,
            self.length,
            &[0.0, 0.0, self.clamp_angle, m0, 0.0, 1.0],
        )
    }

    /// Newton on `m(0)` from `m0`; `None` if it does not converge.
    fn newton(&self, mut m0: f64, integ: &Gbs) -> Option<f64> {
        let scale = self.ei / self.length;
        for _ in 0..50 {
            let y = self.shoot(m0, integ);
            if !y.iter().all(|v| v.is_finite()) {
                return None;
            }
            if y[3].abs() <= 1e-13 * scale {
                return Some(m0);
            }
            let step = y[3] / y[5];
            // Limit the step to a fraction of the bending scale (large loads).
            let limit = 0.5 * scale.max(m0.abs());
            m0 -= step.clamp(-limit, limit);
        }
        let y = self.shoot(m0, integ);
        (y[3].abs() <= 1e-11 * scale).then_some(m0)
    }

    /// Solves with the default integrator (64 macro steps, order 16).
    pub fn solve(&self) -> HeavySolution {
        self.solve_with(&Gbs::default())
    }

    /// Solves with the given integrator, by continuation in the load (and tip force)
    /// from the unloaded rod.
    ///
    /// # Panics
    /// If the shooting fails.
    pub fn solve_with(&self, integ: &Gbs) -> HeavySolution {
        let mut m0 = 0.0;
        let steps = 20;
        for k in 1..=steps {
            let t = k as f64 / steps as f64;
            let partial = HeavyCantilever {
                load: t * self.load,
                tip_force: [t * self.tip_force[0], t * self.tip_force[1]],
                ..*self
            };
            m0 = partial
                .newton(m0, integ)
                .unwrap_or_else(|| panic!("heavy cantilever shooting failed at {t}"));
        }
        let f = |s: f64, y: &[f64; 6]| self.rhs(s, y);
        let (nodes, states6) = integ.integrate_grid(
            &f,
            0.0,
            self.length,
            &[0.0, 0.0, self.clamp_angle, m0, 0.0, 1.0],
        );
        let states: Vec<[f64; 4]> = states6.iter().map(|y| [y[0], y[1], y[2], y[3]]).collect();
        let last = states.last().unwrap();
        HeavySolution {
            problem: *self,
            clamp_moment: m0,
            tip: [last[0], last[1]],
            tip_angle: last[2],
            tip_moment: last[3],
            nodes,
            states,
            integrator: *integ,
        }
    }
}

impl HeavySolution {
    /// State `[x, y, θ, m]` at `s` (m), by one extrapolated step from the previous
    /// grid node (as accurate as the nodes).
    pub fn state(&self, s: f64) -> [f64; 4] {
        let s = s.clamp(0.0, self.problem.length);
        let h = self.problem.length / (self.nodes.len() - 1) as f64;
        let k = ((s / h).floor() as usize).min(self.nodes.len() - 1);
        let y0 = self.states[k];
        let f = |s: f64, y: &[f64; 6]| self.problem.rhs(s, y);
        let y = self.integrator.step(
            &f,
            self.nodes[k],
            &[y0[0], y0[1], y0[2], y0[3], 0.0, 0.0],
            s - self.nodes[k],
        );
        [y[0], y[1], y[2], y[3]]
    }

    /// Position `r(s)` (m).
    pub fn position(&self, s: f64) -> [f64; 2] {
        let y = self.state(s);
        [y[0], y[1]]
    }

    /// Force the clamp exerts on the rod, `−n(0)` (N).
    pub fn clamp_force(&self) -> [f64; 2] {
        let [fx, fy] = self.problem.force(0.0);
        [-fx, -fy]
    }

    /// Moment the clamp exerts on the rod (about the clamp point), `−m(0)` (N·m).
    pub fn clamp_reaction_moment(&self) -> f64 {
        -self.clamp_moment
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn problem(ql3_over_ei: f64) -> HeavyCantilever {
        HeavyCantilever {
            length: 1.0,
            ei: 1.0,
            ga: 1e4,
            ea: 3e4,
            load: ql3_over_ei,
            tip_force: [0.0, 0.0],
            clamp_angle: 0.0,
        }
    }

    #[test]
    fn small_load_matches_the_timoshenko_beam() {
        let p = HeavyCantilever {
            load: 1e-4,
            ..problem(0.0)
        };
        let sol = p.solve();
        let linear = p.load / (8.0 * p.ei) + p.load / (2.0 * p.ga);
        // Geometric nonlinearity is O(q²): relative 1e-4 at this load.
        assert!(
            ((-sol.tip[1] - linear) / linear).abs() < 1e-6,
            "{} vs {linear}",
            -sol.tip[1]
        );
        assert!(((sol.clamp_moment + p.load / 2.0) / (p.load / 2.0)).abs() < 1e-6);
    }

    #[test]
    fn global_moment_balance_and_integrator_refinement() {
        for (load, tip) in [(10.0, [0.0, 0.0]), (50.0, [0.0, 0.0]), (10.0, [1.0, -2.0])] {
            let p = HeavyCantilever {
                tip_force: tip,
                clamp_angle: 0.3,
                ..problem(load)
            };
            let sol = p.solve();
            assert!(sol.tip_moment.abs() < 1e-12);
            // Moment balance of the whole rod about the clamp point:
            // m(0) = ∫ x q ds·(−1)·(−1)... i.e. m(0) = r_tip × P + ∫ r × (0, −q) ds (z).
            let n = 2000;
            let h = p.length / n as f64;
            let mut integral = 0.0;
            // Composite Simpson on the dense solution.
            for k in 0..=n {
                let wgt = if k == 0 || k == n {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                integral += wgt * sol.position(k as f64 * h)[0];
            }
            integral *= h / 3.0;
            let moment_about_clamp = sol.tip[0] * tip[1] - sol.tip[1] * tip[0] - p.load * integral;
            // The part [0, L] is acted on by −n(0), −m(0) at the clamp and the loads:
            // −m(0) + moment_about_clamp = 0.
            assert!(
                (sol.clamp_moment - moment_about_clamp).abs() < 1e-10 * load,
                "{} vs {moment_about_clamp}",
                sol.clamp_moment
            );
            let coarse = p.solve_with(&Gbs::new(32, 8));
            assert!(
                (coarse.tip[0] - sol.tip[0]).abs() < 1e-12
                    && (coarse.tip[1] - sol.tip[1]).abs() < 1e-12,
                "{:?} vs {:?}",
                coarse.tip,
                sol.tip
            );
        }
    }

    #[test]
    fn heavier_cantilever_droops_further() {
        let (a, b) = (problem(10.0).solve(), problem(50.0).solve());
        assert!(b.tip[1] < a.tip[1] && a.tip[1] < 0.0);
        assert!(b.tip[0] < a.tip[0]);
    }
}
