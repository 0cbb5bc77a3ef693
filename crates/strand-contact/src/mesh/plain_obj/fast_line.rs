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

/// `10^k` for `k = 0..=22`, each exact in `f64` (see [`super::number`]).
const POWERS_OF_TEN: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// The largest mantissa that is exact in `f64`, 2⁵³.
const EXACT_MANTISSA: u64 = 1 << 53;

/// The most digits of a face reference read here (larger ones: the general path).
const REFERENCE_DIGITS: usize = 9;

/// The most references of a face read here (longer faces: the general path).
const FACE_REFERENCES: usize = 16;

/// Bytes that split words within a line (what `char::is_whitespace` says of ASCII,
/// without the newline that ends the line).
#[inline]
fn is_blank(b: u8) -> bool {
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

/// The decimal digits at `at`, at most `limit` of them read (`limit + 1` are
/// counted): their value and where they end.
#[inline]
fn digits(text: &[u8], mut at: usize, limit: usize) -> (u64, usize) {
    let start = at;
    let mut value: u64 = 0;
    while at < text.len() && text[at].is_ascii_digit() && at - start <= limit {
        // Wraps past 19 digits, which the callers refuse.
        value = value
            .wrapping_mul(10)
            .wrapping_add(u64::from(text[at] - b'0'));
        at += 1;
    }
    (value, at)
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
        (whole * 10u64.pow(fraction as u32) + part, fraction, end)
    } else {
        (whole, 0, point)
    };
    if !word_ends(text, end) || mantissa > EXACT_MANTISSA || fraction > 22 {
        return None;
    }
    let magnitude = mantissa as f64 / POWERS_OF_TEN[fraction];
    Some((if negative { -magnitude } else { magnitude }, end))
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
        let mut words = [[0i64; 3]; FACE_REFERENCES];
        let mut count = 0;
        let next = loop {
            at = skip_blanks(text, at);
            match text.get(at) {
                None => break at,
                Some(b'\n') => break at + 1,
                Some(_) => {}
            }
            let (word, end) = face_word(text, at)?;
            *words.get_mut(count)? = word;
            count += 1;
            at = end;
        };
        if count < 3 {
            return None;
        }
        // Checked and counted as the general path does (`Chunk::reference` and
        // `Chunk::corner`): every reference is positive, so every corner is absolute.
        let local = self.positions.len() as i64;
        for &[vertex, texcoord, normal] in &words[..count] {
            self.vertices_needed_before = self.vertices_needed_before.max(vertex - local);
            if texcoord != 0 {
                self.texcoords_needed_before =
                    self.texcoords_needed_before.max(texcoord - self.texcoords);
            }
            if normal != 0 {
                self.normals_needed_before = self.normals_needed_before.max(normal - self.normals);
            }
        }
        let corner = |k: usize| (words[k][0] - 1) as u32;
        let first = corner(0);
        for k in 2..count {
            self.corners
                .extend_from_slice(&[first, corner(k - 1), corner(k)]);
        }
        Some(next)
    }
}
