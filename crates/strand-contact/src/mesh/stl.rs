//! STL meshes (binary and ASCII) in and out, and loading a mesh file whatever its
//! format ([`ObstacleMesh::load`]: OBJ or STL, told apart by content).
//!
//! **Reading.** A binary STL is an 80-byte header, a little-endian `u32` triangle count
//! `n` and `n` records of 50 bytes (normal, three corners as `f32`, a 2-byte attribute);
//! the file must hold exactly `84 + 50 n` bytes. An ASCII STL is `solid name`,
//! `facet normal … / outer loop / vertex x y z (×3) / endloop / endfacet` blocks and
//! `endsolid`; its coordinates are parsed as `f64` (no `f32` rounding). Normals are
//! ignored (the winding defines the triangle). Many CAD systems write `solid` at the
//! start of *binary* headers too, so the format is decided by content
//! ([`detect_format`]), not by the extension or the first word alone.
//!
//! **Welding.** STL stores every triangle's corners separately. Corners closer than
//! [`STL_WELD_RELATIVE_TOLERANCE`] times the diagonal of the file's bounding box
//! (1 nm for a 1 m part) are merged into one vertex (the first one met keeps its
//! position), so the topology diagnostics (open and non-manifold edges, closedness,
//! smooth patches) are those of the indexed mesh the STL was exported from.
//!
//! **Writing.** [`write_binary_stl`] and [`write_ascii_stl`] write triangles with their
//! right-hand-rule normals (binary: `f32`, ASCII: shortest round-trip `f64` text).

use std::collections::HashMap;
use std::io::{self, Write};
use std::path::Path;

use nalgebra::{Isometry3, Point3};

use super::from_triangles::build;
use super::{MeshError, ObstacleMesh};

/// Corners of STL triangles closer than this fraction of the file's bounding-box
/// diagonal are welded into one vertex (see the [module docs](self)).
pub const STL_WELD_RELATIVE_TOLERANCE: f64 = 1e-9;

/// Bytes of a binary STL header (before the triangle count).
const HEADER: usize = 80;
/// Bytes of one binary STL triangle record.
const RECORD: usize = 50;

/// The format of a mesh file, decided from its content.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Wavefront OBJ (text).
    Obj,
    /// Binary STL.
    BinaryStl,
    /// ASCII STL.
    AsciiStl,
}

/// Decides the format of a mesh file from its bytes (`extension` only breaks ties):
/// binary STL when the size is exactly `84 + 50 n` for the count `n` in its header
/// (whatever the header says in words); ASCII STL when it is text starting with
/// `solid`; binary STL (then reported as broken) when it has an `.stl` extension or is
/// not text; OBJ otherwise.
pub fn detect_format(bytes: &[u8], extension: Option<&str>) -> MeshFormat {
    if binary_size_matches(bytes) {
        return MeshFormat::BinaryStl;
    }
    // Text (UTF-8 without a NUL) starting with `solid` after white space, or other
    // text; `None` for bytes that are not text.
    // (`contains` on bytes is std's word-at-a-time `memchr`.)
    let text_says_solid = if bytes.contains(&0) {
        None
    } else {
        std::str::from_utf8(bytes)
            .ok()
            .map(|t| t.trim_start().starts_with("solid"))
    };
    match text_says_solid {
        Some(true) => MeshFormat::AsciiStl,
        Some(false) if !extension.is_some_and(|e| e.eq_ignore_ascii_case("stl")) => MeshFormat::Obj,
        _ => MeshFormat::BinaryStl,
    }
}

impl ObstacleMesh {
    /// Loads a mesh file, OBJ ([`ObstacleMesh::load_obj`]) or STL
    /// ([`ObstacleMesh::load_stl`]), the format told by [`detect_format`]. Units and
    /// placement as for OBJ: `x_world = pose · (scale_to_metres · x_file)` (m, rad).
    pub fn load(
        path: impl AsRef<Path>,
        scale_to_metres: f64,
        pose: &Isometry3<f64>,
    ) -> Result<Self, MeshError> {
        let path = path.as_ref();
        let bytes = read(path)?;
        mesh_from_bytes(path, &bytes, scale_to_metres, pose)
    }

    /// Loads a binary or ASCII STL file (told apart by content), welds its corners
    /// (see [`STL_WELD_RELATIVE_TOLERANCE`]) and places it:
    /// `x_world = pose · (scale_to_metres · x_file)` (m, rad). The mesh is named after
    /// the file stem. Errors name the path and what is wrong: missing file, truncated
    /// binary file or a header claiming more triangles than the file holds, malformed
    /// ASCII (with its line), NaN or infinite coordinates (with the triangle), no
    /// triangles.
    pub fn load_stl(
        path: impl AsRef<Path>,
        scale_to_metres: f64,
        pose: &Isometry3<f64>,
    ) -> Result<Self, MeshError> {
        let path = path.as_ref();
        let bytes = read(path)?;
        stl_mesh(path, &bytes, scale_to_metres, pose)
    }
}

/// The mesh of the file `path` whose content is `bytes`, OBJ or STL (see
/// [`ObstacleMesh::load`]).
pub(crate) fn mesh_from_bytes(
    path: &Path,
    bytes: &[u8],
    scale_to_metres: f64,
    pose: &Isometry3<f64>,
) -> Result<ObstacleMesh, MeshError> {
    let extension = path.extension().and_then(|e| e.to_str());
    match detect_format(bytes, extension) {
        MeshFormat::Obj => super::load_obj::obj_mesh(path, bytes, scale_to_metres, pose),
        MeshFormat::BinaryStl if extension.is_some_and(|e| e.eq_ignore_ascii_case("obj")) => {
            // Named OBJ, not text, and not the size of a binary STL: a damaged OBJ
            // more likely than an STL saved under the wrong name.
            match binary_size_matches(bytes) {
                true => stl_mesh(path, bytes, scale_to_metres, pose),
                false => Err(stl_error(
                    path,
                    format!(
                        "not a mesh file: an OBJ file is text, but byte {} (0x{:02x}) is not \
                         (a NUL or not UTF-8), and its {} bytes are not those of a binary STL \
                         (84 + 50 per triangle)",
                        first_non_text(bytes),
                        bytes[first_non_text(bytes)],
                        bytes.len()
                    ),
                    "the file is damaged or not a mesh: export the part again as OBJ or STL",
                )),
            }
        }
        _ => stl_mesh(path, bytes, scale_to_metres, pose),
    }
}

/// Whether `bytes` have the size of a binary STL with the triangle count in its header.
fn binary_size_matches(bytes: &[u8]) -> bool {
    bytes.len() >= HEADER + 4 && {
        let count = u32::from_le_bytes(bytes[HEADER..HEADER + 4].try_into().expect("4 bytes"));
        (HEADER + 4) as u64 + RECORD as u64 * u64::from(count) == bytes.len() as u64
    }
}

/// The offset of the first byte of `bytes` that is not text (a NUL, or where UTF-8
/// breaks); `bytes` must hold one.
fn first_non_text(bytes: &[u8]) -> usize {
    let nul = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    let utf8 = std::str::from_utf8(bytes)
        .err()
        .map_or(bytes.len(), |e| e.valid_up_to());
    nul.min(utf8).min(bytes.len().saturating_sub(1))
}

/// The bytes of a mesh file.
pub(crate) fn read(path: &Path) -> Result<Vec<u8>, MeshError> {
    let read = || -> std::io::Result<Vec<u8>> {
        use std::io::Read;
        let mut file = std::fs::File::open(path)?;
        let length = file.metadata()?.len() as usize;
        // One byte more than the length, so that reading to the end needs no second
        // allocation (an error, not an abort, where that much memory is not to be
        // had, as `std::fs::read`); huge pages advised before the bytes are written.
        let mut bytes = Vec::new();
        bytes
            .try_reserve_exact(length.saturating_add(1))
            .map_err(|e| std::io::Error::new(std::io::ErrorKind::OutOfMemory, e))?;
        crate::huge_pages::advise(bytes.spare_capacity_mut());
        file.read_to_end(&mut bytes)?;
        Ok(bytes)
    };
    read().map_err(|source| MeshError::Read {
        path: path.to_path_buf(),
        source,
    })
}

/// An STL error naming the file.
fn stl_error(path: &Path, problem: impl Into<String>, hint: &str) -> MeshError {
    MeshError::Stl {
        path: path.to_path_buf(),
        problem: problem.into(),
        hint: hint.to_string(),
    }
}

const REEXPORT: &str = "export the part again as STL (binary or ASCII) from the CAD system";

fn stl_mesh(
    path: &Path,
    bytes: &[u8],
    scale_to_metres: f64,
    pose: &Isometry3<f64>,
) -> Result<ObstacleMesh, MeshError> {
    let label = path.display().to_string();
    super::load_obj::check_placement(&label, scale_to_metres, pose)?;
    let extension = path.extension().and_then(|e| e.to_str());
    let corners = match detect_format(bytes, extension) {
        MeshFormat::AsciiStl => parse_ascii(path, bytes)?,
        _ => parse_binary(path, bytes)?,
    };
    if corners.is_empty() {
        return Err(MeshError::NoTriangles {
            mesh: label,
            detail: " (the STL file holds 0 triangles)".to_string(),
        });
    }
    let (vertices, triangles) = weld(&corners);
    let vertices = vertices
        .into_iter()
        .map(|p| {
            let world = pose * Point3::from(p.coords * scale_to_metres);
            [world.x, world.y, world.z]
        })
        .collect();
    build(super::load_obj::name_of(path), vertices, triangles).map_err(|e| e.of_file(&label))
}

/// The corners of every triangle of a binary STL (file units).
fn parse_binary(path: &Path, bytes: &[u8]) -> Result<Vec<[Point3<f64>; 3]>, MeshError> {
    if bytes.len() < HEADER + 4 {
        return Err(stl_error(
            path,
            format!(
                "truncated binary STL: {} bytes, less than the 84-byte header and triangle count",
                bytes.len()
            ),
            REEXPORT,
        ));
    }
    let count = u32::from_le_bytes(bytes[HEADER..HEADER + 4].try_into().expect("4 bytes")) as u64;
    let expected = (HEADER + 4) as u64 + RECORD as u64 * count;
    let held = ((bytes.len() - HEADER - 4) / RECORD) as u64;
    if (bytes.len() as u64) < expected {
        return Err(stl_error(
            path,
            format!(
                "truncated binary STL: the header claims {count} triangles ({expected} bytes) but \
                 the file holds {} bytes ({held} whole triangles)",
                bytes.len()
            ),
            "the file was cut short (an interrupted copy or export?): export it again",
        ));
    }
    if (bytes.len() as u64) > expected {
        return Err(stl_error(
            path,
            format!(
                "inconsistent binary STL: the header claims {count} triangles ({expected} bytes) \
                 but the file holds {} bytes",
                bytes.len()
            ),
            "the triangle count in the header does not match the data: export the file again",
        ));
    }
    let mut corners = Vec::with_capacity(count as usize);
    for (t, record) in bytes[HEADER + 4..].chunks_exact(RECORD).enumerate() {
        let value = |k: usize| {
            let at = 12 + 4 * k;
            f64::from(f32::from_le_bytes(
                record[at..at + 4].try_into().expect("4 bytes"),
            ))
        };
        let triangle: [Point3<f64>; 3] =
            std::array::from_fn(|c| Point3::new(value(3 * c), value(3 * c + 1), value(3 * c + 2)));
        check_finite(path, t, &triangle, "")?;
        corners.push(triangle);
    }
    Ok(corners)
}

/// Errors on a non-finite corner of triangle `t` (0-based).
fn check_finite(
    path: &Path,
    t: usize,
    triangle: &[Point3<f64>; 3],
    at: &str,
) -> Result<(), MeshError> {
    if let Some((c, p)) = triangle
        .iter()
        .enumerate()
        .find(|(_, p)| !p.iter().all(|x| x.is_finite()))
    {
        return Err(stl_error(
            path,
            format!(
                "triangle {} corner {}{at} has a non-finite coordinate ({}, {}, {})",
                t + 1,
                c + 1,
                p.x,
                p.y,
                p.z
            ),
            "repair the part in the CAD system (NaN/inf coordinates) and export it again",
        ));
    }
    Ok(())
}

/// The corners of every triangle of an ASCII STL (file units, `f64`).
fn parse_ascii(path: &Path, bytes: &[u8]) -> Result<Vec<[Point3<f64>; 3]>, MeshError> {
    let text = String::from_utf8_lossy(bytes);
    let mut corners = Vec::new();
    let mut current: Vec<Point3<f64>> = Vec::new();
    let mut in_facet = false;
    let mut facet_line = 0;
    let malformed = |line: usize, what: String| {
        stl_error(
            path,
            format!("not a valid ASCII STL file: line {line}: {what}"),
            REEXPORT,
        )
    };
    for (number, raw) in text.lines().enumerate() {
        let line = number + 1;
        let mut words = raw.split_whitespace();
        match words.next() {
            None | Some("solid") | Some("endsolid") | Some("outer") | Some("endloop") => {}
            Some("facet") => {
                if in_facet {
                    return Err(malformed(line, "`facet` inside a facet".to_string()));
                }
                in_facet = true;
                facet_line = line;
                current.clear();
            }
            Some("vertex") => {
                if !in_facet {
                    return Err(malformed(line, "`vertex` outside a facet".to_string()));
                }
                let values: Vec<&str> = words.collect();
                let parsed: Option<Vec<f64>> = values.iter().map(|w| w.parse().ok()).collect();
                match parsed {
                    Some(v) if v.len() == 3 => current.push(Point3::new(v[0], v[1], v[2])),
                    _ => {
                        return Err(malformed(
                            line,
                            format!(
                                "expected `vertex x y z` with three numbers, found `{}`",
                                raw.trim()
                            ),
                        ));
                    }
                }
            }
            Some("endfacet") => {
                if !in_facet || current.len() != 3 {
                    return Err(malformed(
                        line,
                        format!(
                            "a facet (from line {facet_line}) needs exactly 3 vertices, found {}",
                            current.len()
                        ),
                    ));
                }
                let triangle = [current[0], current[1], current[2]];
                check_finite(
                    path,
                    corners.len(),
                    &triangle,
                    &format!(" (facet at line {facet_line})"),
                )?;
                corners.push(triangle);
                in_facet = false;
            }
            Some(other) => {
                return Err(malformed(line, format!("unknown keyword `{other}`")));
            }
        }
    }
    if in_facet {
        return Err(stl_error(
            path,
            format!(
                "truncated ASCII STL: the facet from line {facet_line} is not closed by `endfacet`"
            ),
            "the file was cut short: export it again",
        ));
    }
    Ok(corners)
}

/// Welds the corners (see [`STL_WELD_RELATIVE_TOLERANCE`]): distinct vertices in order
/// of first appearance and 0-based triangles. Corners are hashed into cells of the
/// tolerance's size; each corner is compared with the vertices in its cell and the 26
/// neighbouring ones.
fn weld(corners: &[[Point3<f64>; 3]]) -> (Vec<Point3<f64>>, Vec<[u32; 3]>) {
    let mut min = Point3::from([f64::INFINITY; 3]);
    let mut max = Point3::from([f64::NEG_INFINITY; 3]);
    for p in corners.iter().flatten() {
        min = min.inf(p);
        max = max.sup(p);
    }
    let tolerance = STL_WELD_RELATIVE_TOLERANCE * (max - min).norm();
    let cell_size = if tolerance > 0.0 { tolerance } else { 1.0 };
    let cell = |p: &Point3<f64>| {
        let c = (p - min) / cell_size;
        [c.x, c.y, c.z].map(|x| x.floor() as i64)
    };
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    let mut vertices: Vec<Point3<f64>> = Vec::new();
    let mut triangles = Vec::with_capacity(corners.len());
    for triangle in corners {
        let indices = triangle.map(|p| {
            let [i, j, k] = cell(&p);
            for di in -1..=1 {
                for dj in -1..=1 {
                    for dk in -1..=1 {
                        if let Some(list) = grid.get(&[i + di, j + dj, k + dk])
                            && let Some(&v) = list
                                .iter()
                                .find(|&&v| (vertices[v as usize] - p).norm() <= tolerance)
                        {
                            return v;
                        }
                    }
                }
            }
            let v = u32::try_from(vertices.len()).expect("fewer than 2^32 vertices");
            vertices.push(p);
            grid.entry([i, j, k]).or_default().push(v);
            v
        });
        triangles.push(indices);
    }
    (vertices, triangles)
}

/// The unit normal of a triangle by the right-hand rule (zero for a degenerate one).
fn normal(t: &[Point3<f64>; 3]) -> nalgebra::Vector3<f64> {
    (t[1] - t[0])
        .cross(&(t[2] - t[0]))
        .try_normalize(0.0)
        .unwrap_or_default()
}

/// Writes `triangles` (corners in any unit) as a binary STL: `header` (cut or padded
/// to 80 bytes; it must not start with `solid`, which would mislead other readers, so
/// such a header is prefixed by `binary `), the count, and `f32` normal and corners.
pub fn write_binary_stl(
    out: &mut impl Write,
    header: &str,
    triangles: &[[Point3<f64>; 3]],
) -> io::Result<()> {
    let mut head = [b' '; HEADER];
    let text = if header.trim_start().starts_with("solid") {
        format!("binary {header}")
    } else {
        header.to_string()
    };
    for (slot, byte) in head.iter_mut().zip(text.bytes()) {
        *slot = byte;
    }
    out.write_all(&head)?;
    let count = u32::try_from(triangles.len())
        .map_err(|_| io::Error::other("more than 2^32 triangles for one STL file"))?;
    out.write_all(&count.to_le_bytes())?;
    let mut record = [0u8; RECORD];
    for t in triangles {
        let n = normal(t);
        let values = n.iter().chain(t.iter().flat_map(|p| p.coords.iter()));
        for (k, x) in values.enumerate() {
            record[4 * k..4 * k + 4].copy_from_slice(&(*x as f32).to_le_bytes());
        }
        out.write_all(&record)?;
    }
    Ok(())
}

/// Writes `triangles` as an ASCII STL solid named `name`, coordinates as shortest
/// round-trip `f64` text (read back exactly by [`ObstacleMesh::load_stl`]).
pub fn write_ascii_stl(
    out: &mut impl Write,
    name: &str,
    triangles: &[[Point3<f64>; 3]],
) -> io::Result<()> {
    writeln!(out, "solid {name}")?;
    for t in triangles {
        let n = normal(t);
        writeln!(out, "  facet normal {:?} {:?} {:?}", n.x, n.y, n.z)?;
        writeln!(out, "    outer loop")?;
        for p in t {
            writeln!(out, "      vertex {:?} {:?} {:?}", p.x, p.y, p.z)?;
        }
        writeln!(out, "    endloop")?;
        writeln!(out, "  endfacet")?;
    }
    writeln!(out, "endsolid {name}")
}

#[cfg(test)]
#[path = "stl_tests.rs"]
mod tests;
