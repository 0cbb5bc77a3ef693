//! The relative rotation vector `φ = 2 log(q_a* ⊗ q_b)` of two frames and its first
//! and second derivatives with respect to right increments of both frames.
//!
//! With increments `α` (frame a) and `β` (frame b), `p(α, β) = exp(−α/2) ⊗ p ⊗ exp(β/2)`
//! with `p = (w, v) = q_a* ⊗ q_b` is a quadratic polynomial to second order, and
//! `φ(p) = 2 S(|v|², w) v` with `S = atan(|v|/w)/|v|` is the quaternion logarithm
//! (representative with `w > 0`). Both are differentiated analytically and combined by
//! the chain rule; the Hessian is delivered contracted with a co-vector `μ`
//! (`∇²(μ·φ)`), which is all an energy needs.
//!
//! The products of the chain rule are written out for their structure (fixed-size
//! arrays, no general matrix products): with `∂v/∂α = ½(−w I + [v]×)`,
//! `∂v/∂β = ½(w I + [v]×)` and `vᵀ[v]× = 0` the Jacobian is
//! `∂φ/∂α = k v vᵀ − S w I + S [v]×`, `∂φ/∂β = −(∂φ/∂α)ᵀ` with `k = S_w − 2 w S_u`, and
//! the curvature term of `p(α, β)` is a closed-form 3×3 block (see
//! [`RelativeRotation::contracted_hessian`]). `reference.rs` keeps the first, general
//! implementation for the tests.

use nalgebra::{Quaternion, SMatrix, UnitQuaternion, Vector3};

use crate::so3::atan_ratio;

#[cfg(test)]
mod reference;
#[cfg(test)]
mod tests;

/// `φ = log(q_aᵀ q_b)` with derivatives; local unknowns ordered `(α, β)`.
#[derive(Clone, Debug)]
pub struct RelativeRotation {
    /// The rotation vector `φ` (rad), expressed in frame a (equivalently in frame b).
    pub phi: Vector3<f64>,
    /// `∂φ/∂(α, β)` (dimensionless, rad per rad), 3×6.
    pub jacobian: SMatrix<f64, 3, 6>,
    /// Real part `w` of `p = q_a* ⊗ q_b` (positive representative, at least 1e-12).
    w: f64,
    /// Vector part `v` of `p`.
    v: [f64; 3],
    s: LogCoefficients,
}

/// `S(u, w)` and its first and second partial derivatives.
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

/// `[v]×` as rows.
#[inline]
fn skew(v: &[f64; 3]) -> [[f64; 3]; 3] {
    [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]
}

#[inline]
fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
fn delta(i: usize, j: usize) -> f64 {
    if i == j { 1.0 } else { 0.0 }
}

impl RelativeRotation {
    /// Evaluates `φ` and its Jacobian. The frames must be closer than a half turn
    /// (`w = cos(|φ|/2) > 0`); the representative with positive real part is used.
    pub fn new(q_a: &UnitQuaternion<f64>, q_b: &UnitQuaternion<f64>) -> Self {
        let mut p: Quaternion<f64> = q_a.quaternion().conjugate() * q_b.quaternion();
        if p.w < 0.0 {
            p = -p;
        }
        // Guard against an exact half turn: the logarithm is not differentiable there.
        let w = p.w.max(1e-12);
        let v = [p.i, p.j, p.k];
        let s = LogCoefficients::new(dot(&v, &v), w);

        let k = s.s_w - 2.0 * w * s.s_u;
        let x = skew(&v);
        let mut jacobian = SMatrix::<f64, 3, 6>::zeros();
        for i in 0..3 {
            for j in 0..3 {
                let symmetric = k * v[i] * v[j] - s.s * w * delta(i, j);
                let skew_part = s.s * x[i][j];
                jacobian[(i, j)] = symmetric + skew_part;
                jacobian[(i, 3 + j)] = skew_part - symmetric;
            }
        }
        let two_s = 2.0 * s.s;
        Self {
            phi: Vector3::new(two_s * v[0], two_s * v[1], two_s * v[2]),
            jacobian,
            w,
            v,
            s,
        }
    }

    /// `∇²(μ·φ)` with respect to `(α, β)` for a fixed co-vector `μ`, 6×6 symmetric.
    ///
    /// Two parts. First `(∂p)ᵀ ∇²ψ(p) ∂p` with `ψ(p) = μ·φ(p)`: with
    /// `∂p/∂σ = ½ (−s_σ vᵀ; E_σ)`, `E_σ = [v]× + s_σ w I`, `s_α = −1`, `s_β = +1`
    /// (so `E_σᵀ v = s_σ w v`) and `∇²ψ = (h_ww, h_vwᵀ; h_vw, H_vv)`,
    /// `h_vw = b₁ μ + b₂ v`, `H_vv = a₁ (μ vᵀ + v μᵀ) + a₂ v vᵀ + a₃ I`, block `(σ, τ)` is
    /// `¼ [s_σ s_τ κ v vᵀ + λ (s_τ m_σ vᵀ + s_σ v m_τᵀ) + a₃ E_σᵀ E_τ]` with
    /// `m_σ = E_σᵀ μ`, `κ = h_ww − 2 b₂ w + a₂ w²`, `λ = a₁ w − b₁`,
    /// `E_σᵀ E_σ = (w² + u) I − v vᵀ` and `E_αᵀ E_β = (u − w²) I − v vᵀ − 2 w [v]×`.
    /// Then the curvature of `p(α, β)` weighted by `c = ∇ψ(p) = (c₀, c_v)`: `−¼ (c·p) I`
    /// on both diagonal blocks, and in the `(α, β)` block
    /// `−¼ c·(e_i ⊗ p ⊗ e_j) = −¼ M_ij` with
    /// `M = (c_v·v − c₀ w) I − (c_v vᵀ + v c_vᵀ) − [c₀ v + w c_v]×`.
    pub fn contracted_hessian(&self, mu: &Vector3<f64>) -> SMatrix<f64, 6, 6> {
        let s = &self.s;
        let (w, v) = (self.w, &self.v);
        let mu = [mu.x, mu.y, mu.z];
        let g = dot(&mu, v);
        let u = dot(v, v);

        // Coefficients of ∇²ψ(p).
        let h_ww = 2.0 * g * s.s_ww;
        let (b1, b2) = (2.0 * s.s_w, 4.0 * g * s.s_uw);
        let (a1, a2, a3) = (4.0 * s.s_u, 8.0 * g * s.s_uu, 4.0 * g * s.s_u);
        let kappa = h_ww - 2.0 * b2 * w + a2 * w * w;
        let lambda = a1 * w - b1;

        // c = ∇ψ(p) and its curvature terms.
        let c0 = 2.0 * s.s_w * g;
        let cv = [
            2.0 * s.s * mu[0] + 4.0 * s.s_u * g * v[0],
            2.0 * s.s * mu[1] + 4.0 * s.s_u * g * v[1],
            2.0 * s.s * mu[2] + 4.0 * s.s_u * g * v[2],
        ];
        let cv_dot_v = dot(&cv, v);
        let quarter_c_dot_p = 0.25 * (c0 * w + cv_dot_v);
        let m_diagonal = cv_dot_v - c0 * w;
        let m_axis = [
            c0 * v[0] + w * cv[0],
            c0 * v[1] + w * cv[1],
            c0 * v[2] + w * cv[2],
        ];

        // m_σ = E_σᵀ μ = μ × v + s_σ w μ.
        let mu_x_v = [
            mu[1] * v[2] - mu[2] * v[1],
            mu[2] * v[0] - mu[0] * v[2],
            mu[0] * v[1] - mu[1] * v[0],
        ];
        let m_alpha = [
            mu_x_v[0] - w * mu[0],
            mu_x_v[1] - w * mu[1],
            mu_x_v[2] - w * mu[2],
        ];
        let m_beta = [
            mu_x_v[0] + w * mu[0],
            mu_x_v[1] + w * mu[1],
            mu_x_v[2] + w * mu[2],
        ];

        let mut hessian = SMatrix::<f64, 6, 6>::zeros();
        // Diagonal blocks (σ = τ, s_σ² = 1): symmetric, upper triangle mirrored.
        for (offset, sign, m) in [(0, -1.0, &m_alpha), (3, 1.0, &m_beta)] {
            for i in 0..3 {
                for j in i..3 {
                    let vv = v[i] * v[j];
                    let value = 0.25
                        * (kappa * vv
                            + sign * lambda * (m[i] * v[j] + v[i] * m[j])
                            + a3 * ((w * w + u) * delta(i, j) - vv))
                        - quarter_c_dot_p * delta(i, j);
                    hessian[(offset + i, offset + j)] = value;
                    hessian[(offset + j, offset + i)] = value;
                }
            }
        }
        // The (α, β) block (s_α s_β = −1) and its transpose.
        let x = skew(v);
        let a = skew(&m_axis);
        for i in 0..3 {
            for j in 0..3 {
                let vv = v[i] * v[j];
                let second = -kappa * vv
                    + lambda * (m_alpha[i] * v[j] - v[i] * m_beta[j])
                    + a3 * ((u - w * w) * delta(i, j) - vv - 2.0 * w * x[i][j]);
                let curvature = m_diagonal * delta(i, j) - (cv[i] * v[j] + v[i] * cv[j]) - a[i][j];
                let value = 0.25 * (second - curvature);
                hessian[(i, 3 + j)] = value;
                hessian[(3 + j, i)] = value;
            }
        }
        hessian
    }
}
