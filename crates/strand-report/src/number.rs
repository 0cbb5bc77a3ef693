//! Numbers as text for the result files: shortest round-trip decimals, byte for byte
//! what `std`'s `{}` / `{:e}` print, without `std`'s formatting machinery (the OBJ
//! writer got 1.6 times, the CSV writer 1.45 times faster with `ryu`; `zmij` takes
//! about half `ryu`'s time per number).
//!
//! The shortest digits that read back to the same `f64`, the nearest to the exact value
//! of those, come from `zmij` (Zverovich's Schubfach variant, the formatter serde_json
//! uses for `result.json`; about twice as fast as `ryu`, which gives the same digits),
//! the digits `std` finds by Grisu with a Dragon fallback through the formatting
//! machinery (most of the time of writing CSV, VTK and OBJ files); they are laid out
//! here in `std`'s notation (`0.25`, `-13.5`, `100`, `7.16e-19`, `2.5e20`). The test
//! below checks the text against `std`'s on 800 000 values, and `zmij`'s digits
//! against `ryu`'s.

/// Appends `value` in its shortest round-trip form: positional (`0.25`, `-13.5`) for
/// magnitudes in [1e-5, 1e16), exponent form (`7.16e-19`) otherwise, so that round-off
/// noise does not print as a long run of zeros; `0`, `-0`, `NaN`, `inf`, `-inf` as
/// `std` prints them.
pub fn push_number(out: &mut String, value: f64) {
    let exponent_form = !(1e-5..1e16).contains(&value.abs());
    if !value.is_finite() || value == 0.0 || may_tie(value) {
        // Rare: `std` prints these (`NaN`, `inf`, `-inf`, `0`, `-0`, ties).
        use std::fmt::Write;
        let _ = if exponent_form && value.is_finite() && value != 0.0 {
            write!(out, "{value:e}")
        } else {
            write!(out, "{value}")
        };
        return;
    }
    let mut buffer = zmij::Buffer::new();
    let text = buffer.format_finite(value);
    if !exponent_form {
        // `zmij` writes this range positionally too, as `std` does, apart from the `.0`
        // it appends to an integer (`100.0`); copied without laying the digits out.
        let positional = text.strip_suffix(".0").unwrap_or(text);
        // (The cheap test first: looking for the point is a `memchr` call.)
        if !(positional.ends_with('0') && positional.contains('.')) {
            out.push_str(positional);
            return;
        }
    }
    let text = text.as_bytes();
    let (negative, text) = match text.split_first() {
        Some((b'-', rest)) => (true, rest),
        _ => (false, text),
    };
    // `text` is `mantissa[e±exponent]` (`zmij` writes `e+20` where `std` writes
    // `e20`); the mantissa's digits with the decimal point
    // after `point` of them.
    let (mantissa, exponent) = match text.iter().position(|&b| b == b'e') {
        Some(at) => (&text[..at], parse_exponent(&text[at + 1..])),
        None => (text, 0),
    };
    let mut digits = [0u8; 24];
    let (mut count, mut point) = (0, None);
    for &b in mantissa {
        if b == b'.' {
            point = Some(count);
        } else {
            digits[count] = b;
            count += 1;
        }
    }
    // value = 0.d₁d₂… × 10^before, with the leading and trailing zeros dropped.
    let mut before = point.unwrap_or(count) as i32 + exponent;
    let leading = digits[..count].iter().take_while(|&&d| d == b'0').count();
    before -= leading as i32;
    let trailing = digits[leading..count]
        .iter()
        .rev()
        .take_while(|&&d| d == b'0')
        .count();
    let digits = &digits[leading..count - trailing];
    let digits = std::str::from_utf8(digits).expect("ASCII digits");
    if negative {
        out.push('-');
    }
    if exponent_form {
        out.push_str(&digits[..1]);
        if digits.len() > 1 {
            out.push('.');
            out.push_str(&digits[1..]);
        }
        out.push('e');
        push_integer(out, i64::from(before - 1));
    } else if before <= 0 {
        out.push_str("0.");
        (0..-before).for_each(|_| out.push('0'));
        out.push_str(digits);
    } else if before as usize >= digits.len() {
        out.push_str(digits);
        (digits.len()..before as usize).for_each(|_| out.push('0'));
    } else {
        out.push_str(&digits[..before as usize]);
        out.push('.');
        out.push_str(&digits[before as usize..]);
    }
}

/// Whether the exact value of `value` may lie halfway between its two nearest shortest
/// decimals, where `zmij` (like `ryu`) rounds the tie to even and `std` up: its exact decimal
/// expansion is short (at most 18 significant digits, ending in 5:
/// `0.59510040283203125`, `2164804563772078.25`), or it is an integer of 18 digits or
/// more. Such values have few significant bits and are rare in results; `std` prints
/// them.
fn may_tie(value: f64) -> bool {
    let bits = value.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let fraction = bits & ((1 << 52) - 1);
    let (mantissa, exponent) = if biased == 0 {
        (fraction, -1074)
    } else {
        (fraction | (1 << 52), biased - 1075)
    };
    let zeros = mantissa.trailing_zeros();
    let (mantissa, exponent) = (mantissa >> zeros, exponent + zeros as i32);
    if exponent >= 0 {
        return value.abs() >= 1e17;
    }
    // value = mantissa · 5^k / 10^k: its significant digits are those of mantissa · 5^k
    // (odd, so no trailing zero). At most 18 of them need 5^k < 10^18, k ≤ 25.
    let k = (-exponent) as u32;
    k <= 25 && u128::from(mantissa) * 5u128.pow(k) < 1_000_000_000_000_000_000
}

/// The exponent after `e`: optional sign, decimal digits.
fn parse_exponent(text: &[u8]) -> i32 {
    let (sign, digits) = match text.split_first() {
        Some((b'-', rest)) => (-1, rest),
        Some((b'+', rest)) => (1, rest),
        _ => (1, text),
    };
    sign * digits
        .iter()
        .fold(0i32, |v, &d| 10 * v + i32::from(d - b'0'))
}

/// Appends the integer `value` in decimal (`itoa`, without the formatting machinery).
pub fn push_integer(out: &mut String, value: impl itoa::Integer) {
    out.push_str(itoa::Buffer::new().format(value));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What the writers printed before, with `std`.
    fn reference(value: f64) -> String {
        let magnitude = value.abs();
        if value != 0.0 && value.is_finite() && !(1e-5..1e16).contains(&magnitude) {
            format!("{value:e}")
        } else {
            format!("{value}")
        }
    }

    /// Byte for byte `std`'s text on 800 000 values: random bit patterns (every
    /// magnitude), random decimals of a few digits, integers, values of few significant
    /// bits (where the 17-digit ties are), and the edges of the positional range.
    #[test]
    fn prints_exactly_what_std_prints() {
        let mut state = 0x853c_49e6_748f_ea9b_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut values = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.1,
            0.25,
            -13.5,
            100.0,
            1e15,
            9.999999999999998e15,
            1e16,
            1e-5,
            9.99999e-6,
            1.0000000000000002e-5,
            5e-324,
            f64::MAX,
            f64::MIN_POSITIVE,
            -7.163972553141504e-19,
            2.5e20,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            123456789012345680.0,
            0.3,
            2.0 / 3.0,
            2164804563772078.2, // exactly 2164804563772078.25 (the shortest literal of that f64)
            2.5e17,
            1.5e-300,
        ];
        for _ in 0..200_000 {
            values.push(f64::from_bits(next()));
            let digits = (next() % 1_000_000) as f64;
            let scale = 10f64.powi((next() % 40) as i32 - 20);
            values.push(digits * scale);
            values.push(-((next() % 100_000) as f64));
            let few_bits = (next() % (1 << 20)) as f64 * 2f64.powi((next() % 120) as i32 - 60);
            values.push(few_bits);
        }
        let mut out = String::new();
        for value in values {
            out.clear();
            push_number(&mut out, value);
            assert_eq!(out, reference(value), "{value:?}");
            if value.is_finite() && value != 0.0 {
                // The same shortest digits as `ryu` (the formatter used before).
                let digits = |t: &str| {
                    let mantissa = t.split('e').next().unwrap_or(t).replace(['-', '.'], "");
                    mantissa
                        .trim_start_matches('0')
                        .trim_end_matches('0')
                        .to_string()
                };
                assert_eq!(
                    digits(zmij::Buffer::new().format_finite(value)),
                    digits(ryu::Buffer::new().format_finite(value)),
                    "{value:?}"
                );
            }
            if value.is_finite() {
                assert_eq!(out.parse::<f64>().unwrap().to_bits(), value.to_bits());
            }
        }
    }

    #[test]
    fn integers_print_in_decimal() {
        let mut out = String::new();
        for v in [0i64, 7, -42, i64::MAX, i64::MIN] {
            out.clear();
            push_integer(&mut out, v);
            assert_eq!(out, v.to_string());
        }
    }
}
