//! The length unit of a case file and its conversion to SI.

use std::fmt;

/// Length unit of a case file (`units: (length: "mm")`). Only lengths are scaled; every
/// other quantity is SI in the file already.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum LengthUnit {
    /// Millimetre, `"mm"` (0.001 m).
    Millimetre,
    /// Metre, `"m"`.
    Metre,
}

impl LengthUnit {
    /// Every accepted spelling, for messages.
    pub const ACCEPTED: &'static str = "\"mm\" or \"m\"";

    /// Parses the unit as written in the file (`"mm"` or `"m"`).
    pub fn parse(text: &str) -> Option<Self> {
        match text {
            "mm" => Some(LengthUnit::Millimetre),
            "m" => Some(LengthUnit::Metre),
            _ => None,
        }
    }

    /// One unit in m.
    pub fn metres(self) -> f64 {
        match self {
            LengthUnit::Millimetre => 1e-3,
            LengthUnit::Metre => 1.0,
        }
    }

    /// The unit's symbol, `"mm"` or `"m"`.
    pub fn symbol(self) -> &'static str {
        match self {
            LengthUnit::Millimetre => "mm",
            LengthUnit::Metre => "m",
        }
    }
}

impl fmt::Display for LengthUnit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol())
    }
}

/// `value` in decimal with at most `decimals` decimals, trailing zeros (and a bare
/// point) dropped, `-0` as `0`: the form batch ids and design points name values in.
///
/// ```
/// assert_eq!(strand_case::canonical_decimal(-249.99999995633672, 6), "-250");
/// assert_eq!(strand_case::canonical_decimal(0.125, 9), "0.125");
/// assert_eq!(strand_case::canonical_decimal(-1e-12, 6), "0");
/// ```
pub fn canonical_decimal(value: f64, decimals: usize) -> String {
    let text = format!("{value:.decimals$}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".to_string()
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_scales() {
        assert_eq!(LengthUnit::parse("mm"), Some(LengthUnit::Millimetre));
        assert_eq!(LengthUnit::parse("m").map(LengthUnit::metres), Some(1.0));
        assert_eq!(LengthUnit::parse("cm"), None);
        assert_eq!(LengthUnit::Millimetre.to_string(), "mm");
    }
}
