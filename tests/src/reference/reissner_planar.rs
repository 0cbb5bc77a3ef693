//! Planar Reissner elastica (extensible, shearable), clamped at `s = 0`,
//! loaded by a constant sectional force (a dead force at the free tip).
//!
//! # Model
//!
//! Reference arc length `s ∈ [0, L]` (m).  Director angle `θ(s)` (rad),
//! tangent director `t = (cos θ, sin θ)`, normal director
//! `d = (−sin θ, cos θ)`.  With no distributed load the internal force
//! `n = (f₁, f₂)` (N, force exerted by the part `s⁺` on the part `s⁻`) is
//! constant and equal to the dead load applied at the tip.
//!
//! * material force components: axial `N = n·t`, shear `Q = n·d` (N);
//! * strains: stretch `ν = 1 + N/EA`, shear `γ = Q/GA` (dimensionless),
//!   curvature `κ = θ'` (1/m);
//! * centreline: `r' = ν t + γ d`;
//! * bending moment `m = EI θ'` (N·m);
//! * moment balance `m' + (r' × n)_z = 0`, i.e.
//!   `EI θ'' = −(r'ₓ n_y − r'_y nₓ) = −(ν Q − γ N)`.
//!
//! Boundary conditions: `r(0) = 0`, `θ(0) = 0`, and at the free end
//! `m(L) = 0`.  The boundary value problem is solved by shooting on the
//! clamp moment `m(0)`.
//!
//! # First integrals
//!
//! * `M₃ = m + x n_y − y nₓ` (N·m) — moment about the origin;
//!   `M₃' = m' + (r' × n)_z = 0`.
//! * `H = ½ m²/EI + N + ½ (N²/EA + Q²/GA)` (N).  Using `N' = θ' Q`,
//!   `Q' = −θ' N` and `m' = −Q − NQ/EA + NQ/GA` one finds
//!   `H' = θ' (m' + Q + NQ/EA − NQ/GA) = 0`, so `H` (as stated, with
//!   these signs) is conserved.
//!
//! # Accuracy
//!
//! The ODE is integrated with the 16th-order [`Gbs`] extrapolation method
//! (64 macro steps by default).  Halving the macro step changes the tip
//! position by less than 1e-14 m for the load cases of the tests (|n| up to
//! ≈ 22 EI/L²), the Newton iterations are converged to round-off, and an
//! independent RK4 + Richardson integration agrees to < 1e-11 m.  The tip
//! position error is therefore well below 1e-12 m.

use super::ode::Gbs;

/// Geometry and stiffnesses of a straight, planar Reissner rod.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanarRod {
    /// Reference length `L` (m).
    pub length: f64,
    /// Bending stiffness `EI` (N·m²).
    pub ei: f64,
    /// Effective shear stiffness `GA` (N) (shear correction included);
    /// `f64::INFINITY` means unshearable.
    pub ga: f64,
    /// Axial stiffness `EA` (N); `f64::INFINITY` means inextensible.
    pub ea: f64,
}

impl PlanarRod {
    /// Rod of length `length` (m) with bending stiffness `ei` (N·m²),
    /// shear stiffness `ga` (N) and axial stiffness `ea` (N).
    pub fn new(length: f64, ei: f64, ga: f64, ea: f64) -> Self {
        Self { length, ei, ga, ea }
    }

    /// Inextensible, unshearable (Kirchhoff / Euler elastica) rod of length
    /// `length` (m) and bending stiffness `ei` (N·m²): `GA = EA = ∞`.
    pub fn kirchhoff(length: f64, ei: f64) -> Self {
        Self::new(length, ei, f64::INFINITY, f64::INFINITY)
    }

    /// Material force components `[N, Q]` (N) of the global force
    /// `force = [nₓ, n_y]` (N) at director angle `theta` (rad).
    pub fn material_force(theta: f64, force: [f64; 2]) -> [f64; 2] {
        let (sn, cs) = theta.sin_cos();
        [
            force[0] * cs + force[1] * sn,
            -force[0] * sn + force[1] * cs,
        ]
    }

    /// Strains `[ν, γ]` (dimensionless) produced by the material force
    /// `[N, Q]` (N): `ν = 1 + N/EA`, `γ = Q/GA`.
    pub fn strains(&self, material_force: [f64; 2]) -> [f64; 2] {
        [
            1.0 + material_force[0] / self.ea,
            material_force[1] / self.ga,
        ]
    }

    /// Right-hand side of the first-order system for the state
    /// `y = [x (m), y (m), θ (rad), m (N·m)]` under the constant force
    /// `force` (N): `x' = ν cos θ − γ sin θ`, `y' = ν sin θ + γ cos θ`,
    /// `θ' = m/EI`, `m' = −(ν Q − γ N)`.
    pub fn rhs(&self, force: [f64; 2], y: &[f64; 4]) -> [f64; 4] {
        let theta = y[2];
        let (sn, cs) = theta.sin_cos();
        let [n, q] = Self::material_force(theta, force);
        let [nu, gamma] = self.strains([n, q]);
        [
            nu * cs - gamma * sn,
            nu * sn + gamma * cs,
            y[3] / self.ei,
            -(nu * q - gamma * n),
        ]
    }

    /// Characteristic moment `EI/L` (N·m) used for scaling.
    fn moment_scale(&self) -> f64 {
        self.ei / self.length
    }

    /// Characteristic force `EI/L²` (N) used for scaling.
    fn force_scale(&self) -> f64 {
        self.ei / (self.length * self.length)
    }
}

/// State of the rod at one arc-length station.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanarState {
    /// Reference arc length `s` (m).
    pub s: f64,
    /// Centreline position `r(s) = [x, y]` (m).
    pub position: [f64; 2],
    /// Director angle `θ(s)` (rad), measured from +x.
    pub angle: f64,
    /// Bending moment `m(s) = EI θ'(s)` (N·m).
    pub moment: f64,
}

/// Equilibrium of a [`PlanarRod`] under a constant internal force, with a
/// dense representation of the whole solution.
#[derive(Clone, Debug)]
pub struct PlanarSolution {
    /// The rod.
    pub rod: PlanarRod,
    /// Constant internal force `n = [nₓ, n_y]` (N) = dead load at the tip.
    pub force: [f64; 2],
    /// Clamp moment `m(0)` (N·m).
    pub clamp_moment: f64,
    /// Tip position `r(L)` (m).
    pub tip: [f64; 2],
    /// Tip director angle `θ(L)` (rad).
    pub tip_angle: f64,
    /// Tip moment `m(L)` (N·m); zero up to round-off for the solutions of
    /// [`dead_load_tip`] and [`position_controlled`].
    pub tip_moment: f64,
    integrator: Gbs,
    nodes: Vec<f64>,
    states: Vec<[f64; 4]>,
}

impl PlanarSolution {
    /// State at arc length `s` (m), clamped to `[0, L]`.  Values between
    /// grid nodes are obtained by one extrapolated step from the previous
    /// node, so they are as accurate as the nodes themselves.
    pub fn state(&self, s: f64) -> PlanarState {
        let s = s.clamp(0.0, self.rod.length);
        let h = self.rod.length / (self.nodes.len() - 1) as f64;
        let k = ((s / h).floor() as usize).min(self.nodes.len() - 1);
        let (s_k, y_k) = (self.nodes[k], self.states[k]);
        let f = |_s: f64, y: &[f64; 4]| self.rod.rhs(self.force, y);
        let y = self.integrator.step(&f, s_k, &y_k, s - s_k);
        to_state(s, &y)
    }

    /// Centreline position `r(s)` (m).
    pub fn position(&self, s: f64) -> [f64; 2] {
        self.state(s).position
    }

    /// Director angle `θ(s)` (rad).
    pub fn angle(&self, s: f64) -> f64 {
        self.state(s).angle
    }

    /// Bending moment `m(s)` (N·m).
    pub fn moment(&self, s: f64) -> f64 {
        self.state(s).moment
    }

    /// Material force `[N, Q]` (N) at `s` (m).
    pub fn material_force(&self, s: f64) -> [f64; 2] {
        PlanarRod::material_force(self.angle(s), self.force)
    }

    /// Strains `[ν, γ, κ]` at `s` (m): stretch ν and shear γ
    /// (dimensionless) and curvature `κ = θ' = m/EI` (1/m).
    pub fn strains(&self, s: f64) -> [f64; 3] {
        let st = self.state(s);
        let [nu, gamma] = self
            .rod
            .strains(PlanarRod::material_force(st.angle, self.force));
        [nu, gamma, st.moment / self.rod.ei]
    }

    /// First integral `M₃(s) = m + x n_y − y nₓ` (N·m), the moment about
    /// the origin; constant along an equilibrium.
    pub fn moment_invariant(&self, s: f64) -> f64 {
        let st = self.state(s);
        st.moment + st.position[0] * self.force[1] - st.position[1] * self.force[0]
    }

    /// First integral `H(s) = ½ m²/EI + N + ½ (N²/EA + Q²/GA)` (N);
    /// constant along an equilibrium (see the module docs).
    pub fn hamiltonian(&self, s: f64) -> f64 {
        let st = self.state(s);
        let [n, q] = PlanarRod::material_force(st.angle, self.force);
        0.5 * st.moment * st.moment / self.rod.ei
            + n
            + 0.5 * (n * n / self.rod.ea + q * q / self.rod.ga)
    }

    /// All stored grid states (`Gbs::steps + 1` equally spaced stations
    /// from `s = 0` to `s = L`).
    pub fn grid(&self) -> Vec<PlanarState> {
        self.nodes
            .iter()
            .zip(&self.states)
            .map(|(&s, y)| to_state(s, y))
            .collect()
    }

    /// `n + 1` equally spaced samples from `s = 0` to `s = L`.
    pub fn sample(&self, n: usize) -> Vec<PlanarState> {
        (0..=n)
            .map(|i| self.state(self.rod.length * i as f64 / n.max(1) as f64))
            .collect()
    }
}

fn to_state(s: f64, y: &[f64; 4]) -> PlanarState {
    PlanarState {
        s,
        position: [y[0], y[1]],
        angle: y[2],
        moment: y[3],
    }
}

/// Tip state `[x, y, θ, m](L)` of the initial value problem.
fn shoot(p: &PlanarRod, force: [f64; 2], clamp_moment: f64, integ: &Gbs) -> [f64; 4] {
    let f = |_s: f64, y: &[f64; 4]| p.rhs(force, y);
    integ.integrate(&f, 0.0, p.length, &[0.0, 0.0, 0.0, clamp_moment])
}

/// Solves the initial value problem `r(0) = 0`, `θ(0) = 0`,
/// `m(0) = clamp_moment` (N·m) under the constant force `force` (N) with the
/// default integrator.  The result satisfies `m(L) = 0` only if
/// `clamp_moment` is the right one.
pub fn integrate_ivp(p: &PlanarRod, force: [f64; 2], clamp_moment: f64) -> PlanarSolution {
    integrate_ivp_with(p, force, clamp_moment, &Gbs::default())
}

/// [`integrate_ivp`] with an explicit integrator.
pub fn integrate_ivp_with(
    p: &PlanarRod,
    force: [f64; 2],
    clamp_moment: f64,
    integ: &Gbs,
) -> PlanarSolution {
    let f = |_s: f64, y: &[f64; 4]| p.rhs(force, y);
    let (nodes, states) = integ.integrate_grid(&f, 0.0, p.length, &[0.0, 0.0, 0.0, clamp_moment]);
    let tip = *states.last().expect("grid has at least two nodes");
    PlanarSolution {
        rod: *p,
        force,
        clamp_moment,
        tip: [tip[0], tip[1]],
        tip_angle: tip[2],
        tip_moment: tip[3],
        integrator: *integ,
        nodes,
        states,
    }
}

/// Scaled residual below which a Newton iterate that can no longer be
/// improved (round-off floor) is accepted (dimensionless).
const ACCEPT_RESIDUAL: f64 = 1e-10;

/// `true` if `new < old` (and neither is NaN).
fn decreases(new: f64, old: f64) -> bool {
    new < old
}

/// Newton iteration (central finite-difference derivative, backtracking)
/// for `m(L; m₀) = 0` at fixed force, starting from `m0`.  Iterates until
/// the update is at round-off level or the residual stops decreasing.
/// Returns `None` if it does not converge within `max_iter` iterations.
fn newton_clamp_moment(
    p: &PlanarRod,
    force: [f64; 2],
    m0: f64,
    integ: &Gbs,
    max_iter: usize,
) -> Option<f64> {
    let scale = p.moment_scale();
    let g = |m: f64| shoot(p, force, m, integ)[3] / scale;
    let mut m = m0;
    let mut gm = g(m);
    for _ in 0..max_iter {
        if gm == 0.0 {
            return Some(m);
        }
        let delta = 1e-6 * (m.abs() + scale);
        let dg = (g(m + delta) - g(m - delta)) / (2.0 * delta);
        if !(dg.is_finite() && dg != 0.0) {
            return None;
        }
        let step = -gm / dg;
        let mut alpha = 1.0;
        let mut g_new = g(m + step);
        while !decreases(g_new.abs(), gm.abs()) && alpha > 1e-3 {
            alpha *= 0.5;
            g_new = g(m + alpha * step);
        }
        if !decreases(g_new.abs(), gm.abs()) {
            // No further decrease: round-off floor (or failure).
            return (gm.abs() < ACCEPT_RESIDUAL).then_some(m);
        }
        m += alpha * step;
        gm = g_new;
        if (alpha * step).abs() <= 1e-14 * (m.abs() + scale) {
            return (gm.abs() < ACCEPT_RESIDUAL).then_some(m);
        }
    }
    (gm.abs() < ACCEPT_RESIDUAL).then_some(m)
}

/// Natural-parameter continuation `μ: 0 → 1` for `K` unknowns.
///
/// `solve(μ, predictor)` runs a corrector (Newton) from the predictor.
/// The predictor is the secant extrapolation of the last two converged
/// points.  A step is rejected (and halved) if the corrector fails or lands
/// farther than `0.25 (|u| + scale)` from the predictor in any component,
/// which keeps the path on one continuous solution branch.
///
/// # Panics
/// If the step size drops below 1e-8 (limit point or non-convergence).
fn continuation<const K: usize>(
    start: [f64; K],
    scales: [f64; K],
    max_step: f64,
    what: &str,
    solve: impl Fn(f64, [f64; K]) -> Option<[f64; K]>,
) -> [f64; K] {
    let (mut prev, mut last) = ((0.0, start), (0.0, start));
    let mut step = max_step;
    while last.0 < 1.0 {
        let mu = (last.0 + step).min(1.0);
        let predictor: [f64; K] = std::array::from_fn(|j| {
            if last.0 > prev.0 {
                last.1[j] + (last.1[j] - prev.1[j]) / (last.0 - prev.0) * (mu - last.0)
            } else {
                last.1[j]
            }
        });
        let accepted = solve(mu, predictor).filter(|u| {
            (0..K).all(|j| (u[j] - predictor[j]).abs() <= 0.25 * (last.1[j].abs() + scales[j]))
        });
        match accepted {
            Some(u) => {
                prev = last;
                last = (mu, u);
                step = (1.5 * step).min(max_step);
            }
            None => {
                step *= 0.5;
                assert!(step > 1e-8, "{what}: continuation failed at μ = {}", last.0);
            }
        }
    }
    last.1
}

/// Equilibrium of the rod under the dead tip load `force = [nₓ, n_y]` (N)
/// with a moment-free tip, using the default integrator.
///
/// The clamp moment is found by shooting (Newton on `m(0)`), with a load
/// continuation `λ·force`, `λ: 0 → 1` in (at least) 20 steps starting
/// from the straight, unloaded rod, so the returned equilibrium is the one
/// continuously connected to the unloaded state.
///
/// # Panics
/// If the continuation fails (e.g. at a limit point of the load path).
pub fn dead_load_tip(p: &PlanarRod, force: [f64; 2]) -> PlanarSolution {
    dead_load_tip_with(p, force, &Gbs::default())
}

/// [`dead_load_tip`] with an explicit integrator.
///
/// # Panics
/// If the continuation fails.
pub fn dead_load_tip_with(p: &PlanarRod, force: [f64; 2], integ: &Gbs) -> PlanarSolution {
    let [m0] = continuation(
        [0.0],
        [p.moment_scale()],
        1.0 / 20.0,
        "dead_load_tip",
        |lambda, [pred]| {
            let f = [lambda * force[0], lambda * force[1]];
            newton_clamp_moment(p, f, pred, integ, 20).map(|m| [m])
        },
    );
    integrate_ivp_with(p, force, m0, integ)
}

/// Scaled residual `[m(L) L/EI, (x(L) − X)/L, (y(L) − Y)/L]` of the
/// position-controlled problem for the unknowns `u = [m₀, f₁, f₂]`.
fn position_residual(p: &PlanarRod, tip: [f64; 2], u: [f64; 3], integ: &Gbs) -> [f64; 3] {
    let y = shoot(p, [u[1], u[2]], u[0], integ);
    [
        y[3] / p.moment_scale(),
        (y[0] - tip[0]) / p.length,
        (y[1] - tip[1]) / p.length,
    ]
}

fn norm3(v: &[f64; 3]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Newton iteration with central finite-difference Jacobian and
/// backtracking for the position-controlled problem; same termination
/// logic as [`newton_clamp_moment`].
fn newton_position(
    p: &PlanarRod,
    tip: [f64; 2],
    u0: [f64; 3],
    integ: &Gbs,
    max_iter: usize,
) -> Option<[f64; 3]> {
    let scales = [p.moment_scale(), p.force_scale(), p.force_scale()];
    let residual = |u: [f64; 3]| position_residual(p, tip, u, integ);
    let mut u = u0;
    let mut r = norm3(&residual(u));
    let mut r_vec = residual(u);
    for _ in 0..max_iter {
        if r == 0.0 {
            return Some(u);
        }
        let mut jac = nalgebra::Matrix3::zeros();
        for j in 0..3 {
            let delta = 1e-6 * (u[j].abs() + scales[j]);
            let (mut up, mut um) = (u, u);
            up[j] += delta;
            um[j] -= delta;
            let (rp, rm) = (residual(up), residual(um));
            for i in 0..3 {
                jac[(i, j)] = (rp[i] - rm[i]) / (2.0 * delta);
            }
        }
        let step = jac.lu().solve(&nalgebra::Vector3::from(r_vec))?;
        let trial = |alpha: f64| -> [f64; 3] { std::array::from_fn(|j| u[j] - alpha * step[j]) };
        let mut alpha = 1.0;
        let mut r_new_vec = residual(trial(alpha));
        while !decreases(norm3(&r_new_vec), r) && alpha > 1e-3 {
            alpha *= 0.5;
            r_new_vec = residual(trial(alpha));
        }
        if !decreases(norm3(&r_new_vec), r) {
            return (r < ACCEPT_RESIDUAL).then_some(u);
        }
        let u_new = trial(alpha);
        let small = (0..3).all(|j| (u_new[j] - u[j]).abs() <= 1e-14 * (u[j].abs() + scales[j]));
        u = u_new;
        r_vec = r_new_vec;
        r = norm3(&r_vec);
        if small {
            return (r < ACCEPT_RESIDUAL).then_some(u);
        }
    }
    (r < ACCEPT_RESIDUAL).then_some(u)
}

/// Equilibrium whose free, moment-free end (`m(L) = 0`) is held at the
/// prescribed tip position `tip = [X, Y]` (m); the unknowns are the clamp
/// moment and the constant force `n` (N), available as
/// [`PlanarSolution::force`] (this is the force the tip support exerts on
/// the rod).
///
/// Method: the dead-load equilibrium for `guess_force` (N) is computed
/// first; then the prescribed tip is moved quasi-statically from that
/// equilibrium's tip to `tip` (polar angle linear, chord length quadratic
/// in the path parameter) in adaptive continuation steps, each solved by
/// Newton on `(m₀, f₁, f₂)` with a finite-difference Jacobian.  Position
/// control does not select a unique equilibrium in general; the one
/// returned is the end of this path, so pass a `guess_force` close to the
/// expected force (`[0, 0]` works for moderate deflections).
///
/// # Panics
/// If the continuation fails (e.g. for an unreachable tip position).
pub fn position_controlled(p: &PlanarRod, tip: [f64; 2], guess_force: [f64; 2]) -> PlanarSolution {
    position_controlled_with(p, tip, guess_force, &Gbs::default())
}

/// [`position_controlled`] with an explicit integrator.
///
/// # Panics
/// If the continuation fails.
pub fn position_controlled_with(
    p: &PlanarRod,
    tip: [f64; 2],
    guess_force: [f64; 2],
    integ: &Gbs,
) -> PlanarSolution {
    let start = dead_load_tip_with(p, guess_force, integ);
    let path = tip_path(start.tip, tip);
    let u0 = [start.clamp_moment, guess_force[0], guess_force[1]];
    let scales = [p.moment_scale(), p.force_scale(), p.force_scale()];
    let u = continuation(u0, scales, 0.25, "position_controlled", |mu, pred| {
        newton_position(p, path(mu), pred, integ, 30)
    });
    integrate_ivp_with(p, [u[1], u[2]], u[0], integ)
}

/// Path of prescribed tip positions from `from` (μ = 0) to `to` (μ = 1)
/// in polar coordinates about the clamp: the polar angle varies linearly
/// and the chord length quadratically in μ.  Near the straight rod the
/// chord shortening of a bent rod is quadratic in the tip deflection, so
/// this path stays close to low-force equilibria (a straight segment would
/// demand huge compressive forces and end on higher buckling modes).
fn tip_path(from: [f64; 2], to: [f64; 2]) -> impl Fn(f64) -> [f64; 2] {
    let (rho0, psi0) = (from[0].hypot(from[1]), from[1].atan2(from[0]));
    let (rho1, psi1) = (to[0].hypot(to[1]), to[1].atan2(to[0]));
    let mut d_psi = psi1 - psi0;
    if d_psi > std::f64::consts::PI {
        d_psi -= 2.0 * std::f64::consts::PI;
    } else if d_psi < -std::f64::consts::PI {
        d_psi += 2.0 * std::f64::consts::PI;
    }
    move |mu: f64| {
        if mu >= 1.0 {
            return to;
        }
        let rho = rho0 + mu * mu * (rho1 - rho0);
        let (sn, cs) = (psi0 + mu * d_psi).sin_cos();
        [rho * cs, rho * sn]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lead_rod() -> PlanarRod {
        PlanarRod::new(1.0, 1.0, 1e4, 3e4)
    }

    fn assert_close(what: &str, got: f64, want: f64, tol: f64) {
        assert!(
            (got - want).abs() <= tol,
            "{what}: got {got:.12}, want {want:.12} (diff {:.3e}, tol {tol:.1e})",
            got - want
        );
    }

    fn assert_tip(sol: &PlanarSolution, tip: [f64; 2], moment: f64, tip_tol: f64, rel_m: f64) {
        assert_close("tip x", sol.tip[0], tip[0], tip_tol);
        assert_close("tip y", sol.tip[1], tip[1], tip_tol);
        assert_close(
            "clamp moment",
            sol.clamp_moment,
            moment,
            rel_m * moment.abs(),
        );
        assert!(sol.tip_moment.abs() < 1e-11, "m(L) = {}", sol.tip_moment);
    }

    #[test]
    fn lead_case_moderate_load() {
        let sol = dead_load_tip(&lead_rod(), [2.0, 1.0]);
        assert_tip(&sol, [0.98061297, 0.18066080], 0.619291, 1e-8, 1e-6);
    }

    #[test]
    fn lead_case_large_load() {
        let sol = dead_load_tip(&lead_rod(), [17.8, -12.8]);
        assert_tip(&sol, [0.87218789, -0.46597468], -2.869656, 1e-8, 1e-6);
    }

    #[test]
    fn stiff_limit_is_kirchhoff_elastica() {
        for rod in [
            PlanarRod::new(1.0, 1.0, 1e12, 1e12),
            PlanarRod::kirchhoff(1.0, 1.0),
        ] {
            let a = dead_load_tip(&rod, [2.0, 1.0]);
            assert_tip(&a, [0.980550, 0.180601], 0.61935, 1e-6, 1e-5);
            let b = dead_load_tip(&rod, [17.8, -12.8]);
            assert_tip(&b, [0.871610, -0.465452], -2.87156, 1e-6, 1e-5);
        }
    }

    #[test]
    fn first_integrals_are_conserved() {
        for force in [[2.0, 1.0], [17.8, -12.8], [-3.0, 4.0]] {
            let sol = dead_load_tip(&lead_rod(), force);
            let (m3, h) = (sol.moment_invariant(0.0), sol.hamiltonian(0.0));
            for i in 0..=97 {
                let s = i as f64 / 97.0;
                assert!((sol.moment_invariant(s) - m3).abs() < 1e-10);
                assert!((sol.hamiltonian(s) - h).abs() < 1e-10);
            }
            // M₃ at the tip equals r(L) × n since m(L) = 0.
            assert!((m3 - (sol.tip[0] * force[1] - sol.tip[1] * force[0])).abs() < 1e-12);
        }
    }

    #[test]
    fn dense_samples_match_grid_and_tip() {
        let sol = dead_load_tip(&lead_rod(), [17.8, -12.8]);
        for node in sol.grid() {
            let st = sol.state(node.s);
            assert!((st.position[0] - node.position[0]).abs() < 1e-14);
            assert!((st.angle - node.angle).abs() < 1e-14);
        }
        let end = sol.state(1.0);
        assert!((end.position[0] - sol.tip[0]).abs() < 1e-15);
        assert_eq!(sol.sample(10).len(), 11);
        // Between nodes: compare with an independent IVP on a finer grid.
        let fine = integrate_ivp_with(&sol.rod, sol.force, sol.clamp_moment, &Gbs::new(256, 8));
        for s in [0.0123, 0.377, 0.5, 0.9991] {
            let (a, b) = (sol.state(s), fine.state(s));
            assert!((a.position[0] - b.position[0]).abs() < 1e-13);
            assert!((a.position[1] - b.position[1]).abs() < 1e-13);
            assert!((a.moment - b.moment).abs() < 1e-12);
        }
    }

    /// Classical RK4, `n` steps, for the same ODE (independent check of
    /// the GBS integrator).
    fn rk4_tip(p: &PlanarRod, force: [f64; 2], m0: f64, n: usize) -> [f64; 4] {
        let h = p.length / n as f64;
        let mut y = [0.0, 0.0, 0.0, m0];
        let add = |y: &[f64; 4], c: f64, k: &[f64; 4]| -> [f64; 4] {
            std::array::from_fn(|i| y[i] + c * k[i])
        };
        for _ in 0..n {
            let k1 = p.rhs(force, &y);
            let k2 = p.rhs(force, &add(&y, 0.5 * h, &k1));
            let k3 = p.rhs(force, &add(&y, 0.5 * h, &k2));
            let k4 = p.rhs(force, &add(&y, h, &k3));
            y = std::array::from_fn(|i| {
                y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
            });
        }
        y
    }

    #[test]
    fn independent_rk4_richardson_agrees() {
        let rod = lead_rod();
        for force in [[2.0, 1.0], [17.8, -12.8]] {
            let sol = dead_load_tip(&rod, force);
            let coarse = rk4_tip(&rod, force, sol.clamp_moment, 4000);
            let fine = rk4_tip(&rod, force, sol.clamp_moment, 8000);
            for i in 0..4 {
                let rich = (16.0 * fine[i] - coarse[i]) / 15.0;
                let want = [sol.tip[0], sol.tip[1], sol.tip_angle, sol.tip_moment][i];
                assert!(
                    (rich - want).abs() < 1e-11,
                    "component {i}: {rich} vs {want}"
                );
            }
        }
    }

    #[test]
    fn integrator_refinement_does_not_change_the_solution() {
        let rod = lead_rod();
        for force in [[2.0, 1.0], [17.8, -12.8]] {
            let a = dead_load_tip(&rod, force);
            let b = dead_load_tip_with(&rod, force, &Gbs::new(128, 8));
            let c = dead_load_tip_with(&rod, force, &Gbs::new(40, 10));
            for other in [&b, &c] {
                assert!((a.tip[0] - other.tip[0]).abs() < 1e-13);
                assert!((a.tip[1] - other.tip[1]).abs() < 1e-13);
                assert!((a.clamp_moment - other.clamp_moment).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn position_controlled_recovers_dead_load() {
        let rod = lead_rod();
        let cases = [
            ([2.0, 1.0], [0.0, 0.0]),
            ([2.0, 1.0], [1.0, 3.0]),
            ([17.8, -12.8], [0.0, 0.0]),
            ([17.8, -12.8], [10.0, -5.0]),
        ];
        for (force, guess) in cases {
            let dead = dead_load_tip(&rod, force);
            let pc = position_controlled(&rod, dead.tip, guess);
            assert!((pc.force[0] - force[0]).abs() < 1e-8, "{:?}", pc.force);
            assert!((pc.force[1] - force[1]).abs() < 1e-8, "{:?}", pc.force);
            assert!((pc.clamp_moment - dead.clamp_moment).abs() < 1e-9);
            assert!((pc.tip[0] - dead.tip[0]).abs() < 1e-13);
            assert!((pc.tip[1] - dead.tip[1]).abs() < 1e-13);
            assert!(pc.tip_moment.abs() < 1e-11);
        }
    }

    #[test]
    fn small_load_matches_timoshenko_cantilever() {
        // Linear limit: tip deflection P L³/(3EI) + P L/GA, rotation
        // P L²/(2EI), axial stretch Nₓ L/EA.
        let rod = PlanarRod::new(2.0, 3.0, 50.0, 70.0);
        let p = 1e-5;
        let sol = dead_load_tip(&rod, [0.0, p]);
        let (l, ei) = (rod.length, rod.ei);
        let w = p * l.powi(3) / (3.0 * ei) + p * l / rod.ga;
        assert!((sol.tip[1] / w - 1.0).abs() < 1e-8);
        assert!((sol.tip_angle / (p * l * l / (2.0 * ei)) - 1.0).abs() < 1e-8);
        assert!((sol.clamp_moment / (p * l) - 1.0).abs() < 1e-8);
        // Pure tension keeps the rod straight: x(L) = L (1 + P/EA) exactly.
        let ax = dead_load_tip(&rod, [5.0, 0.0]);
        assert!((ax.tip[0] - l * (1.0 + 5.0 / rod.ea)).abs() < 1e-14);
        assert!(ax.tip[1].abs() < 1e-15 && ax.clamp_moment.abs() < 1e-15);
    }
}
