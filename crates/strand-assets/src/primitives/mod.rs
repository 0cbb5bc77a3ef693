//! Mesh primitives with sizes in metres (one file per primitive).

pub(crate) mod axis_box;
pub(crate) mod chamfered_box;
pub(crate) mod cylinder;
pub(crate) mod parallelogram;
pub(crate) mod plane;
pub(crate) mod tube;
pub(crate) mod wavy_surface;

/// Panics with a message naming the argument unless `value` is finite and positive.
pub(crate) fn require_positive(name: &str, value: f64) {
    assert!(
        value.is_finite() && value > 0.0,
        "{name} = {value}: must be a finite length > 0"
    );
}
