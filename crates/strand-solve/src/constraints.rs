//! Inequality constraints of the minimisation, linearised at an iterate: joint limits
//! and (through [`Constraints`]) contact. Each is a row `value + Σ_k gradient_k d_k ≥ 0`
//! in the step `d`; its multiplier is the force (N) or moment (N·m) that holds it.

use strand_system::{Model, SystemState};

/// Identifies a constraint across iterates, so its multiplier carries over.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RowKey {
    /// The lower (`upper == false`) or upper stop of clip `clip`'s joint.
    Limit {
        /// Clip index.
        clip: usize,
        /// Whether this is the upper stop.
        upper: bool,
    },
    /// A contact pair, numbered by the [`Constraints`] that made it.
    Contact(u64),
}

/// One linearised inequality `value + gradient · d ≥ 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Identity of the constraint.
    pub key: RowKey,
    /// Constraint value at the iterate (a gap in m, or a joint's distance to its stop
    /// in rad or m).
    pub value: f64,
    /// Sparse gradient with respect to the unknowns: `(unknown index, ∂value/∂d)`.
    pub gradient: Vec<(usize, f64)>,
}

impl Row {
    /// `value + gradient · step`: the linearised constraint after `step`.
    pub fn linearised(&self, step: &[f64]) -> f64 {
        self.value + self.gradient.iter().map(|&(k, a)| a * step[k]).sum::<f64>()
    }
}

/// Inequality constraints beyond joint limits (contact), evaluated at every iterate.
pub trait Constraints: Sync {
    /// Appends the rows at `state`: the constraints that can become active within one
    /// step (e.g. contact pairs within a search margin). `Err` with a message when the
    /// state is not admissible (a centreline passes through an obstacle).
    fn rows(&self, model: &Model, state: &SystemState, out: &mut Vec<Row>) -> Result<(), String>;

    /// Checks a starting state: `Err` names where it violates a constraint (a hose that
    /// starts inside an obstacle).
    fn check_start(&self, model: &Model, state: &SystemState) -> Result<(), String>;

    /// Largest translation of any vertex in one step, m, so that no obstacle outside the
    /// search margin can be reached within one step.
    fn max_translation_m(&self) -> f64;
}

/// The joint-limit rows at `state`: `d_i − lower_i ≥ 0` and `upper_i − d_i ≥ 0` for
/// every limited joint (`lower_i`, `upper_i` the stops minus the current value).
pub fn limit_rows(model: &Model, state: &SystemState, out: &mut Vec<Row>) {
    let system = model.system();
    for (clip, spec) in system.clips.iter().enumerate() {
        let (Some((lower, upper)), Some(block)) = (spec.limits, model.dofs().clip(clip)) else {
            continue;
        };
        let index = 3 * block;
        let value = state.clips[clip].value;
        out.push(Row {
            key: RowKey::Limit { clip, upper: false },
            value: value - lower,
            gradient: vec![(index, 1.0)],
        });
        out.push(Row {
            key: RowKey::Limit { clip, upper: true },
            value: upper - value,
            gradient: vec![(index, -1.0)],
        });
    }
}
