//! Independent reference solutions (see the crate docs).

pub mod euler_bernoulli;
pub mod kirchhoff_helix;
pub mod ode;
pub mod reissner_planar;
