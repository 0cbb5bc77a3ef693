//! Numbers as the messages of `strand` print them (residuals in N, lengths, times):
//! the same text in the command line's output and in this crate's warnings, so that
//! other front ends (the Python package) show exactly what `strand` shows.

/// `x` with six significant digits; exponent form for very small or large values.
pub fn number(x: f64) -> String {
    significant(x, 6)
}

/// `x` with `digits` significant digits (the report's own formatting, one copy).
pub use strand_report::significant;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_digits_trailing_zeros_and_exponents() {
        assert_eq!(number(3.6e-12), "3.6e-12");
        assert_eq!(number(1.0), "1");
        assert_eq!(number(0.123456789), "0.123457");
        assert_eq!(significant(2.5e6, 3), "2.5e6");
        assert_eq!(significant(-0.00001, 3), "-1e-5");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(f64::INFINITY), "inf");
    }
}
