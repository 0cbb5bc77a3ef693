//! # strand-system
//!
//! Rods plus supports assembled into one energy minimisation (DESIGN §2).
//!
//! A [`System`] lists rods with their end conditions and loads. [`Model::try_new`]
//! validates it and performs the *symbolic* phase once: the numbering of unknowns
//! ([`Dofs`]; attached vertices and boundary frames are eliminated, not constrained) and
//! the fixed sparsity pattern of the Hessian with the scatter map of every element.
//! [`Model::evaluate`] is the *numeric* phase: energy, gradient and Hessian values of a
//! [`SystemState`]. Reactions follow from the gradient with respect to the eliminated
//! coordinates.

mod attachment;
mod chain;
mod dofs;
mod initial;
mod model;
mod pattern;
mod reactions;
mod reals;
mod route;
mod support_ramp;
mod system;
mod translate;

pub use dofs::{BlockKind, ClipIndex, Dofs};
pub use initial::{Station, initial_state, initial_state_with, rod_state_along, rod_stations};
pub use model::{EdgeStresses, Evaluation, GradientDifference, Model, Residual};
pub use pattern::HessianPattern;
pub use reactions::{Reaction, ReactionKind};
pub use route::RouteShape;
pub use system::{
    BodyHandle, BodySpec, ClipReach, ClipSpec, End, EndLoad, Joint, JointState, Port, Pose,
    RodHandle, RodSpec, Support, System, SystemError, SystemState,
};

#[cfg(test)]
mod tests;

#[cfg(test)]
mod moulded_clip_tests;
