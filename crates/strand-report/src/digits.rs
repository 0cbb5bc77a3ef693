//! Numbers as the terminal and the files' headers print them.

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
