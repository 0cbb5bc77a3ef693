//! Fittings: the junction bodies, connectors and clips of a result as simple solids,
//! for the 3D view of the report and for `tubes.obj`, so that a T-junction shows no gap
//! between its hoses and every hose end shows what holds it.
//!
//! - A **junction** body is one cylinder from the body's origin to each of its ports
//!   (the rod ends held by it), as thick as the rod held there, and a ball at the
//!   origin as large as the thickest of them: the hoses' tubes end at the ports, so the
//!   body fills the T between them.
//! - A **connector** (a clamp or pin fixed in space) is a collar of
//!   [`CONNECTOR_RADIUS_FACTOR`] times the hose radius around the held end, reaching
//!   [`CONNECTOR_OVERLAP_FACTOR`] radii over the hose and [`CONNECTOR_LENGTH_FACTOR`]
//!   radii beyond it along the end tangent.
//! - A **clip** is a band of [`CLIP_RADIUS_FACTOR`] times the hose radius around the
//!   held vertex, [`CLIP_WIDTH_FACTOR`] radii wide along the hose.
//!
//! These are glyphs at the true positions and hose sizes, not the parts' CAD shapes
//! (the case does not carry them). Lengths in m, world frame.

use crate::result::{ResultDoc, RodResult};
use crate::tube::tube_radius;

/// Radius of a connector's collar, in hose outer radii.
pub const CONNECTOR_RADIUS_FACTOR: f64 = 1.4;
/// How far a connector's collar reaches beyond the hose end, in hose outer radii.
pub const CONNECTOR_LENGTH_FACTOR: f64 = 2.0;
/// How far a connector's collar reaches over the hose end, in hose outer radii.
pub const CONNECTOR_OVERLAP_FACTOR: f64 = 1.0;
/// Radius of a clip's band, in hose outer radii.
pub const CLIP_RADIUS_FACTOR: f64 = 1.5;
/// Width of a clip's band along the hose, in hose outer radii.
pub const CLIP_WIDTH_FACTOR: f64 = 1.6;

/// What a fitting is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FittingKind {
    /// A junction body (its ports hold rod ends).
    Junction,
    /// A connector fixed in space holding a rod end.
    Connector,
    /// A clip holding a rod vertex.
    Clip,
}

impl FittingKind {
    /// `"junction"`, `"connector"` or `"clip"`.
    pub fn as_str(self) -> &'static str {
        match self {
            FittingKind::Junction => "junction",
            FittingKind::Connector => "connector",
            FittingKind::Clip => "clip",
        }
    }
}

/// One solid piece of a fitting, m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FittingPiece {
    /// A capped cylinder along the segment `start_m`–`end_m`.
    Cylinder {
        /// One end of the axis, m.
        start_m: [f64; 3],
        /// The other end of the axis, m.
        end_m: [f64; 3],
        /// Radius, m.
        radius_m: f64,
    },
    /// A ball.
    Ball {
        /// Centre, m.
        centre_m: [f64; 3],
        /// Radius, m.
        radius_m: f64,
    },
}

/// A fitting: its kind, name and pieces.
#[derive(Clone, Debug, PartialEq)]
pub struct Fitting {
    /// What it is.
    pub kind: FittingKind,
    /// The junction's, connector's or clip's name.
    pub name: String,
    /// Its solid pieces.
    pub pieces: Vec<FittingPiece>,
}

fn sub(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn along(p: &[f64; 3], t: &[f64; 3], d: f64) -> [f64; 3] {
    [p[0] + d * t[0], p[1] + d * t[1], p[2] + d * t[2]]
}

/// `v / |v|`, or `None` for a zero or non-finite vector.
fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (n > 0.0 && n.is_finite()).then(|| v.map(|x| x / n))
}

/// The unit tangent of `rod` at vertex `j` (central difference inside, one-sided at
/// the ends), pointing towards increasing arc length.
fn tangent(rod: &RodResult, j: usize) -> Option<[f64; 3]> {
    let p = &rod.position_m;
    let last = p.len().checked_sub(1)?;
    let (a, b) = (j.saturating_sub(1), (j + 1).min(last));
    unit(sub(&p[b], &p[a]))
}

fn rod_named<'a>(doc: &'a ResultDoc, name: &str) -> Option<&'a RodResult> {
    doc.rods.iter().find(|r| r.name == name)
}

/// Every fitting of `doc`: junction bodies (from `bodies` and the `port` reactions
/// named `<body>.<port>`), connectors (the `connector` reactions) and clips, in that
/// order. Fittings whose place is not finite are left out.
pub fn fittings(doc: &ResultDoc) -> Vec<Fitting> {
    let mut out = Vec::new();
    let finite = |p: &[f64; 3]| p.iter().all(|x| x.is_finite());
    for body in &doc.bodies {
        if !finite(&body.position_m) {
            continue;
        }
        let prefix = format!("{}.", body.name);
        let mut pieces = Vec::new();
        let mut ball = 0.0_f64;
        for port in doc
            .reactions
            .iter()
            .filter(|r| r.kind == "port" && r.name.starts_with(&prefix))
        {
            let Some(rod) = rod_named(doc, &port.rod) else {
                continue;
            };
            let (radius, _) = tube_radius(rod);
            ball = ball.max(radius);
            if finite(&port.position_m) && unit(sub(&port.position_m, &body.position_m)).is_some() {
                pieces.push(FittingPiece::Cylinder {
                    start_m: body.position_m,
                    end_m: port.position_m,
                    radius_m: radius,
                });
            }
        }
        if ball > 0.0 {
            pieces.push(FittingPiece::Ball {
                centre_m: body.position_m,
                radius_m: ball,
            });
            out.push(Fitting {
                kind: FittingKind::Junction,
                name: body.name.clone(),
                pieces,
            });
        }
    }
    for connector in doc.reactions.iter().filter(|r| r.kind == "connector") {
        let Some(rod) = rod_named(doc, &connector.rod) else {
            continue;
        };
        let at_end = connector.end == "end";
        let j = if at_end { rod.position_m.len() - 1 } else { 0 };
        let (Some(t), Some(p)) = (tangent(rod, j), rod.position_m.get(j)) else {
            continue;
        };
        if !finite(p) {
            continue;
        }
        // Outward: along the rod at its end, against it at its start.
        let out_dir = if at_end { t } else { t.map(|x| -x) };
        let (radius, _) = tube_radius(rod);
        out.push(Fitting {
            kind: FittingKind::Connector,
            name: connector.name.clone(),
            pieces: vec![FittingPiece::Cylinder {
                start_m: along(p, &out_dir, -CONNECTOR_OVERLAP_FACTOR * radius),
                end_m: along(p, &out_dir, CONNECTOR_LENGTH_FACTOR * radius),
                radius_m: CONNECTOR_RADIUS_FACTOR * radius,
            }],
        });
    }
    for clip in &doc.clips {
        let Some(rod) = rod_named(doc, &clip.rod) else {
            continue;
        };
        let Some(t) = tangent(rod, clip.vertex) else {
            continue;
        };
        if !finite(&clip.position_m) {
            continue;
        }
        let (radius, _) = tube_radius(rod);
        let half = 0.5 * CLIP_WIDTH_FACTOR * radius;
        out.push(Fitting {
            kind: FittingKind::Clip,
            name: clip.name.clone(),
            pieces: vec![FittingPiece::Cylinder {
                start_m: along(&clip.position_m, &t, -half),
                end_m: along(&clip.position_m, &t, half),
                radius_m: CLIP_RADIUS_FACTOR * radius,
            }],
        });
    }
    out
}
