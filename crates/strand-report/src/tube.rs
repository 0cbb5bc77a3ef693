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
use crate::csv::push_number;
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
        for k in 0..TUBE_SIDES {
            let phi = std::f64::consts::TAU * k as f64 / TUBE_SIDES as f64;
            let d = u * phi.cos() + v_j * phi.sin();
            let stretched = match bend {
                Some(w) => d + w * (d.dot(&w) * (1.0 / half_cos - 1.0)),
                None => d,
            };
            rings.push(points[j] + stretched * radius);
        }
    }
    Some(rings)
}

/// The text of `tubes.obj`: one tube object per rod of `doc` (see the module docs).
/// Rods whose centreline is not finite are left out, with a comment saying so.
/// Coordinates in m; see [`tubes_obj_in`] for another unit.
pub fn tubes_obj(doc: &ResultDoc) -> String {
    tubes_obj_in(doc, &ExportUnit::metre())
}

/// As [`tubes_obj`], with every coordinate in `unit` (e.g. the case's mm, so that the
/// file loads into the CAD system next to the parts it was modelled from).
pub fn tubes_obj_in(doc: &ResultDoc, unit: &ExportUnit) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# strand: tube surfaces of the rods of case {}, {}; {TUBE_SIDES} vertices around, one object per rod",
        doc.case.replace(['\n', '\r'], " "),
        unit.symbol
    );
    let mut base = 1; // OBJ indices are 1-based.
    for rod in &doc.rods {
        let (radius, default) = tube_radius(rod);
        let Some(rings) = tube_rings(&rod.position_m, radius) else {
            let _ = writeln!(
                out,
                "# {}: centreline not finite or of zero extent; no tube",
                rod.name
            );
            continue;
        };
        let _ = writeln!(out, "o {}", rod.name);
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
        let caps = [
            &rod.position_m[0],
            &rod.position_m[rod.position_m.len() - 1],
        ];
        for p in rings
            .iter()
            .map(|p| [p.x, p.y, p.z])
            .chain(caps.map(|c| *c))
        {
            out.push('v');
            for x in p {
                out.push(' ');
                push_number(&mut out, x / unit.metres);
            }
            out.push('\n');
        }
        let rings_count = rings.len() / TUBE_SIDES;
        let at = |ring: usize, k: usize| base + ring * TUBE_SIDES + k % TUBE_SIDES;
        for ring in 0..rings_count - 1 {
            for k in 0..TUBE_SIDES {
                let (a, b) = (at(ring, k), at(ring, k + 1));
                let (c, d) = (at(ring + 1, k + 1), at(ring + 1, k));
                let _ = writeln!(out, "f {a} {b} {c}\nf {a} {c} {d}");
            }
        }
        let (start, end) = (base + rings.len(), base + rings.len() + 1);
        let last = rings_count - 1;
        for k in 0..TUBE_SIDES {
            let _ = writeln!(out, "f {start} {} {}", at(0, k + 1), at(0, k));
            let _ = writeln!(out, "f {end} {} {}", at(last, k), at(last, k + 1));
        }
        base = end + 1;
    }
    out
}
