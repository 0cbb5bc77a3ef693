//! Pre-deformed (moulded) rods: the stress-free reference taken from a nominal
//! centreline, e.g. the CAD centreline of a moulded hose (paper §4, "pre-deformation":
//! reference strains "extracted from a desired nominal shape").
//!
//! 1. **Curve.** The nominal points are joined by a smooth (G1) cubic Hermite spline.
//!    Its tangent directions come from circles through three consecutive points
//!    (exact on circular arcs and straight lines, and at the junction of a straight
//!    run and a bend; see `estimated_directions`), or from the `a3` of `frames` when
//!    given; each piece's handle is the classic cubic approximation of the circular
//!    arc between its end tangents. A CAD centreline of straight runs and circular
//!    bends is thus reproduced closely (a 90° bend given every 15°, legs by their end
//!    points only: within 1e-7 m for a 300 mm hose), and a few points through a bend
//!    give a smooth bend. Two points give a straight rod.
//! 2. **Vertices.** The curve is cut into `N` pieces of equal arc length (arc length by
//!    Gauss–Legendre quadrature, inverted by bisection, both to round-off); the end
//!    vertices are the first and last points exactly.
//! 3. **Frames.** Without `frames` the edge frames are parallel-transported along the
//!    edges (least rotation from edge to edge) from the start frame, whose `a3` is the
//!    curve's tangent and which is the least rotation of the world frame onto it; the
//!    nominal shape then carries no twist (`K0₃ = 0`). With `frames` (one per point),
//!    they are interpolated (slerp in arc length) to the edge midpoints and turned by
//!    the least rotation that aligns `a3` with the edge. The nominal end frames are the
//!    first/last given frames, or the transported frame turned onto the curve's tangent.
//! 4. **Reference.** The discrete configuration so obtained *is* the stress-free shape:
//!    `h = |r_{j+1} − r_j|`, `Γ0 = Rᵀ(r_{j+1} − r_j)/h` (`= e3` up to round-off),
//!    `K0_j = 2 log(q*_{j−1/2} q_{j+1/2})/h̄_j` inside and, with the nominal end frames
//!    as boundary frames, `K0_0`, `K0_N` at the ends — computed with the very functions
//!    the energy uses. A rod mounted at its nominal end frames without loads is
//!    therefore in equilibrium at the nominal shape with zero sectional forces and
//!    moments (to round-off); a free or pinned end simply ignores its `K0`.

use nalgebra::{UnitQuaternion, Vector3};

use crate::element::{BendTwist, StretchShear};
use crate::sectional::{BoundaryFrames, vertex_frames};
use crate::so3::{exp, frame_with_tangent, relative_rotation_vector};
use crate::{Rod, RodError, RodState, Section};

/// A nominal (stress-free) centreline, e.g. exported from CAD.
#[derive(Clone, Debug, PartialEq)]
pub struct NominalShape {
    /// Points along the centreline in m, from the rod's start to its end (at least 2,
    /// consecutive points distinct).
    pub points: Vec<Vector3<f64>>,
    /// Optional material frames at the points (one per point; `a3` along the
    /// centreline, pointing from the start towards the end). They set the tangent
    /// directions of the curve and the twist of the section; without them the frames
    /// are parallel-transported (no twist).
    pub frames: Option<Vec<UnitQuaternion<f64>>>,
}

impl NominalShape {
    /// A centreline through `points` (m) without frames.
    pub fn from_points(points: Vec<Vector3<f64>>) -> Self {
        Self {
            points,
            frames: None,
        }
    }

    /// The point of the smooth curve through the points nearest to `point` (m): its arc
    /// length from the start (m) and its distance from `point` (m). Found by sampling
    /// every sub-interval of the curve and refining the best sample by golden-section
    /// search on its neighbourhood (to ~1e-12 of the curve's length).
    pub fn project(&self, point: &Vector3<f64>) -> Result<(f64, f64), NominalError> {
        let spline = Spline::try_new(self)?;
        const SAMPLES: usize = 8;
        let intervals = spline.table.len() - 1;
        let parameter = |k: usize, t: f64| {
            let (segment, sub) = (k / SUBINTERVALS, k % SUBINTERVALS);
            (segment, (sub as f64 + t) / SUBINTERVALS as f64)
        };
        let distance = |k: usize, t: f64| {
            let (segment, u) = parameter(k, t);
            (spline.point(segment, u) - point).norm()
        };
        let mut best = (0, 0.0, f64::INFINITY);
        for k in 0..intervals {
            for j in 0..=SAMPLES {
                let t = j as f64 / SAMPLES as f64;
                let d = distance(k, t);
                if d < best.2 {
                    best = (k, t, d);
                }
            }
        }
        // Golden-section search on the best sample's interval and its neighbours.
        let golden = |k: usize| {
            let (mut lo, mut hi) = (0.0, 1.0);
            let g = 0.5 * (5f64.sqrt() - 1.0);
            for _ in 0..80 {
                let (a, b) = (hi - g * (hi - lo), lo + g * (hi - lo));
                if distance(k, a) < distance(k, b) {
                    hi = b;
                } else {
                    lo = a;
                }
            }
            let t = 0.5 * (lo + hi);
            (k, t, distance(k, t))
        };
        let (k, t, _) = (best.0.saturating_sub(1)..=(best.0 + 1).min(intervals - 1))
            .map(golden)
            .chain([best])
            .min_by(|a, b| a.2.total_cmp(&b.2))
            .expect("at least the best sample");
        let (segment, u) = parameter(k, t);
        let u0 = (k % SUBINTERVALS) as f64 / SUBINTERVALS as f64;
        let station = spline.table[k] + spline.arc(segment, u0, u);
        Ok((station, distance(k, t)))
    }

    /// Arc length in m of the smooth curve through the points (the curve the rod's
    /// vertices are placed on; slightly longer than the rod's polygon).
    pub fn arc_length(&self) -> Result<f64, NominalError> {
        Ok(Spline::try_new(self)?.length())
    }
}

/// A pre-deformed rod built from a [`NominalShape`].
#[derive(Clone, Debug)]
pub struct NominalRod {
    /// The rod, whose stress-free reference is the nominal shape.
    pub rod: Rod,
    /// The nominal configuration (vertices on the nominal curve, edge frames); an
    /// initial guess, and the equilibrium when mounted at the nominal end frames
    /// without loads.
    pub state: RodState,
    /// The nominal frame at vertex 0 (`a3` = the curve's tangent): clamp the start here
    /// to mount the rod as moulded.
    pub start_frame: UnitQuaternion<f64>,
    /// The nominal frame at vertex N: clamp the end here to mount the rod as moulded.
    pub end_frame: UnitQuaternion<f64>,
    /// Arc length of every vertex along the nominal curve in m (`0` … the curve's
    /// length; the rod's own arc lengths, along its polygon, are slightly shorter).
    pub stations: Vec<f64>,
}

impl NominalRod {
    /// The nominal end frames as boundary frames (for [`crate::sectional::sectional`]).
    pub fn boundary_frames(&self) -> BoundaryFrames {
        BoundaryFrames {
            start: Some(self.start_frame),
            end: Some(self.end_frame),
            clips: Vec::new(),
            end_loads: Default::default(),
        }
    }

    /// The nominal start position `r_0` in m (the first point).
    pub fn start_position(&self) -> Vector3<f64> {
        self.state.positions[0]
    }

    /// The nominal frame at interior vertex `vertex` (`0 < vertex < N`) in which a clip
    /// holds the rod without stress: `q_{j−1/2} exp(h_{j−1}/2 · K0_j)`, a half-cell of
    /// rest curvature `K0_j` past the frame of the edge before it. The half-cells on both
    /// sides of a clip there (weights `h_{j−1}/2` and `h_j/2`) are then exactly at their
    /// rest curvature `K0_j`, as the unclipped vertex is.
    pub fn clip_frame(&self, vertex: usize) -> UnitQuaternion<f64> {
        let half = 0.5 * self.rod.edge_length(vertex - 1);
        self.state.frames[vertex - 1] * exp(&(half * self.rod.rest_curvature(vertex)))
    }

    /// The nominal end position `r_N` in m (the last point).
    pub fn end_position(&self) -> Vector3<f64> {
        *self.state.positions.last().expect("a rod has vertices")
    }
}

/// The largest angle, degrees, between consecutive chords of a nominal centreline's
/// points: a CAD centreline sampled at any spacing that follows a hose turns by far
/// less between neighbouring chords; beyond it the points double back (a point given
/// twice in another order, a copy-and-paste slip), see [`NominalError::DoublesBack`].
pub const MAX_CHORD_TURN_DEG: f64 = 150.0;
/// Why a nominal shape cannot define a rod.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum NominalError {
    /// Fewer than two points.
    #[error("a nominal shape needs at least 2 points (got {0})")]
    TooFewPoints(usize),
    /// A point or frame has a non-finite coordinate.
    #[error("nominal {what}[{index}] is not finite")]
    NotFinite {
        /// `"points"` or `"frames"`.
        what: &'static str,
        /// Index of the offending entry.
        index: usize,
    },
    /// Two consecutive points coincide.
    #[error(
        "nominal points[{index}] repeats points[{}] (consecutive points must be distinct)",
        .index - 1
    )]
    RepeatedPoint {
        /// Index of the second of the two points.
        index: usize,
    },
    /// The centreline turns back on itself at a point: consecutive chords point in
    /// nearly opposite directions (more than [`MAX_CHORD_TURN_DEG`] apart), so the curve
    /// through the points makes a loop no hose has.
    #[error(
        "the nominal centreline turns back on itself at points[{index}] (the chords \
         before and after it are {angle_deg:.1}° apart, more than {max:.0}°)",
        max = MAX_CHORD_TURN_DEG
    )]
    DoublesBack {
        /// Index of the point where it turns.
        index: usize,
        /// The angle between the chords before and after it, degrees.
        angle_deg: f64,
    },
    /// `frames` has not one frame per point.
    #[error("nominal frames: expected one per point ({points}), got {frames}")]
    FrameCount {
        /// Number of points.
        points: usize,
        /// Number of frames.
        frames: usize,
    },
    /// A frame's `a3` points away from a neighbouring point.
    #[error(
        "nominal frames[{index}]: its tangent a3 points away from points[{neighbour}] \
         (a3 must point along the centreline, from its start towards its end)"
    )]
    FrameAgainstCentreline {
        /// Index of the frame.
        index: usize,
        /// Index of the neighbouring point.
        neighbour: usize,
    },
    /// Vertex stations that do not run strictly upwards from 0 to the curve's length.
    #[error(
        "nominal stations: expected at least 2 arc lengths increasing strictly from 0 to the \
         curve's length {length} m, got {count}"
    )]
    Stations {
        /// The curve's arc length in m.
        length: f64,
        /// Number of stations given.
        count: usize,
    },
    /// The rod could not be built (segments, or a degenerate edge).
    #[error(transparent)]
    Rod(#[from] RodError),
}

impl Rod {
    /// A pre-deformed rod whose stress-free shape is `shape`, cut into `segments` edges
    /// of (nearly) equal length; see the [module documentation](crate::nominal) for the
    /// construction. Returns the rod, its nominal configuration and nominal end frames.
    pub fn try_from_nominal(
        section: Section,
        shape: &NominalShape,
        segments: usize,
    ) -> Result<NominalRod, NominalError> {
        if segments == 0 {
            return Err(RodError::Segments(0).into());
        }
        let spline = Spline::try_new(shape)?;
        let total = spline.length();
        // Vertices at equal arc length; the ends exactly at the first and last points.
        let mut targets: Vec<f64> = (0..=segments)
            .map(|j| total * j as f64 / segments as f64)
            .collect();
        targets[segments] = total;
        Self::nominal_at(section, shape, &spline, targets)
    }

    /// As [`Rod::try_from_nominal`], but with the vertices at the given arc lengths
    /// `stations` (m along the nominal curve, see [`NominalShape::arc_length`]):
    /// strictly increasing from `0` to the curve's length (the last one is snapped onto
    /// the end; at least 2). Used to put a vertex exactly at every clip.
    pub fn try_from_nominal_stations(
        section: Section,
        shape: &NominalShape,
        stations: &[f64],
    ) -> Result<NominalRod, NominalError> {
        let spline = Spline::try_new(shape)?;
        let total = spline.length();
        let increasing = stations.windows(2).all(|w| w[1] > w[0]);
        let ends = stations.first() == Some(&0.0)
            && stations
                .last()
                .is_some_and(|&s| (s - total).abs() <= 1e-9 * total);
        if stations.len() < 2 || !increasing || !ends {
            return Err(NominalError::Stations {
                length: total,
                count: stations.len(),
            });
        }
        let mut targets = stations.to_vec();
        *targets.last_mut().expect("≥ 2 stations") = total;
        Self::nominal_at(section, shape, &spline, targets)
    }

    /// The nominal rod with its vertices at arc lengths `targets` (0 … total).
    fn nominal_at(
        section: Section,
        shape: &NominalShape,
        spline: &Spline,
        targets: Vec<f64>,
    ) -> Result<NominalRod, NominalError> {
        let n = targets.len() - 1;
        let mut positions = Vec::with_capacity(n + 1);
        positions.push(shape.points[0]);
        for &s in &targets[1..n] {
            let (segment, u) = spline.locate(s);
            positions.push(spline.point(segment, u));
        }
        positions.push(*shape.points.last().expect("checked: ≥ 2 points"));
        let edge = |e: usize| positions[e + 1] - positions[e];

        // Edge frames and nominal end frames.
        let (start_frame, frames, end_frame) = match &shape.frames {
            None => {
                let start =
                    frame_with_tangent(&spline.end_tangent(false), &UnitQuaternion::identity());
                let mut frames = Vec::with_capacity(n);
                let mut previous = start;
                for e in 0..n {
                    previous = frame_with_tangent(&edge(e), &previous);
                    frames.push(previous);
                }
                let end = frame_with_tangent(&spline.end_tangent(true), &previous);
                (start, frames, end)
            }
            Some(given) => {
                let frames = (0..n)
                    .map(|e| {
                        let s = 0.5 * (targets[e] + targets[e + 1]);
                        frame_with_tangent(&edge(e), &spline.slerp_frames(given, s))
                    })
                    .collect();
                (given[0], frames, *given.last().expect("one per point"))
            }
        };
        let state = RodState::new(positions, frames);

        // The reference, extracted with the energy's own formulas.
        let lengths: Vec<f64> = (0..n).map(|e| state.edge_vector(e).norm()).collect();
        let provisional = Rod::try_new(
            section,
            lengths.clone(),
            vec![Vector3::z(); n],
            vec![Vector3::zeros(); n + 1],
        )?;
        let c_gamma = section.strain_stiffness();
        let c_kappa = section.curvature_stiffness();
        let zero = Vector3::zeros();
        let rest_strains = (0..n)
            .map(|e| {
                StretchShear {
                    edge_vector: state.edge_vector(e),
                    frame: &state.frames[e],
                    length: lengths[e],
                    stiffness: &c_gamma,
                    rest_strain: &zero,
                }
                .strain()
            })
            .collect();
        let boundary = BoundaryFrames {
            start: Some(start_frame),
            end: Some(end_frame),
            clips: Vec::new(),
            end_loads: Default::default(),
        };
        let rest_curvatures = (0..=n)
            .map(|j| {
                let (frame_a, frame_b) =
                    vertex_frames(&state, &boundary, j).expect("both boundary frames are set");
                BendTwist {
                    frame_a,
                    frame_b,
                    weight: provisional.vertex_weight(j),
                    stiffness: &c_kappa,
                    rest_curvature: &zero,
                }
                .curvature()
            })
            .collect();
        let rod = Rod::try_new(section, lengths, rest_strains, rest_curvatures)?;
        Ok(NominalRod {
            rod,
            state,
            start_frame,
            end_frame,
            stations: targets,
        })
    }
}

/// Sub-intervals per spline segment of the arc-length table.
const SUBINTERVALS: usize = 16;

/// Five-point Gauss–Legendre nodes and weights on [−1, 1].
const GAUSS: [(f64, f64); 5] = [
    (0.0, 0.568_888_888_888_888_9),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];

/// The G1 cubic Hermite spline through the nominal points, with an arc-length table.
///
/// Segment `i` is `p(u) = H00 p_i + H10 a_i d_i + H01 p_{i+1} + H11 a_i d_{i+1}`,
/// `u ∈ [0, 1]`, with unit tangent directions `d` at the points and the handle
/// `a_i = |c_i| / cos²(θ_i/4)` (`c_i` the chord, `θ_i` the angle between `d_i` and
/// `d_{i+1}`), the classic cubic approximation of a circular arc (radial error
/// 3e-4 R for a 90° segment, falling as θ⁶).
struct Spline {
    points: Vec<Vector3<f64>>,
    /// Unit tangent directions at the points.
    directions: Vec<Vector3<f64>>,
    /// Handle length `a_i` of every segment in m.
    handles: Vec<f64>,
    /// Arc length at the start of every sub-interval, and the total at the end.
    table: Vec<f64>,
}

impl Spline {
    fn try_new(shape: &NominalShape) -> Result<Self, NominalError> {
        let points = &shape.points;
        let count = points.len();
        if count < 2 {
            return Err(NominalError::TooFewPoints(count));
        }
        if let Some(index) = points.iter().position(|p| !p.iter().all(|x| x.is_finite())) {
            return Err(NominalError::NotFinite {
                what: "points",
                index,
            });
        }
        let chords: Vec<Vector3<f64>> = points.windows(2).map(|w| w[1] - w[0]).collect();
        let polyline: f64 = chords.iter().map(|c| c.norm()).sum();
        if let Some(i) = chords.iter().position(|c| c.norm() <= 1e-9 * polyline) {
            return Err(NominalError::RepeatedPoint { index: i + 1 });
        }
        if let Some((i, angle)) = chords
            .windows(2)
            .map(|w| w[0].angle(&w[1]).to_degrees())
            .enumerate()
            .find(|(_, angle)| *angle > MAX_CHORD_TURN_DEG)
        {
            return Err(NominalError::DoublesBack {
                index: i + 1,
                angle_deg: angle,
            });
        }
        let m = chords.len();
        let directions = match &shape.frames {
            None => estimated_directions(points),
            Some(frames) => {
                if frames.len() != count {
                    return Err(NominalError::FrameCount {
                        points: count,
                        frames: frames.len(),
                    });
                }
                if let Some(index) = frames
                    .iter()
                    .position(|q| !q.coords.iter().all(|x| x.is_finite()))
                {
                    return Err(NominalError::NotFinite {
                        what: "frames",
                        index,
                    });
                }
                let directions: Vec<Vector3<f64>> =
                    frames.iter().map(|q| q * Vector3::z()).collect();
                for (i, d) in directions.iter().enumerate() {
                    for (chord, neighbour) in [(i.wrapping_sub(1), i.wrapping_sub(1)), (i, i + 1)] {
                        if chord < m && d.dot(&chords[chord]) <= 0.0 {
                            return Err(NominalError::FrameAgainstCentreline {
                                index: i,
                                neighbour,
                            });
                        }
                    }
                }
                directions
            }
        };
        let handles = (0..m)
            .map(|i| {
                let (a, b) = (&directions[i], &directions[i + 1]);
                let angle = a.cross(b).norm().atan2(a.dot(b));
                chords[i].norm() / (0.25 * angle).cos().powi(2)
            })
            .collect();
        let mut spline = Self {
            points: points.clone(),
            directions,
            handles,
            table: Vec::with_capacity(m * SUBINTERVALS + 1),
        };
        let mut acc = 0.0;
        for segment in 0..m {
            for k in 0..SUBINTERVALS {
                spline.table.push(acc);
                let (u0, u1) = (
                    k as f64 / SUBINTERVALS as f64,
                    (k + 1) as f64 / SUBINTERVALS as f64,
                );
                acc += spline.arc(segment, u0, u1);
            }
        }
        spline.table.push(acc);
        Ok(spline)
    }

    fn segments(&self) -> usize {
        self.handles.len()
    }

    fn length(&self) -> f64 {
        *self.table.last().expect("table has an end")
    }

    /// The point at parameter `u ∈ [0, 1]` of segment `i`.
    fn point(&self, i: usize, u: f64) -> Vector3<f64> {
        let a = self.handles[i];
        let (u2, u3) = (u * u, u * u * u);
        self.points[i] * (2.0 * u3 - 3.0 * u2 + 1.0)
            + self.directions[i] * (a * (u3 - 2.0 * u2 + u))
            + self.points[i + 1] * (-2.0 * u3 + 3.0 * u2)
            + self.directions[i + 1] * (a * (u3 - u2))
    }

    /// `dp/du` of segment `i` at `u`.
    fn derivative(&self, i: usize, u: f64) -> Vector3<f64> {
        let a = self.handles[i];
        let u2 = u * u;
        (self.points[i + 1] - self.points[i]) * (6.0 * u - 6.0 * u2)
            + self.directions[i] * (a * (3.0 * u2 - 4.0 * u + 1.0))
            + self.directions[i + 1] * (a * (3.0 * u2 - 2.0 * u))
    }

    /// The unit tangent at the start (`at_end = false`) or end of the curve.
    fn end_tangent(&self, at_end: bool) -> Vector3<f64> {
        if at_end {
            self.directions[self.directions.len() - 1]
        } else {
            self.directions[0]
        }
    }

    /// Arc length of segment `i` between `u0` and `u1` (Gauss–Legendre).
    fn arc(&self, i: usize, u0: f64, u1: f64) -> f64 {
        let (mid, half) = (0.5 * (u0 + u1), 0.5 * (u1 - u0));
        GAUSS
            .iter()
            .map(|(x, w)| w * self.derivative(i, mid + half * x).norm())
            .sum::<f64>()
            * half
    }

    /// Segment and parameter of arc length `s` (bisection to round-off).
    fn locate(&self, s: f64) -> (usize, f64) {
        let last = self.table.len() - 2;
        let k = self
            .table
            .partition_point(|&t| t <= s)
            .saturating_sub(1)
            .min(last);
        let (segment, sub) = (k / SUBINTERVALS, k % SUBINTERVALS);
        let u0 = sub as f64 / SUBINTERVALS as f64;
        let (mut lo, mut hi) = (u0, (sub + 1) as f64 / SUBINTERVALS as f64);
        let target = s - self.table[k];
        for _ in 0..64 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if self.arc(segment, u0, mid) < target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        (segment, 0.5 * (lo + hi))
    }

    /// The given frames interpolated (slerp in arc length) at arc length `s`.
    fn slerp_frames(&self, frames: &[UnitQuaternion<f64>], s: f64) -> UnitQuaternion<f64> {
        let at = |i: usize| self.table[i * SUBINTERVALS];
        let i = (0..self.segments())
            .rev()
            .find(|&i| at(i) <= s)
            .unwrap_or(0);
        let w = ((s - at(i)) / (at(i + 1) - at(i))).clamp(0.0, 1.0);
        frames[i] * exp(&(w * relative_rotation_vector(&frames[i], &frames[i + 1])))
    }
}

/// The unit tangent at the middle point `b` of the circle through `a, b, c` (exact for
/// points on a circle or a line; `None` when the points turn back on themselves).
fn circle_tangent(a: &Vector3<f64>, b: &Vector3<f64>, c: &Vector3<f64>) -> Option<Vector3<f64>> {
    let (c0, c1) = (b - a, c - b);
    let t = c0 * c1.norm_squared() + c1 * c0.norm_squared();
    let scale = c0.norm() * c1.norm() * (c0.norm() + c1.norm());
    (t.norm() > 1e-9 * scale).then(|| t.normalize())
}

/// The tangent at one end of a circular arc (chord `chord`) from the tangent `t` at
/// its other end: `t` mirrored at the chord.
fn mirror(t: &Vector3<f64>, chord: &Vector3<f64>) -> Vector3<f64> {
    let u = chord.normalize();
    u * (2.0 * t.dot(&u)) - t
}

/// Tangent directions at the points when no frames are given.
///
/// At an inner point `p_i` the circle through three consecutive points gives up to
/// three estimates: centred (`p_{i−1}, p_i, p_{i+1}`) and one-sided (`p_{i−2}, p_{i−1}, p_i`
/// and `p_i, p_{i+1}, p_{i+2}`, the tangent at `p_i` mirrored from the middle one). Of
/// three, the two that agree best are averaged: all three coincide on a circle or a
/// line, and at the junction of a straight run and a circular bend (CAD centrelines)
/// two of the three are exact. Of two (next to an end), the more local one is
/// strongly preferred (weights `1/span⁸`, `span` the length of the three points'
/// polyline), so that a straight leg given by its two end points stays straight next
/// to a densely sampled bend. At the ends, the neighbour's tangent is mirrored at the
/// end chord (exact on a circle and a line). Two points give the chord.
fn estimated_directions(points: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    let count = points.len();
    let chord = |i: usize| points[i + 1] - points[i];
    if count == 2 {
        let u = chord(0).normalize();
        return vec![u, u];
    }
    let mut directions = vec![Vector3::zeros(); count];
    for i in 1..count - 1 {
        // (estimate, span of its three points)
        let mut estimates: Vec<(Vector3<f64>, f64)> = Vec::with_capacity(3);
        let span =
            |a: usize| (points[a + 1] - points[a]).norm() + (points[a + 2] - points[a + 1]).norm();
        if i >= 2
            && let Some(t) = circle_tangent(&points[i - 2], &points[i - 1], &points[i])
        {
            estimates.push((mirror(&t, &chord(i - 1)), span(i - 2)));
        }
        if let Some(t) = circle_tangent(&points[i - 1], &points[i], &points[i + 1]) {
            estimates.push((t, span(i - 1)));
        }
        if i + 2 < count
            && let Some(t) = circle_tangent(&points[i], &points[i + 1], &points[i + 2])
        {
            estimates.push((mirror(&t, &chord(i)), span(i)));
        }
        let sum = if estimates.len() == 3 {
            let angle = |a: &Vector3<f64>, b: &Vector3<f64>| a.cross(b).norm().atan2(a.dot(b));
            [(0, 1), (1, 2), (0, 2)]
                .into_iter()
                .min_by(|x, y| {
                    let ax = angle(&estimates[x.0].0, &estimates[x.1].0);
                    let ay = angle(&estimates[y.0].0, &estimates[y.1].0);
                    ax.total_cmp(&ay)
                })
                .map(|(a, b)| estimates[a].0 + estimates[b].0)
                .expect("three pairs")
        } else {
            // The more local estimate is strongly preferred (weights 1/span⁸).
            estimates.iter().map(|(t, span)| t / span.powi(8)).sum()
        };
        let (u0, u1) = (chord(i - 1).normalize(), chord(i).normalize());
        // Fall back to the mean chord direction when the estimate is degenerate or
        // points against either chord (a turn-back in the points).
        directions[i] = match sum.try_normalize(1e-12) {
            Some(d) if d.dot(&u0) > 0.0 && d.dot(&u1) > 0.0 => d,
            _ => (u0 + u1).try_normalize(1e-12).unwrap_or(u1),
        };
    }
    for (end, inner, c) in [(0, 1, chord(0)), (count - 1, count - 2, chord(count - 2))] {
        let t = mirror(&directions[inner], &c);
        directions[end] = if t.dot(&c) > 0.0 { t } else { c.normalize() };
    }
    directions
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::{bend_twist, stretch_shear};
    use crate::sectional::{edge_element, sectional};

    fn section() -> Section {
        Section::try_explicit(3e4, 1e4, 1.0, 1.0, 0.1, 0.0).unwrap()
    }

    fn arc_points(radius: f64, angle: f64, count: usize) -> Vec<Vector3<f64>> {
        (0..count)
            .map(|k| {
                let phi = angle * k as f64 / (count - 1) as f64;
                Vector3::new(radius * phi.sin(), radius * (1.0 - phi.cos()), 0.0)
            })
            .collect()
    }

    /// The total elastic gradient at the nominal state, clamped at the nominal frames.
    fn elastic_gradient_norm(nominal: &NominalRod) -> f64 {
        let (rod, state) = (&nominal.rod, &nominal.state);
        let n = rod.segments();
        let c_gamma = rod.section().strain_stiffness();
        let c_kappa = rod.section().curvature_stiffness();
        let mut largest: f64 = 0.0;
        for e in 0..n {
            let d = stretch_shear(&edge_element(rod, state, &c_gamma, e));
            largest = largest.max(d.gradient.amax());
        }
        let boundary = nominal.boundary_frames();
        for j in 0..=n {
            let (frame_a, frame_b) = vertex_frames(state, &boundary, j).unwrap();
            let d = bend_twist(&BendTwist {
                frame_a,
                frame_b,
                weight: rod.vertex_weight(j),
                stiffness: &c_kappa,
                rest_curvature: rod.rest_curvature(j),
            });
            largest = largest.max(d.gradient.amax());
        }
        largest
    }

    #[test]
    fn circular_arc_gives_constant_curvature_and_no_stress() {
        let radius = 0.3;
        let angle = 2.0;
        let nominal = Rod::try_from_nominal(
            section(),
            &NominalShape::from_points(arc_points(radius, angle, 9)),
            40,
        )
        .unwrap();
        let rod = &nominal.rod;
        // The spline through 9 points reproduces the arc (0.25 rad per piece).
        for p in &nominal.state.positions {
            let distance = (p - Vector3::new(0.0, radius, 0.0)).norm();
            assert!((distance - radius).abs() < 1e-7 * radius, "{distance}");
        }
        // Σ chords = 2 N R sin(θ/2N).
        let chords = 80.0 * radius * (angle / 80.0).sin();
        assert!(
            (rod.length() - chords).abs() < 1e-7 * chords,
            "{}",
            rod.length()
        );
        let h = rod.length() / 40.0;
        for e in 0..40 {
            assert!((rod.rest_strain(e) - Vector3::z()).norm() < 1e-14);
            assert!((rod.edge_length(e) - h).abs() < 1e-3 * h);
        }
        for j in 0..=40 {
            let k = rod.rest_curvature(j);
            // Planar, untwisted, bending about a2 (a1 = -z would bend about ±a2).
            assert!(k.z.abs() < 1e-12, "twist at {j}: {k:?}");
            assert!((k.norm() * radius - 1.0).abs() < 1e-3, "{j}: {k:?}");
        }
        let out = sectional(rod, &nominal.state, &nominal.boundary_frames());
        for j in 0..=40 {
            assert!(out.forces[j].norm() < 1e-10 && out.moments[j].norm() < 1e-12);
        }
        assert!(elastic_gradient_norm(&nominal) < 1e-10);
        // End frames are tangent to the curve.
        let t0 = nominal.start_frame * Vector3::z();
        assert!((t0 - Vector3::x()).norm() < 1e-12, "{t0:?}");
    }

    /// Exact distance of `p` from an L: the x axis up to x = 0.1, a quarter circle of
    /// radius 0.06 about (0.1, 0.06), then the line x = 0.16 upwards.
    fn distance_from_l(p: &Vector3<f64>) -> f64 {
        let (x, y) = (p.x, p.y);
        let planar = if x <= 0.1 {
            y.abs()
        } else if y >= 0.06 {
            (x - 0.16).abs()
        } else {
            ((x - 0.1).hypot(y - 0.06) - 0.06).abs()
        };
        planar.hypot(p.z)
    }

    #[test]
    fn straight_legs_and_circular_bends_of_a_cad_centreline_are_kept() {
        // Legs given by their end points only, the bend every 15°.
        let mut points = vec![Vector3::zeros()];
        for k in 0..=6 {
            let phi = std::f64::consts::FRAC_PI_2 * k as f64 / 6.0;
            points.push(Vector3::new(
                0.1 + 0.06 * phi.sin(),
                0.06 * (1.0 - phi.cos()),
                0.0,
            ));
        }
        points.push(Vector3::new(0.16, 0.16, 0.0));
        let nominal =
            Rod::try_from_nominal(section(), &NominalShape::from_points(points), 60).unwrap();
        let worst = nominal
            .state
            .positions
            .iter()
            .map(distance_from_l)
            .fold(0.0, f64::max);
        assert!(worst < 2e-7, "largest distance from the L: {worst} m");
        assert!((nominal.start_frame * Vector3::z() - Vector3::x()).norm() < 1e-5);
        assert!((nominal.end_frame * Vector3::z() - Vector3::y()).norm() < 1e-5);
        let s = nominal.rod.arc_lengths();
        for j in 0..=60 {
            let k = nominal.rod.rest_curvature(j).norm();
            let h = nominal.rod.edge_length(0);
            if s[j] < 0.1 - h || s[j] > 0.1 + 0.03 * std::f64::consts::PI + h {
                assert!(k < 1e-3, "leg vertex {j}: {k} 1/m");
            } else if s[j] > 0.1 + h && s[j] < 0.1 + 0.03 * std::f64::consts::PI - h {
                assert!((k * 0.06 - 1.0).abs() < 1e-3, "bend vertex {j}: {k} 1/m");
            }
        }
    }

    #[test]
    fn given_frames_set_tangents_and_twist() {
        // A helix with its Frenet-like frames (a1 towards the axis).
        let (radius, pitch): (f64, f64) = (0.2, 0.1);
        let count = 13;
        let c = (radius * radius + pitch * pitch).sqrt();
        let points: Vec<Vector3<f64>> = (0..count)
            .map(|k| {
                let phi = 3.0 * k as f64 / (count - 1) as f64;
                Vector3::new(radius * phi.cos(), radius * phi.sin(), pitch * phi)
            })
            .collect();
        let frames: Vec<UnitQuaternion<f64>> = (0..count)
            .map(|k| {
                let phi = 3.0 * k as f64 / (count - 1) as f64;
                let t = Vector3::new(-radius * phi.sin(), radius * phi.cos(), pitch) / c;
                let normal = Vector3::new(-phi.cos(), -phi.sin(), 0.0);
                let binormal = t.cross(&normal);
                UnitQuaternion::from_rotation_matrix(&nalgebra::Rotation3::from_matrix_unchecked(
                    nalgebra::Matrix3::from_columns(&[normal, binormal, t]),
                ))
            })
            .collect();
        let shape = NominalShape {
            points,
            frames: Some(frames.clone()),
        };
        let nominal = Rod::try_from_nominal(section(), &shape, 60).unwrap();
        assert_eq!(nominal.start_frame, frames[0]);
        assert_eq!(nominal.end_frame, frames[count - 1]);
        // Constant Kirchhoff curvature (κ, 0, τ) up to discretisation and interpolation.
        let (kappa, tau) = (radius / (c * c), pitch / (c * c));
        for j in 0..=60 {
            let k = nominal.rod.rest_curvature(j);
            let expected = Vector3::new(0.0, kappa, tau);
            assert!(
                (k - expected).norm() < 3e-3 * kappa,
                "{j}: {k:?} vs {expected:?}"
            );
        }
        assert!(elastic_gradient_norm(&nominal) < 1e-10);
    }

    #[test]
    fn straight_points_reproduce_a_straight_rod() {
        let points = vec![
            Vector3::new(0.1, 0.2, 0.3),
            Vector3::new(0.25, 0.2, 0.3),
            Vector3::new(0.9, 0.2, 0.3),
            Vector3::new(1.1, 0.2, 0.3),
        ];
        let nominal =
            Rod::try_from_nominal(section(), &NominalShape::from_points(points), 10).unwrap();
        let straight = Rod::try_straight(section(), 1.0, 10).unwrap();
        for e in 0..10 {
            assert!((nominal.rod.edge_length(e) - straight.edge_length(e)).abs() < 1e-15);
            assert!((nominal.rod.rest_strain(e) - Vector3::z()).norm() < 1e-15);
        }
        for j in 0..=10 {
            assert!(nominal.rod.rest_curvature(j).norm() < 1e-13);
        }
    }

    #[test]
    fn bad_shapes_are_rejected() {
        let s = section();
        let p = |x: f64| Vector3::new(x, 0.0, 0.0);
        let err = |shape: NominalShape, n| Rod::try_from_nominal(s, &shape, n).unwrap_err();
        assert_eq!(
            err(NominalShape::from_points(vec![p(0.0)]), 4),
            NominalError::TooFewPoints(1)
        );
        assert_eq!(
            err(NominalShape::from_points(vec![p(0.0), p(1.0), p(1.0)]), 4),
            NominalError::RepeatedPoint { index: 2 }
        );
        // Back and forth along x: it turns back at points[1] (180°).
        assert_eq!(
            err(
                NominalShape::from_points(vec![p(0.0), p(1.0), p(0.0), p(1.0)]),
                4
            ),
            NominalError::DoublesBack {
                index: 1,
                angle_deg: 180.0
            }
        );
        // A hairpin sampled every 30° turns by 30° per point: a shape.
        let hairpin: Vec<Vector3<f64>> = (0..=6)
            .map(|k| {
                let a = (k as f64 * 30.0).to_radians();
                Vector3::new(a.sin(), 1.0 - a.cos(), 0.0)
            })
            .collect();
        assert!(Rod::try_from_nominal(s, &NominalShape::from_points(hairpin), 12).is_ok());
        assert_eq!(
            err(NominalShape::from_points(vec![p(0.0), p(f64::NAN)]), 4),
            NominalError::NotFinite {
                what: "points",
                index: 1
            }
        );
        assert_eq!(
            err(NominalShape::from_points(vec![p(0.0), p(1.0)]), 0),
            NominalError::Rod(RodError::Segments(0))
        );
        let along_x =
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
        assert_eq!(
            err(
                NominalShape {
                    points: vec![p(0.0), p(1.0)],
                    frames: Some(vec![along_x]),
                },
                4
            ),
            NominalError::FrameCount {
                points: 2,
                frames: 1
            }
        );
        assert_eq!(
            err(
                NominalShape {
                    points: vec![p(0.0), p(1.0)],
                    frames: Some(vec![along_x, along_x.inverse()]),
                },
                4
            ),
            NominalError::FrameAgainstCentreline {
                index: 1,
                neighbour: 0
            }
        );
    }

    #[test]
    fn stations_place_vertices_and_points_project_onto_the_curve() {
        use std::f64::consts::{FRAC_PI_2, PI};
        // A quarter circle of radius 0.2 m (centre (0, 0.2, 0)), given every 15°.
        let shape = NominalShape::from_points(arc_points(0.2, FRAC_PI_2, 7));
        let total = shape.arc_length().unwrap();
        assert!((total - 0.1 * PI).abs() < 1e-6 * total, "{total}");
        let stations = [0.0, 0.1 * total, 0.15 * total, 0.6 * total, total];
        let nominal = Rod::try_from_nominal_stations(section(), &shape, &stations).unwrap();
        assert_eq!(nominal.rod.segments(), 4);
        assert_eq!(nominal.stations, stations);
        for (j, s) in stations.iter().enumerate() {
            // The vertex at arc length s of the circle: angle s / R.
            let phi = s / total * FRAC_PI_2;
            let expected = Vector3::new(0.2 * phi.sin(), 0.2 * (1.0 - phi.cos()), 0.0);
            assert!((nominal.state.positions[j] - expected).norm() < 1e-6, "{j}");
        }
        // The clip frame halves the bend of the vertex cell: its tangent is the circle's.
        let phi = 0.15 * FRAC_PI_2;
        let tangent = nominal.clip_frame(2) * Vector3::z();
        assert!((tangent - Vector3::new(phi.cos(), phi.sin(), 0.0)).norm() < 1e-3);
        // A point 10 mm outside the circle at 30° projects back to 30°.
        let phi = PI / 6.0;
        let outside = Vector3::new(0.21 * phi.sin(), 0.2 - 0.21 * phi.cos(), 0.0);
        let (station, distance) = shape.project(&outside).unwrap();
        assert!((distance - 0.01).abs() < 1e-6, "{distance}");
        assert!((station - total / 3.0).abs() < 1e-6, "{station}");
        // Stations must run from 0 to the length, strictly increasing.
        let bad = Rod::try_from_nominal_stations(section(), &shape, &[0.0, 0.5, 0.4, total]);
        assert!(matches!(bad, Err(NominalError::Stations { .. })));
    }
}
