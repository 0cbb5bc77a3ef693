//! Cross-section properties: the diagonal stiffness matrices `C_Γ`, `C_K` and the mass
//! per length `ρ_L` of paper §2.1.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Isotropic linear-elastic material of a tube.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TubeMaterial {
    /// Young's modulus `E` in Pa.
    pub youngs_modulus: f64,
    /// Poisson's ratio `ν` (dimensionless, `-1 < ν ≤ 0.5`).
    pub poisson_ratio: f64,
    /// Mass density `ρ` in kg/m³.
    pub density: f64,
}

/// Effective stiffnesses and mass per length of a rod cross section.
///
/// `C_Γ = diag(GA1, GA2, EA)` (N) and `C_K = diag(EI1, EI2, GJ)` (N·m²), DESIGN §1.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Section {
    /// Shear stiffness along director `a1`, `GA1`, in N.
    pub shear_stiffness_1: f64,
    /// Shear stiffness along director `a2`, `GA2`, in N.
    pub shear_stiffness_2: f64,
    /// Axial stiffness `EA` in N.
    pub axial_stiffness: f64,
    /// Bending stiffness about `a1`, `EI1`, in N·m².
    pub bending_stiffness_1: f64,
    /// Bending stiffness about `a2`, `EI2`, in N·m².
    pub bending_stiffness_2: f64,
    /// Torsional stiffness `GJ` in N·m².
    pub torsional_stiffness: f64,
    /// Mass per length `ρ_L` in kg/m.
    pub mass_per_length: f64,
    /// Outer radius in m (for contact and drawing; 0 when unknown).
    pub outer_radius: f64,
}

/// Why a section could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SectionError {
    /// A stiffness, radius or density is not a finite positive number.
    #[error("{field} must be a finite number > 0 (got {value})")]
    NotPositive {
        /// The offending quantity.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// A quantity that may be zero is negative or not finite.
    #[error("{field} must be a finite number ≥ 0 (got {value})")]
    Negative {
        /// The offending quantity.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// The inner radius is not smaller than the outer radius.
    #[error("inner radius {inner} m must be smaller than outer radius {outer} m")]
    InnerNotSmaller {
        /// Inner radius in m.
        inner: f64,
        /// Outer radius in m.
        outer: f64,
    },
    /// Poisson's ratio outside `(-1, 0.5]`.
    #[error("Poisson's ratio must lie in (-1, 0.5] (got {0})")]
    PoissonRatio(f64),
}

fn positive(field: &'static str, value: f64) -> Result<f64, SectionError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(SectionError::NotPositive { field, value })
    }
}

fn non_negative(field: &'static str, value: f64) -> Result<f64, SectionError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(SectionError::Negative { field, value })
    }
}

impl Section {
    /// Shear factor of a thin-walled circular tube (Timoshenko), used by [`Section::try_tube`].
    pub const TUBE_SHEAR_FACTOR: f64 = 0.5;

    /// A section from explicit stiffnesses (isotropic in bending and shear).
    ///
    /// `ea`, `ga` in N; `ei`, `gj` in N·m²; `mass_per_length` in kg/m (may be 0);
    /// `outer_radius` in m (may be 0 when unknown).
    pub fn try_explicit(
        ea: f64,
        ga: f64,
        ei: f64,
        gj: f64,
        mass_per_length: f64,
        outer_radius: f64,
    ) -> Result<Self, SectionError> {
        Ok(Self {
            shear_stiffness_1: positive("GA", ga)?,
            shear_stiffness_2: ga,
            axial_stiffness: positive("EA", ea)?,
            bending_stiffness_1: positive("EI", ei)?,
            bending_stiffness_2: ei,
            torsional_stiffness: positive("GJ", gj)?,
            mass_per_length: non_negative("mass per length", mass_per_length)?,
            outer_radius: non_negative("outer radius", outer_radius)?,
        })
    }

    /// A circular tube: `A = π(ro²−ri²)`, `I = π(ro⁴−ri⁴)/4`, `J = 2I`,
    /// `G = E/(2(1+ν))`, `GA = k G A` with the shear factor `k`
    /// ([`Section::TUBE_SHEAR_FACTOR`]), `ρ_L = ρ A`. Radii in m; `inner_radius` may be 0
    /// (solid rod).
    pub fn try_tube(
        material: &TubeMaterial,
        inner_radius: f64,
        outer_radius: f64,
    ) -> Result<Self, SectionError> {
        let e = positive("Young's modulus", material.youngs_modulus)?;
        let nu = material.poisson_ratio;
        if !(nu.is_finite() && nu > -1.0 && nu <= 0.5) {
            return Err(SectionError::PoissonRatio(nu));
        }
        let rho = non_negative("density", material.density)?;
        let ro = positive("outer radius", outer_radius)?;
        let ri = non_negative("inner radius", inner_radius)?;
        if ri >= ro {
            return Err(SectionError::InnerNotSmaller {
                inner: ri,
                outer: ro,
            });
        }
        let pi = std::f64::consts::PI;
        let area = pi * (ro * ro - ri * ri);
        let inertia = pi * (ro.powi(4) - ri.powi(4)) / 4.0;
        let g = e / (2.0 * (1.0 + nu));
        let shear_factor = if ri == 0.0 {
            0.9
        } else {
            Self::TUBE_SHEAR_FACTOR
        };
        Ok(Self {
            shear_stiffness_1: shear_factor * g * area,
            shear_stiffness_2: shear_factor * g * area,
            axial_stiffness: e * area,
            bending_stiffness_1: e * inertia,
            bending_stiffness_2: e * inertia,
            torsional_stiffness: g * 2.0 * inertia,
            mass_per_length: rho * area,
            outer_radius: ro,
        })
    }

    /// `diag(C_Γ) = (GA1, GA2, EA)` in N.
    pub fn strain_stiffness(&self) -> Vector3<f64> {
        Vector3::new(
            self.shear_stiffness_1,
            self.shear_stiffness_2,
            self.axial_stiffness,
        )
    }

    /// `diag(C_K) = (EI1, EI2, GJ)` in N·m².
    pub fn curvature_stiffness(&self) -> Vector3<f64> {
        Vector3::new(
            self.bending_stiffness_1,
            self.bending_stiffness_2,
            self.torsional_stiffness,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tube_matches_hand_computation() {
        let rubber = TubeMaterial {
            youngs_modulus: 5e6,
            poisson_ratio: 0.5,
            density: 1100.0,
        };
        let s = Section::try_tube(&rubber, 0.0144, 0.0184).unwrap();
        let area = std::f64::consts::PI * (0.0184f64.powi(2) - 0.0144f64.powi(2));
        assert!((s.axial_stiffness - 5e6 * area).abs() < 1e-9);
        assert!((s.mass_per_length - 1100.0 * area).abs() < 1e-12);
        // G = E/3 for ν = 1/2 and J = 2I give GJ = 2/3 EI.
        assert!((s.torsional_stiffness - 2.0 / 3.0 * s.bending_stiffness_1).abs() < 1e-12);
    }

    #[test]
    fn rejects_bad_values() {
        let m = TubeMaterial {
            youngs_modulus: 5e6,
            poisson_ratio: 0.5,
            density: 1100.0,
        };
        assert!(matches!(
            Section::try_tube(&m, 0.02, 0.01),
            Err(SectionError::InnerNotSmaller { .. })
        ));
        assert!(Section::try_explicit(f64::NAN, 1.0, 1.0, 1.0, 0.0, 0.0).is_err());
        assert!(Section::try_explicit(1.0, 1.0, -1.0, 1.0, 0.0, 0.0).is_err());
        assert!(
            Section::try_tube(
                &TubeMaterial {
                    poisson_ratio: 0.7,
                    ..m
                },
                0.0,
                0.01
            )
            .is_err()
        );
    }
}
