//! Tube surface meshes of the rods (`tubes.obj`, Wavefront OBJ), for any CAD viewer.
//!
//! Each rod becomes one object (`o <rod name>`): a ring of [`TUBE_SIDES`] vertices at
//! every centreline vertex, joined by triangles, and a flat cap (centre vertex and a
//! triangle fan) at each end. The rings follow parallel-transported frames, so the
//! tube does not twist. At an interior vertex the ring lies in the bisector plane of
//! the two adjacent edges and is stretched across the bend by `1/cos(α/2)` (`α` the
//! bend angle), a mitred joint: every ring vertex lies at exactly the tube radius
//! from the lines of *both* adjacent edges, so the surface is the union of the edges'
//! cylinders. The stretch is capped at [`MAX_MITRE`] for very sharp bends.
//!
//! The radius is the rod's `outer_radius_m`; a rod without one is drawn with
//! [`DEFAULT_RADIUS_FRACTION`] of its length, and the file says so in a comment.
//! Triangles are wound counter-clockwise seen from outside. Lengths in m.

use std::fmt::Write;

use nalgebra::{Unit, UnitQuaternion, Vector3};

use crate::cad::ExportUnit;
use crate::fittings::FittingPiece;
use crate::number::{push_integer, push_number};
use crate::result::{ResultDoc, RodResult};

/// Vertices around each ring of a tube.
pub const TUBE_SIDES: usize = 16;

/// Tube radius of a rod without an outer radius, as a fraction of its length.
pub const DEFAULT_RADIUS_FRACTION: f64 = 0.01;

/// Largest stretch of a mitred ring across a bend (reached at a bend of ≈ 151°).
pub const MAX_MITRE: f64 = 4.0;

/// The tube radius drawn for `rod`, m, and whether it is the default.
pub fn tube_radius(rod: &RodResult) -> (f64, bool) {
    match rod.outer_radius_m {
        Some(r) if r.is_finite() && r > 0.0 => (r, false),
        _ => (DEFAULT_RADIUS_FRACTION * rod.length_m, true),
    }
}

fn vector(p: &[f64; 3]) -> Vector3<f64> {
    Vector3::new(p[0], p[1], p[2])
}

/// Unit edge directions of a centreline; a zero-length edge takes its neighbour's
/// direction (`None` if every edge has zero length).
fn edge_directions(points: &[Vector3<f64>]) -> Option<Vec<Vector3<f64>>> {
    let raw: Vec<Option<Vector3<f64>>> = points
        .windows(2)
        .map(|w| (w[1] - w[0]).try_normalize(1e-300))
        .collect();
    let first = raw.iter().flatten().next().copied()?;
    let mut last = first;
    Some(
        raw.into_iter()
            .map(|d| {
                last = d.unwrap_or(last);
                last
            })
            .collect(),
    )
}

/// A unit vector perpendicular to `t`.
fn any_perpendicular(t: &Vector3<f64>) -> Vector3<f64> {
    let axis = if t.x.abs() <= t.y.abs() && t.x.abs() <= t.z.abs() {
        Vector3::x()
    } else if t.y.abs() <= t.z.abs() {
        Vector3::y()
    } else {
        Vector3::z()
    };
    (axis - t * t.dot(&axis)).normalize()
}

/// The ring vertices of one rod (ring by ring, [`TUBE_SIDES`] each), or `None` for a
/// centreline that is not finite or has no extent.
pub fn tube_rings(positions: &[[f64; 3]], radius: f64) -> Option<Vec<Vector3<f64>>> {
    let points: Vec<Vector3<f64>> = positions.iter().map(vector).collect();
    if points.len() < 2 || points.iter().any(|p| !p.iter().all(|x| x.is_finite())) {
        return None;
    }
    let edges = edge_directions(&points)?;
    let n = points.len();
    let mut rings = Vec::with_capacity(n * TUBE_SIDES);
    let mut normal = edges[0];
    let mut u = any_perpendicular(&normal);
    // The directions around a ring (the same numbers at every ring).
    let around: [(f64, f64); TUBE_SIDES] = std::array::from_fn(|k| {
        let phi = std::f64::consts::TAU * k as f64 / TUBE_SIDES as f64;
        (phi.cos(), phi.sin())
    });
    for j in 0..n {
        // Ring plane normal (bisector) and the bend direction with its mitre stretch.
        let (before, after) = (edges[j.saturating_sub(1)], edges[j.min(n - 2)]);
        let bisector = (before + after).try_normalize(1e-12).unwrap_or(after);
        let bend = (after - before).try_normalize(1e-12);
        let half_cos = bisector.dot(&after).clamp(1.0 / MAX_MITRE, 1.0);
        // Parallel transport of u from the previous ring plane to this one.
        if let Some(rotation) = UnitQuaternion::rotation_between(&normal, &bisector) {
            u = rotation * u;
        }
        normal = bisector;
        let u_j = Unit::new_normalize(u - bisector * bisector.dot(&u));
        let v_j = bisector.cross(&u_j);
        u = u_j.into_inner();
        for &(cos, sin) in &around {
            let d = u * cos + v_j * sin;
            let stretched = match bend {
                Some(w) => d + w * (d.dot(&w) * (1.0 / half_cos - 1.0)),
                None => d,
            };
            rings.push(points[j] + stretched * radius);
        }
    }
    Some(rings)
}

/// An indexed triangle mesh: vertices (m) and faces (0-based indices into them,
/// wound counter-clockwise seen from outside).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TubeMesh {
    /// Vertex positions, m.
    pub vertices: Vec<Vector3<f64>>,
    /// Triangles as 0-based vertex indices.
    pub faces: Vec<[usize; 3]>,
}

/// The closed tube surface along `positions` (m) of `radius` (m): the rings of
/// [`tube_rings`], then the two cap centres, joined by triangles; `None` where
/// [`tube_rings`] gives none.
pub fn tube_mesh(positions: &[[f64; 3]], radius: f64) -> Option<TubeMesh> {
    let mut vertices = tube_rings(positions, radius)?;
    let count = vertices.len() / TUBE_SIDES;
    let at = |ring: usize, k: usize| ring * TUBE_SIDES + k % TUBE_SIDES;
    let mut faces = Vec::with_capacity(2 * count * TUBE_SIDES);
    for ring in 0..count - 1 {
        for k in 0..TUBE_SIDES {
            let (a, b) = (at(ring, k), at(ring, k + 1));
            let (c, d) = (at(ring + 1, k + 1), at(ring + 1, k));
            faces.push([a, b, c]);
            faces.push([a, c, d]);
        }
    }
    let (start, end) = (vertices.len(), vertices.len() + 1);
    vertices.push(vector(&positions[0]));
    vertices.push(vector(&positions[positions.len() - 1]));
    for k in 0..TUBE_SIDES {
        faces.push([start, at(0, k + 1), at(0, k)]);
        faces.push([end, at(count - 1, k), at(count - 1, k + 1)]);
    }
    Some(TubeMesh { vertices, faces })
}

/// Latitude bands of [`ball_mesh`].
pub const BALL_BANDS: usize = 8;

/// A closed ball surface of `radius` (m) around `centre` (m): two poles and
/// `BALL_BANDS − 1` rings of [`TUBE_SIDES`] vertices on the sphere.
pub fn ball_mesh(centre: &[f64; 3], radius: f64) -> TubeMesh {
    let c = vector(centre);
    let mut vertices = vec![c + Vector3::z() * radius, c - Vector3::z() * radius];
    for band in 1..BALL_BANDS {
        let theta = std::f64::consts::PI * band as f64 / BALL_BANDS as f64;
        for k in 0..TUBE_SIDES {
            let phi = std::f64::consts::TAU * k as f64 / TUBE_SIDES as f64;
            let d = Vector3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            vertices.push(c + d * radius);
        }
    }
    let at = |ring: usize, k: usize| 2 + ring * TUBE_SIDES + k % TUBE_SIDES;
    let rings = BALL_BANDS - 1;
    let mut faces = Vec::new();
    for k in 0..TUBE_SIDES {
        faces.push([0, at(0, k), at(0, k + 1)]);
        faces.push([1, at(rings - 1, k + 1), at(rings - 1, k)]);
    }
    for ring in 0..rings - 1 {
        for k in 0..TUBE_SIDES {
            let (a, b) = (at(ring, k), at(ring, k + 1));
            let (c, d) = (at(ring + 1, k + 1), at(ring + 1, k));
            faces.push([a, d, c]);
            faces.push([a, c, b]);
        }
    }
    TubeMesh { vertices, faces }
}

/// Writes `mesh` as OBJ object `name` (vertices in `unit`), its faces numbered from
/// `*base` (OBJ's 1-based global index), which is then moved past its vertices.
fn push_object(out: &mut String, name: &str, mesh: &TubeMesh, unit: &ExportUnit, base: &mut usize) {
    let _ = writeln!(out, "o {name}");
    for p in &mesh.vertices {
        out.push('v');
        for x in [p.x, p.y, p.z] {
            out.push(' ');
            push_number(out, x / unit.metres);
        }
        out.push('\n');
    }
    for f in &mesh.faces {
        out.push('f');
        for i in f {
            out.push(' ');
            push_integer(out, *base + i);
        }
        out.push('\n');
    }
    *base += mesh.vertices.len();
}

/// The tube surface of every rod of `doc` in rod order ([`tube_mesh`] at its
/// [`tube_radius`], vertices in m), `None` for a rod whose centreline is not finite or
/// has no extent: what `tubes.obj` and `tubes.stl` draw, computed once for both
/// ([`tubes_obj_of`], [`crate::tubes_stl_of`]).
pub fn rod_tube_meshes(doc: &ResultDoc) -> Vec<Option<TubeMesh>> {
    doc.rods
        .iter()
        .map(|rod| tube_mesh(&rod.position_m, tube_radius(rod).0))
        .collect()
}

/// The text of `tubes.obj`: one tube object per rod of `doc` (see the module docs).
/// Rods whose centreline is not finite are left out, with a comment saying so.
/// Coordinates in m; see [`tubes_obj_in`] for another unit.
pub fn tubes_obj(doc: &ResultDoc) -> String {
    tubes_obj_in(doc, &ExportUnit::metre())
}

/// As [`tubes_obj`], with every coordinate in `unit` (e.g. the case's mm, so that the
/// file loads into the CAD system next to the parts it was modelled from). After the
/// rods, one object per fitting ([`crate::fittings`]: junction bodies, connectors,
/// clips) named `<kind>_<name>`, so that a T-junction shows no gap.
pub fn tubes_obj_in(doc: &ResultDoc, unit: &ExportUnit) -> String {
    tubes_obj_of(doc, &rod_tube_meshes(doc), unit)
}

/// As [`tubes_obj_in`], with the rods' tube surfaces given (`meshes`, from
/// [`rod_tube_meshes`] of `doc`, one per rod in rod order), so that `tubes.stl` can
/// take the same ones.
pub fn tubes_obj_of(doc: &ResultDoc, meshes: &[Option<TubeMesh>], unit: &ExportUnit) -> String {
    // About 40 bytes per vertex line and 20 per face line.
    let vertices: usize = meshes.iter().flatten().map(|m| m.vertices.len()).sum();
    let mut out = String::with_capacity(1024 + 80 * vertices);
    let _ = writeln!(
        out,
        "# strand: tube surfaces of the rods of case {}, {}; {TUBE_SIDES} vertices around, one object per rod, then one per fitting (junction_, connector_, clip_)",
        doc.case.replace(['\n', '\r'], " "),
        unit.symbol
    );
    let mut base = 1; // OBJ indices are 1-based.
    for (rod, mesh) in doc.rods.iter().zip(meshes) {
        let (radius, default) = tube_radius(rod);
        let Some(mesh) = mesh else {
            let _ = writeln!(
                out,
                "# {}: centreline not finite or of zero extent; no tube",
                rod.name
            );
            continue;
        };
        if default {
            let _ = writeln!(
                out,
                "# {}: no outer radius in the results; drawn with {} % of its length = {} {}",
                rod.name,
                100.0 * DEFAULT_RADIUS_FRACTION,
                radius / unit.metres,
                unit.symbol
            );
        } else {
            let _ = writeln!(
                out,
                "# {}: outer radius {} {}",
                rod.name,
                radius / unit.metres,
                unit.symbol
            );
        }
        push_object(&mut out, &rod.name, mesh, unit, &mut base);
    }
    for fitting in crate::fittings::fittings(doc) {
        let mut mesh = TubeMesh::default();
        for piece in &fitting.pieces {
            let part = match *piece {
                FittingPiece::Cylinder {
                    start_m,
                    end_m,
                    radius_m,
                } => tube_mesh(&[start_m, end_m], radius_m),
                FittingPiece::Ball { centre_m, radius_m } => Some(ball_mesh(&centre_m, radius_m)),
            };
            if let Some(part) = part {
                let offset = mesh.vertices.len();
                mesh.vertices.extend(part.vertices);
                mesh.faces
                    .extend(part.faces.iter().map(|f| f.map(|i| i + offset)));
            }
        }
        let name = format!(
            "{}_{}",
            fitting.kind.as_str(),
            fitting.name.replace(char::is_whitespace, "_")
        );
        push_object(&mut out, &name, &mesh, unit, &mut base);
    }
    out
}
