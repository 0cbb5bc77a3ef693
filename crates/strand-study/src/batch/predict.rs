//! The start of a variant from the solved variants before it on its parameter line:
//! each solved state is carried onto the new variant's rods
//! ([`strand_case::warm_start`], by arc-length fraction), then extrapolated to the
//! variant's value ([`strand_solve::continuation::predictor`]).

use strand_case::{BuiltCase, warm_start};
use strand_solve::continuation::predictor::extrapolate;
use strand_system::{Model, SystemState};

/// A solved variant (or the case itself, `n = None`).
pub(crate) struct Solved {
    /// The variant's index in the plan (`None`: the case itself).
    pub n: Option<usize>,
    /// Its built case.
    pub built: BuiltCase,
    /// Its equilibrium.
    pub state: SystemState,
}

/// The start of `target` from the solved `samples` (nearest first) at parameter
/// values `xs`, extrapolated to `x`. One sample: the plain warm start.
pub(crate) fn predicted_start(
    samples: &[&Solved],
    xs: &[f64],
    x: f64,
    target: &Model,
) -> SystemState {
    let carried: Vec<SystemState> = samples
        .iter()
        .map(|s| warm_start(&s.built.model, &s.state, target))
        .collect();
    extrapolate(&carried, xs, x)
}
