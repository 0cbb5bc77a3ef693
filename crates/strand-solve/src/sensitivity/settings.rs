//! Settings of the sensitivity computation.

use serde::{Deserialize, Serialize};

use crate::SettingsError;

/// Settings of [`super::Sensitivities::compute`].
///
/// ```
/// use strand_solve::sensitivity::SensitivitySettings;
/// assert!(SensitivitySettings::default().validate().is_ok());
/// let bad = SensitivitySettings { relative_step: 0.0, ..SensitivitySettings::default() };
/// assert_eq!(bad.validate().unwrap_err().field, "relative_step");
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SensitivitySettings {
    /// Difference step of every parameter as a fraction of its scale
    /// ([`super::Design::step`]): small enough that the `O(h⁴)` truncation error of the
    /// extrapolated central differences is negligible, large enough that the round-off
    /// `ε·|g|/h` is (`ε·C`, with `C` the axial stiffness, is the gradient's round-off).
    pub relative_step: f64,
    /// The largest difference step of the outputs along the first-order path
    /// ([`super::Sensitivities::derivative`], which also tries a tenth and a
    /// hundredth of it) as a fraction of the parameter's scale.
    pub output_relative_step: f64,
    /// The refinement of the derivative against the exact directional derivative of
    /// the KKT conditions stops when its residual is below this fraction of the
    /// right-hand side's (in the solver's combined force measure, N, and in m or rad
    /// for the active rows). Where the active rows are curved (the first solve leaves
    /// their curvature out), it goes on until the residual stops falling (round-off)
    /// instead: outputs such as reactions are small differences of the stiffness
    /// terms that set the residual's scale (an axial force's change 1e-8 of them on
    /// `cable_over_box`, where stopping at 1e-9 left reactions 1e-4 off).
    pub refinement_tolerance: f64,
    /// Largest number of refinement steps per parameter: with curved active rows a
    /// step gains as little as a factor of 15 (everyday_s35_008, a cable pressed
    /// onto ridges: 12 steps to round-off, its reactions 8e-5 off after 8).
    pub max_refinements: usize,
    /// Whether `∂Φ/∂p` is the Richardson extrapolation of central differences of steps
    /// `h` and `2h` (truncation error `O(h⁴)`, four evaluations; default) or the central
    /// difference of step `h` alone (`O(h²)`, two evaluations: enough for a predictor).
    pub richardson: bool,
    /// An active row whose multiplier is below this fraction of the largest one (or
    /// of 1 N) is flagged as about to open.
    pub near_zero_multiplier: f64,
    /// An open row whose gap is below this (m for contact, rad or m for joint stops)
    /// is flagged as about to close.
    pub near_zero_gap: f64,
    /// Whether the differences of `∂Φ/∂p` evaluate only the elements whose inputs the
    /// parameter changes ([`strand_system::Model::gradient_difference`]; default) or
    /// the whole model's gradient at each side (the reference path: the same
    /// derivatives to the gradients' round-off, at the cost of every element).
    pub element_differences: bool,
    /// Whether `∂Φ/∂p` of a parameter that moves the model along a line of its real
    /// numbers ([`super::Design::model_line`]) is the closed-form derivative of the
    /// elements' gradients along it ([`strand_system::Model::gradient_derivative`]:
    /// no design built, one evaluation per element the parameter changes; default),
    /// or the differences of designs built at `±h`, `±2h` (the reference path). Active
    /// contact or stop rows add their part, zero where the line moves nothing they
    /// read, else from the rows at the model moved along the line; lines that move a
    /// body's geometry, a clip or a frame take the differences of designs either way.
    pub exact_right_hand_sides: bool,
}

impl Default for SensitivitySettings {
    fn default() -> Self {
        Self {
            relative_step: 1e-4,
            output_relative_step: 1e-4,
            refinement_tolerance: 1e-9,
            max_refinements: 20,
            richardson: true,
            near_zero_multiplier: 1e-6,
            near_zero_gap: 1e-6,
            element_differences: true,
            exact_right_hand_sides: true,
        }
    }
}

impl SensitivitySettings {
    /// Checks every setting.
    pub fn validate(&self) -> Result<(), SettingsError> {
        let positive = SettingsError::require_positive;
        positive("relative_step", self.relative_step)?;
        positive("output_relative_step", self.output_relative_step)?;
        positive("refinement_tolerance", self.refinement_tolerance)?;
        positive("near_zero_multiplier", self.near_zero_multiplier)?;
        positive("near_zero_gap", self.near_zero_gap)?;
        Ok(())
    }
}
