//! One piece of a plain OBJ file (whole lines), parsed on its own: its vertices, its
//! faces fanned into triangles as tobj fans them, and what the pieces before it must
//! hold for its references to be the ones tobj accepts.

use super::number::{parse_f64, parse_reference};

/// A parsed piece of the file. Indices are 0-based; a reference relative to the end
/// (`-k`) depends on the vertices before the piece and is listed in `relative`.
#[derive(Default)]
#[cfg_attr(test, derive(Debug, PartialEq))]
pub(super) struct Chunk {
    /// The `v` lines' coordinates, in file order (file units).
    pub positions: Vec<[f64; 3]>,
    /// The triangles' corners, three per triangle: an absolute vertex index, or (for
    /// the slots in `relative`) an index counted from the piece's first vertex.
    pub corners: Vec<u32>,
    /// `(slot in corners, index from the piece's first vertex)` of negative references.
    pub relative: Vec<(usize, i64)>,
    /// Vertices that must precede the piece for every reference to be a vertex defined
    /// before its face (what the plain path accepts; tobj may accept more).
    pub vertices_needed_before: i64,
    /// `vt` lines in the piece.
    pub texcoords: i64,
    /// Like `vertices_needed_before`, for the texture coordinates referenced.
    pub texcoords_needed_before: i64,
    /// `vn` lines in the piece.
    pub normals: i64,
    /// Like `vertices_needed_before`, for the normals referenced.
    pub normals_needed_before: i64,
    /// The number of triangles of the piece before each `o` or `g` line (where tobj
    /// starts a new model).
    pub model_starts: Vec<usize>,
}

/// Bytes that split words: what `char::is_whitespace` says of ASCII (tobj splits
/// lines with `split_whitespace`).
#[inline]
fn is_space(b: u8) -> bool {
    b == b'\n' || super::fast_line::is_blank(b)
}

/// The words of an ASCII line.
struct AsciiWords<'a> {
    /// The rest of the line.
    rest: &'a [u8],
}

impl<'a> Iterator for AsciiWords<'a> {
    type Item = &'a [u8];

    #[inline]
    fn next(&mut self) -> Option<&'a [u8]> {
        let start = self.rest.iter().position(|&b| !is_space(b))?;
        let word = &self.rest[start..];
        let end = word.iter().position(|&b| is_space(b)).unwrap_or(word.len());
        self.rest = &word[end..];
        Some(&word[..end])
    }
}

/// Parses `text` (whole lines). `None` when a line is outside the plain subset (see
/// [`super`]) and the file must go to tobj.
pub(super) fn parse_chunk(text: &[u8]) -> Option<Chunk> {
    parse(text, true)
}

/// [`parse_chunk`] with every line read by the general path ([`Chunk::line`]), which
/// the fast one must match (tests).
#[cfg(test)]
pub(super) fn parse_chunk_general(text: &[u8]) -> Option<Chunk> {
    parse(text, false)
}

/// [`parse_chunk`], the common lines read by
/// [`Chunk::fast_line`] if `fast`.
fn parse(text: &[u8], fast: bool) -> Option<Chunk> {
    let mut chunk = Chunk::default();
    let ascii = text.is_ascii();
    if !ascii {
        // tobj reads lines as UTF-8 and fails on anything else.
        std::str::from_utf8(text).ok()?;
    }
    let mut corners: Vec<(i64, i64, i64)> = Vec::new();
    let mut at = 0;
    while at < text.len() {
        // The fast path reads only ASCII bytes, whatever the rest of the piece holds.
        if fast && let Some(next) = chunk.fast_line(text, at) {
            at = next;
            continue;
        }
        let end = text[at..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(text.len(), |k| at + k);
        let line = &text[at..end];
        at = end + 1;
        let handled = if ascii || line.is_ascii() {
            chunk.line(line, AsciiWords { rest: line }, &mut corners)
        } else {
            let line = std::str::from_utf8(line).ok()?;
            chunk.line(
                line.as_bytes(),
                line.split_whitespace().map(str::as_bytes),
                &mut corners,
            )
        };
        handled?;
    }
    Some(chunk)
}

impl Chunk {
    /// One line (`raw`, split into `words`); `None` outside the plain subset.
    /// `corners` is scratch space for the references of a face.
    fn line<'a>(
        &mut self,
        raw: &[u8],
        mut words: impl Iterator<Item = &'a [u8]>,
        corners: &mut Vec<(i64, i64, i64)>,
    ) -> Option<()> {
        let Some(keyword) = words.next() else {
            return Some(());
        };
        match keyword {
            b"v" => {
                let x = parse_f64(words.next()?)?;
                let y = parse_f64(words.next()?)?;
                let z = parse_f64(words.next()?)?;
                // A weight or a colour changes what tobj makes of the line.
                if words.next().is_some() {
                    return None;
                }
                self.positions.push([x, y, z]);
            }
            b"vt" => {
                parse_f64(words.next()?)?;
                parse_f64(words.next()?)?;
                self.texcoords += 1;
            }
            b"vn" => {
                parse_f64(words.next()?)?;
                parse_f64(words.next()?)?;
                parse_f64(words.next()?)?;
                self.normals += 1;
            }
            b"f" => {
                corners.clear();
                for word in words {
                    corners.push(self.reference(word)?);
                }
                // Points and lines (one or two references) and empty faces: tobj.
                if corners.len() < 3 {
                    return None;
                }
                let first = self.corner(corners[0])?;
                let mut previous = self.corner(corners[1])?;
                for &c in &corners[2..] {
                    let next = self.corner(c)?;
                    for corner in [first, previous, next] {
                        self.push(corner);
                    }
                    previous = next;
                }
            }
            b"o" | b"g" => self.model_starts.push(self.corners.len() / 3),
            // A material name: tobj needs a space and a name after it.
            b"usemtl" => {
                let line = std::str::from_utf8(raw).ok()?;
                if line.split_once(' ').unwrap_or_default().1.trim().is_empty() {
                    return None;
                }
            }
            // Lines (`l`) become faces in tobj; leave them to it.
            b"l" => return None,
            // Comments, `mtllib`, `s` and every unknown keyword: tobj ignores them too.
            _ => {}
        }
        Some(())
    }

    /// The `(vertex, texcoord, normal)` references of a face word `v`, `v/t`, `v//n`
    /// or `v/t/n` (0 where absent), checking the texcoord and normal references
    /// against the lines so far. `None` outside the plain subset.
    fn reference(&mut self, word: &[u8]) -> Option<(i64, i64, i64)> {
        let mut parts = word.split(|&b| b == b'/');
        let vertex = parse_reference(parts.next()?)?;
        let mut others = [0i64; 2];
        for (k, part) in parts.enumerate() {
            if part.is_empty() {
                continue;
            }
            // A fourth number makes tobj fail.
            let slot = others.get_mut(k)?;
            *slot = parse_reference(part)?;
        }
        let [texcoord, normal] = others;
        if texcoord != 0 {
            let needed = needed_before(texcoord, self.texcoords);
            self.texcoords_needed_before = self.texcoords_needed_before.max(needed);
        }
        if normal != 0 {
            let needed = needed_before(normal, self.normals);
            self.normals_needed_before = self.normals_needed_before.max(needed);
        }
        Some((vertex, texcoord, normal))
    }

    /// The corner of a face reference, checked against the vertices so far.
    fn corner(&mut self, (vertex, _, _): (i64, i64, i64)) -> Option<Corner> {
        let local = self.positions.len() as i64;
        let needed = needed_before(vertex, local);
        self.vertices_needed_before = self.vertices_needed_before.max(needed);
        if vertex > 0 {
            u32::try_from(vertex - 1).ok().map(Corner::Absolute)
        } else {
            Some(Corner::FromPieceStart(local + vertex))
        }
    }

    /// Appends a triangle corner.
    #[inline]
    fn push(&mut self, corner: Corner) {
        match corner {
            Corner::Absolute(index) => self.corners.push(index),
            Corner::FromPieceStart(index) => {
                self.relative.push((self.corners.len(), index));
                self.corners.push(0);
            }
        }
    }
}

/// A triangle corner while its piece is parsed.
#[derive(Clone, Copy)]
enum Corner {
    /// A 0-based vertex index of the file.
    Absolute(u32),
    /// A 0-based index counted from the piece's first vertex (may be negative).
    FromPieceStart(i64),
}

/// How many items must precede a piece in which `defined` items came before a
/// reference `reference` (1-based from the start, or negative from the end) for the
/// reference to name one of them.
#[inline]
fn needed_before(reference: i64, defined: i64) -> i64 {
    if reference > 0 {
        reference - defined
    } else {
        -(defined + reference)
    }
}
