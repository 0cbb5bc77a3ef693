//! Initial guesses: a route polyline when the case gives one, otherwise a cubic Hermite
//! curve between the held ends whose length matches the rod, or a straight rod hanging
//! from its only held end. Frames follow the curve by parallel transport from the
//! start's boundary frame.

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::RodState;
use strand_rod::so3::frame_with_tangent;

use crate::system::{Pose, System, SystemState};

/// The initial configuration of every rod.
pub fn initial_state(system: &System) -> SystemState {
    let poses = system.body_poses();
    SystemState {
        rods: (0..system.rods.len())
            .map(|r| initial_rod_state(system, r, &poses))
            .collect(),
        bodies: poses,
        clips: vec![Default::default(); system.clips.len()],
    }
}

/// Where a held end is (m) and its boundary frame, at the bodies' initial poses.
struct Placement {
    position: Option<Vector3<f64>>,
    frame: Option<UnitQuaternion<f64>>,
}

impl Placement {
    fn position(&self) -> Option<Vector3<f64>> {
        self.position
    }

    fn frame(&self) -> Option<UnitQuaternion<f64>> {
        self.frame
    }
}

fn initial_rod_state(system: &System, rod: usize, poses: &[Pose]) -> RodState {
    let spec = &system.rods[rod];
    let length = spec.rod.length();
    let place = |end, at_end| {
        let (position, frame) = system.end_placement(end, at_end, poses);
        Placement { position, frame }
    };
    let (start, end) = (place(&spec.start, false), place(&spec.end, true));
    let polyline: Vec<Vector3<f64>> = match spec.route.as_ref().filter(|r| r.len() >= 2) {
        Some(route) => route.clone(),
        None => guide_curve(&held_stations(system, rod, &start, &end), length),
    };
    let positions = resample(&polyline, &spec.rod.arc_lengths(), length);
    let first_frame = start.frame().unwrap_or_else(|| {
        let t = positions[1] - positions[0];
        frame_with_tangent(&t, &UnitQuaternion::identity())
    });
    let mut frames = Vec::with_capacity(spec.rod.segments());
    let mut frame = first_frame;
    for e in 0..spec.rod.segments() {
        let t = positions[e + 1] - positions[e];
        if t.norm() > 0.0 {
            frame = frame_with_tangent(&t, &frame);
        }
        frames.push(frame);
    }
    if let Some(end_frame) = end.frame() {
        distribute_twist(&mut frames, &end_frame, &spec.rod.arc_lengths());
    }
    RodState::new(positions, frames)
}

/// A point the rod must pass: arc length (m), position (m), tangent if known.
struct Station {
    s: f64,
    position: Vector3<f64>,
    tangent: Option<Vector3<f64>>,
}

/// The held ends and clips of a rod at their initial placement, in arc-length order.
fn held_stations(
    system: &System,
    rod_index: usize,
    start: &Placement,
    end: &Placement,
) -> Vec<Station> {
    let spec = &system.rods[rod_index];
    let tangent_of = |frame: Option<UnitQuaternion<f64>>| frame.map(|q| q * Vector3::z());
    let arc = spec.rod.arc_lengths();
    let mut stations = Vec::new();
    if let Some(position) = start.position() {
        stations.push(Station {
            s: 0.0,
            position,
            tangent: tangent_of(start.frame()),
        });
    }
    let mut clips: Vec<usize> = (0..system.clips.len())
        .filter(|&c| system.clips[c].rod.0 == rod_index)
        .collect();
    clips.sort_by_key(|&c| system.clips[c].vertex);
    let joints = vec![Default::default(); system.clips.len()];
    for c in clips {
        let clip = &system.clips[c];
        let output = system.clip_output(c, &joints, &system.body_poses());
        stations.push(Station {
            s: arc[clip.vertex],
            position: output.position,
            tangent: Some(output.orientation * Vector3::z()),
        });
    }
    if let Some(position) = end.position() {
        stations.push(Station {
            s: spec.rod.length(),
            position,
            tangent: tangent_of(end.frame()),
        });
    }
    stations
}

/// A polyline through the stations whose pieces have the reference lengths between
/// them: cubic Hermite pieces between stations, straight pieces beyond the first and
/// last station along their tangents.
fn guide_curve(stations: &[Station], length: f64) -> Vec<Vector3<f64>> {
    let Some(first) = stations.first() else {
        return vec![Vector3::zeros(), Vector3::x() * length];
    };
    let last = stations.last().expect("non-empty");
    let chord_direction = |a: &Station, b: &Station| {
        let chord = b.position - a.position;
        if chord.norm() > 0.0 {
            chord.normalize()
        } else {
            Vector3::x()
        }
    };
    let mut polyline = Vec::new();
    let lead = first.tangent.unwrap_or_else(|| {
        if stations.len() > 1 {
            chord_direction(first, &stations[1])
        } else {
            Vector3::x()
        }
    });
    if first.s > 0.0 {
        polyline.push(first.position - lead * first.s);
    }
    polyline.push(first.position);
    for pair in stations.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        let direction = chord_direction(a, b);
        let piece = hermite_with_length(
            a.position,
            a.tangent.unwrap_or(direction),
            b.position,
            b.tangent.unwrap_or(direction),
            b.s - a.s,
        );
        polyline.extend_from_slice(&piece[1..]);
    }
    if last.s < length {
        let trail = last.tangent.unwrap_or_else(|| {
            if stations.len() > 1 {
                chord_direction(&stations[stations.len() - 2], last)
            } else {
                lead
            }
        });
        polyline.push(last.position + trail * (length - last.s));
    }
    polyline
}

/// Points at the fractions `s / length` of the polyline's arc length.
fn resample(polyline: &[Vector3<f64>], arc_lengths: &[f64], length: f64) -> Vec<Vector3<f64>> {
    let mut cumulative = vec![0.0];
    for w in polyline.windows(2) {
        cumulative.push(cumulative.last().unwrap() + (w[1] - w[0]).norm());
    }
    let total = *cumulative.last().unwrap();
    let mut segment = 0;
    arc_lengths
        .iter()
        .map(|s| {
            let target = total * s / length;
            while segment + 2 < cumulative.len() && cumulative[segment + 1] < target {
                segment += 1;
            }
            let span = cumulative[segment + 1] - cumulative[segment];
            let t = if span > 0.0 {
                ((target - cumulative[segment]) / span).clamp(0.0, 1.0)
            } else {
                0.0
            };
            polyline[segment] + (polyline[segment + 1] - polyline[segment]) * t
        })
        .collect()
}

/// A cubic Hermite curve from `a` (tangent `t0`) to `b` (tangent `t1`, both scaled by
/// the chord length) plus a bow `β sin²(πt) n` (`n` ⟂ chord, sagging towards −z where
/// possible), sampled densely, with `β ≥ 0` chosen by bisection so that the curve's
/// length is `length`.
fn hermite_with_length(
    a: Vector3<f64>,
    t0: Vector3<f64>,
    b: Vector3<f64>,
    t1: Vector3<f64>,
    length: f64,
) -> Vec<Vector3<f64>> {
    const SAMPLES: usize = 400;
    let chord = b - a;
    let scale = chord.norm().max(1e-3 * length);
    let axis = if chord.norm() > 0.0 {
        chord.normalize()
    } else {
        Vector3::x()
    };
    let mut normal = -Vector3::z() + axis * axis.z;
    if normal.norm() < 1e-6 {
        normal = axis.cross(&Vector3::x());
        if normal.norm() < 1e-6 {
            normal = axis.cross(&Vector3::y());
        }
    }
    let normal = normal.normalize();
    let curve = |bow: f64| -> Vec<Vector3<f64>> {
        (0..=SAMPLES)
            .map(|i| {
                let t = i as f64 / SAMPLES as f64;
                let (t2, t3) = (t * t, t * t * t);
                a * (2.0 * t3 - 3.0 * t2 + 1.0)
                    + t0 * scale * (t3 - 2.0 * t2 + t)
                    + b * (-2.0 * t3 + 3.0 * t2)
                    + t1 * scale * (t3 - t2)
                    + normal * bow * (std::f64::consts::PI * t).sin().powi(2)
            })
            .collect()
    };
    let curve_length =
        |points: &[Vector3<f64>]| points.windows(2).map(|w| (w[1] - w[0]).norm()).sum::<f64>();
    if curve_length(&curve(0.0)) >= length {
        return curve(0.0);
    }
    let (mut lo, mut hi) = (0.0, length);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if curve_length(&curve(mid)) < length {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    curve(0.5 * (lo + hi))
}

/// Spreads the twist between the transported last frame and a clamped end frame
/// linearly along the rod, so that neither end starts with a concentrated twist (for a
/// route on a helix this recovers the Frenet-type frames exactly).
fn distribute_twist(
    frames: &mut [UnitQuaternion<f64>],
    end_frame: &UnitQuaternion<f64>,
    arc_lengths: &[f64],
) {
    let last = *frames.last().expect("at least one edge");
    // Twist angle about the last edge's a3 that best aligns its a1 with the end frame's.
    let target_a1 = last.inverse() * (end_frame * Vector3::x());
    let twist = target_a1.y.atan2(target_a1.x);
    let length = *arc_lengths.last().expect("vertices");
    let n = frames.len();
    for (e, frame) in frames.iter_mut().enumerate() {
        // The last edge receives the whole twist; the end vertex's half cell starts untwisted.
        let share = if e + 1 == n {
            1.0
        } else {
            0.5 * (arc_lengths[e] + arc_lengths[e + 1]) / length
        };
        *frame *= UnitQuaternion::from_axis_angle(&Vector3::z_axis(), twist * share);
    }
}
