//! Independent reference solutions (see the crate docs).

pub mod buckling;
pub mod catenary;
pub mod euler_bernoulli;
pub mod heavy_cantilever;
pub mod kirchhoff_helix;
pub mod ode;
pub mod reissner_planar;
