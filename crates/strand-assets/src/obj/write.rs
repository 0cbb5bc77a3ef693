//! Atomic OBJ writer.

use std::fmt::Write as _;
use std::io::{BufWriter, Write};
use std::path::Path;

use crate::{AssetError, TriangleMesh};

/// How [`write_obj`] writes coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjOptions {
    /// Comment written at the top of the file, one `# ` line per line of text (state
    /// the unit here: OBJ has no unit of its own).
    pub header: String,
    /// Factor applied to every coordinate (1000 writes a mesh given in m as mm).
    pub scale: f64,
    /// Digits after the decimal point (trailing zeros are dropped).
    pub decimals: usize,
}

impl Default for ObjOptions {
    fn default() -> Self {
        Self {
            header: String::new(),
            scale: 1.0,
            decimals: 6,
        }
    }
}

/// Writes `objects` (name, mesh) to `path` as one OBJ file: the header comment, then
/// per object an `o name` line (omitted for an empty name), its `v x y z` lines and
/// its `f a b c` lines (1-based, global indices). The file is written to a temporary
/// file in the same directory and renamed into place, so `path` is either the old
/// file or the complete new one; missing parent directories are created.
///
/// Errors: an object name with whitespace or a non-finite scale is
/// [`AssetError::InvalidArgument`]; file system failures are [`AssetError::Io`].
pub fn write_obj(
    path: &Path,
    objects: &[(&str, &TriangleMesh)],
    options: &ObjOptions,
) -> Result<(), AssetError> {
    if let Some((name, _)) = objects
        .iter()
        .find(|(name, _)| name.chars().any(char::is_whitespace))
    {
        return Err(AssetError::InvalidArgument {
            name: "object name",
            value: format!("{name:?}"),
            requirement: "must not contain whitespace (use '_')".to_string(),
        });
    }
    if !options.scale.is_finite() || options.scale == 0.0 {
        return Err(AssetError::InvalidArgument {
            name: "scale",
            value: options.scale.to_string(),
            requirement: "must be finite and non-zero".to_string(),
        });
    }
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(|e| AssetError::io(dir, e))?;
    let staged = tempfile::NamedTempFile::new_in(dir).map_err(|e| AssetError::io(dir, e))?;
    let mut out = BufWriter::with_capacity(1 << 20, staged);
    write_body(&mut out, objects, options).map_err(|e| AssetError::io(path, e))?;
    let staged = out
        .into_inner()
        .map_err(|e| AssetError::io(path, e.into_error()))?;
    staged
        .as_file()
        .sync_all()
        .map_err(|e| AssetError::io(path, e))?;
    staged
        .persist(path)
        .map_err(|e| AssetError::io(path, e.error))?;
    Ok(())
}

fn write_body(
    out: &mut impl Write,
    objects: &[(&str, &TriangleMesh)],
    options: &ObjOptions,
) -> std::io::Result<()> {
    for line in options.header.lines() {
        writeln!(out, "# {line}")?;
    }
    let mut line = String::with_capacity(96);
    let mut offset: u64 = 1;
    for (name, mesh) in objects {
        if !name.is_empty() {
            writeln!(out, "o {name}")?;
        }
        for v in &mesh.vertices {
            line.clear();
            line.push('v');
            for k in 0..3 {
                line.push(' ');
                push_number(&mut line, v[k] * options.scale, options.decimals);
            }
            line.push('\n');
            out.write_all(line.as_bytes())?;
        }
        for t in &mesh.triangles {
            let [a, b, c] = t.map(|i| u64::from(i) + offset);
            writeln!(out, "f {a} {b} {c}")?;
        }
        offset += mesh.vertices.len() as u64;
    }
    out.flush()
}

/// Appends `x` with `decimals` digits, dropping trailing zeros (and `-0` → `0`).
fn push_number(line: &mut String, x: f64, decimals: usize) {
    let start = line.len();
    let _ = write!(line, "{x:.decimals$}");
    if line[start..].contains('.') {
        let trimmed = line[start..]
            .trim_end_matches('0')
            .trim_end_matches('.')
            .len();
        line.truncate(start + trimmed);
    }
    if &line[start..] == "-0" {
        line.truncate(start);
        line.push('0');
    }
}

#[cfg(test)]
mod tests {
    use super::push_number;

    #[test]
    fn numbers_are_written_short_but_exact_to_the_digits_asked() {
        let cases = [
            (120.0, 4, "120"),
            (-0.5, 4, "-0.5"),
            (1.23456789, 4, "1.2346"),
            (-0.00001, 4, "0"),
            (1e-7, 9, "0.0000001"),
        ];
        for (x, d, expected) in cases {
            let mut s = String::new();
            push_number(&mut s, x, d);
            assert_eq!(s, expected);
        }
    }
}
