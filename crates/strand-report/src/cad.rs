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
use crate::tube::{TUBE_SIDES, tube_radius, tube_rings};

/// The length unit of exported geometry: how many metres one unit is, and its symbol.
#[derive(Clone, Debug, PartialEq)]
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
        let Some(rings) = tube_rings(&rod.position_m, radius) else {
            continue;
        };
        let ring = |r: usize, k: usize| Point3::from(rings[r * TUBE_SIDES + k % TUBE_SIDES]);
        let count = rings.len() / TUBE_SIDES;
        for r in 0..count - 1 {
            for k in 0..TUBE_SIDES {
                let (a, b) = (ring(r, k), ring(r, k + 1));
                let (c, d) = (ring(r + 1, k + 1), ring(r + 1, k));
                out.push([a, b, c]);
                out.push([a, c, d]);
            }
        }
        let point = |p: &[f64; 3]| Point3::new(p[0], p[1], p[2]);
        let start = point(&rod.position_m[0]);
        let end = point(&rod.position_m[rod.position_m.len() - 1]);
        for k in 0..TUBE_SIDES {
            out.push([start, ring(0, k + 1), ring(0, k)]);
            out.push([end, ring(count - 1, k), ring(count - 1, k + 1)]);
        }
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
