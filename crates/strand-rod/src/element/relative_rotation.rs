//! The relative rotation vector `φ = 2 log(q_a* ⊗ q_b)` of two frames and its first
//! and second derivatives with respect to right increments of both frames.
//!
//! With increments `α` (frame a) and `β` (frame b), `p(α, β) = exp(−α/2) ⊗ p ⊗ exp(β/2)`
//! with `p = q_a* ⊗ q_b` is a quadratic polynomial to second order, and
//! `φ(p) = 2 S(|v|², w) v` with `S = atan(|v|/w)/|v|` is the quaternion logarithm
//! (representative with `w > 0`). Both are differentiated analytically and combined by
//! the chain rule; the Hessian is delivered contracted with a co-vector `μ`
//! (`∇²(μ·φ)`), which is all an energy needs.

use nalgebra::{Matrix3, Matrix4, Quaternion, SMatrix, UnitQuaternion, Vector3, Vector4};

use crate::so3::{atan_ratio, skew};

/// `φ = log(q_aᵀ q_b)` with derivatives; local unknowns ordered `(α, β)`.
#[derive(Clone, Debug)]
pub struct RelativeRotation {
    /// The rotation vector `φ` (rad), expressed in frame a (equivalently in frame b).
    pub phi: Vector3<f64>,
    /// `∂φ/∂(α, β)`, 3×6.
    pub jacobian: SMatrix<f64, 3, 6>,
    p: Quaternion<f64>,
    dp: SMatrix<f64, 4, 6>,
    dphi_dp: SMatrix<f64, 3, 4>,
    s: LogCoefficients,
}

#[derive(Clone, Copy, Debug)]
struct LogCoefficients {
    s: f64,
    s_u: f64,
    s_w: f64,
    s_uu: f64,
    s_uw: f64,
    s_ww: f64,
}

impl LogCoefficients {
    /// `S(u, w) = A(u/w²)/w` and its partial derivatives (u = |v|²).
    fn new(u: f64, w: f64) -> Self {
        let z = u / (w * w);
        let (a, da, dda) = atan_ratio(z);
        let w2 = w * w;
        let w3 = w2 * w;
        Self {
            s: a / w,
            s_u: da / w3,
            s_w: -(a + 2.0 * z * da) / w2,
            s_uu: dda / (w3 * w2),
            s_uw: -(2.0 * z * dda + 3.0 * da) / (w2 * w2),
            s_ww: (2.0 * a + 10.0 * z * da + 4.0 * z * z * dda) / w3,
        }
    }
}

/// Components `(w, x, y, z)` of a quaternion as a 4-vector.
fn as_vec4(q: &Quaternion<f64>) -> Vector4<f64> {
    Vector4::new(q.w, q.i, q.j, q.k)
}

fn pure(v: Vector3<f64>) -> Quaternion<f64> {
    Quaternion::from_parts(0.0, v)
}

impl RelativeRotation {
    /// Evaluates `φ` and its Jacobian. The frames must be closer than a half turn
    /// (`w = cos(|φ|/2) > 0`); the representative with positive real part is used.
    pub fn new(q_a: &UnitQuaternion<f64>, q_b: &UnitQuaternion<f64>) -> Self {
        let mut p = q_a.quaternion().conjugate() * q_b.quaternion();
        if p.w < 0.0 {
            p = -p;
        }
        // Guard against an exact half turn: the logarithm is not differentiable there.
        let w = p.w.max(1e-12);
        let v = p.vector().into_owned();
        let u = v.norm_squared();
        let s = LogCoefficients::new(u, w);

        // dp: rows (w, v), columns (α, β).
        let mut dp = SMatrix::<f64, 4, 6>::zeros();
        let half_skew_v = 0.5 * skew(&v);
        let dv_da = -0.5 * w * Matrix3::identity() + half_skew_v;
        let dv_db = 0.5 * w * Matrix3::identity() + half_skew_v;
        for c in 0..3 {
            dp[(0, c)] = 0.5 * v[c];
            dp[(0, 3 + c)] = -0.5 * v[c];
        }
        dp.fixed_view_mut::<3, 3>(1, 0).copy_from(&dv_da);
        dp.fixed_view_mut::<3, 3>(1, 3).copy_from(&dv_db);

        // dφ/dp with φ = 2 S v.
        let mut dphi_dp = SMatrix::<f64, 3, 4>::zeros();
        dphi_dp
            .fixed_view_mut::<3, 1>(0, 0)
            .copy_from(&(2.0 * s.s_w * v));
        dphi_dp
            .fixed_view_mut::<3, 3>(0, 1)
            .copy_from(&(2.0 * s.s * Matrix3::identity() + 4.0 * s.s_u * v * v.transpose()));

        Self {
            phi: 2.0 * s.s * v,
            jacobian: dphi_dp * dp,
            p: Quaternion::from_parts(w, v),
            dp,
            dphi_dp,
            s,
        }
    }

    /// `∇²(μ·φ)` with respect to `(α, β)` for a fixed co-vector `μ`, 6×6 symmetric.
    pub fn contracted_hessian(&self, mu: &Vector3<f64>) -> SMatrix<f64, 6, 6> {
        let s = &self.s;
        let v = self.p.vector().into_owned();
        let g = mu.dot(&v);
        // Hessian of ψ(p) = μ·φ(p) in p = (w, v).
        let mut h_pp = Matrix4::<f64>::zeros();
        h_pp[(0, 0)] = 2.0 * g * s.s_ww;
        let h_vw = 2.0 * s.s_w * mu + 4.0 * g * s.s_uw * v;
        let h_vv = 4.0 * s.s_u * (mu * v.transpose() + v * mu.transpose())
            + 8.0 * g * s.s_uu * v * v.transpose()
            + 4.0 * g * s.s_u * Matrix3::identity();
        h_pp.fixed_view_mut::<3, 1>(1, 0).copy_from(&h_vw);
        h_pp.fixed_view_mut::<1, 3>(0, 1)
            .copy_from(&h_vw.transpose());
        h_pp.fixed_view_mut::<3, 3>(1, 1).copy_from(&h_vv);
        let mut hessian = self.dp.transpose() * h_pp * self.dp;

        // Curvature of p(α, β): c·∇²p with c = ∂ψ/∂p.
        let c = self.dphi_dp.transpose() * mu;
        let c_dot_p = c.dot(&as_vec4(&self.p));
        for i in 0..3 {
            hessian[(i, i)] -= 0.25 * c_dot_p;
            hessian[(3 + i, 3 + i)] -= 0.25 * c_dot_p;
        }
        let c_quat = Quaternion::new(c[0], c[1], c[2], c[3]);
        for i in 0..3 {
            let left = pure(Vector3::ith(i, 1.0)) * self.p;
            for j in 0..3 {
                let bilinear = left * pure(Vector3::ith(j, 1.0));
                let value = -0.25 * c_quat.coords.dot(&bilinear.coords);
                hessian[(i, 3 + j)] += value;
                hessian[(3 + j, i)] += value;
            }
        }
        hessian
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::so3::{exp, log, right_jacobian};

    fn phi_at(q_a: &UnitQuaternion<f64>, q_b: &UnitQuaternion<f64>, x: &[f64; 6]) -> Vector3<f64> {
        let a = q_a * exp(&Vector3::new(x[0], x[1], x[2]));
        let b = q_b * exp(&Vector3::new(x[3], x[4], x[5]));
        log(&(a.inverse() * b))
    }

    /// `∇(μ·φ)` at chart point `x` of the fixed chart at `(q_a, q_b)`, from the
    /// analytic Jacobian at the moved frames and the right Jacobian of SO(3).
    fn chart_gradient(
        q_a: &UnitQuaternion<f64>,
        q_b: &UnitQuaternion<f64>,
        x: &[f64; 6],
        mu: &Vector3<f64>,
    ) -> [f64; 6] {
        let (xa, xb) = (
            Vector3::new(x[0], x[1], x[2]),
            Vector3::new(x[3], x[4], x[5]),
        );
        let rel = RelativeRotation::new(&(q_a * exp(&xa)), &(q_b * exp(&xb)));
        let local = rel.jacobian.transpose() * mu;
        let ga = right_jacobian(&xa).transpose() * local.fixed_rows::<3>(0);
        let gb = right_jacobian(&xb).transpose() * local.fixed_rows::<3>(3);
        [ga[0], ga[1], ga[2], gb[0], gb[1], gb[2]]
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let cases = [
            (Vector3::new(0.3, -0.2, 0.5), Vector3::new(0.1, 0.9, -0.4)),
            (Vector3::new(0.3, -0.2, 0.5), Vector3::new(0.3, -0.2, 0.5)), // φ = 0
            (Vector3::new(0.0, 0.0, 0.0), Vector3::new(2.5, 0.3, 0.0)),   // large angle
            (Vector3::new(0.0, 0.0, 0.0), Vector3::new(0.05, 0.0, 0.02)), // series branch
        ];
        let mu = Vector3::new(0.7, -1.3, 0.4);
        for (ta, tb) in cases {
            let (q_a, q_b) = (exp(&ta), exp(&tb));
            let rel = RelativeRotation::new(&q_a, &q_b);
            assert!((rel.phi - log(&(q_a.inverse() * q_b))).norm() < 1e-14);
            let hess = rel.contracted_hessian(&mu);
            let h = 1e-6;
            for k in 0..6 {
                let mut xp = [0.0; 6];
                let mut xm = [0.0; 6];
                xp[k] = h;
                xm[k] = -h;
                let fd = (phi_at(&q_a, &q_b, &xp) - phi_at(&q_a, &q_b, &xm)) / (2.0 * h);
                assert!(
                    (fd - rel.jacobian.column(k)).norm() < 1e-8,
                    "jacobian column {k}"
                );
                let (gp, gm) = (
                    chart_gradient(&q_a, &q_b, &xp, &mu),
                    chart_gradient(&q_a, &q_b, &xm, &mu),
                );
                for l in 0..6 {
                    let fd = (gp[l] - gm[l]) / (2.0 * h);
                    assert!(
                        (fd - hess[(l, k)]).abs() < 1e-8,
                        "hessian ({l},{k}): fd {fd} vs {}",
                        hess[(l, k)]
                    );
                }
            }
        }
    }
}
