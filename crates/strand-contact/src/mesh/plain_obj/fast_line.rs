//! The common `v` and `f` lines of a piece read in one pass over their bytes: the
//! words found and their numbers parsed together, the line's end found on the way.
//! Such a line is ASCII (every byte taken is one of a few ASCII bytes).
//!
//! A line is taken here only in the simplest spelling that the general path
//! ([`Chunk::line`]) reads the same way: `v` and three short decimals (as
//! [`super::number`]'s fast path reads them), or `f` and three or more references of
//! at most nine digits, each `v`, `v/t`, `v//n` or `v/t/n` (positive, not zero).
//! Anything else is declined before the piece is changed, and the general path reads
//! the line (or refuses the file), so the piece comes out the same either way.

use super::chunk::Chunk;
use super::number::exact_decimal;

/// `10^k` for `k = 0..=19`, as integers.
const INTEGER_POWERS_OF_TEN: [u64; 20] = {
    let mut powers = [1u64; 20];
    let mut k = 1;
    while k < 20 {
        powers[k] = powers[k - 1] * 10;
        k += 1;
    }
    powers
};

/// The most digits of a face reference read here (larger ones: the general path).
const REFERENCE_DIGITS: usize = 9;

/// The most references of a face read here (longer faces: the general path).
const FACE_REFERENCES: usize = 16;

/// Bytes that split words within a line (what `char::is_whitespace` says of ASCII,
/// without the newline that ends the line).
#[inline]
pub(super) fn is_blank(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | 0x0b | 0x0c)
}

/// Whether a word ends before byte `at` of `text`: at the end of the text, a newline
/// or a blank.
#[inline]
fn word_ends(text: &[u8], at: usize) -> bool {
    text.get(at).is_none_or(|&b| b == b'\n' || is_blank(b))
}

/// The first non-blank byte at or after `at`.
#[inline]
fn skip_blanks(text: &[u8], mut at: usize) -> usize {
    while at < text.len() && is_blank(text[at]) {
        at += 1;
    }
    at
}

/// The end of the line at `at`: past its newline, or the end of the text. `None` if a
/// word is left before it.
#[inline]
fn line_end(text: &[u8], at: usize) -> Option<usize> {
    let at = skip_blanks(text, at);
    match text.get(at) {
        None => Some(at),
        Some(b'\n') => Some(at + 1),
        Some(_) => None,
    }
}

/// The decimal digits at `at`: their value (wrapping past 19 digits) and where they
/// end. Stops early once more than `limit` are read (the callers refuse those), so
/// the end is exact only for runs of at most `limit` digits.
#[inline]
fn digits(text: &[u8], at: usize, limit: usize) -> (u64, usize) {
    let mut value: u64 = 0;
    let mut end = at;
    // Eight bytes at a time while eight are left.
    while let Some(bytes) = text.get(end..end + 8) {
        let word = u64::from_le_bytes(bytes.try_into().expect("eight bytes"));
        let (run, count) = leading_digits(word);
        if count > 0 {
            value = value
                .wrapping_mul(INTEGER_POWERS_OF_TEN[count])
                .wrapping_add(run);
        }
        end += count;
        if count < 8 || end - at > limit {
            return (value, end);
        }
    }
    while end < text.len() && text[end].is_ascii_digit() && end - at <= limit {
        value = value
            .wrapping_mul(10)
            .wrapping_add(u64::from(text[end] - b'0'));
        end += 1;
    }
    (value, end)
}

/// The decimal digits that begin `word` (eight bytes of text, the first in the lowest
/// byte): their value and how many there are (0 to 8), SWAR.
#[inline]
fn leading_digits(word: u64) -> (u64, usize) {
    const ONES: u64 = 0x0101_0101_0101_0101;
    // Digits become 0..=9; a byte is one iff it is below 10 as it is (no high bit) and
    // after adding 0x76 (no carry reaches the first non-digit byte: the bytes below
    // it are digits).
    let x = word ^ (0x30 * ONES);
    let not_digit = (x.wrapping_add(0x76 * ONES) | x) & (0x80 * ONES);
    let count = (not_digit.trailing_zeros() / 8) as usize;
    if count == 0 {
        return (0, 0);
    }
    // The digits moved to the top bytes, zeros (leading zeros of the number) below.
    let mut v = x << (8 * (8 - count));
    // Pairs, then fours, then all eight, each step's sums in the low byte, half-word
    // and word of its group.
    v = (v.wrapping_mul(10) + (v >> 8)) & 0x00ff_00ff_00ff_00ff;
    v = (v.wrapping_mul(100) + (v >> 16)) & 0x0000_ffff_0000_ffff;
    v = v.wrapping_mul(10_000) + (v >> 32);
    (v & 0xffff_ffff, count)
}

/// The word at `at` (a non-blank byte) as a short decimal `[-]digits[.digits]` with at
/// most 19 digits, a mantissa ≤ 2⁵³ and at most 22 after the point (the numbers
/// [`super::number`] parses without std, to the same `f64`), and where it ends.
/// `None` for any other word.
#[inline]
fn short_decimal(text: &[u8], at: usize) -> Option<(f64, usize)> {
    let negative = text.get(at) == Some(&b'-');
    let start = at + usize::from(negative);
    // 19 digits fit a u64; one more is counted and refused.
    let (whole, point) = digits(text, start, 19);
    let whole_digits = point - start;
    if whole_digits == 0 || whole_digits > 19 {
        return None;
    }
    let (mantissa, fraction, end) = if text.get(point) == Some(&b'.') {
        let limit = 19 - whole_digits;
        let (part, end) = digits(text, point + 1, limit);
        let fraction = end - point - 1;
        if fraction == 0 || fraction > limit {
            return None;
        }
        (
            whole * INTEGER_POWERS_OF_TEN[fraction] + part,
            fraction,
            end,
        )
    } else {
        (whole, 0, point)
    };
    if !word_ends(text, end) {
        return None;
    }
    Some((exact_decimal(negative, mantissa, fraction)?, end))
}

/// A positive reference of at most [`REFERENCE_DIGITS`] digits at `at` and where it
/// ends; `(0, at)` when there are no digits; `None` for a zero or a longer number.
#[inline]
fn reference(text: &[u8], at: usize) -> Option<(i64, usize)> {
    let (value, end) = digits(text, at, REFERENCE_DIGITS);
    match end - at {
        0 => Some((0, at)),
        n if n > REFERENCE_DIGITS || value == 0 => None,
        _ => Some((value as i64, end)),
    }
}

/// The face word at `at` (a non-blank byte), `v`, `v/t`, `v//n` or `v/t/n` with
/// positive references, as `(vertex, texcoord, normal)` (0 where absent) and where it
/// ends. `None` for anything else.
#[inline]
fn face_word(text: &[u8], at: usize) -> Option<([i64; 3], usize)> {
    let (vertex, mut end) = reference(text, at)?;
    if vertex == 0 {
        return None;
    }
    let mut others = [0i64; 2];
    for slot in &mut others {
        if text.get(end) != Some(&b'/') {
            break;
        }
        (*slot, end) = reference(text, end + 1)?;
    }
    word_ends(text, end).then_some(([vertex, others[0], others[1]], end))
}

impl Chunk {
    /// Reads the line starting at byte `at` of `text` (a piece) if it is a `v`
    /// or `f` line in the simplest spelling (see the [module docs](self)), returning
    /// where the next line starts; `None` (the piece unchanged) otherwise.
    #[inline]
    pub(super) fn fast_line(&mut self, text: &[u8], at: usize) -> Option<usize> {
        if !text.get(at + 1).copied().is_some_and(is_blank) {
            return None;
        }
        match text[at] {
            b'v' => self.fast_vertex(text, at + 1),
            b'f' => self.fast_face(text, at + 1),
            _ => None,
        }
    }

    /// The rest of a `v` line from `at`: three short decimals.
    #[inline]
    fn fast_vertex(&mut self, text: &[u8], at: usize) -> Option<usize> {
        let (x, at) = short_decimal(text, skip_blanks(text, at))?;
        let (y, at) = short_decimal(text, skip_blanks(text, at))?;
        let (z, at) = short_decimal(text, skip_blanks(text, at))?;
        let next = line_end(text, at)?;
        self.positions.push([x, y, z]);
        Some(next)
    }

    /// The rest of an `f` line from `at`: three to [`FACE_REFERENCES`] face words.
    #[inline]
    fn fast_face(&mut self, text: &[u8], mut at: usize) -> Option<usize> {
        // Checked and counted as the general path does (`Chunk::reference` and
        // `Chunk::corner`): every reference is positive, so every corner is absolute.
        let mut corners = [0u32; FACE_REFERENCES];
        let mut count = 0;
        let (mut vertex_max, mut texcoord_max, mut normal_max) = (0i64, 0i64, 0i64);
        let next = loop {
            at = skip_blanks(text, at);
            match text.get(at) {
                None => break at,
                Some(b'\n') => break at + 1,
                Some(_) => {}
            }
            let ([vertex, texcoord, normal], end) = face_word(text, at)?;
            *corners.get_mut(count)? = (vertex - 1) as u32;
            count += 1;
            vertex_max = vertex_max.max(vertex);
            texcoord_max = texcoord_max.max(texcoord);
            normal_max = normal_max.max(normal);
            at = end;
        };
        if count < 3 {
            return None;
        }
        let local = self.positions.len() as i64;
        self.vertices_needed_before = self.vertices_needed_before.max(vertex_max - local);
        if texcoord_max != 0 {
            self.texcoords_needed_before = self
                .texcoords_needed_before
                .max(texcoord_max - self.texcoords);
        }
        if normal_max != 0 {
            self.normals_needed_before = self.normals_needed_before.max(normal_max - self.normals);
        }
        for k in 2..count {
            self.corners
                .extend_from_slice(&[corners[0], corners[k - 1], corners[k]]);
        }
        Some(next)
    }
}

#[cfg(test)]
mod tests {
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    #[test]
    fn digit_runs_are_read_as_one_digit_at_a_time_reads_them() {
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let alphabet = b"0123456789/.- \n\x7f\xff:";
        for _ in 0..50_000 {
            let length = rng.random_range(0..30);
            let text: Vec<u8> = (0..length)
                .map(|_| {
                    if rng.random_bool(0.7) {
                        b'0' + rng.random_range(0..10u8)
                    } else {
                        alphabet[rng.random_range(0..alphabet.len())]
                    }
                })
                .collect();
            let at = rng.random_range(0..=length);
            let run = text[at..].iter().take_while(|b| b.is_ascii_digit()).count();
            let expected = text[at..at + run].iter().fold(0u64, |v, &b| {
                v.wrapping_mul(10).wrapping_add(u64::from(b - b'0'))
            });
            for limit in [0, 3, 9, 19, 40] {
                let (value, end) = digits(&text, at, limit);
                if run <= limit {
                    assert_eq!((value, end), (expected, at + run), "{text:?} at {at}");
                } else {
                    assert!(end - at > limit && end - at <= run, "{text:?} at {at}");
                }
            }
        }
    }

    #[test]
    fn short_decimals_are_the_bits_std_parses() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let mut taken = 0;
        for _ in 0..200_000 {
            let x: f64 = rng.random_range(-2000.0..2000.0);
            let places = rng.random_range(0..=14);
            let mantissa: u64 = rng.random_range(0..(1u64 << 55));
            let digits = mantissa.to_string();
            let split = rng.random_range(0..=digits.len());
            for word in [
                format!("{x:.places$}"),
                format!("{x}"),
                format!("{}.{}", &digits[..split], &digits[split..]),
                format!("-{}", &digits[..split]),
            ] {
                let text = format!("{word} 1");
                if let Some((value, end)) = short_decimal(text.as_bytes(), 0) {
                    assert_eq!(end, word.len(), "{word}");
                    assert_eq!(
                        value.to_bits(),
                        word.parse::<f64>().unwrap().to_bits(),
                        "{word}"
                    );
                    taken += 1;
                }
            }
        }
        assert!(taken > 300_000, "{taken} taken");
    }
}
