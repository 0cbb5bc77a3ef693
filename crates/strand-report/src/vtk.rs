//! The rod centrelines as VTK XML PolyData (`rods.vtp`, ASCII), for ParaView.
//!
//! One polyline (`<Lines>` cell) per rod through its vertices, in the order of
//! [`ResultDoc::rods`]. Point data, per vertex (the unit in every name; lengths in the
//! export unit, [`rods_vtp_in`], forces and moments in N and N·m):
//! `s_m` (`s_mm` in mm), `force_N` (3 components), `moment_Nm` (3), `force_magnitude_N`,
//! `moment_magnitude_Nm`, `tangential_force_N`, `shear_force_N`,
//! `bending_moment_Nm`, `torsion_Nm`, `curvature_1pm` (3, section frame),
//! `bend_radius_<unit>` (1/|κ| in the unit of the points, `inf` where straight),
//! `outer_radius_<unit>` (in the unit of the points), `contact_force_N` (3), the section frame's directors `section_d1`,
//! `section_d2`, `section_d3` (unit vectors) and `rod_id` (the rod's index). Cell data:
//! `rod_id`, one per polyline. Field data: `rod_names`, a VTK string array (one tuple per
//! rod, index = `rod_id`; VTK writes ASCII strings as their byte values, each string
//! followed by a 0), and the names are repeated in an XML comment for human readers.

use std::fmt::Write;

use crate::number::{push_integer, push_number};
use crate::plot::escape;
use crate::result::{ResultDoc, RodResult};
use crate::study::magnitude;

/// A point-data array of the `.vtp`: its name, number of components, and how to get
/// the values of one rod (flattened, `components` numbers per vertex).
pub struct VtkPointArray {
    /// Array name (with its unit suffix); for a [`VtkPointArray::length`] array the
    /// stem, completed by the export unit (`s` → `s_mm`).
    pub name: &'static str,
    /// Whether the values are lengths in m, written in the export unit.
    pub length: bool,
    /// Components per point (1 for scalars, 3 for vectors).
    pub components: usize,
    /// The flattened values of one rod.
    pub values: fn(&RodResult) -> Vec<f64>,
}

fn flat(values: &[[f64; 3]]) -> Vec<f64> {
    values.iter().flatten().copied().collect()
}

/// The point-data arrays of one rod written to `rods.vtp`, in file order (the arrays
/// that need the whole result and `rod_id`, an integer array, are
/// written after them).
pub const VTK_POINT_ARRAYS: [VtkPointArray; 9] = [
    VtkPointArray {
        name: "s",
        length: true,
        components: 1,
        values: |r| r.s_m.clone(),
    },
    VtkPointArray {
        name: "force_N",
        length: false,
        components: 3,
        values: |r| flat(&r.force_n),
    },
    VtkPointArray {
        name: "moment_Nm",
        length: false,
        components: 3,
        values: |r| flat(&r.moment_nm),
    },
    VtkPointArray {
        name: "force_magnitude_N",
        length: false,
        components: 1,
        values: |r| r.force_n.iter().map(magnitude).collect(),
    },
    VtkPointArray {
        name: "moment_magnitude_Nm",
        length: false,
        components: 1,
        values: |r| r.moment_nm.iter().map(magnitude).collect(),
    },
    VtkPointArray {
        name: "tangential_force_N",
        length: false,
        components: 1,
        values: |r| r.tangential_force_n.clone(),
    },
    VtkPointArray {
        name: "shear_force_N",
        length: false,
        components: 1,
        values: |r| r.shear_force_n.clone(),
    },
    VtkPointArray {
        name: "bending_moment_Nm",
        length: false,
        components: 1,
        values: |r| r.bending_moment_nm.clone(),
    },
    VtkPointArray {
        name: "torsion_Nm",
        length: false,
        components: 1,
        values: |r| r.torsion_nm.clone(),
    },
];

/// The point-data arrays of `rods.vtp` after [`VTK_POINT_ARRAYS`], each as (name,
/// components, values of every rod's vertices in rod order):
/// - `curvature_1pm`: the material curvature (section frame), 1/m;
/// - `bend_radius_<unit>`: `1/|(K1, K2)|` in the unit of the points (`inf` where
///   straight);
/// - `outer_radius_<unit>`: the tube radius drawn (the rod's outer radius, else
///   [`crate::DEFAULT_RADIUS_FRACTION`] of its length) in the unit of the points, for
///   ParaView's Tube filter;
/// - `contact_force_N`: the contact forces on the rod (force along the normal),
///   each added to the vertex nearest its arc length, N; zero elsewhere;
/// - `section_d1`, `section_d2`, `section_d3`: the directors of the section frame
///   (unit vectors, dimensionless; `d3` the section normal), at a vertex the mean of
///   its edges' frames; written only when every rod carries its frames.
pub(crate) fn doc_arrays(
    doc: &ResultDoc,
    unit: &crate::cad::ExportUnit,
) -> Vec<(String, usize, Vec<f64>)> {
    let mut arrays = vec![
        (
            "curvature_1pm".to_string(),
            3,
            doc.rods
                .iter()
                .flat_map(|r| flat(&r.curvature_1pm))
                .collect(),
        ),
        (
            format!("bend_radius_{}", unit.symbol),
            1,
            doc.rods
                .iter()
                .flat_map(crate::findings::bend_radii)
                .map(|r| r / unit.metres)
                .collect(),
        ),
    ];
    arrays.push((
        format!("outer_radius_{}", unit.symbol),
        1,
        doc.rods
            .iter()
            .flat_map(|r| {
                let radius = crate::tube::tube_radius(r).0 / unit.metres;
                std::iter::repeat_n(radius, r.position_m.len())
            })
            .collect(),
    ));
    let mut contact = Vec::new();
    for rod in &doc.rods {
        let mut forces = vec![[0.0; 3]; rod.position_m.len()];
        for c in doc.contacts.iter().filter(|c| c.rod == rod.name) {
            let nearest = rod
                .s_m
                .iter()
                .enumerate()
                .min_by(|a, b| (a.1 - c.s_m).abs().total_cmp(&(b.1 - c.s_m).abs()))
                .map(|(j, _)| j);
            if let Some(j) = nearest.filter(|j| *j < forces.len()) {
                for (f, n) in forces[j].iter_mut().zip(c.normal) {
                    *f += c.force_n * n;
                }
            }
        }
        contact.extend(forces.into_iter().flatten());
    }
    arrays.push(("contact_force_N".to_string(), 3, contact));
    let framed = doc
        .rods
        .iter()
        .all(|r| r.section_frames_wxyz.len() + 1 == r.position_m.len());
    if framed {
        let frames: Vec<[[f64; 3]; 3]> = doc.rods.iter().flat_map(vertex_frames).collect();
        for (k, name) in ["section_d1", "section_d2", "section_d3"]
            .iter()
            .enumerate()
        {
            arrays.push((
                name.to_string(),
                3,
                frames.iter().flat_map(|f| f[k]).collect(),
            ));
        }
    }
    arrays
}

/// The directors `[d1, d2, d3]` at every vertex of `rod`: the frame of the mean of
/// the adjacent edges' quaternions (sign-aligned), the end edge's frame at the ends.
fn vertex_frames(rod: &RodResult) -> Vec<[[f64; 3]; 3]> {
    let q: Vec<nalgebra::Quaternion<f64>> = rod
        .section_frames_wxyz
        .iter()
        .map(|[w, x, y, z]| nalgebra::Quaternion::new(*w, *x, *y, *z))
        .collect();
    let last = q.len().saturating_sub(1);
    (0..rod.position_m.len())
        .map(|j| {
            let (a, b) = (q[j.saturating_sub(1).min(last)], q[j.min(last)]);
            let sum = if a.dot(&b) < 0.0 { a - b } else { a + b };
            let m = nalgebra::UnitQuaternion::from_quaternion(sum).to_rotation_matrix();
            [0, 1, 2].map(|c| [m[(0, c)], m[(1, c)], m[(2, c)]])
        })
        .collect()
}

/// Writes `values` as the body of an ASCII `DataArray`, `per_line` numbers a line.
fn push_values(out: &mut String, values: impl IntoIterator<Item = f64>, per_line: usize) {
    for (i, v) in values.into_iter().enumerate() {
        out.push(if i % per_line == 0 { '\n' } else { ' ' });
        if v.is_finite() {
            push_number(out, v);
        } else {
            // VTK's ASCII reader (strtod) reads these.
            out.push_str(if v.is_nan() {
                "nan"
            } else if v > 0.0 {
                "inf"
            } else {
                "-inf"
            });
        }
    }
    out.push('\n');
}

fn push_integers(out: &mut String, values: impl IntoIterator<Item = usize>) {
    for (i, v) in values.into_iter().enumerate() {
        out.push(if i % 16 == 0 { '\n' } else { ' ' });
        push_integer(out, v);
    }
    out.push('\n');
}

/// The text of `rods.vtp`: VTK XML PolyData (ASCII) of the centrelines of every rod in
/// `doc` with their sectional quantities as point data (see the module docs).
pub fn rods_vtp(doc: &ResultDoc) -> String {
    rods_vtp_in(doc, &crate::cad::ExportUnit::metre())
}

/// As [`rods_vtp`], with the point coordinates (array `position_<unit>`, e.g.
/// `position_mm`) and the length arrays (`s_<unit>`) in `unit`; forces and moments stay
/// in N and N·m, as named.
pub fn rods_vtp_in(doc: &ResultDoc, unit: &crate::cad::ExportUnit) -> String {
    let rods = &doc.rods;
    let points: usize = rods.iter().map(|r| r.position_m.len()).sum();
    let mut out = String::with_capacity(1024 + 400 * points);
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let names: Vec<String> = rods.iter().map(|r| r.name.replace("--", "- -")).collect();
    let _ = writeln!(
        out,
        "<!-- strand: case {}; rods (rod_id order): {} -->",
        doc.case.replace("--", "- -"),
        names.join(", ")
    );
    out.push_str(
        "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<PolyData>\n",
    );
    // Rod names as a string array; ASCII strings are byte values, each ended by 0.
    let _ = write!(
        out,
        "<FieldData>\n<DataArray type=\"String\" Name=\"rod_names\" NumberOfTuples=\"{}\" format=\"ascii\">",
        rods.len()
    );
    push_integers(
        &mut out,
        rods.iter()
            .flat_map(|r| r.name.bytes().map(usize::from).chain([0])),
    );
    out.push_str("</DataArray>\n</FieldData>\n");
    let _ = writeln!(
        out,
        "<Piece NumberOfPoints=\"{points}\" NumberOfVerts=\"0\" NumberOfLines=\"{}\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">",
        rods.len()
    );
    out.push_str("<PointData Scalars=\"force_magnitude_N\" Vectors=\"force_N\">\n");
    for array in &VTK_POINT_ARRAYS {
        let (name, scale) = if array.length {
            (format!("{}_{}", array.name, unit.symbol), unit.metres)
        } else {
            (array.name.to_string(), 1.0)
        };
        let _ = write!(
            out,
            "<DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"ascii\">",
            escape(&name),
            array.components
        );
        push_values(
            &mut out,
            rods.iter()
                .flat_map(|r| (array.values)(r))
                .map(|v| v / scale),
            6 * array.components,
        );
        out.push_str("</DataArray>\n");
    }
    for (name, components, values) in doc_arrays(doc, unit) {
        let _ = write!(
            out,
            "<DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{components}\" format=\"ascii\">",
            escape(&name)
        );
        push_values(&mut out, values, 6 * components);
        out.push_str("</DataArray>\n");
    }
    out.push_str("<DataArray type=\"Int32\" Name=\"rod_id\" format=\"ascii\">");
    push_integers(
        &mut out,
        rods.iter()
            .enumerate()
            .flat_map(|(i, r)| std::iter::repeat_n(i, r.position_m.len())),
    );
    out.push_str("</DataArray>\n</PointData>\n");
    out.push_str("<CellData Scalars=\"rod_id\">\n<DataArray type=\"Int32\" Name=\"rod_id\" format=\"ascii\">");
    push_integers(&mut out, 0..rods.len());
    out.push_str("</DataArray>\n</CellData>\n");
    let _ = write!(
        out,
        "<Points>\n<DataArray type=\"Float64\" Name=\"position_{}\" NumberOfComponents=\"3\" format=\"ascii\">",
        unit.symbol
    );
    push_values(
        &mut out,
        rods.iter()
            .flat_map(|r| flat(&r.position_m))
            .map(|x| x / unit.metres),
        6,
    );
    out.push_str("</DataArray>\n</Points>\n");
    out.push_str("<Lines>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">");
    push_integers(&mut out, 0..points);
    out.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">");
    push_integers(
        &mut out,
        rods.iter().scan(0, |end, r| {
            *end += r.position_m.len();
            Some(*end)
        }),
    );
    out.push_str("</DataArray>\n</Lines>\n</Piece>\n</PolyData>\n</VTKFile>\n");
    out
}
