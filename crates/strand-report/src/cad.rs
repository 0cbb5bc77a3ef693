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
use crate::tube::{tube_mesh, tube_radius};

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
    let mut out = Vec::new();
    for rod in &doc.rods {
        let (radius, _) = tube_radius(rod);
        let Some(mesh) = tube_mesh(&rod.position_m, radius) else {
            continue;
        };
        let point = |i: usize| Point3::from(mesh.vertices[i]);
        out.extend(mesh.faces.iter().map(|f| f.map(point)));
    }
    out
}

/// `tubes.stl`: the tube surfaces of `doc` ([`tube_triangles`]) as a binary STL with
/// coordinates in `unit`; the 80-byte header names the case and the unit.
pub fn tubes_stl(doc: &ResultDoc, unit: &ExportUnit) -> Vec<u8> {
    let triangles: Vec<[Point3<f64>; 3]> = tube_triangles(doc)
        .into_iter()
        .map(|t| t.map(|p| Point3::from(p.coords / unit.metres)))
        .collect();
    let header = format!(
        "strand tubes, unit {}, case {}",
        unit.symbol,
        doc.case.replace(['\n', '\r'], " ")
    );
    let mut out = Vec::with_capacity(84 + 50 * triangles.len());
    strand_contact::write_binary_stl(&mut out, &header, &triangles)
        .expect("writing to memory cannot fail");
    out
}
