//! The first implementation of [`super::RelativeRotation`], kept as a test-only
//! reference: the same derivatives assembled from general products of the dense
//! factors `∂p/∂(α, β)` (4×6), `∂φ/∂p` (3×4) and `∇²ψ(p)` (4×4), and the curvature of
//! `p(α, β)` from nine quaternion products. The optimised kernel must agree with it to
//! round-off (`tests.rs`).

use nalgebra::{Matrix3, Matrix4, Quaternion, SMatrix, UnitQuaternion, Vector3, Vector4};

use super::LogCoefficients;
use crate::so3::skew;

/// `φ = log(q_aᵀ q_b)` with derivatives; local unknowns ordered `(α, β)`.
#[derive(Clone, Debug)]
pub(super) struct ReferenceRotation {
    /// The rotation vector `φ` (rad), expressed in frame a (equivalently in frame b).
    pub(super) phi: Vector3<f64>,
    /// `∂φ/∂(α, β)`, 3×6.
    pub(super) jacobian: SMatrix<f64, 3, 6>,
    p: Quaternion<f64>,
    dp: SMatrix<f64, 4, 6>,
    dphi_dp: SMatrix<f64, 3, 4>,
    s: LogCoefficients,
}

/// Components `(w, x, y, z)` of a quaternion as a 4-vector.
fn as_vec4(q: &Quaternion<f64>) -> Vector4<f64> {
    Vector4::new(q.w, q.i, q.j, q.k)
}

fn pure(v: Vector3<f64>) -> Quaternion<f64> {
    Quaternion::from_parts(0.0, v)
}

impl ReferenceRotation {
    /// Evaluates `φ` and its Jacobian. The frames must be closer than a half turn
    /// (`w = cos(|φ|/2) > 0`); the representative with positive real part is used.
    pub(super) fn new(q_a: &UnitQuaternion<f64>, q_b: &UnitQuaternion<f64>) -> Self {
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
    pub(super) fn contracted_hessian(&self, mu: &Vector3<f64>) -> SMatrix<f64, 6, 6> {
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
