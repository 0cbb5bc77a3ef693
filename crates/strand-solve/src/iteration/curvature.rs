//! The curvature `dᵀHd` of the energy's quadratic model along this iteration's step `d`
//! (J), which the acceptance ratio of the globalisation needs.
//!
//! For the plain damped Newton step (no rows, no augmented SQP model) it is known from
//! the step itself: `d` solves `(H + λD) d = −g` on the unknowns the gauge leaves free
//! (and is zero on the held ones), so `dᵀHd = −gᵀd − λ Σ D_i d_i²`, exact up to the
//! round-off of the solve — the same order as the round-off of a Hessian–vector
//! product, which it saves (at 19 edges about 17k of the 190k instructions of a Newton
//! step). Any other step (projected by the rows' QP, or of the augmented model, whose
//! Hessian is not the energy's) takes the product.

use super::{Workspace, damping_scale};
use crate::linear::symmetric_product;
use strand_system::HessianPattern;

impl Workspace {
    /// `dᵀHd` (J) for the step `d` in `step` with the energy Hessian `H` of `eval`.
    /// `newton_step`: whether `step` is the damped Newton step `−(H + damping·D)⁻¹ g`
    /// of this factor (gauge held) with the energy's own gradient and Hessian; then the
    /// curvature follows from the step, otherwise from the product `H d` (left in
    /// `product`). `slope` is `gᵀd` (J).
    pub fn step_curvature(
        &mut self,
        pattern: &HessianPattern,
        newton_step: bool,
        damping: f64,
        slope: f64,
    ) -> f64 {
        if newton_step {
            let damped = if damping > 0.0 {
                let scale = damping_scale(
                    &self.eval.hessian,
                    &self.diagonal,
                    &self.rotation,
                    &self.bending_scale,
                );
                damping
                    * scale
                        .iter()
                        .zip(&self.step)
                        .map(|(d, s)| d * s * s)
                        .sum::<f64>()
            } else {
                0.0
            };
            return -slope - damped;
        }
        symmetric_product(pattern, &self.eval.hessian, &self.step, &mut self.product);
        self.step
            .iter()
            .zip(&self.product)
            .map(|(s, p)| s * p)
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{UnitQuaternion, Vector3};
    use strand_rod::Section;
    use strand_system::{End, initial_state};

    use crate::gauge::tests::rod_between;
    use crate::linear::symmetric_product;
    use crate::newton::Solver;
    use crate::{SolverSettings, solve};

    /// Against the Hessian–vector product, for the undamped and damped Newton steps of
    /// a cantilever and of a clamped–clamped rod bent by its supports, each at its
    /// equilibrium (a positive definite Hessian, which the undamped step needs) with a
    /// generic gradient (the identity holds for any right-hand side).
    #[test]
    fn the_newton_step_gives_its_curvature_without_a_product() {
        let section = Section::try_explicit(1e4, 1e4, 1.0, 1.0, 0.5, 0.005).unwrap();
        let along_x =
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
        let turned = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 1.0) * along_x;
        let models = [
            rod_between(
                End::clamped(Vector3::zeros(), along_x),
                End::free(),
                section,
            ),
            rod_between(
                End::clamped(Vector3::zeros(), along_x),
                End::clamped(Vector3::new(0.7, 0.2, 0.0), turned),
                section,
            ),
        ];
        for model in &models {
            let settings = SolverSettings::default();
            let solution = solve(model, initial_state(model.system()), &settings).unwrap();
            assert!(solution.report.converged && solution.report.stable);
            let mut solver = Solver::try_new(model).unwrap();
            let work = &mut solver.work;
            model.evaluate(&solution.state, &mut work.eval, true);
            for (k, g) in work.eval.gradient.iter_mut().enumerate() {
                *g = (0.7 * k as f64).sin() * if k % 2 == 0 { 1.0 } else { 1e-3 };
            }
            let pattern = model.pattern();
            for damping in [0.0, 1e-3, 0.5, 20.0] {
                work.set_damped(None, damping);
                assert!(work.cholesky.factor(&work.damped), "damping {damping}");
                for (s, g) in work.step.iter_mut().zip(&work.eval.gradient) {
                    *s = -g;
                }
                work.gauge.fix_vector(&mut work.step);
                work.cholesky.solve_in_place(&mut work.step);
                let slope: f64 = work
                    .step
                    .iter()
                    .zip(&work.eval.gradient)
                    .map(|(s, g)| s * g)
                    .sum();
                let from_step = work.step_curvature(pattern, true, damping, slope);
                let mut product = vec![0.0; work.step.len()];
                symmetric_product(pattern, &work.eval.hessian, &work.step, &mut product);
                let brute: f64 = work.step.iter().zip(&product).map(|(s, p)| s * p).sum();
                let from_product = work.step_curvature(pattern, false, damping, slope);
                assert_eq!(from_product, brute);
                assert!(brute > 0.0, "damping {damping}: curvature {brute}");
                assert!(
                    (from_step - brute).abs() <= 1e-9 * brute,
                    "damping {damping}: from the step {from_step:e} J, product {brute:e} J"
                );
                // The damping term matters at large damping: without it the identity
                // would be off by far more than round-off.
                if damping >= 0.5 {
                    assert!((-slope - brute).abs() > 1e-6 * brute, "damping {damping}");
                }
            }
        }
    }
}
