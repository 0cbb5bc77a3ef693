//! # strand-rod
//!
//! The discrete quaternionic Cosserat rod of Linn et al. (paper §2.3, eqs. 5–7):
//! vertices `r_0..r_N`, one unit quaternion per edge, shear–extension strains `Γ` on
//! edges and curvatures `K` on vertices. This crate holds the *pure* mechanics:
//!
//! - [`Section`]: stiffnesses and mass per length (tube from material data, or explicit);
//! - [`so3`]: rotation helpers (skew matrices, the quaternion logarithm);
//! - [`element`]: the element energies with their exact gradients and Hessians with
//!   respect to vertex positions and right rotation increments `q ← q ⊗ exp(δθ/2)`;
//! - [`Rod`], [`RodState`]: reference geometry and a configuration;
//! - [`nominal`]: pre-deformed (moulded) rods whose stress-free shape is a nominal
//!   centreline ([`Rod::try_from_nominal`]);
//! - [`sectional`]: sectional forces, moments and the first integrals of paper §3;
//!   [`sectional_at`]: force, moment and curvature of one vertex alone;
//!   [`sectional_tangent`]: their exact first-order changes along a tangent.
//!
//! Units are SI throughout: m, N, N·m, kg, rad. No I/O happens here.

pub mod element;
pub mod nominal;
mod rod;
mod section;
pub mod sectional;
pub mod sectional_at;
pub mod sectional_tangent;
pub mod so3;

pub use nominal::{NominalError, NominalRod, NominalShape};
pub use rod::{Rod, RodError, RodState};
pub use section::{Section, SectionError, TubeMaterial};
#[cfg(test)]
mod test_rods;
