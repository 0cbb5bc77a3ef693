//! Clips of a case file: joints fixed in space that hold a rod at an interior point.
//!
//! ```ron
//! clips: {
//!     "grommet": (
//!         rod: "trunk",
//!         at: 250,                                   // arc length along the rod, length unit
//!         base: (position: (240, 0, 0), direction: (1, 0, 0), normal: (0, 0, 1)),
//!         joint: Revolute(axis: (0, 0, 1)),          // base coordinates: about the cable
//!         limits: (-0.5, 0.5),                       // optional: rad (revolute), length unit (prismatic)
//!     ),
//! },
//! ```
//!
//! The base frame has `a3` along `direction` (the rod's direction through the clip,
//! towards increasing arc length) and `a1` along `normal`; joint axes are given in it.
//! The optional `offset` (same form as `base`, in base coordinates) places the output
//! frame relative to the joint's moving frame; by default the output frame is the
//! joint frame.
//!
//! The rod is discretised so that a vertex lies exactly at every clip's `at`: its
//! segments are split between the pieces between clips in proportion to their lengths
//! (at least one each), each piece cut into equal edges.

use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};
use strand_rod::{NominalRod, Rod};
use strand_system::{BodyHandle, ClipSpec, Joint, Pose, RodHandle, RodSpec};

use crate::ends::frame_from_tangent_normal;
use crate::error::{CaseError, Reporter};
use crate::schema::{CaseFile, RodDef, Vec3};
use crate::units::LengthUnit;

/// Largest deviation of a joint axis from unit length.
pub const AXIS_UNIT_TOLERANCE: f64 = 1e-6;

/// Largest distance of a clip's `at_point` from the nominal centreline, as a fraction
/// of the rod's length, for a section without an outer radius (otherwise the outer
/// radius is the limit).
pub const CLIP_POINT_TOLERANCE: f64 = 1e-3;

/// A frame as written in a clip: origin, `a3` along `direction`, `a1` along `normal`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClipFrameDef {
    /// Origin in the case's length unit.
    pub position: Vec3,
    /// Direction of `a3`: the rod's direction through the clip (any non-zero length).
    pub direction: Vec3,
    /// Direction of `a1` (not parallel to `direction`).
    pub normal: Vec3,
}

/// The joint of a clip between its base and output frames.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum JointDef {
    /// No freedom.
    Fixed,
    /// Rotation about `axis` (unit, base coordinates) through the base origin.
    Revolute {
        /// Unit axis in base coordinates (`(0, 0, 1)`: about the rod).
        axis: Vec3,
    },
    /// Translation along `axis` (unit, base coordinates): a rail.
    Prismatic {
        /// Unit axis in base coordinates.
        axis: Vec3,
    },
    /// Free rotation about the base origin (ball joint).
    Spherical,
}

/// A clip: `(rod: "hose", at: 250, base: (...), joint: Fixed)`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClipDef {
    /// Name of the rod held.
    pub rod: String,
    /// Arc length along the rod (from its start) where the clip holds it, length unit
    /// (on a moulded rod: along its nominal centreline). Give `at` or `at_point`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at: Option<f64>,
    /// Instead of `at`, for a moulded rod: a point (length unit, world) projected onto
    /// the nominal centreline; the clip holds the rod at the nearest point of the
    /// centreline. Refused when that is farther than the section's outer radius (the
    /// point must lie inside the hose as moulded; [`CLIP_POINT_TOLERANCE`] of the rod's
    /// length for a section without radius). The distance is reported in
    /// [`crate::BuiltCase::clip_projections`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at_point: Option<Vec3>,
    /// The junction or the earlier clip that carries this clip's base, if any: the base
    /// (and with it the joint axes) is then given in that junction's body frame, or in
    /// that clip's output frame, and moves with it: a clip mounted on a T-piece; on a
    /// light junction without ports, one half of a hose-to-hose clip; on another clip,
    /// a chain of joints. Default: the base is fixed in space.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub on: Option<String>,
    /// The base frame: in the world, or in the body frame of the junction `on` (the
    /// output frame of the clip `on`).
    /// May be omitted for a clip on a moulded rod (one with a `nominal` shape): the
    /// base is then the rod's nominal frame at `at`
    /// ([`strand_rod::NominalRod::clip_frame`]), where the clip holds it stress-free;
    /// carried by a junction (or a clip), that frame is taken relative to the
    /// junction's `position` and `orientation` as given (the carrier clip's output
    /// frame at joint value 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<ClipFrameDef>,
    /// The joint.
    pub joint: JointDef,
    /// Limits `(lower, upper)` of a revolute (rad) or prismatic (length unit) joint,
    /// with `lower ≤ 0 ≤ upper`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limits: Option<(f64, f64)>,
    /// Output frame relative to the joint's moving frame (default: the same frame).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub offset: Option<ClipFrameDef>,
    /// The motion this clip's `base` rides on (only a base in the world, not `on` a junction or clip) (optional; see [`crate::motion`]): the part is
    /// where it is written at the motion's parameter 0 and moves rigidly with the
    /// motion, `moves_with: "engine_roll"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moves_with: Option<String>,
}

/// A clip converted to SI, its vertex not yet known.
#[derive(Clone, Debug)]
pub(crate) struct PendingClip {
    item: String,
    spec: ClipSpec,
    at_m: f64,
    at_file: f64,
    /// `at_point` in m, projected onto the nominal centreline when the rod is built.
    at_point: Option<Vector3<f64>>,
    /// The base is the rod's nominal frame at the clip (no `base` given).
    nominal_base: bool,
}

fn valid_name(name: &str) -> bool {
    !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-'))
}

fn pose(
    report: &Reporter,
    item: &str,
    unit: LengthUnit,
    def: &ClipFrameDef,
) -> Result<Pose, CaseError> {
    let position = report.finite3(
        &format!("{item}.position"),
        &def.position,
        &format!(" {unit}"),
    )? * unit.metres();
    let d = report.finite3(&format!("{item}.direction"), &def.direction, "")?;
    let n = report.finite3(&format!("{item}.normal"), &def.normal, "")?;
    let orientation = frame_from_tangent_normal(&d, &n).map_err(|e| {
        report.invalid(
            item,
            e.to_string().replace("tangent", "direction"),
            "direction is the rod's direction through the clip (towards increasing arc length), \
             normal any direction across it, e.g. direction (1, 0, 0), normal (0, 0, 1)",
        )
    })?;
    Ok(Pose {
        position,
        orientation,
    })
}

fn axis(report: &Reporter, item: &str, axis: &Vec3) -> Result<Vector3<f64>, CaseError> {
    let a = report.finite3(item, axis, "")?;
    let norm = a.norm();
    if (norm - 1.0).abs() > AXIS_UNIT_TOLERANCE {
        return Err(report.invalid(
            item,
            format!(
                "the joint axis ({}, {}, {}) must be a unit vector (its length is {norm})",
                axis[0], axis[1], axis[2]
            ),
            "give a unit vector in base coordinates (the base frame has a3 = direction, \
             a1 = normal), e.g. (0, 0, 1) about or along the rod, (1, 0, 0) along the normal",
        ));
    }
    Ok(a / norm)
}

/// Converts and checks the file's clips (rod names, frames, joints, limits); their
/// vertices are found by [`place_clips`].
pub(crate) fn resolve_clips(
    report: &Reporter,
    unit: LengthUnit,
    file: &CaseFile,
) -> Result<Vec<PendingClip>, CaseError> {
    let mut out = Vec::with_capacity(file.clips.len());
    for (name, def) in &file.clips {
        let item = format!("clips '{name}'");
        if !valid_name(name) {
            return Err(report.invalid(
                &item,
                format!("invalid clip name '{name}'"),
                "use letters, digits, '_' and '-' only",
            ));
        }
        let Some(rod) = file.rods.iter().position(|r| r.name == def.rod) else {
            let defined: Vec<&str> = file.rods.iter().map(|r| r.name.as_str()).collect();
            return Err(report.invalid(
                format!("{item}.rod"),
                format!(
                    "rod '{}' is not defined (defined: {})",
                    def.rod,
                    defined.join(", ")
                ),
                "name one of the case's rods",
            ));
        };
        let (body, parent) = match &def.on {
            None => (None, None),
            Some(carrier) => {
                let junction = file.junctions.iter().position(|(j, _)| j == carrier);
                let earlier = file.clips.iter().position(|(c, _)| c == carrier);
                match (junction, earlier) {
                    (Some(b), _) => (Some(BodyHandle(b)), None),
                    (None, Some(c)) if c < out.len() => (None, Some(c)),
                    _ => {
                        let junctions: Vec<&str> =
                            file.junctions.iter().map(|(j, _)| j.as_str()).collect();
                        let clips: Vec<&str> = file.clips[..out.len()]
                            .iter()
                            .map(|(c, _)| c.as_str())
                            .collect();
                        let list = |names: Vec<&str>| {
                            if names.is_empty() {
                                "none".to_string()
                            } else {
                                names.join(", ")
                            }
                        };
                        return Err(report.invalid(
                            format!("{item}.on"),
                            format!(
                                "'{carrier}' is neither a junction (defined: {}) nor a clip \
                                 defined before this one ({})",
                                list(junctions),
                                list(clips)
                            ),
                            "name a junction, or a clip listed earlier in `clips` (a chain \
                             of joints), or remove `on` for a base fixed in space",
                        ));
                    }
                }
            }
        };
        let (at_file, at_point) = match (def.at, &def.at_point) {
            (Some(at), None) => (
                report.finite(&format!("{item}.at"), at, &format!(" {unit}"))?,
                None,
            ),
            (None, Some(point)) if file.rods[rod].nominal.is_some() => {
                let p = report.finite3(&format!("{item}.at_point"), point, &format!(" {unit}"))?;
                (f64::NAN, Some(p * unit.metres()))
            }
            (None, Some(_)) => {
                return Err(report.invalid(
                    format!("{item}.at_point"),
                    format!(
                        "rod '{}' has no nominal centreline to project the point onto",
                        def.rod
                    ),
                    "give the clip's arc length `at` (points are projected onto a moulded \
                     rod's `nominal` centreline only)",
                ));
            }
            (Some(_), Some(_)) => {
                return Err(report.invalid(
                    format!("{item}.at_point"),
                    "both `at` and `at_point` are given",
                    "give the clip's place once: an arc length `at` or a point `at_point`",
                ));
            }
            (None, None) => {
                return Err(report.invalid(
                    format!("{item}.at"),
                    "missing field `at`",
                    "give the arc length `at` from the rod's start to the clip (length unit), \
                     or for a moulded rod a point `at_point` near its nominal centreline",
                ));
            }
        };
        let nominal_base = def.base.is_none();
        let base = match &def.base {
            Some(base) => pose(report, &format!("{item}.base"), unit, base)?,
            None if file.rods[rod].nominal.is_some() => Pose {
                position: Vector3::zeros(),
                orientation: UnitQuaternion::identity(),
            },
            None => {
                return Err(report.invalid(
                    format!("{item}.base"),
                    "missing field `base`",
                    "give the clip's base frame (position, direction, normal); only a clip \
                     on a rod with a `nominal` shape may omit it (its base is then the \
                     nominal frame at `at`)",
                ));
            }
        };
        let offset = match &def.offset {
            None => Pose {
                position: Vector3::zeros(),
                orientation: UnitQuaternion::identity(),
            },
            Some(o) => pose(report, &format!("{item}.offset"), unit, o)?,
        };
        let joint_item = format!("{item}.joint.axis");
        let (joint, limit_scale) = match &def.joint {
            JointDef::Fixed => (Joint::Fixed, None),
            JointDef::Spherical => (Joint::Spherical, None),
            JointDef::Revolute { axis: a } => (
                Joint::Revolute {
                    axis: axis(report, &joint_item, a)?,
                },
                Some(("rad", 1.0)),
            ),
            JointDef::Prismatic { axis: a } => (
                Joint::Prismatic {
                    axis: axis(report, &joint_item, a)?,
                },
                Some((unit.symbol(), unit.metres())),
            ),
        };
        let limits = match (def.limits, limit_scale) {
            (None, _) => None,
            (Some(_), None) => {
                return Err(report.invalid(
                    format!("{item}.limits"),
                    "only revolute and prismatic joints take limits",
                    "remove `limits`, or use a Revolute or Prismatic joint",
                ));
            }
            (Some((lower, upper)), Some((u, scale))) => {
                let ok = lower.is_finite()
                    && upper.is_finite()
                    && lower <= 0.0
                    && 0.0 <= upper
                    && lower < upper;
                if !ok {
                    return Err(report.invalid(
                        format!("{item}.limits"),
                        format!(
                            "limits ({lower}, {upper}) {u} must be finite with lower ≤ 0 ≤ upper \
                             and lower < upper"
                        ),
                        "the joint value is 0 at the base frame, so the range must contain 0, \
                         e.g. (-0.2, 0.2)",
                    ));
                }
                Some((lower * scale, upper * scale))
            }
        };
        out.push(PendingClip {
            spec: ClipSpec {
                parent,
                body,
                name: name.clone(),
                base,
                joint,
                offset,
                rod: RodHandle(rod),
                vertex: 0,
                limits,
            },
            at_m: at_file * unit.metres(),
            at_file,
            at_point,
            item,
            nominal_base,
        });
    }
    Ok(out)
}

/// Projects the `at_point` of every clip on rod `rod` onto its nominal centreline
/// `shape` (m), setting the clip's station; returns `(clip name, distance m)` per
/// projected clip. `outer_radius` (m) bounds the distance (see [`ClipDef::at_point`]).
pub(crate) fn project_clip_points(
    report: &Reporter,
    unit: LengthUnit,
    rod: usize,
    shape: &strand_rod::NominalShape,
    outer_radius: f64,
    clips: &mut [PendingClip],
) -> Result<Vec<(String, f64)>, CaseError> {
    let mut out = Vec::new();
    for clip in clips.iter_mut().filter(|c| c.spec.rod.0 == rod) {
        let Some(point) = clip.at_point else { continue };
        let (station, distance) = shape.project(&point).map_err(|e| {
            report.invalid(
                format!("{}.at_point", clip.item),
                e.to_string(),
                "correct the rod's nominal shape",
            )
        })?;
        let length = shape.arc_length().unwrap_or(station);
        let limit = if outer_radius > 0.0 {
            outer_radius
        } else {
            CLIP_POINT_TOLERANCE * length
        };
        let m = unit.metres();
        if distance > limit {
            return Err(report.invalid(
                format!("{}.at_point", clip.item),
                format!(
                    "the point is {:.6} {unit} from the nominal centreline (nearest at arc length \
                     {:.6} {unit}), more than the allowed {:.6} {unit}",
                    distance / m,
                    station / m,
                    limit / m
                ),
                "give a point on (or inside the hose around) the rod's nominal centreline, or the \
                 arc length `at`",
            ));
        }
        clip.at_m = station;
        clip.at_file = station / m;
        out.push((clip.spec.name.clone(), distance));
    }
    Ok(out)
}

/// The arc lengths (m) of the clips on rod `rod`, in file order.
pub(crate) fn clips_on_rod(clips: &[PendingClip], rod: usize) -> Vec<f64> {
    clips
        .iter()
        .filter(|c| c.spec.rod.0 == rod)
        .map(|c| c.at_m)
        .collect()
}

/// Vertex stations (m along a nominal curve of arc length `total`) for `segments`
/// edges with a vertex at every clip station: the pieces between clips get edges in
/// proportion to their lengths ([`allocate`]), equal in arc length within a piece.
/// `None` when the stations cannot all get an interior vertex (then
/// [`place_clips`] reports why).
pub(crate) fn station_targets(stations: &[f64], total: f64, segments: usize) -> Option<Vec<f64>> {
    let mut inner = stations.to_vec();
    inner.sort_by(f64::total_cmp);
    let margin = 1e-9 * total;
    let inside = inner.iter().all(|&s| s > margin && s < total - margin);
    let distinct = inner.windows(2).all(|w| w[1] - w[0] > margin);
    if !inside || !distinct || segments < inner.len() + 1 {
        return None;
    }
    let mut bounds = vec![0.0];
    bounds.extend(inner);
    bounds.push(total);
    let pieces: Vec<f64> = bounds.windows(2).map(|w| w[1] - w[0]).collect();
    let counts = allocate(&pieces, segments);
    let mut targets = vec![0.0];
    for (w, &n) in bounds.windows(2).zip(&counts) {
        targets.extend((1..n).map(|k| w[0] + (w[1] - w[0]) * k as f64 / n as f64));
        targets.push(w[1]);
    }
    Some(targets)
}

/// The edges of each piece between the clips `on_rod` (sorted along the rod) when
/// every clip keeps its `pinned` vertex: `None` without pins or when the pinned
/// vertices are not strictly increasing inside the rod's `segments` edges.
fn pinned_counts(
    pinned: Option<&[usize]>,
    on_rod: &[usize],
    segments: usize,
) -> Option<Vec<usize>> {
    let pinned = pinned?;
    let mut vertices = vec![0];
    for &c in on_rod {
        vertices.push(*pinned.get(c)?);
    }
    vertices.push(segments);
    vertices
        .windows(2)
        .map(|w| (w[1] > w[0]).then(|| w[1] - w[0]))
        .collect()
}

/// Splits `segments` edges between pieces of the given lengths in proportion to them,
/// at least one each (`segments ≥ pieces.len()`).
pub(crate) fn allocate(pieces: &[f64], segments: usize) -> Vec<usize> {
    let total: f64 = pieces.iter().sum();
    let mut counts: Vec<usize> = pieces
        .iter()
        .map(|l| ((segments as f64 * l / total).round() as usize).max(1))
        .collect();
    let edge = |i: usize, counts: &[usize]| pieces[i] / counts[i] as f64;
    while counts.iter().sum::<usize>() > segments {
        // Take an edge from the most refined piece that has more than one.
        let i = (0..pieces.len())
            .filter(|&i| counts[i] > 1)
            .min_by(|&a, &b| {
                let (ea, eb) = (
                    pieces[a] / (counts[a] - 1) as f64,
                    pieces[b] / (counts[b] - 1) as f64,
                );
                ea.total_cmp(&eb)
            })
            .expect("segments ≥ pieces");
        counts[i] -= 1;
    }
    while counts.iter().sum::<usize>() < segments {
        // Give an edge to the coarsest piece.
        let i = (0..pieces.len())
            .max_by(|&a, &b| edge(a, &counts).total_cmp(&edge(b, &counts)))
            .expect("at least one piece");
        counts[i] += 1;
    }
    counts
}

/// Edge lengths of `counts[i]` equal edges between consecutive `stations` (arc lengths
/// from 0 to `L`), such that the running sum (as in [`Rod::arc_lengths`]) hits every
/// station exactly.
pub(crate) fn edge_lengths(stations: &[f64], counts: &[usize]) -> Vec<f64> {
    let mut edges = Vec::with_capacity(counts.iter().sum());
    let mut acc = 0.0;
    for (w, &n) in stations.windows(2).zip(counts) {
        for k in 1..=n {
            let target = if k == n {
                w[1]
            } else {
                w[0] + (w[1] - w[0]) * k as f64 / n as f64
            };
            let mut h = target - acc;
            for _ in 0..4 {
                let reached = acc + h;
                if reached == target {
                    break;
                }
                h += target - reached;
            }
            acc += h;
            edges.push(h);
        }
    }
    edges
}

/// Rebuilds rod `index` (`spec`, from `def`) so that a vertex lies at every clip on it
/// and records those vertices; rods without clips are returned unchanged. With
/// `pinned` (a vertex per clip, in clip order: a base build's) a straight rod keeps
/// those vertices while they stay in the clips' order, so that a design that moves
/// a clip along its rod keeps its mesh (the edges between two clips stretch) instead
/// of handing an edge from one piece to the next where the allocation ties.
#[allow(clippy::too_many_arguments)]
pub(crate) fn place_clips(
    report: &Reporter,
    item: &str,
    unit: LengthUnit,
    index: usize,
    def: &RodDef,
    mut spec: RodSpec,
    nominal: Option<&NominalRod>,
    clips: &mut [PendingClip],
    pinned: Option<&[usize]>,
) -> Result<RodSpec, CaseError> {
    let mut on_rod: Vec<usize> = (0..clips.len())
        .filter(|&c| clips[c].spec.rod.0 == index)
        .collect();
    if on_rod.is_empty() {
        return Ok(spec);
    }
    // A moulded rod's clips sit at arc lengths along its nominal curve.
    let length = match nominal {
        Some(n) => *n.stations.last().expect("a rod has vertices"),
        None => spec.rod.length(),
    };
    let m = unit.metres();
    for &c in &on_rod {
        let clip = &clips[c];
        // Not at (or within round-off of) an end.
        let margin = 1e-9 * length;
        if !(clip.at_m > margin && clip.at_m < length - margin) {
            return Err(report.invalid(
                format!("{}.at", clip.item),
                format!(
                    "at = {} {unit} is not inside rod '{}' (0 < at < {} {unit})",
                    clip.at_file,
                    def.name,
                    (length / m * 1e9).round() / 1e9
                ),
                "give the arc length from the rod's start to the clip, strictly between its ends \
                 (hold an end with a connector instead)",
            ));
        }
    }
    on_rod.sort_by(|&a, &b| clips[a].at_m.total_cmp(&clips[b].at_m));
    for w in on_rod.windows(2) {
        let (a, b) = (&clips[w[0]], &clips[w[1]]);
        if b.at_m - a.at_m <= 1e-9 * length {
            return Err(report.invalid(
                format!("{}.at", b.item),
                format!(
                    "clips '{}' and '{}' both hold rod '{}' at {} {unit}",
                    a.spec.name, b.spec.name, def.name, b.at_file
                ),
                "one clip per place: remove one of them or move it along the rod",
            ));
        }
    }
    let segments = spec.rod.segments();
    if segments < on_rod.len() + 1 {
        return Err(report.invalid(
            format!("{item}.segments"),
            format!(
                "{} segment(s) cannot hold {} clip(s): every clip needs a vertex between the rod's ends",
                segments,
                on_rod.len()
            ),
            format!(
                "use at least {} segments (or a larger --segments)",
                on_rod.len() + 1
            ),
        ));
    }
    let mut stations = vec![0.0];
    stations.extend(on_rod.iter().map(|&c| clips[c].at_m));
    stations.push(length);
    let pieces: Vec<f64> = stations.windows(2).map(|w| w[1] - w[0]).collect();
    let counts = match pinned_counts(pinned, &on_rod, segments) {
        Some(counts) if nominal.is_none() => counts,
        _ => allocate(&pieces, segments),
    };
    let mut vertex = 0;
    for (&c, &n) in on_rod.iter().zip(&counts) {
        vertex += n;
        clips[c].spec.vertex = vertex;
    }
    if let Some(nominal) = nominal {
        // Built with a vertex at every clip (`station_targets`, the same allocation).
        for &c in &on_rod {
            let clip = &mut clips[c];
            let v = clip.spec.vertex;
            debug_assert!((nominal.stations[v] - clip.at_m).abs() <= 1e-9 * length);
            if clip.nominal_base {
                clip.spec.base = Pose {
                    position: nominal.state.positions[v],
                    orientation: nominal.clip_frame(v),
                };
            }
        }
        return Ok(spec);
    }
    let edges = edge_lengths(&stations, &counts);
    spec.rod = Rod::try_new(
        *spec.rod.section(),
        edges,
        vec![Vector3::z(); segments],
        vec![Vector3::zeros(); segments + 1],
    )
    .map_err(|e| {
        report.invalid(
            item,
            e.to_string(),
            "move the clips apart or use more segments",
        )
    })?;
    Ok(spec)
}

/// `a` followed by `b` (`b` given in `a`'s coordinates).
fn compose(a: &Pose, b: &Pose) -> Pose {
    Pose {
        position: a.transform_point(&b.position),
        orientation: a.orientation * b.orientation,
    }
}

/// The clips as [`ClipSpec`]s, in file order. A clip on a moulded rod without `base`
/// (its base the nominal frame, in the world) carried by a junction or an earlier
/// clip gets that frame in its carrier's coordinates: relative to the junction's pose
/// in `bodies` (as given: the pose of a mounted one, the initial guess of a free one)
/// or to the carrier clip's output frame at joint value 0, so that the clip holds
/// the rod at its nominal frame when the carriers are where the case puts them.
pub(crate) fn clip_specs(
    clips: Vec<PendingClip>,
    bodies: &[strand_system::BodySpec],
) -> Vec<ClipSpec> {
    let mut outputs: Vec<Pose> = Vec::with_capacity(clips.len());
    let mut specs = Vec::with_capacity(clips.len());
    for clip in clips {
        let mut spec = clip.spec;
        let carrier = match (spec.body, spec.parent) {
            (Some(body), _) => Some(bodies[body.0].pose),
            (None, Some(parent)) => Some(outputs[parent]),
            (None, None) => None,
        };
        if let Some(carrier) = carrier
            && clip.nominal_base
        {
            let inverse = carrier.orientation.inverse();
            spec.base = Pose {
                position: inverse * (spec.base.position - carrier.position),
                orientation: inverse * spec.base.orientation,
            };
        }
        let base = carrier.map_or(spec.base, |c| compose(&c, &spec.base));
        outputs.push(compose(&base, &spec.offset));
        specs.push(spec);
    }
    specs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Case, CaseError};

    const ORIGIN: &str = "cases/clips.ron";

    /// Two clamped hoses; `CLIPS` is replaced by each test.
    const BASE: &str = r#"(
    units: (length: "mm"),
    sections: { "cable": Explicit(ea: 1e4, ga: 4e3, ei: 0.05, gj: 0.04, mass_per_length: 0.2) },
    rods: [
        (
            name: "hose", section: "cable", length: 1000, segments: 20,
            start: Clamp(position: (0, 0, 0), tangent: (1, 0, 0), normal: (0, 0, 1)),
            end: Clamp(position: (950, 0, 0), tangent: (1, 0, 0), normal: (0, 0, 1)),
        ),
        (
            name: "other", section: "cable", length: 300, segments: 7,
            start: Clamp(position: (0, 100, 0), tangent: (1, 0, 0), normal: (0, 0, 1)),
            end: Free(),
        ),
    ],
    gravity: (0, 0, -9.81),
    clips: { CLIPS },
)"#;

    fn case(clips: &str) -> String {
        BASE.replace("CLIPS", clips)
    }

    /// A clip on `rod` at `at` mm, its base on the line of the rod's start (within
    /// reach of it: the 'other' rod starts 100 mm off the first).
    fn clip(name: &str, rod: &str, at: f64, joint: &str, extra: &str) -> String {
        format!(
            "\"{name}\": (rod: \"{rod}\", at: {at}, base: (position: ({x}, {y}, 0), direction: (1, 0, 0), \
             normal: (0, 0, 1)), joint: {joint}{extra}),",
            x = at * 0.95,
            y = if rod == "other" { 100 } else { 0 }
        )
    }

    fn build(text: &str, segments: Option<usize>) -> Result<crate::BuiltCase, CaseError> {
        Case::from_str(text, ORIGIN).and_then(|c| c.build(segments))
    }

    fn err(text: &str) -> String {
        match build(text, None) {
            Ok(_) => panic!("expected an error for:\n{text}"),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn clipped_vertices_lie_exactly_at_their_arc_length() {
        let clips = [
            clip("a", "hose", 250.0, "Fixed", ""),
            clip("b", "hose", 333.3, "Spherical", ""),
            clip(
                "c",
                "hose",
                900.0,
                "Revolute(axis: (0, 0, 1))",
                ", limits: (-0.3, 0.2)",
            ),
            clip(
                "d",
                "other",
                10.0,
                "Prismatic(axis: (1, 0, 0))",
                ", limits: (-5, 5)",
            ),
        ]
        .concat();
        for segments in [None, Some(9), Some(40), Some(157)] {
            let built = build(&case(&clips), segments).unwrap();
            let system = built.model.system();
            assert_eq!(system.clips.len(), 4);
            for (rod, given) in [(0, 20), (1, 7)] {
                let spec = &system.rods[rod];
                assert_eq!(spec.rod.segments(), segments.unwrap_or(given));
                let length = [1.0, 0.3][rod];
                assert!(
                    (spec.rod.length() - length).abs() < 1e-15,
                    "{}",
                    spec.rod.length()
                );
            }
            let mm = crate::LengthUnit::Millimetre.metres();
            for (clip, at) in system.clips.iter().zip([250.0, 333.3, 900.0, 10.0]) {
                let arc = system.rods[clip.rod.0].rod.arc_lengths();
                assert_eq!(
                    arc[clip.vertex],
                    at * mm,
                    "clip '{}' at {segments:?}",
                    clip.name
                );
            }
            assert_eq!(system.clips[3].limits, Some((-0.005, 0.005)));
            assert_eq!(system.clips[2].limits, Some((-0.3, 0.2)));
            assert_eq!(
                system.clips[2].offset.orientation,
                UnitQuaternion::identity()
            );
        }
        // Each piece is uniform and the split follows the piece lengths.
        let built = build(&case(&clips), Some(40)).unwrap();
        let rod = &built.model.system().rods[0].rod;
        let vertices: Vec<usize> = built.model.system().clips[..3]
            .iter()
            .map(|c| c.vertex)
            .collect();
        assert_eq!(vertices, [10, 13, 36]);
        for piece in [0..10, 10..13, 13..36, 36..40] {
            let h = &rod.edge_lengths()[piece];
            assert!(h.iter().all(|x| (x - h[0]).abs() < 1e-15), "{h:?}");
        }
    }

    #[test]
    fn allocation_is_proportional_with_one_segment_at_least() {
        assert_eq!(allocate(&[0.25, 0.75], 20), [5, 15]);
        assert_eq!(allocate(&[0.001, 0.999], 3), [1, 2]);
        assert_eq!(allocate(&[1.0, 1.0, 1.0], 3), [1, 1, 1]);
        assert_eq!(allocate(&[0.5, 0.5], 3).iter().sum::<usize>(), 3);
        assert_eq!(allocate(&[0.1, 0.1, 0.1, 0.7], 5), [1, 1, 1, 2]);
    }

    #[test]
    fn clip_errors_name_the_item_and_hint() {
        let cases: [(String, &[&str]); 12] = [
            (
                // A chain must be built from earlier clips.
                [
                    clip("a", "hose", 250.0, "Fixed", ", on: \"b\""),
                    clip("b", "hose", 500.0, "Spherical", ""),
                ]
                .concat(),
                &[
                    "clips 'a'.on",
                    "'b' is neither a junction (defined: none) nor a clip defined before this one (none)",
                    "hint: name a junction, or a clip listed earlier",
                ],
            ),
            (
                clip("a", "hoes", 250.0, "Fixed", ""),
                &[
                    "clips 'a'.rod",
                    "rod 'hoes' is not defined (defined: hose, other)",
                    "hint",
                ],
            ),
            (
                clip("a", "hose", 0.0, "Fixed", ""),
                &["clips 'a'.at", "not inside rod 'hose'", "0 < at < 1000 mm"],
            ),
            (
                clip("a", "hose", 1000.0, "Fixed", ""),
                &["clips 'a'.at", "not inside"],
            ),
            (
                clip("a", "hose", -5.0, "Fixed", ""),
                &["clips 'a'.at", "not inside"],
            ),
            (
                [
                    clip("a", "hose", 250.0, "Fixed", ""),
                    clip("b", "hose", 250.0, "Spherical", ""),
                ]
                .concat(),
                &[
                    "clips 'b'.at",
                    "clips 'a' and 'b' both hold rod 'hose' at 250 mm",
                    "one clip per place",
                ],
            ),
            (
                clip("a", "hose", 250.0, "Revolute(axis: (0, 0, 2))", ""),
                &[
                    "clips 'a'.joint.axis",
                    "must be a unit vector",
                    "hint: give a unit vector",
                ],
            ),
            (
                clip("a", "hose", 250.0, "Prismatic(axis: (0, 0, 0))", ""),
                &["clips 'a'.joint.axis", "must be a unit vector"],
            ),
            (
                clip("a", "hose", 250.0, "Spherical", ", limits: (-1, 1)"),
                &[
                    "clips 'a'.limits",
                    "only revolute and prismatic joints take limits",
                    "remove `limits`",
                ],
            ),
            (
                clip("a", "hose", 250.0, "Fixed", ", limits: (-1, 1)"),
                &["clips 'a'.limits", "only revolute and prismatic"],
            ),
            (
                clip(
                    "a",
                    "hose",
                    250.0,
                    "Revolute(axis: (1, 0, 0))",
                    ", limits: (0.1, 0.3)",
                ),
                &[
                    "clips 'a'.limits",
                    "lower ≤ 0 ≤ upper",
                    "rad",
                    "must contain 0",
                ],
            ),
            (
                clip("a b", "hose", 250.0, "Fixed", ""),
                &["clips 'a b'", "invalid clip name"],
            ),
        ];
        for (clips, expected) in cases {
            let message = err(&case(&clips));
            assert!(message.starts_with(ORIGIN), "{message}");
            for e in expected {
                assert!(message.contains(e), "{e:?} not in {message}");
            }
        }
        let message = err(&case(&clip(
            "a",
            "hose",
            250.0,
            "Prismatic(axis: (1, 0, 0))",
            ", limits: (3, 5)",
        )));
        assert!(message.contains("(3, 5) mm"), "{message}");
        let message = err(&case(
            &clip("a", "hose", 250.0, "Fixed", "")
                .replace("normal: (0, 0, 1)", "normal: (2, 0, 0)"),
        ));
        assert!(
            message.contains("clips 'a'.base") && message.contains("parallel to the direction"),
            "{message}"
        );
        let message = err(&case(
            &clip("a", "hoes", 250.0, "Fixed", "").replace("rod:", "rood:"),
        ));
        assert!(message.contains("rood"), "{message}");
    }

    #[test]
    fn too_few_segments_are_rejected_and_moulded_rods_take_clips() {
        let clips = [
            clip("a", "other", 100.0, "Fixed", ""),
            clip("b", "other", 200.0, "Fixed", ""),
        ]
        .concat();
        let Err(e) = build(&case(&clips), Some(2)) else {
            panic!("expected an error")
        };
        let message = e.to_string();
        assert!(
            message.contains("rods[1] 'other'.segments") && message.contains("at least 3 segments"),
            "{message}"
        );
        assert!(build(&case(&clips), Some(3)).is_ok());
        let moulded = case(&clip("a", "hose", 250.0, "Fixed", "")).replace(
            "length: 1000, segments: 20,",
            "segments: 20, nominal: (points: [(0, 0, 0), (1000, 0, 0)]),",
        );
        let built = build(&moulded, None).unwrap();
        let held = &built.model.system().clips[0];
        let vertex = held.vertex;
        let rod = &built.model.system().rods[held.rod.0].rod;
        // A straight nominal line: the station is the arc length along the rod.
        assert!((rod.arc_lengths()[vertex] - 0.25).abs() < 1e-12);
        // Without a base, a clip needs a moulded rod (its nominal frame)...
        let no_base = |text: &str| {
            let start = text.find("base: (").unwrap();
            let end = start + text[start..].find("), joint").unwrap() + 3;
            format!("{}{}", &text[..start], &text[end..])
        };
        let message = err(&no_base(&case(&clip("a", "hose", 250.0, "Fixed", ""))));
        assert!(
            message.contains("clips 'a'.base") && message.contains("nominal"),
            "{message}"
        );
        // ...and then takes the nominal frame at `at` (here along x, at x = 250 mm).
        let built = build(&no_base(&moulded), None).unwrap();
        let base = built.model.system().clips[0].base;
        assert!((base.position - nalgebra::Vector3::new(0.25, 0.0, 0.0)).norm() < 1e-12);
        assert!(
            (base.orientation * nalgebra::Vector3::z() - nalgebra::Vector3::x()).norm() < 1e-12
        );
    }
}
