//! Helical equilibria of an isotropic, inextensible, unshearable
//! Kirchhoff rod (Love, *Mathematical Theory of Elasticity*, Art. 270).
//!
//! # Geometry
//!
//! Helix of radius `ρ` (m) and pitch angle `α` (rad, angle between the
//! tangent and the horizontal plane) about the `e₃` axis, parametrised by
//! arc length `s` (m):
//!
//! `r(s) = (ρ cos φ, ρ sin φ, s sin α)`, `φ = s cos α/ρ`.
//!
//! Frenet frame: tangent `t = (−cos α sin φ, cos α cos φ, sin α)`,
//! principal normal `n = (−cos φ, −sin φ, 0)` (pointing to the axis),
//! binormal `b = t × n = (sin α sin φ, −sin α cos φ, cos α)`; curvature
//! `κ = cos²α/ρ`, torsion `τ = sin α cos α/ρ` (right-handed for `α > 0`).
//!
//! Material frame (columns of the rotation `R = [d₁ d₂ d₃]`): `d₃ = t`,
//! and `d₁, d₂` are `n, b` rotated about `t` by the extra twist angle
//! `ω s` (`ω` in rad/m): `d₁ = cos(ωs) n + sin(ωs) b`,
//! `d₂ = −sin(ωs) n + cos(ωs) b`.  It satisfies `R' = R [K]×` with the
//! material curvature
//!
//! `K = (κ sin ωs, κ cos ωs, τ + ω)`, i.e. `K = (0, cos²α/ρ, sin α cos α/ρ)`
//! for `ω = 0`.
//!
//! # Statics
//!
//! With `EI₁ = EI₂ = EI` the internal moment (exerted by the part `s⁺` on
//! the part `s⁻`) is `m = R diag(EI, EI, GJ) K = EI t × t' + GJ κ₃ t
//! = EI κ b + GJ κ₃ t`, independent of the extra twist except through
//! `κ₃ = τ + ω`.  Then `m' = κ (GJ κ₃ − EI τ) n`, and the balance laws
//! `n' = 0`, `m' + r' × n = 0` are satisfied by the constant internal
//! force `F e₃` with
//!
//! `F = GJ κ₃ cos α/ρ − EI sin α cos²α/ρ²` (N)
//!
//! (use `t × e₃ = −cos α n`).  `F > 0` means the helix is pulled apart
//! along its axis (tension for `α > 0`).  The conserved resultant moment is
//! `m + r × F e₃ = M e₃` with the axial couple
//! `M = EI κ cos α + GJ κ₃ sin α` (N·m): the helix is held by a wrench
//! (force `F`, couple `M`) along its axis.

use nalgebra::{Matrix3, Vector3};

/// A helical equilibrium of an isotropic Kirchhoff rod.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Helix {
    /// Helix radius `ρ` (m).
    pub radius: f64,
    /// Pitch angle `α` (rad) between the tangent and the plane ⟂ `e₃`.
    pub pitch_angle: f64,
    /// Extra twist rate `ω` (rad/m) of the material frame relative to the
    /// Frenet frame.
    pub extra_twist: f64,
    /// Bending stiffness `EI = EI₁ = EI₂` (N·m²).
    pub ei: f64,
    /// Torsional stiffness `GJ` (N·m²).
    pub gj: f64,
}

impl Helix {
    /// Helix of radius `radius` (m) and pitch angle `pitch_angle` (rad)
    /// with bending stiffness `ei` and torsional stiffness `gj` (N·m²),
    /// material frame = Frenet frame (no extra twist).
    pub fn new(radius: f64, pitch_angle: f64, ei: f64, gj: f64) -> Self {
        Self {
            radius,
            pitch_angle,
            extra_twist: 0.0,
            ei,
            gj,
        }
    }

    /// Same helix with the material frame twisted by the additional rate
    /// `omega` (rad/m) about the tangent.
    pub fn with_extra_twist(self, omega: f64) -> Self {
        Self {
            extra_twist: omega,
            ..self
        }
    }

    /// Azimuth `φ(s) = s cos α/ρ` (rad) at arc length `s` (m).
    pub fn azimuth(&self, s: f64) -> f64 {
        s * self.pitch_angle.cos() / self.radius
    }

    /// Axial rise per turn `2π ρ tan α` (m).
    pub fn pitch(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.radius * self.pitch_angle.tan()
    }

    /// Centreline `r(s) = (ρ cos φ, ρ sin φ, s sin α)` (m).
    pub fn centreline(&self, s: f64) -> Vector3<f64> {
        let (sp, cp) = self.azimuth(s).sin_cos();
        Vector3::new(
            self.radius * cp,
            self.radius * sp,
            s * self.pitch_angle.sin(),
        )
    }

    /// Unit tangent `t = r'` (dimensionless).
    pub fn tangent(&self, s: f64) -> Vector3<f64> {
        let (sp, cp) = self.azimuth(s).sin_cos();
        let (sa, ca) = self.pitch_angle.sin_cos();
        Vector3::new(-ca * sp, ca * cp, sa)
    }

    /// Frenet frame as a rotation matrix with columns `(n, b, t)`
    /// (principal normal towards the axis, binormal, tangent).
    pub fn frenet_frame(&self, s: f64) -> Matrix3<f64> {
        let (sp, cp) = self.azimuth(s).sin_cos();
        let (sa, ca) = self.pitch_angle.sin_cos();
        let n = Vector3::new(-cp, -sp, 0.0);
        let b = Vector3::new(sa * sp, -sa * cp, ca);
        let t = Vector3::new(-ca * sp, ca * cp, sa);
        Matrix3::from_columns(&[n, b, t])
    }

    /// Material frame `R(s) = [d₁ d₂ d₃]` (columns): the Frenet frame
    /// rotated about `t` by `ω s`; satisfies `R' = R [K]×`.
    pub fn material_frame(&self, s: f64) -> Matrix3<f64> {
        let (sw, cw) = (self.extra_twist * s).sin_cos();
        let rot_z = Matrix3::new(cw, -sw, 0.0, sw, cw, 0.0, 0.0, 0.0, 1.0);
        self.frenet_frame(s) * rot_z
    }

    /// Curvature `κ = cos²α/ρ` (1/m).
    pub fn curvature(&self) -> f64 {
        self.pitch_angle.cos().powi(2) / self.radius
    }

    /// Torsion `τ = sin α cos α/ρ` (1/m).
    pub fn torsion(&self) -> f64 {
        self.pitch_angle.sin() * self.pitch_angle.cos() / self.radius
    }

    /// Material twist `κ₃ = τ + ω` (1/m).
    pub fn twist(&self) -> f64 {
        self.torsion() + self.extra_twist
    }

    /// Material curvature `K(s) = (κ sin ωs, κ cos ωs, τ + ω)` (1/m),
    /// components in the material frame, `R' = R [K]×`.
    pub fn material_curvature(&self, s: f64) -> Vector3<f64> {
        let (sw, cw) = (self.extra_twist * s).sin_cos();
        let k = self.curvature();
        Vector3::new(k * sw, k * cw, self.twist())
    }

    /// Darboux vector `R K = τ t + κ b + ω t` (1/m) in the global frame.
    pub fn darboux(&self, s: f64) -> Vector3<f64> {
        self.material_frame(s) * self.material_curvature(s)
    }

    /// Magnitude of the bending moment `EI κ = EI cos²α/ρ` (N·m).
    pub fn bending_moment(&self) -> f64 {
        self.ei * self.curvature()
    }

    /// Torsional moment `GJ κ₃` (N·m).
    pub fn torsional_moment(&self) -> f64 {
        self.gj * self.twist()
    }

    /// Internal moment `m(s) = EI κ b + GJ κ₃ t` (N·m), global components,
    /// exerted by the part `s⁺` on the part `s⁻`.
    pub fn internal_moment(&self, s: f64) -> Vector3<f64> {
        let f = self.frenet_frame(s);
        f.column(1) * self.bending_moment() + f.column(2) * self.torsional_moment()
    }

    /// Axial force `F = GJ κ₃ cos α/ρ − EI sin α cos²α/ρ²` (N) along
    /// `e₃` (positive: tension for `α > 0`).
    pub fn axial_force(&self) -> f64 {
        let (sa, ca) = self.pitch_angle.sin_cos();
        let rho = self.radius;
        self.gj * self.twist() * ca / rho - self.ei * sa * ca * ca / (rho * rho)
    }

    /// Internal force `n = F e₃` (N), exerted by the part `s⁺` on `s⁻`.
    pub fn internal_force(&self) -> Vector3<f64> {
        Vector3::new(0.0, 0.0, self.axial_force())
    }

    /// Axial couple `M = EI κ cos α + GJ κ₃ sin α` (N·m): the constant
    /// resultant moment `m + r × n = M e₃` about the origin.
    pub fn axial_couple(&self) -> f64 {
        let (sa, ca) = self.pitch_angle.sin_cos();
        self.bending_moment() * ca + self.torsional_moment() * sa
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fourth-order central difference `(f(-2h) − 8f(−h) + 8f(h) − f(2h))/12h`.
    fn d_ds<T>(f: impl Fn(f64) -> T, s: f64, h: f64) -> T
    where
        T: std::ops::Sub<Output = T> + std::ops::Add<Output = T> + std::ops::Mul<f64, Output = T>,
    {
        (f(s - 2.0 * h) - f(s + 2.0 * h) + (f(s + h) - f(s - h)) * 8.0) * (1.0 / (12.0 * h))
    }

    fn skew(k: &Vector3<f64>) -> Matrix3<f64> {
        Matrix3::new(0.0, -k.z, k.y, k.z, 0.0, -k.x, -k.y, k.x, 0.0)
    }

    fn helices() -> Vec<Helix> {
        vec![
            Helix::new(0.3, 0.4, 1.2, 0.8),
            Helix::new(0.05, 1.1, 0.02, 0.05).with_extra_twist(7.0),
            Helix::new(1.0, -0.3, 2.0, 1.0).with_extra_twist(-0.8),
        ]
    }

    const STATIONS: [f64; 4] = [0.0, 0.37, 1.9, 5.3];

    /// Largest angular rate (1/m) of the helix quantities.
    fn rate(h: &Helix) -> f64 {
        (h.pitch_angle.cos() / h.radius).abs() + h.material_curvature(0.0).norm() + 1.0
    }

    /// Finite-difference step adapted to the helix (1/m rates ≈ 1e-3/h).
    fn fd_step(h: &Helix) -> f64 {
        2e-3 / rate(h)
    }

    #[test]
    fn untwisted_curvature_formula() {
        let h = Helix::new(0.3, 0.4, 1.2, 0.8);
        let (sa, ca) = h.pitch_angle.sin_cos();
        let k = h.material_curvature(2.1);
        assert!(k.x.abs() < 1e-15);
        assert!((k.y - ca * ca / 0.3).abs() < 1e-14);
        assert!((k.z - sa * ca / 0.3).abs() < 1e-14);
        // d₁ points towards the axis.
        let r = h.centreline(2.1);
        let d1 = h.material_frame(2.1).column(0).into_owned();
        assert!((d1 + Vector3::new(r.x, r.y, 0.0) / 0.3).norm() < 1e-15);
    }

    #[test]
    fn frame_is_a_rotation_with_d3_tangent() {
        for h in helices() {
            for s in STATIONS {
                let r = h.material_frame(s);
                assert!((r.transpose() * r - Matrix3::identity()).norm() < 1e-14);
                assert!((r.determinant() - 1.0).abs() < 1e-14);
                let dr = d_ds(|x| h.centreline(x), s, fd_step(&h));
                assert!((dr - r.column(2)).norm() < 1e-10);
                assert!((h.tangent(s) - r.column(2)).norm() < 1e-15);
            }
        }
    }

    #[test]
    fn material_curvature_generates_the_frame() {
        // R' = R [K]× by finite differences.
        for h in helices() {
            for s in STATIONS {
                let dr = d_ds(|x| h.material_frame(x), s, fd_step(&h));
                let want = h.material_frame(s) * skew(&h.material_curvature(s));
                assert!(
                    (dr - want).norm() < 1e-9 * rate(&h),
                    "{}",
                    (dr - want).norm()
                );
            }
        }
    }

    #[test]
    fn kirchhoff_balance_holds_with_axial_force() {
        for h in helices() {
            let n = h.internal_force();
            let dh = fd_step(&h);
            for s in STATIONS {
                // Constitutive moment in the material frame.
                let m_of = |x: f64| {
                    let k = h.material_curvature(x);
                    h.material_frame(x) * Vector3::new(h.ei * k.x, h.ei * k.y, h.gj * k.z)
                };
                assert!((m_of(s) - h.internal_moment(s)).norm() < 1e-13);
                let t = h.tangent(s);
                let t_prime = d_ds(|x| h.tangent(x), s, dh);
                let m_alt = t.cross(&t_prime) * h.ei + t * (h.gj * h.twist());
                assert!((m_alt - m_of(s)).norm() < 1e-9 * h.ei.max(h.gj) * rate(&h));
                let residual = d_ds(m_of, s, dh) + t.cross(&n);
                let scale = h.bending_moment().abs() + h.torsional_moment().abs();
                assert!(
                    residual.norm() < 1e-9 * scale * rate(&h),
                    "{}",
                    residual.norm()
                );
                // The opposite sign of F would violate the balance.
                let wrong = d_ds(m_of, s, dh) - t.cross(&n);
                assert!(h.axial_force() == 0.0 || wrong.norm() > 1e-3 * scale);
                // Conserved resultant moment: m + r × n = M e₃.
                let total = m_of(s) + h.centreline(s).cross(&n);
                assert!((total - Vector3::z() * h.axial_couple()).norm() < 1e-12 * (1.0 + scale));
            }
        }
    }

    #[test]
    fn love_special_cases() {
        // Twist-free (κ₃ = 0) helix: F = −EI sin α cos²α/ρ² (compression).
        let h = Helix::new(0.5, 0.6, 2.0, 1.0);
        let h0 = h.with_extra_twist(-h.torsion());
        assert!(h0.twist().abs() < 1e-15);
        let (sa, ca) = h.pitch_angle.sin_cos();
        assert!((h0.axial_force() + 2.0 * sa * ca * ca / 0.25).abs() < 1e-13);
        // Force-free helix: GJ κ₃ = EI τ (a free helical spring).
        let hf = h.with_extra_twist(h.ei / h.gj * h.torsion() - h.torsion());
        assert!(hf.axial_force().abs() < 1e-13);
        // Planar ring (α = 0): no axial force without twist, and the
        // couple is the bending moment EI/ρ.
        let ring = Helix::new(0.5, 0.0, 2.0, 1.0);
        assert!(ring.axial_force().abs() < 1e-15);
        assert!((ring.axial_couple() - 4.0).abs() < 1e-15);
        assert!((h.pitch() - 2.0 * std::f64::consts::PI * 0.5 * 0.6f64.tan()).abs() < 1e-15);
    }
}
