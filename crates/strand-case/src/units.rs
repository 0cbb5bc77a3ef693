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
