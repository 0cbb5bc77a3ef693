//! Initial guesses: a route polyline when the case gives one, otherwise a curve through
//! the held ends and clips whose length matches the rod, shaped by the rod's weight:
//!
//! - between two held points, a catenary through both with the rod's length (in the
//!   vertical plane of the chord) when the weight dominates the bending stiffness or no
//!   end is clamped; otherwise (no gravity, a vertical or taut chord, a stiff hose
//!   between clamps) a cubic Hermite curve leaving along the clamp directions;
//! - beyond the last (before the first) held point, a free tail that turns from the
//!   clamp direction towards gravity over a bending length and hangs.
//!
//! Clamped ends start along their clamp direction (the catenary is blended into it over
//! the first and last few percent). Frames follow the curve by parallel transport from
//! the start's boundary frame; the twist to the end's boundary frame, including whole
//! extra turns ([`crate::End::twist_turns`]), is spread linearly along the rod.

use std::f64::consts::{FRAC_PI_2, TAU};

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::RodState;
use strand_rod::so3::frame_with_tangent;

use crate::route::{RouteShape, smooth_route};
use crate::system::{Pose, System, SystemState};

/// Ratio `w L³ / EI` (weight per length `w` in N/m, length `L` in m, bending stiffness
/// `EI` in N·m²) above which the weight rather than the bending stiffness shapes a rod
/// between two clamps: the guess is then a catenary blended into the clamp directions,
/// below it a Hermite curve along them.
pub const SAG_RATIO: f64 = 100.0;

/// Points per piece of a guide curve.
const SAMPLES: usize = 400;

/// The initial configuration of every rod, routes smoothed ([`RouteShape::Smoothed`]).
pub fn initial_state(system: &System) -> SystemState {
    initial_state_with(system, RouteShape::Smoothed)
}

/// The initial configuration of every rod, with the routes shaped as `routes` says.
pub fn initial_state_with(system: &System, routes: RouteShape) -> SystemState {
    let poses = system.body_poses();
    SystemState {
        rods: (0..system.rods.len())
            .map(|r| initial_rod_state(system, r, &poses, routes))
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

/// What shapes the guess of one rod besides its supports.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Loading {
    /// Gravitational acceleration in m/s².
    pub gravity: Vector3<f64>,
    /// Weight per length `ρ_L |g|` in N/m.
    pub weight: f64,
    /// Smaller bending stiffness `EI` in N·m².
    pub bending: f64,
}

impl Loading {
    /// The unit direction of gravity, if the rod has weight.
    fn down(&self) -> Option<Vector3<f64>> {
        let g = self.gravity.norm();
        (g > 0.0 && self.weight > 0.0 && g.is_finite() && self.weight.is_finite())
            .then(|| self.gravity / g)
    }

    /// `w ℓ³ / EI` for a piece of length `ℓ` (m): large for a limp cable.
    fn sag_ratio(&self, length: f64) -> f64 {
        self.weight * length.powi(3) / self.bending.max(f64::MIN_POSITIVE)
    }
}

fn initial_rod_state(system: &System, rod: usize, poses: &[Pose], routes: RouteShape) -> RodState {
    let spec = &system.rods[rod];
    let length = spec.rod.length();
    let (start, end) = placements(system, rod, poses);
    let arc = spec.rod.arc_lengths();
    let section = spec.rod.section();
    let stiffness = section.curvature_stiffness();
    let loading = Loading {
        gravity: system.gravity,
        weight: section.mass_per_length * system.gravity.norm(),
        bending: stiffness.x.min(stiffness.y),
    };
    let polyline: Vec<Vector3<f64>> = match spec.route.as_ref().filter(|r| r.len() >= 2) {
        Some(route) => match routes {
            RouteShape::Smoothed => smooth_route(
                route,
                start.frame().map(|q| q * Vector3::z()),
                end.frame().map(|q| q * Vector3::z()),
                length,
            ),
            RouteShape::AsDrawn => route.clone(),
        },
        None => guide_curve(
            &held_stations(system, rod, &start, &end, &arc, poses),
            length,
            &loading,
        ),
    };
    let positions = resample(&polyline, &arc, length);
    framed(system, rod, &start, &end, positions)
}

/// Rod `rod` at `positions` (m, one per vertex) with frames carried along by parallel
/// transport from the start's boundary frame (from the first edge at an unclamped
/// start) and the twist to the end's boundary frame spread linearly along the rod.
fn framed(
    system: &System,
    rod: usize,
    start: &Placement,
    end: &Placement,
    positions: Vec<Vector3<f64>>,
) -> RodState {
    let spec = &system.rods[rod];
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
        let turns = i64::from(spec.end.twist_turns) - i64::from(spec.start.twist_turns);
        distribute_twist(&mut frames, &end_frame, &spec.rod.arc_lengths(), turns);
    }
    RodState::new(positions, frames)
}

/// The held ends and clips of rod `rod` at the bodies' `poses` (clips' joints at
/// rest), in arc-length order: the points its guesses pass.
pub fn rod_stations(system: &System, rod: usize, poses: &[Pose]) -> Vec<Station> {
    let spec = &system.rods[rod];
    let (start, end) = placements(system, rod, poses);
    held_stations(system, rod, &start, &end, &spec.rod.arc_lengths(), poses)
}

/// Rod `rod` laid along `pieces`, one polyline (m) per stretch between consecutive
/// knots: its two ends and its stations ([`rod_stations`]: held ends and clips), in
/// arc-length order. The vertices of a stretch spread over its piece in proportion
/// to their arc length (a piece shorter than the rod between its knots compresses
/// it), frames as the initial guess carries them. `None` unless there is one piece of
/// at least two points per stretch.
pub fn rod_state_along(
    system: &System,
    rod: usize,
    poses: &[Pose],
    pieces: &[Vec<Vector3<f64>>],
) -> Option<RodState> {
    let spec = &system.rods[rod];
    let (start, end) = placements(system, rod, poses);
    let arc = spec.rod.arc_lengths();
    let stations = held_stations(system, rod, &start, &end, &arc, poses);
    let mut knots = vec![0];
    knots.extend(stations.iter().map(|s| s.vertex));
    knots.push(arc.len() - 1);
    knots.dedup();
    if pieces.len() + 1 != knots.len() || pieces.iter().any(|p| p.len() < 2) {
        return None;
    }
    let mut positions = Vec::with_capacity(arc.len());
    positions.push(pieces[0][0]);
    for (piece, pair) in pieces.iter().zip(knots.windows(2)) {
        let (from, to) = (pair[0], pair[1]);
        let local: Vec<f64> = arc[from..=to].iter().map(|s| s - arc[from]).collect();
        let laid = resample(piece, &local, arc[to] - arc[from]);
        positions.extend_from_slice(&laid[1..]);
    }
    (positions.len() == arc.len()).then(|| framed(system, rod, &start, &end, positions))
}

/// Where rod `rod`'s ends are held at the bodies' `poses`.
fn placements(system: &System, rod: usize, poses: &[Pose]) -> (Placement, Placement) {
    let spec = &system.rods[rod];
    let place = |end, at_end| {
        let (position, frame) = system.end_placement(end, at_end, poses);
        Placement { position, frame }
    };
    (place(&spec.start, false), place(&spec.end, true))
}

/// A point a rod must pass: a held end or a clip.
#[derive(Clone, Debug, PartialEq)]
pub struct Station {
    /// Arc length (m) from the rod's start.
    pub s: f64,
    /// The vertex held there.
    pub vertex: usize,
    /// Where it is held (m).
    pub position: Vector3<f64>,
    /// The rod's unit tangent there where the support fixes it (a clamp, a clip).
    pub tangent: Option<Vector3<f64>>,
}

/// The held ends and clips of a rod at their initial placement, in arc-length order.
fn held_stations(
    system: &System,
    rod_index: usize,
    start: &Placement,
    end: &Placement,
    arc: &[f64],
    poses: &[Pose],
) -> Vec<Station> {
    let tangent_of = |frame: Option<UnitQuaternion<f64>>| frame.map(|q| q * Vector3::z());
    let mut stations = Vec::new();
    if let Some(position) = start.position() {
        stations.push(Station {
            s: 0.0,
            vertex: 0,
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
        let output = system.clip_output(c, &joints, poses);
        stations.push(Station {
            s: arc[clip.vertex],
            vertex: clip.vertex,
            position: output.position,
            tangent: Some(output.orientation * Vector3::z()),
        });
    }
    if let Some(position) = end.position() {
        stations.push(Station {
            s: *arc.last().expect("vertices"),
            vertex: arc.len() - 1,
            position,
            tangent: tangent_of(end.frame()),
        });
    }
    stations
}

/// A polyline through the stations whose pieces have the reference lengths between
/// them: a catenary or cubic Hermite piece between consecutive stations
/// ([`sagging_piece`], [`hermite_with_length`]), hanging tails beyond the first and last
/// station ([`hanging_tail`]).
pub(crate) fn guide_curve(
    stations: &[Station],
    length: f64,
    loading: &Loading,
) -> Vec<Vector3<f64>> {
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
    if first.s > 0.0 {
        // The tail before the first station, built outwards from it and reversed.
        let outwards = match first.tangent {
            Some(t) => -t,
            None => loading.down().unwrap_or_else(|| {
                if stations.len() > 1 {
                    -chord_direction(first, &stations[1])
                } else {
                    -Vector3::x()
                }
            }),
        };
        let tail = hanging_tail(first.position, outwards, first.s, loading);
        polyline.extend(tail.iter().rev());
    } else {
        polyline.push(first.position);
    }
    for pair in stations.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        let piece = sagging_piece(a, b, b.s - a.s, loading).unwrap_or_else(|| {
            let direction = chord_direction(a, b);
            hermite_with_length(
                a.position,
                a.tangent.unwrap_or(direction),
                b.position,
                b.tangent.unwrap_or(direction),
                b.s - a.s,
                gravity_direction(loading.gravity),
            )
        });
        polyline.extend_from_slice(&piece[1..]);
    }
    if last.s < length {
        let outwards = match last.tangent {
            Some(t) => t,
            None => loading.down().unwrap_or_else(|| {
                if stations.len() > 1 {
                    chord_direction(&stations[stations.len() - 2], last)
                } else {
                    Vector3::x()
                }
            }),
        };
        let tail = hanging_tail(last.position, outwards, length - last.s, loading);
        polyline.extend_from_slice(&tail[1..]);
    }
    polyline
}

/// The direction a piece without a catenary bows to make up its length: along gravity
/// (also for a weightless rod; −z without gravity).
fn gravity_direction(gravity: Vector3<f64>) -> Vector3<f64> {
    let g = gravity.norm();
    if g > 0.0 && g.is_finite() {
        gravity / g
    } else {
        -Vector3::z()
    }
}

/// A free tail of `length` m leaving `origin` along the unit `direction` and hanging
/// under its weight: its tangent turns from `direction` towards gravity in their plane,
/// by the angle `ψ(s) = min(ψ_lin(s), θ (1 − e^{−s/ℓ}))` with `θ` the angle between
/// `direction` and gravity. `ψ_lin = w_⊥ (L³ − (L − s)³) / (6 EI)` is the slope of a
/// linear cantilever under its transverse weight (a stiff tail barely bends),
/// `ℓ = √(EI / (w L))` the bending length of a tail hanging under its own weight (a limp
/// tail turns within it and hangs straight down). Straight without weight.
pub(crate) fn hanging_tail(
    origin: Vector3<f64>,
    direction: Vector3<f64>,
    length: f64,
    loading: &Loading,
) -> Vec<Vector3<f64>> {
    const STEPS: usize = 2000;
    let straight = vec![origin, origin + direction * length];
    let Some(down) = loading.down() else {
        return straight;
    };
    if length <= 0.0 {
        return straight;
    }
    let cos = direction.dot(&down).clamp(-1.0, 1.0);
    let theta = cos.acos();
    let mut normal = down - direction * cos;
    if normal.norm() < 1e-9 {
        if cos > 0.0 {
            return straight; // already hanging
        }
        // Pointing straight up: fall over to any side.
        normal = direction.cross(&Vector3::x());
        if normal.norm() < 1e-6 {
            normal = direction.cross(&Vector3::y());
        }
    }
    let normal = normal.normalize();
    let w = loading.weight;
    let transverse = if theta <= FRAC_PI_2 {
        w * theta.sin()
    } else {
        w
    };
    let ei = loading.bending.max(f64::MIN_POSITIVE);
    let layer = (ei / (w * length)).sqrt();
    let slope = |s: f64| {
        let linear = transverse / (6.0 * ei) * (length.powi(3) - (length - s).powi(3));
        let layered = theta * (1.0 - (-s / layer).exp());
        linear.min(layered).min(theta)
    };
    let ds = length / STEPS as f64;
    let mut point = origin;
    let mut points = Vec::with_capacity(STEPS + 1);
    points.push(origin);
    for k in 0..STEPS {
        let psi = slope((k as f64 + 0.5) * ds);
        point += (direction * psi.cos() + normal * psi.sin()) * ds;
        points.push(point);
    }
    points
}

/// A catenary from station `a` to station `b` of arc length `length` (m), sampled,
/// blended into the stations' tangents over the first and last few percent: `None`
/// (use the Hermite curve) without weight, for a vertical or taut chord, or when a
/// clamped station meets a rod stiff enough for its bending to shape it
/// ([`SAG_RATIO`]).
pub(crate) fn sagging_piece(
    a: &Station,
    b: &Station,
    length: f64,
    loading: &Loading,
) -> Option<Vec<Vector3<f64>>> {
    let down = loading.down()?;
    let clamped = a.tangent.is_some() || b.tangent.is_some();
    if clamped && loading.sag_ratio(length) < SAG_RATIO {
        return None;
    }
    let chord = (b.position - a.position).norm();
    let curve = |catenary_length: f64| -> Option<Vec<Vector3<f64>>> {
        let catenary = Catenary::through(a.position, b.position, down, catenary_length)?;
        Some(blended_samples(&catenary, a.tangent, b.tangent, loading))
    };
    let plain = curve(length)?;
    if !clamped {
        return Some(plain);
    }
    // The blend changes the length a little: find the catenary length that gives the
    // piece its length (monotone in practice; fall back if the bracket fails).
    let excess = |l: f64| curve(l).map(|p| polyline_length(&p) - length);
    let mut lo = chord + 1e-9 * length;
    let mut hi = length;
    if excess(lo)? > 0.0 {
        return None;
    }
    let mut grown = 0;
    while excess(hi)? < 0.0 {
        hi *= 1.1;
        grown += 1;
        if grown > 20 {
            return None;
        }
    }
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if excess(mid)? < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    curve(0.5 * (lo + hi))
}

/// [`SAMPLES`] points of `catenary` at equal arc length, with the tangent at a clamped
/// end turned to `t0` (start) or `t1` (end): `p(u) = c(u) + Δ₀ H(u) − Δ₁ H(1 − u)` with
/// `H(u) = u (1 − u/δ)²` on `[0, δ]` (zero beyond; `H(0) = 0`, `H'(0) = 1`) and
/// `Δ = ℓ (t − t_c)`, over a fraction `δ` of about two bending lengths (3 %…25 %).
fn blended_samples(
    catenary: &Catenary,
    t0: Option<Vector3<f64>>,
    t1: Option<Vector3<f64>>,
    loading: &Loading,
) -> Vec<Vector3<f64>> {
    let l = catenary.length;
    let layer = (loading.bending / (loading.weight * l)).sqrt() / l;
    let delta = (2.0 * layer).clamp(0.03, 0.25);
    let bump = |u: f64| {
        if u < delta {
            u * (1.0 - u / delta).powi(2)
        } else {
            0.0
        }
    };
    let unit = |t: Vector3<f64>| t.normalize();
    let d0 = t0.map(|t| l * (unit(t) - catenary.tangent(0.0)));
    let d1 = t1.map(|t| l * (unit(t) - catenary.tangent(l)));
    (0..=SAMPLES)
        .map(|i| {
            let u = i as f64 / SAMPLES as f64;
            let mut p = catenary.point(u * l);
            if let Some(d) = d0 {
                p += d * bump(u);
            }
            if let Some(d) = d1 {
                p -= d * bump(1.0 - u);
            }
            p
        })
        .collect()
}

/// Sum of the segment lengths of a polyline, m.
pub(crate) fn polyline_length(points: &[Vector3<f64>]) -> f64 {
    points.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

/// A catenary `y = a (cosh((x − x₀)/a) − cosh(x₀/a))` in the vertical plane through
/// its start and end (`x` horizontal from the start, `y` up against gravity), of a
/// given arc length.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Catenary {
    start: Vector3<f64>,
    across: Vector3<f64>,
    up: Vector3<f64>,
    /// Catenary parameter `a = H / w` in m.
    a: f64,
    /// Horizontal position of the lowest point (vertex) in m (may lie outside).
    x0: f64,
    /// Arc length in m.
    pub length: f64,
}

impl Catenary {
    /// The catenary from `a` to `b` (m) of arc length `length` (m) hanging towards the
    /// unit `down`: `None` if the chord is vertical (horizontal span below 1e-6 of the
    /// length) or not shorter than `length`.
    pub(crate) fn through(
        a: Vector3<f64>,
        b: Vector3<f64>,
        down: Vector3<f64>,
        length: f64,
    ) -> Option<Self> {
        let chord = b - a;
        let rise = -chord.dot(&down);
        let horizontal = chord + down * rise;
        let span = horizontal.norm();
        if !(length.is_finite() && chord.norm() < length && span > 1e-6 * length) {
            return None;
        }
        // sinh(z)/z = √(ℓ² − v²)/H with z = H/(2a): bisection (monotone in z > 0).
        let ratio = (length * length - rise * rise).sqrt() / span;
        let f = |z: f64| {
            if z < 1e-4 {
                1.0 + z * z / 6.0 * (1.0 + z * z / 20.0)
            } else {
                z.sinh() / z
            }
        };
        let mut hi = 1.0;
        while f(hi) < ratio {
            hi *= 2.0;
            if hi > 700.0 {
                return None;
            }
        }
        let mut lo = 0.0;
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if f(mid) < ratio {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo <= f64::EPSILON * hi {
                break;
            }
        }
        let z = 0.5 * (lo + hi);
        if z <= 0.0 {
            return None;
        }
        let param = span / (2.0 * z);
        let x0 = 0.5 * span - param * (rise / length).atanh();
        Some(Self {
            start: a,
            across: horizontal / span,
            up: -down,
            a: param,
            x0,
            length,
        })
    }

    /// `sinh((x − x₀)/a)` at arc length `s` (m) from the start: the slope `dy/dx`.
    fn slope(&self, s: f64) -> f64 {
        s / self.a - (self.x0 / self.a).sinh()
    }

    /// The point at arc length `s` (m) from the start.
    pub(crate) fn point(&self, s: f64) -> Vector3<f64> {
        let x = self.x0 + self.a * self.slope(s).asinh();
        // cosh A − cosh B = 2 sinh((A+B)/2) sinh((A−B)/2), without cancellation.
        let y = 2.0
            * self.a
            * ((x - 2.0 * self.x0) / (2.0 * self.a)).sinh()
            * (x / (2.0 * self.a)).sinh();
        self.start + self.across * x + self.up * y
    }

    /// The unit tangent at arc length `s` (m).
    pub(crate) fn tangent(&self, s: f64) -> Vector3<f64> {
        let slope = self.slope(s);
        (self.across + self.up * slope) / (1.0 + slope * slope).sqrt()
    }
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
/// the chord length) plus a bow `β sin²(πt) n` (`n` ⟂ chord, sagging towards the unit
/// `down` where possible), sampled densely, with `β ≥ 0` chosen by bisection so that the curve's
/// length is `length`.
fn hermite_with_length(
    a: Vector3<f64>,
    t0: Vector3<f64>,
    b: Vector3<f64>,
    t1: Vector3<f64>,
    length: f64,
    down: Vector3<f64>,
) -> Vec<Vector3<f64>> {
    let chord = b - a;
    let scale = chord.norm().max(1e-3 * length);
    let axis = if chord.norm() > 0.0 {
        chord.normalize()
    } else {
        Vector3::x()
    };
    let mut normal = down - axis * axis.dot(&down);
    if normal.norm() < 1e-6 {
        normal = axis.cross(&Vector3::x());
        if normal.norm() < 1e-6 {
            normal = axis.cross(&Vector3::y());
        }
    }
    let normal = normal.normalize();
    // The bow-free curve and the bow's shape sin²(πt), sampled once: each bisection
    // step then costs one pass of additions and norms (no sines, no allocation), with
    // the same floating-point operations in the same order as evaluating the curve
    // afresh.
    let (base, shape): (Vec<Vector3<f64>>, Vec<f64>) = (0..=SAMPLES)
        .map(|i| {
            let t = i as f64 / SAMPLES as f64;
            let (t2, t3) = (t * t, t * t * t);
            let point = a * (2.0 * t3 - 3.0 * t2 + 1.0)
                + t0 * scale * (t3 - 2.0 * t2 + t)
                + b * (-2.0 * t3 + 3.0 * t2)
                + t1 * scale * (t3 - t2);
            (point, (std::f64::consts::PI * t).sin().powi(2))
        })
        .unzip();
    let point = |bow: f64, i: usize| base[i] + normal * bow * shape[i];
    let curve = |bow: f64| -> Vec<Vector3<f64>> { (0..=SAMPLES).map(|i| point(bow, i)).collect() };
    let curve_length = |bow: f64| {
        (1..=SAMPLES)
            .map(|i| (point(bow, i) - point(bow, i - 1)).norm())
            .sum::<f64>()
    };
    if curve_length(0.0) >= length {
        return curve(0.0);
    }
    let (mut lo, mut hi) = (0.0, length);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if curve_length(mid) < length {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    curve(0.5 * (lo + hi))
}

/// Spreads the twist between the transported last frame and a clamped end frame
/// linearly along the rod, so that neither end starts with a concentrated twist (for a
/// route on a helix this recovers the Frenet-type frames exactly). The twist is the
/// shortest one, `φ₀ ∈ (−π, π]`, plus `turns` whole turns; a half turn is `+π` also
/// when round-off puts it just below `−π` ([`HALF_TURN_TIE_RAD`]), so that the same
/// input moved elsewhere (a harness 1 km from the origin) starts from the same guess.
/// How close to `−π` (rad) a shortest twist counts as a half turn `+π`: the twist of an
/// end frame turned by exactly half a turn is `±π` by the round-off of its inputs.
pub(crate) const HALF_TURN_TIE_RAD: f64 = 1e-9;

fn distribute_twist(
    frames: &mut [UnitQuaternion<f64>],
    end_frame: &UnitQuaternion<f64>,
    arc_lengths: &[f64],
    turns: i64,
) {
    let last = *frames.last().expect("at least one edge");
    // Twist angle about the last edge's a3 that best aligns its a1 with the end frame's.
    let target_a1 = last.inverse() * (end_frame * Vector3::x());
    let mut shortest = target_a1.y.atan2(target_a1.x);
    if shortest < -std::f64::consts::PI + HALF_TURN_TIE_RAD {
        shortest += TAU;
    }
    let twist = shortest + TAU * turns as f64;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::{End, RodSpec};
    use strand_rod::{Rod, Section};

    /// Arc length of a curve sampled densely (chord sum; the chord error of 2·10⁵
    /// samples is far below 1e-9 of the length for these curvatures).
    fn dense_length(f: impl Fn(f64) -> Vector3<f64>, length: f64) -> f64 {
        const K: usize = 200_000;
        (0..K)
            .map(|i| {
                (f((i + 1) as f64 * length / K as f64) - f(i as f64 * length / K as f64)).norm()
            })
            .sum()
    }

    fn loading(ei: f64) -> Loading {
        Loading {
            gravity: Vector3::new(0.0, 0.0, -9.81),
            weight: 0.5 * 9.81,
            bending: ei,
        }
    }

    #[test]
    fn catenary_has_the_length_and_passes_through_both_ends() {
        let down = -Vector3::z();
        for (b, length) in [
            (Vector3::new(0.8, 0.0, 0.0), 1.0),
            (Vector3::new(0.3, 0.4, 0.2), 1.0),
            (Vector3::new(0.1, 0.0, -0.5), 3.0),
            (Vector3::new(0.999, 0.0, 0.0), 1.0),
        ] {
            let a = Vector3::new(0.1, -0.2, 0.3);
            let end = a + b;
            let c = Catenary::through(a, end, down, length).unwrap();
            assert!((c.point(0.0) - a).norm() < 1e-12 * length);
            assert!(
                (c.point(length) - end).norm() < 1e-9 * length,
                "{:?}",
                c.point(length) - end
            );
            let measured = dense_length(|s| c.point(s), length);
            assert!(
                (measured / length - 1.0).abs() < 1e-9,
                "{measured} vs {length}"
            );
            // In the vertical plane of the chord.
            let normal = (b - down * b.dot(&down)).cross(&down).normalize();
            assert!((c.point(0.37 * length) - a).dot(&normal).abs() < 1e-12);
        }
        // Sag of the symmetric cable from the closed form: a cosh(H/2a) − a with
        // sinh(H/2a) = L/2a.
        let c = Catenary::through(Vector3::zeros(), Vector3::x() * 0.8, down, 1.0).unwrap();
        let z = {
            let (mut lo, mut hi) = (1e-6, 10.0);
            for _ in 0..200 {
                let mid: f64 = 0.5 * (lo + hi);
                if mid.sinh() / mid < 1.0 / 0.8 {
                    lo = mid
                } else {
                    hi = mid
                }
            }
            0.5 * (lo + hi)
        };
        let a = 0.8 / (2.0 * z);
        let sag = a * z.cosh() - a;
        assert!(
            (c.point(0.5).z + sag).abs() < 1e-12,
            "{} vs {}",
            c.point(0.5).z,
            -sag
        );
    }

    #[test]
    fn catenary_falls_back_for_vertical_or_taut_chords() {
        let down = -Vector3::z();
        assert!(Catenary::through(Vector3::zeros(), Vector3::z() * 0.5, down, 1.0).is_none());
        assert!(Catenary::through(Vector3::zeros(), Vector3::x(), down, 1.0).is_none());
        assert!(Catenary::through(Vector3::zeros(), Vector3::x() * 1.2, down, 1.0).is_none());
    }

    fn station(s: f64, position: Vector3<f64>, tangent: Option<Vector3<f64>>) -> Station {
        Station {
            s,
            vertex: 0,
            position,
            tangent,
        }
    }

    #[test]
    fn pinned_cable_guess_is_the_catenary() {
        let stations = [
            station(0.0, Vector3::zeros(), None),
            station(1.0, Vector3::x() * 0.8, None),
        ];
        let curve = guide_curve(&stations, 1.0, &loading(1e-3));
        let c =
            Catenary::through(Vector3::zeros(), Vector3::x() * 0.8, -Vector3::z(), 1.0).unwrap();
        assert_eq!(curve.len(), SAMPLES + 1);
        for (i, p) in curve.iter().enumerate() {
            assert!((p - c.point(i as f64 / SAMPLES as f64)).norm() < 1e-12);
        }
        // Without gravity: the previous Hermite bow.
        let mut weightless = loading(1e-3);
        weightless.gravity = Vector3::zeros();
        let bow = guide_curve(&stations, 1.0, &weightless);
        assert!((polyline_length(&bow) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn clamped_limp_cable_leaves_along_the_clamps_and_has_its_length() {
        let t0 = Vector3::new(1.0, 0.0, 1.0).normalize();
        let t1 = Vector3::new(1.0, 0.0, -1.0).normalize();
        let stations = [
            station(0.0, Vector3::zeros(), Some(t0)),
            station(1.0, Vector3::x() * 0.8, Some(t1)),
        ];
        let curve = guide_curve(&stations, 1.0, &loading(1e-4));
        assert!((polyline_length(&curve) / 1.0 - 1.0).abs() < 1e-9);
        assert!((curve[0] - stations[0].position).norm() < 1e-12);
        assert!((curve.last().unwrap() - stations[1].position).norm() < 1e-9);
        let first = (curve[1] - curve[0]).normalize();
        let last = (curve[SAMPLES] - curve[SAMPLES - 1]).normalize();
        assert!(first.dot(&t0) > 0.97, "{first:?}");
        assert!(last.dot(&t1) > 0.97, "{last:?}");
        // It sags: its middle is below both ends.
        assert!(curve[SAMPLES / 2].z < -0.1);
        // A stiff hose between the same clamps (w L³/EI = 0.5) keeps the Hermite curve.
        let stiff = guide_curve(&stations, 1.0, &loading(10.0));
        let hermite = hermite_with_length(
            Vector3::zeros(),
            t0,
            Vector3::x() * 0.8,
            t1,
            1.0,
            -Vector3::z(),
        );
        assert_eq!(stiff, hermite);
    }

    #[test]
    fn free_tail_hangs_from_a_horizontal_clamp() {
        let stations = [station(0.0, Vector3::zeros(), Some(Vector3::x()))];
        let limp = guide_curve(&stations, 1.0, &loading(1e-4));
        assert!((polyline_length(&limp) - 1.0).abs() < 1e-12);
        let tip = limp.last().unwrap();
        // Bending length √(EI/(wL)) = 4.5 mm: the tip hangs about a metre down.
        assert!(tip.z < -0.99 && tip.x > 0.0 && tip.x < 0.01, "{tip:?}");
        assert!((limp[1] - limp[0]).normalize().dot(&Vector3::x()) > 0.99);
        // A stiff cantilever deflects like a linear beam: tip slope w L³/(6 EI).
        let stiff = guide_curve(&stations, 1.0, &loading(100.0));
        let n = stiff.len();
        let slope = (stiff[n - 1] - stiff[n - 2]).normalize();
        let expected = 0.5 * 9.81 / (6.0 * 100.0);
        assert!(
            (slope.z.asin() + expected).abs() < 1e-6,
            "{}",
            slope.z.asin()
        );
    }

    #[test]
    fn whole_turns_of_twist_are_spread_along_the_rod() {
        let section = Section::try_explicit(1e4, 1e4, 1.0, 1.0, 0.0, 0.0).unwrap();
        let along_x = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), FRAC_PI_2);
        let twisted =
            along_x * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 190f64.to_radians());
        for (turns, expected) in [(0, -170.0), (1, 190.0), (-1, -530.0)] {
            let system = System {
                rods: vec![RodSpec {
                    name: "rod".into(),
                    rod: Rod::try_straight(section, 1.0, 40).unwrap(),
                    start: End::clamped(Vector3::zeros(), along_x),
                    end: End::clamped(Vector3::x(), twisted).with_twist_turns(turns),
                    route: None,
                }],
                bodies: vec![],
                clips: vec![],
                gravity: Vector3::zeros(),
            };
            let state = initial_state(&system);
            let frames = &state.rods[0].frames;
            // Sum of the twist increments from the clamp through every edge to the end.
            let mut total = 0.0;
            let mut previous = along_x;
            for q in frames.iter().chain(std::iter::once(&twisted)) {
                let relative = strand_rod::so3::log(&(previous.inverse() * q));
                total += relative.z;
                previous = *q;
            }
            assert!(
                (total.to_degrees() - expected).abs() < 1e-9,
                "{turns}: {}",
                total.to_degrees()
            );
        }
    }

    #[test]
    fn a_half_turn_of_twist_starts_the_same_whatever_its_round_off() {
        // An end frame turned by half a turn about the rod, give or take round-off
        // (1e-13 rad either way, as the same input 1 km from the origin), starts with
        // +π spread along the rod, not +π once and −π the other time.
        let section = Section::try_explicit(1e4, 1e4, 1.0, 1.0, 0.0, 0.0).unwrap();
        let along_x = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), FRAC_PI_2);
        let twist_of = |angle: f64| {
            let end = along_x * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), angle);
            let system = System {
                rods: vec![RodSpec {
                    name: "rod".into(),
                    rod: Rod::try_straight(section, 1.0, 10).unwrap(),
                    start: End::clamped(Vector3::zeros(), along_x),
                    end: End::clamped(Vector3::x(), end),
                    route: None,
                }],
                bodies: vec![],
                clips: vec![],
                gravity: Vector3::zeros(),
            };
            let state = initial_state(&system);
            // The twist of the middle edge relative to the clamp.
            strand_rod::so3::log(&(along_x.inverse() * state.rods[0].frames[5])).z
        };
        let (below, above) = (
            twist_of(std::f64::consts::PI - 1e-13),
            twist_of(-std::f64::consts::PI + 1e-13),
        );
        assert!((below - above).abs() < 1e-9, "{below} vs {above}");
        assert!(below > 0.0, "{below}");
        // Farther from the tie than round-off, the shortest twist is still chosen.
        assert!(twist_of(-std::f64::consts::PI + 1e-6) < 0.0);
    }
}
