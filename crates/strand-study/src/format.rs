//! Numbers as the messages of `strand` print them (residuals in N, lengths, times):
//! the same text in the command line's output and in this crate's warnings, so that
//! other front ends (the Python package) show exactly what `strand` shows.

/// `x` with six significant digits; exponent form for very small or large values.
pub fn number(x: f64) -> String {
    significant(x, 6)
}

/// `x` with `digits` significant digits, trailing zeros removed; exponent form below
/// 1e-4 and from 1e6 on.
pub fn significant(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return if x == 0.0 {
            "0".to_string()
        } else {
            x.to_string()
        };
    }
    let digits = digits.max(1);
    let trim = |t: String| {
        if t.contains('.') {
            t.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            t
        }
    };
    let exponent = x.abs().log10().floor();
    if !(-4.0..6.0).contains(&exponent) {
        let text = format!("{x:.prec$e}", prec = digits - 1);
        let (mantissa, exp) = text.split_once('e').unwrap_or((&text, "0"));
        format!("{}e{exp}", trim(mantissa.to_string()))
    } else {
        let decimals = (digits as f64 - 1.0 - exponent).max(0.0) as usize;
        let text = trim(format!("{x:.decimals$}"));
        if text == "-0" { "0".to_string() } else { text }
    }
}

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
