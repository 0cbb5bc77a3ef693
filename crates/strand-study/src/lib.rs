//! # strand-study
//!
//! Design studies over the equilibrium of a case: [`optimize`] finds the best values of
//! design parameters within bounds (lengths, positions, masses, …) for an objective
//! (the largest peak force, a reaction, the energy, any output of
//! `sensitivity.json`) under output constraints (clearances, bend radii), with the
//! exact gradients of [`strand_solve::sensitivity`].

pub mod optimize;
