//! Parameter values and ranges as typed on the command line: `4deg`, `-8deg..8deg:0.5deg`
//! (the unit may be left out; when given it must be the motion's).

/// Why a value or range does not parse or does not fit its motion.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RangeError {
    /// Not of the form `A..B:STEP`.
    #[error("'{text}' is not a range: write FROM..TO:STEP, e.g. -8deg..8deg:0.5deg")]
    Form {
        /// The text given.
        text: String,
    },
    /// A number does not parse.
    #[error("'{text}' is not a number (optionally followed by the unit {unit})")]
    Number {
        /// The text given.
        text: String,
        /// The motion's unit.
        unit: String,
    },
    /// A number carries another unit than the motion's.
    #[error("'{text}' is in {given}, but motion '{motion}' is measured in {unit}")]
    Unit {
        /// The text given.
        text: String,
        /// The unit written.
        given: String,
        /// The motion's name.
        motion: String,
        /// The motion's unit.
        unit: String,
    },
    /// The step is not positive or the range is empty.
    #[error("range {from}..{to}:{step} {unit}: the step must be positive and FROM < TO")]
    Empty {
        /// Start value.
        from: f64,
        /// End value.
        to: f64,
        /// Step.
        step: f64,
        /// The motion's unit.
        unit: String,
    },
    /// More steps than [`MotionRange::MAX_STEPS`].
    #[error("range {from}..{to}:{step} {unit} has {count} steps, more than the {max} allowed")]
    TooMany {
        /// Start value.
        from: f64,
        /// End value.
        to: f64,
        /// Step.
        step: f64,
        /// The motion's unit.
        unit: String,
        /// Steps it would take.
        count: f64,
        /// The limit.
        max: usize,
    },
}

/// A range of parameter values `from..to` in steps of `step` (motion's unit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionRange {
    /// First value.
    pub from: f64,
    /// Last value.
    pub to: f64,
    /// Step between values (the last step may be shorter, to end at `to`).
    pub step: f64,
}

/// Parses one number with an optional unit suffix (`4`, `4deg`, `-0.5 mm`).
pub fn parse_value(text: &str, motion: &str, unit: &str) -> Result<f64, RangeError> {
    let t = text.trim();
    let split = t
        .find(|c: char| c.is_ascii_alphabetic() && c != 'e' && c != 'E')
        .unwrap_or(t.len());
    let (number, given) = (t[..split].trim(), t[split..].trim());
    // The number first: `abc` or `NaNdeg` is no number, whatever its unit would be.
    let value = number
        .parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| RangeError::Number {
            text: text.to_string(),
            unit: unit.to_string(),
        })?;
    if !given.is_empty() && given != unit {
        return Err(RangeError::Unit {
            text: text.to_string(),
            given: given.to_string(),
            motion: motion.to_string(),
            unit: unit.to_string(),
        });
    }
    Ok(value)
}

impl MotionRange {
    /// Most values a range may have.
    pub const MAX_STEPS: usize = 100_000;

    /// Parses `FROM..TO:STEP` for motion `motion` measured in `unit`.
    ///
    /// ```
    /// use strand_case::motion::MotionRange;
    /// let r = MotionRange::parse("-8deg..8deg:0.5deg", "engine_roll", "deg").unwrap();
    /// assert_eq!(r.values().len(), 33);
    /// assert!(MotionRange::parse("-8mm..8mm:1mm", "engine_roll", "deg").is_err());
    /// ```
    pub fn parse(text: &str, motion: &str, unit: &str) -> Result<Self, RangeError> {
        let form = || RangeError::Form {
            text: text.to_string(),
        };
        let (span, step) = text.rsplit_once(':').ok_or_else(form)?;
        let (from, to) = span.split_once("..").ok_or_else(form)?;
        let range = Self {
            from: parse_value(from, motion, unit)?,
            to: parse_value(to, motion, unit)?,
            step: parse_value(step, motion, unit)?,
        };
        let count = ((range.to - range.from) / range.step).ceil();
        if !(range.step > 0.0 && range.from < range.to) {
            return Err(RangeError::Empty {
                from: range.from,
                to: range.to,
                step: range.step,
                unit: unit.to_string(),
            });
        }
        if count >= Self::MAX_STEPS as f64 {
            return Err(RangeError::TooMany {
                from: range.from,
                to: range.to,
                step: range.step,
                unit: unit.to_string(),
                count,
                max: Self::MAX_STEPS,
            });
        }
        Ok(range)
    }

    /// The values `from, from + step, …, to` (the last one exactly `to`; a remainder
    /// below a millionth of a step is dropped).
    pub fn values(&self) -> Vec<f64> {
        let n = ((self.to - self.from) / self.step - 1e-6).ceil().max(1.0) as usize;
        let mut v: Vec<f64> = (0..n).map(|i| self.from + i as f64 * self.step).collect();
        v.push(self.to);
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_and_units() {
        let r = MotionRange::parse("0..90:10", "hinge", "deg").unwrap();
        assert_eq!(
            r.values(),
            (0..=9).map(|k| 10.0 * k as f64).collect::<Vec<_>>()
        );
        let r = MotionRange::parse("0..1:0.3", "lift", "mm").unwrap();
        assert_eq!(r.values().len(), 5);
        assert_eq!(*r.values().last().unwrap(), 1.0);
        assert_eq!(parse_value("-2.5e1deg", "x", "deg"), Ok(-25.0));
        assert!(matches!(
            parse_value("4rad", "x", "deg"),
            Err(RangeError::Unit { .. })
        ));
        // Text that is no number is said to be none, not to be in another unit.
        for text in ["abc", "NaNdeg", "infdeg", "deg", ""] {
            assert!(
                matches!(
                    parse_value(text, "x", "deg"),
                    Err(RangeError::Number { .. })
                ),
                "{text}"
            );
        }
        assert!(matches!(
            MotionRange::parse("0..90", "x", "deg"),
            Err(RangeError::Form { .. })
        ));
        assert!(matches!(
            MotionRange::parse("5..1:1", "x", "deg"),
            Err(RangeError::Empty { .. })
        ));
        assert!(matches!(
            MotionRange::parse("0..1:0", "x", "deg"),
            Err(RangeError::Empty { .. })
        ));
        assert!(matches!(
            MotionRange::parse("0..1e9:1", "x", "deg"),
            Err(RangeError::TooMany { .. })
        ));
    }
}
