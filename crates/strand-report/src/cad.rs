//! CAD out: the solved hoses as surfaces a CAD system loads next to the parts they were
//! routed against, in the case's length unit.
//!
//! - `tubes.obj` ([`crate::tubes_obj_in`]) and `rods.vtp` ([`crate::rods_vtp_in`]) with
//!   coordinates in an [`ExportUnit`];
//! - `tubes.stl` ([`tubes_stl`]): the same tube surfaces (rings of
//!   [`crate::TUBE_SIDES`] vertices, mitred at bends, end caps) as one binary STL, in
//!   the same unit (STL has no unit field: the header says it).
//!
//! [`write_results_in`](crate::write_results_in) writes all three.

use nalgebra::Point3;

use crate::result::ResultDoc;
use crate::tube::{TubeMesh, rod_tube_meshes};

/// The length unit of exported geometry: how many metres one unit is, and its symbol.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ExportUnit {
    /// One unit in m (`0.001` for mm).
    pub metres: f64,
    /// The unit's symbol (`"mm"`), written into headers and array names.
    pub symbol: String,
}

impl ExportUnit {
    /// Metres.
    pub fn metre() -> Self {
        Self {
            metres: 1.0,
            symbol: "m".to_string(),
        }
    }

    /// A unit of `metres` m named `symbol` (e.g. `(0.001, "mm")`).
    pub fn new(metres: f64, symbol: impl Into<String>) -> Self {
        Self {
            metres,
            symbol: symbol.into(),
        }
    }
}

/// The tube surface of every rod of `doc` as triangles (corners in m, wound
/// counter-clockwise seen from outside): the triangles of `tubes.obj`. Rods whose
/// centreline is not finite are left out.
pub fn tube_triangles(doc: &ResultDoc) -> Vec<[Point3<f64>; 3]> {
    triangles_in(&rod_tube_meshes(doc), 1.0)
}

/// The triangles of `meshes` (skipping the `None`s), corners in units of `metres` m.
pub(crate) fn triangles_in(meshes: &[Option<TubeMesh>], metres: f64) -> Vec<[Point3<f64>; 3]> {
    let faces = meshes.iter().flatten().map(|m| m.faces.len()).sum();
    let mut out = Vec::with_capacity(faces);
    for mesh in meshes.iter().flatten() {
        let point = |i: usize| Point3::from(mesh.vertices[i] / metres);
        out.extend(mesh.faces.iter().map(|f| f.map(point)));
    }
    out
}

/// `tubes.stl`: the tube surfaces of `doc` ([`tube_triangles`]) as a binary STL with
/// coordinates in `unit`; the 80-byte header names the case and the unit.
pub fn tubes_stl(doc: &ResultDoc, unit: &ExportUnit) -> Vec<u8> {
    tubes_stl_of(doc, &rod_tube_meshes(doc), unit)
}

/// As [`tubes_stl`], with the rods' tube surfaces given (`meshes`, from
/// [`rod_tube_meshes`] of `doc`), so that `tubes.obj` can take the same ones.
///
/// The bytes of [`strand_contact::write_binary_stl`] of the meshes' triangles (corners
/// in `unit`), made without listing the triangles: each vertex is scaled and rounded
/// to `f32` once (it is a corner of about six triangles), each face's normal is
/// computed from the scaled `f64` corners exactly as there, and the records go
/// straight into the output.
pub fn tubes_stl_of(doc: &ResultDoc, meshes: &[Option<TubeMesh>], unit: &ExportUnit) -> Vec<u8> {
    let header = format!(
        "strand tubes, unit {}, case {}",
        unit.symbol,
        doc.case.replace(['\n', '\r'], " ")
    );
    let faces: usize = meshes.iter().flatten().map(|m| m.faces.len()).sum();
    let mut out = Vec::with_capacity(84 + 50 * faces);
    // The header and a count of 0, then the count set once the records are there.
    strand_contact::write_binary_stl(&mut out, &header, &[])
        .expect("writing to memory cannot fail");
    let mut count: u32 = 0;
    let mut points: Vec<Point3<f64>> = Vec::new();
    let mut corners: Vec<[u8; 12]> = Vec::new();
    for mesh in meshes.iter().flatten() {
        points.clear();
        points.extend(mesh.vertices.iter().map(|v| Point3::from(v / unit.metres)));
        corners.clear();
        corners.extend(points.iter().map(|p| f32_bytes([p.x, p.y, p.z])));
        for f in &mesh.faces {
            let [a, b, c] = f.map(|i| &points[i]);
            let n = (b - a)
                .cross(&(c - a))
                .try_normalize(0.0)
                .unwrap_or_default();
            out.extend_from_slice(&f32_bytes([n.x, n.y, n.z]));
            for &i in f {
                out.extend_from_slice(&corners[i]);
            }
            out.extend_from_slice(&[0, 0]); // the attribute byte count
            count += 1;
        }
    }
    out[80..84].copy_from_slice(&count.to_le_bytes());
    out
}

/// Three values as little-endian `f32`s (the STL's numbers).
fn f32_bytes(values: [f64; 3]) -> [u8; 12] {
    let mut bytes = [0u8; 12];
    for (slot, x) in bytes.chunks_exact_mut(4).zip(values) {
        slot.copy_from_slice(&(x as f32).to_le_bytes());
    }
    bytes
}
