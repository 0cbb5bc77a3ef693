//! The numbers of a plain OBJ line, parsed exactly as tobj parses them.
//!
//! tobj parses coordinates with `f64::from_str` and face references with
//! `isize::from_str`. A coordinate here is the same `f64`, bit for bit: short decimals
//! (`-997.1751`: at most 19 digits, a mantissa below 2⁵³, at most 22 after the point,
//! no exponent) are one correctly rounded IEEE division of two exactly representable
//! numbers (Clinger's fast path), which is the correctly rounded value `from_str`
//! gives; every other spelling goes to `f64::from_str` itself.

/// `10^k` for `k = 0..=22`, each exact in `f64`.
const POWERS_OF_TEN: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// The largest mantissa that is exact in `f64`, 2⁵³.
const EXACT_MANTISSA: u64 = 1 << 53;

/// The value `f64::from_str` gives for `token` (ASCII), or `None` where it fails.
#[inline]
pub(super) fn parse_f64(token: &[u8]) -> Option<f64> {
    match short_decimal(token) {
        Some(x) => Some(x),
        None => std::str::from_utf8(token).ok()?.parse().ok(),
    }
}

/// `[-+]digits[.digits]` with at most 19 digits, a mantissa ≤ 2⁵³ and at most 22
/// digits after the point, as a correctly rounded `f64`; `None` for anything else
/// (including valid numbers of other spellings, which [`parse_f64`] hands to std).
#[inline]
fn short_decimal(token: &[u8]) -> Option<f64> {
    let (negative, digits) = match token.first()? {
        b'-' => (true, &token[1..]),
        b'+' => (false, &token[1..]),
        _ => (false, token),
    };
    let mut mantissa: u64 = 0;
    let mut count = 0usize;
    let mut point: Option<usize> = None;
    for (k, &b) in digits.iter().enumerate() {
        match b {
            b'0'..=b'9' => {
                mantissa = mantissa * 10 + u64::from(b - b'0');
                count += 1;
                if count > 19 {
                    return None;
                }
            }
            b'.' if point.is_none() => point = Some(k),
            _ => return None,
        }
    }
    let fraction = match point {
        // A digit on both sides of the point: "1." and ".5" go to std.
        Some(k) if k == 0 || k + 1 == digits.len() => return None,
        Some(k) => digits.len() - k - 1,
        None if count == 0 => return None,
        None => 0,
    };
    exact_decimal(negative, mantissa, fraction)
}

/// `±mantissa / 10^fraction` as one correctly rounded division of two exact numbers
/// (Clinger's fast path), or `None` where either is not exact in `f64` (a mantissa
/// above 2⁵³ or more than 22 digits after the point).
#[inline]
pub(super) fn exact_decimal(negative: bool, mantissa: u64, fraction: usize) -> Option<f64> {
    if mantissa > EXACT_MANTISSA || fraction > 22 {
        return None;
    }
    let magnitude = mantissa as f64 / POWERS_OF_TEN[fraction];
    Some(if negative { -magnitude } else { magnitude })
}

/// A face reference as tobj's `isize::from_str` reads it, restricted to what the plain
/// subset accepts: `[-]digits`, not zero, at most 18 digits. `None` for anything else
/// (a `+`, a zero, an overflow, a non-digit), which sends the file to tobj.
#[inline]
pub(super) fn parse_reference(token: &[u8]) -> Option<i64> {
    let (negative, digits) = match token.first()? {
        b'-' => (true, &token[1..]),
        _ => (false, token),
    };
    if digits.is_empty() || digits.len() > 18 {
        return None;
    }
    let mut value: i64 = 0;
    for &b in digits {
        if !b.is_ascii_digit() {
            return None;
        }
        value = value * 10 + i64::from(b - b'0');
    }
    match (value, negative) {
        (0, _) => None,
        (v, true) => Some(-v),
        (v, false) => Some(v),
    }
}

#[cfg(test)]
mod tests {
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    /// Bit-identical to `f64::from_str`, or both fail.
    fn same_as_std(token: &str) {
        let ours = parse_f64(token.as_bytes()).map(f64::to_bits);
        let std = token.parse::<f64>().ok().map(f64::to_bits);
        assert_eq!(ours, std, "{token:?}");
    }

    #[test]
    fn coordinates_are_the_bits_std_parses() {
        let spellings = [
            "0",
            "-0",
            "+0",
            "0.0",
            "-0.0",
            "1",
            "-997.1751",
            "3.5452",
            "1e3",
            "1E-3",
            "1.",
            ".5",
            "-.5",
            "+.5",
            ".",
            "-",
            "+",
            "",
            "1..2",
            "1.2.3",
            "inf",
            "-inf",
            "NaN",
            "infinity",
            "1e",
            "1e+",
            "0x10",
            "1_000",
            "12a",
            "9007199254740992",
            "9007199254740993",
            "9007199254740993.0",
            "0.1",
            "0.30000000000000004",
            "1234567890123456789",
            "12345678901234567890",
            "0.0000000000000000000001",
            "0.00000000000000000000001",
            "123.456e-7",
            "1.7976931348623157e308",
            "4.9e-324",
            "2.2250738585072014e-308",
            "00000000000000000001.5",
            " 1",
            "1 ",
        ];
        for s in spellings {
            same_as_std(s);
        }
    }

    #[test]
    fn random_decimals_and_full_precision_floats_are_the_bits_std_parses() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for _ in 0..200_000 {
            let x: f64 = rng.random_range(-2000.0..2000.0);
            // Full round-trip precision (17 digits: mostly std's path) and short
            // decimals of 0 to 12 places (the fast path).
            same_as_std(&format!("{x}"));
            let places = rng.random_range(0..=12);
            same_as_std(&format!("{x:.places$}"));
            same_as_std(&format!("{:.places$}", x * 1e-6));
            let mantissa: u64 = rng.random_range(0..(1u64 << 54));
            let fraction = rng.random_range(0..=23);
            let digits = mantissa.to_string();
            if fraction < digits.len() {
                let (int, frac) = digits.split_at(digits.len() - fraction);
                same_as_std(&format!("{int}.{frac}"));
                same_as_std(&format!("-{int}.{frac}"));
            }
        }
    }

    #[test]
    fn references_are_what_isize_parses_or_refused() {
        for (token, expected) in [
            ("1", Some(1)),
            ("-1", Some(-1)),
            ("710", Some(710)),
            ("0", None),
            ("-0", None),
            ("+1", None),
            ("", None),
            ("-", None),
            ("1a", None),
            ("1234567890123456789", None),
            ("123456789012345678", Some(123_456_789_012_345_678)),
        ] {
            assert_eq!(parse_reference(token.as_bytes()), expected, "{token:?}");
            if let Some(v) = expected {
                assert_eq!(token.parse::<isize>().unwrap() as i64, v);
            }
        }
    }
}
