//! Nested iteration: a coarse-to-fine initial guess for finely discretised rods.
//!
//! Newton's cost per iteration grows with the number of unknowns while the number of
//! iterations from a poor guess does not shrink, so the large-deformation part of the
//! path is solved on a coarse copy of the system (every rod cut into about
//! [`COARSE_SEGMENTS`] edges at a subset of its vertices) and prolonged: positions by
//! cubic Hermite interpolation with the coarse centreline tangents, frames by slerp
//! between coarse frames, each coarse edge's shear kept (see `prolong_rod`). The fine
//! solve then starts in its region of quadratic convergence.

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::{Rod, RodState, so3};
use strand_system::{Model, RodSpec, System, SystemState};

use crate::SolverSettings;

/// Rods with more segments than this are coarsened.
pub const COARSE_THRESHOLD: usize = 64;
/// Target number of segments of a coarsened rod.
pub const COARSE_SEGMENTS: usize = 24;

/// Ratio of the segments of one level to the next coarser one, with contact, for rods
/// long enough that a quarter of them is still above [`COARSE_THRESHOLD`]: such a rod
/// is started
/// from a chain of levels (7426 segments from 1486, 298, 60), each a quarter or a
/// fifth of the last, instead of from [`COARSE_SEGMENTS`] directly. A coarse level is
/// only a start, and the fine level must still move everything it got wrong: a cable
/// draped over a groove's rim at 24 segments (its kinks catch on the rim) slid off it
/// at every finer discretisation, creeping about one edge per iteration over hundreds
/// of fine edges (`everyday_s52_010`, 7426 segments: not solved in 600 s). Through the
/// levels each one moves only as far as the one below got it wrong.
pub const LEVEL_RATIO: usize = 4;

/// Whether a rod of `segments` is long enough to be started through levels (a
/// quarter of it still above [`COARSE_THRESHOLD`]).
fn long_enough_for_levels(segments: usize) -> bool {
    segments / LEVEL_RATIO > COARSE_THRESHOLD
}

/// Whether some rod of `system` is long enough to be started through levels
/// ([`LEVEL_RATIO`]).
pub(crate) fn has_levels(system: &System) -> bool {
    system
        .rods
        .iter()
        .any(|r| long_enough_for_levels(r.rod.segments()))
}

/// The finest level of a nested iteration, as its coarse levels see it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Finest {
    /// Its unknowns.
    pub unknowns: usize,
    /// Whether it is started through levels ([`has_levels`]).
    pub levels: bool,
}

/// The budget of a coarse level of `level_unknowns` Newton iterations under `finest`.
/// Under a rod started through levels: [`SolverSettings::coarse_max_iterations`]
/// iterations of the finest level's work (an iteration costs about its unknowns), at
/// most [`SolverSettings::max_iterations`]: under a 7426-segment cable the 60-segment
/// level gets all 200 it may need to slide the cable off a rim (166, 1 ms each).
/// Otherwise (one coarse level of about [`COARSE_SEGMENTS`]: no contact, or rods of at
/// most 4 × 64 segments) the coarse budget itself, as measured on the convergence map
/// (`tests/validation/convergence_map.rs`): scaled there, its stiff cases' coarse
/// levels spend up to 200 iterations per continuation step for no better start
/// (maximum 96 → 99 of 100).
pub(crate) fn level_budget(
    settings: &SolverSettings,
    level_unknowns: usize,
    finest: Finest,
) -> usize {
    if !finest.levels {
        return settings.coarse_max_iterations.min(settings.max_iterations);
    }
    let ratio = finest.unknowns as f64 / level_unknowns.max(1) as f64;
    let budget = (settings.coarse_max_iterations as f64 * ratio).floor() as usize;
    budget.clamp(
        settings.coarse_max_iterations.min(settings.max_iterations),
        settings.max_iterations,
    )
}

/// The coarse vertex indices of a rod with `segments` edges: every `k`-th and the last,
/// about [`COARSE_SEGMENTS`] edges, or with `levels` a quarter of a rod long enough.
fn coarse_indices(segments: usize, levels: bool) -> Vec<usize> {
    let target = if levels && long_enough_for_levels(segments) {
        segments / LEVEL_RATIO
    } else {
        COARSE_SEGMENTS
    };
    let k = segments.div_ceil(target).max(1);
    let mut indices: Vec<usize> = (0..segments).step_by(k).collect();
    indices.push(segments);
    indices
}

/// Whether nested iteration starts `system` from a coarse level (a rod of more than
/// [`COARSE_THRESHOLD`] segments).
pub(crate) fn is_nested(system: &System) -> bool {
    system
        .rods
        .iter()
        .any(|r| r.rod.segments() > COARSE_THRESHOLD)
}

/// The system with every long rod coarsened (with `levels`, long ones to a quarter:
/// [`LEVEL_RATIO`]), and per rod the kept vertex indices.
pub(crate) fn coarsen(system: &System, levels: bool) -> Option<(System, Vec<Vec<usize>>)> {
    if !is_nested(system) {
        return None;
    }
    let mut rods = Vec::with_capacity(system.rods.len());
    let mut kept = Vec::with_capacity(system.rods.len());
    for (r, spec) in system.rods.iter().enumerate() {
        let n = spec.rod.segments();
        let mut indices = if n > COARSE_THRESHOLD {
            coarse_indices(n, levels)
        } else {
            (0..=n).collect()
        };
        // Clipped vertices stay vertices of the coarse rod.
        indices.extend(
            system
                .clips
                .iter()
                .filter(|c| c.rod.0 == r)
                .map(|c| c.vertex),
        );
        indices.sort_unstable();
        indices.dedup();
        let coarse = coarse_rod(&spec.rod, &indices)?;
        rods.push(RodSpec {
            rod: coarse,
            ..spec.clone()
        });
        kept.push(indices);
    }
    let clips = system
        .clips
        .iter()
        .map(|clip| {
            let vertex = kept[clip.rod.0]
                .binary_search(&clip.vertex)
                .expect("clipped vertex kept");
            strand_system::ClipSpec {
                vertex,
                ..clip.clone()
            }
        })
        .collect();
    Some((
        System {
            rods,
            bodies: system.bodies.clone(),
            clips,
            gravity: system.gravity,
        },
        kept,
    ))
}

/// The rod cut at the kept vertices, with a stress-free reference that is the fine
/// rod's own: the fine reference frames are integrated from the rest curvatures
/// (`R_e = R_{e−1} exp(h̄_e K0_e)`), each coarse edge takes the frame of its middle fine
/// edge (as [`restrict`] does), and the coarse `Γ0`, `K0` are the strains of that
/// configuration. A moulded rod's coarse copy is then stress-free in its nominal shape.
fn coarse_rod(rod: &Rod, indices: &[usize]) -> Option<Rod> {
    let n = rod.segments();
    let relative = |j: usize| so3::exp(&(rod.vertex_weight(j) * rod.rest_curvature(j)));
    let mut frames = Vec::with_capacity(n);
    frames.push(UnitQuaternion::identity());
    for e in 1..n {
        frames.push(frames[e - 1] * relative(e));
    }
    let middle = |w: &[usize]| (w[0] + w[1] - 1) / 2;
    let mut lengths = Vec::with_capacity(indices.len() - 1);
    let mut strains = Vec::with_capacity(indices.len() - 1);
    let mut coarse_frames = Vec::with_capacity(indices.len() - 1);
    for w in indices.windows(2) {
        let length: f64 = (w[0]..w[1]).map(|e| rod.edge_length(e)).sum();
        let chord: Vector3<f64> = (w[0]..w[1])
            .map(|e| frames[e] * rod.rest_strain(e) * rod.edge_length(e))
            .sum();
        let frame = frames[middle(w)];
        lengths.push(length);
        strains.push(frame.inverse() * chord / length);
        coarse_frames.push(frame);
    }
    let nc = coarse_frames.len();
    let start_boundary = frames[0] * relative(0).inverse();
    let end_boundary = frames[n - 1] * relative(n);
    let mut curvatures = Vec::with_capacity(nc + 1);
    curvatures.push(
        so3::relative_rotation_vector(&start_boundary, &coarse_frames[0]) / (0.5 * lengths[0]),
    );
    for c in 1..nc {
        let weight = 0.5 * (lengths[c - 1] + lengths[c]);
        curvatures
            .push(so3::relative_rotation_vector(&coarse_frames[c - 1], &coarse_frames[c]) / weight);
    }
    curvatures.push(
        so3::relative_rotation_vector(&coarse_frames[nc - 1], &end_boundary)
            / (0.5 * lengths[nc - 1]),
    );
    Rod::try_new(*rod.section(), lengths, strains, curvatures).ok()
}

/// The fine state restricted to the kept vertices (frames of the middle fine edge).
pub(crate) fn restrict(state: &SystemState, kept: &[Vec<usize>]) -> SystemState {
    let rods = state
        .rods
        .iter()
        .zip(kept)
        .map(|(rod_state, indices)| {
            let positions = indices.iter().map(|&j| rod_state.positions[j]).collect();
            let frames = indices
                .windows(2)
                .map(|w| rod_state.frames[(w[0] + w[1] - 1) / 2])
                .collect();
            RodState::new(positions, frames)
        })
        .collect();
    SystemState {
        rods,
        bodies: state.bodies.clone(),
        clips: state.clips.clone(),
    }
}

/// The coarse solution carried to the fine model.
pub(crate) fn prolong(
    fine: &Model,
    coarse: &Model,
    coarse_state: &SystemState,
    kept: &[Vec<usize>],
) -> SystemState {
    let rods = fine
        .system()
        .rods
        .iter()
        .enumerate()
        .map(|(r, spec)| prolong_rod(spec, coarse, r, coarse_state, &kept[r]))
        .collect();
    SystemState {
        rods,
        bodies: coarse_state.bodies.clone(),
        clips: coarse_state.clips.clone(),
    }
}

/// One rod of the coarse solution carried to the fine rod.
///
/// The coarse equilibrium shears: its directors' `a3` is not its centreline tangent
/// (a thick soft cable of 8669 segments shears by 0.01 rad under 2.6 N). Each coarse
/// edge's chord is therefore kept in its own frame (`t_c = R_cᵀ (x_{c+1} − x_c)/|…|`,
/// the direction of its strain `Γ_c`), and both halves of the prolongation use it:
/// - positions: a cubic Hermite curve per coarse edge through its end vertices, with
///   the centreline tangents `R t` at the vertices (`R` and `t` interpolated in arc
///   length between the two edges' midpoints; the boundary frame and the end edge's
///   `t` at an end);
/// - frames: slerped in arc length between the coarse edges' midpoints (and the
///   boundary frames), each turned by the least rotation that carries its
///   interpolated `t` onto its fine edge, so the fine edge shears as the coarse one.
///
/// Taking `a3` as the tangent instead puts a wiggle of the shear angle into every
/// coarse edge's fine edges, whose bending costs `EI/h γ²` per fine vertex: 5.7 J of
/// bending on a 3247-segment cable whose equilibrium holds 0.58 J.
fn prolong_rod(
    spec: &RodSpec,
    coarse: &Model,
    rod: usize,
    coarse_system_state: &SystemState,
    indices: &[usize],
) -> RodState {
    let s = spec.rod.arc_lengths();
    let boundary = coarse.boundary_frames(rod, coarse_system_state);
    let coarse_state = &coarse_system_state.rods[rod];
    let coarse_frames = &coarse_state.frames;
    let nc = coarse_frames.len();
    // Each coarse edge's chord direction in its own frame.
    let local_tangents: Vec<Vector3<f64>> = (0..nc)
        .map(|c| {
            let chord = coarse_frames[c].inverse() * coarse_state.edge_vector(c);
            chord.try_normalize(0.0).unwrap_or_else(Vector3::z)
        })
        .collect();
    // Unit centreline tangents at the coarse vertices: between the two edges' frames
    // and chord directions, interpolated from the edges' midpoints to the vertex (the
    // last coarse edge may be much shorter than the one before it).
    let middle = |c: usize| 0.5 * (s[indices[c]] + s[indices[c + 1]]);
    let tangent_at = |c: usize| -> Vector3<f64> {
        match c {
            0 => boundary.start.unwrap_or(coarse_frames[0]) * local_tangents[0],
            c if c == nc => boundary.end.unwrap_or(coarse_frames[nc - 1]) * local_tangents[nc - 1],
            c => {
                let u = (s[indices[c]] - middle(c - 1)) / (middle(c) - middle(c - 1));
                let (q0, q1) = (&coarse_frames[c - 1], &coarse_frames[c]);
                let frame = q0 * so3::exp(&(u * so3::relative_rotation_vector(q0, q1)));
                let local = (local_tangents[c - 1] * (1.0 - u) + local_tangents[c] * u)
                    .try_normalize(0.0)
                    .unwrap_or_else(Vector3::z);
                frame * local
            }
        }
    };
    let mut positions = Vec::with_capacity(s.len());
    for c in 0..nc {
        let (a, b) = (indices[c], indices[c + 1]);
        let (pa, pb) = (coarse_state.positions[c], coarse_state.positions[c + 1]);
        let chord = (pb - pa).norm();
        let (ta, tb) = (tangent_at(c) * chord, tangent_at(c + 1) * chord);
        for j in a..b {
            let u = (s[j] - s[a]) / (s[b] - s[a]);
            let (u2, u3) = (u * u, u * u * u);
            positions.push(
                pa * (2.0 * u3 - 3.0 * u2 + 1.0)
                    + ta * (u3 - 2.0 * u2 + u)
                    + pb * (-2.0 * u3 + 3.0 * u2)
                    + tb * (u3 - u2),
            );
        }
    }
    positions.push(*coarse_state.positions.last().expect("vertices"));

    // Frames and chord directions: interpolated in arc length between anchors.
    let mut anchors: Vec<(f64, UnitQuaternion<f64>, Vector3<f64>)> = Vec::with_capacity(nc + 2);
    if let Some(q) = boundary.start {
        anchors.push((0.0, q, local_tangents[0]));
    }
    for c in 0..nc {
        anchors.push((middle(c), coarse_frames[c], local_tangents[c]));
    }
    if let Some(q) = boundary.end {
        anchors.push((*s.last().expect("vertices"), q, local_tangents[nc - 1]));
    }
    let mut anchor = 0;
    let mut frames = Vec::with_capacity(spec.rod.segments());
    let mut local = Vec::with_capacity(spec.rod.segments());
    for e in 0..spec.rod.segments() {
        let mid = 0.5 * (s[e] + s[e + 1]);
        while anchor + 2 < anchors.len() && anchors[anchor + 1].0 < mid {
            anchor += 1;
        }
        let (s0, q0, t0) = anchors[anchor];
        let (s1, q1, t1) = anchors[(anchor + 1).min(anchors.len() - 1)];
        let u = if s1 > s0 {
            ((mid - s0) / (s1 - s0)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        frames.push(q0 * so3::exp(&(u * so3::relative_rotation_vector(&q0, &q1))));
        local.push(
            (t0 * (1.0 - u) + t1 * u)
                .try_normalize(0.0)
                .unwrap_or_else(Vector3::z),
        );
    }
    let mut state = RodState::new(positions, frames);
    // Interpolated frames need not carry their chord direction onto the interpolated
    // centreline; turn each by the least rotation that does.
    for (e, local) in local.iter().enumerate() {
        let edge = state.edge_vector(e);
        let chord = state.frames[e] * local;
        if let Some(turn) = UnitQuaternion::rotation_between(&chord, &edge) {
            state.frames[e] = turn * state.frames[e];
        }
    }
    state
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A system of `rod` alone between `start` and `end`, without gravity.
    fn clamped_rod(rod: Rod, start: strand_system::End, end: strand_system::End) -> System {
        System {
            rods: vec![RodSpec {
                name: "rod".into(),
                start,
                end,
                rod,
                route: None,
            }],
            bodies: vec![],
            clips: Vec::new(),
            gravity: Vector3::zeros(),
        }
    }

    /// The segments of the levels below a rod of `segments`, finest first.
    fn levels(mut segments: usize) -> Vec<usize> {
        let mut out = Vec::new();
        while segments > COARSE_THRESHOLD {
            segments = coarse_indices(segments, true).len() - 1;
            out.push(segments);
        }
        out
    }

    #[test]
    fn a_long_rod_is_started_through_levels_and_a_short_one_from_one() {
        // everyday_s52_010's cable: three levels, each a quarter to a fifth of the last.
        assert_eq!(levels(7426), [1486, 298, 60]);
        assert_eq!(levels(1000), [250, 23]);
        // Up to 4 × 64 segments one coarse level of about 24, as before levels.
        assert_eq!(levels(256), [24]);
        assert_eq!(levels(100), [20]);
        assert_eq!(levels(64), [0usize; 0]);
        // Every level keeps both ends.
        let kept = coarse_indices(7426, true);
        // Without levels (no contact) one level of about 24 whatever the length.
        assert_eq!(coarse_indices(7426, false).len() - 1, 24);
        assert_eq!((kept[0], *kept.last().unwrap()), (0, 7426));
    }

    #[test]
    fn a_coarse_level_gets_its_budget_in_work_of_the_finest_level() {
        let settings = SolverSettings::default();
        let (coarse, most) = (settings.coarse_max_iterations, settings.max_iterations);
        let levels = |unknowns| Finest {
            unknowns,
            levels: true,
        };
        // A level with a quarter of the unknowns: four times the coarse budget, at
        // most the fine budget.
        assert_eq!(
            level_budget(&settings, 1000, levels(4000)),
            (4 * coarse).min(most)
        );
        assert_eq!(level_budget(&settings, 357, levels(44_553)), most);
        // Never below the coarse budget (a level as large as the finest one).
        assert_eq!(level_budget(&settings, 100, levels(100)), coarse);
        let tight = SolverSettings {
            max_iterations: 10,
            ..SolverSettings::default()
        };
        assert_eq!(level_budget(&tight, 100, levels(10_000)), 10);
        // One coarse level under a rod without levels: the coarse budget.
        let single = Finest {
            unknowns: 1203,
            levels: false,
        };
        assert_eq!(level_budget(&settings, 123, single), coarse);
    }

    /// A moulded rod (helical arc) of 200 segments clamped at its nominal end frames:
    /// its coarse copy must be stress-free in the restricted nominal shape.
    #[test]
    fn coarse_copy_of_a_moulded_rod_is_stress_free_in_its_nominal_shape() {
        use strand_rod::{NominalShape, Section};
        use strand_system::{End, Model, SystemState};
        let points = (0..=12)
            .map(|i| {
                let phi = 0.25 * i as f64;
                Vector3::new(0.3 * phi.cos(), 0.3 * phi.sin(), 0.05 * phi)
            })
            .collect();
        let section = Section::try_explicit(3e4, 1e4, 1.0, 0.8, 0.0, 0.0).unwrap();
        let nominal =
            Rod::try_from_nominal(section, &NominalShape::from_points(points), 200).unwrap();
        let system = clamped_rod(
            nominal.rod.clone(),
            End::clamped(nominal.start_position(), nominal.start_frame),
            End::clamped(nominal.end_position(), nominal.end_frame),
        );
        let (coarse_system, kept) = coarsen(&system, false).expect("coarsened");
        let coarse = Model::try_new(coarse_system).unwrap();
        let fine_state = SystemState {
            rods: vec![nominal.state.clone()],
            bodies: vec![],
            clips: vec![],
        };
        let coarse_state = restrict(&fine_state, &kept);
        let mut eval = coarse.new_evaluation();
        coarse.evaluate(&coarse_state, &mut eval, false);
        let residual = coarse.residual(&eval.gradient);
        assert!(residual.combined_n < 1e-8, "coarse residual {residual:?}");
        assert!(eval.energy.abs() < 1e-12, "coarse energy {}", eval.energy);
    }

    /// A circular arc of radius `R` (in the x–z plane) whose directors are turned from
    /// its tangent by a constant shear angle `γ` about the binormal: coarsened,
    /// carried to the fine rod, it must stay a uniformly sheared arc — every fine
    /// edge shears by `γ` and every fine vertex bends by `1/R`. Taking `a3` as the
    /// tangent (the old prolongation) gives unsheared fine edges and a wiggle of `γ`
    /// in the bending at every fine vertex (`γ/h` = 4 1/m here, twice the arc's
    /// curvature). What is left is the Hermite curve's speed, not quite uniform in arc
    /// length: 0.14 % in curvature.
    #[test]
    fn a_sheared_arc_is_prolonged_with_its_shear_and_without_a_wiggle() {
        use strand_rod::Section;
        use strand_system::{End, Model};
        let (radius, shear, length, segments) = (0.5, 0.02, 1.0, 200);
        let section = Section::try_explicit(3e4, 1e4, 1.0, 0.8, 0.0, 0.0).unwrap();
        let rod = Rod::try_straight(section, length, segments).unwrap();
        // Point and sheared frame of the arc at arc length s (tangent angle s/R).
        let point = |s: f64| {
            let phi = s / radius;
            Vector3::new(radius * phi.sin(), 0.0, radius * (1.0 - phi.cos()))
        };
        // Tangent (cos φ, 0, sin φ) at φ = s/R: a turn by −φ about y; a3 leads it by γ.
        let frame =
            |s: f64| UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -(s / radius + shear));
        // Directors: a3 of the frame at tangent angle 0 is +x.
        let base = UnitQuaternion::rotation_between(&Vector3::z(), &Vector3::x()).unwrap();
        let directors = |s: f64| frame(s) * base;
        let system = clamped_rod(
            rod,
            End::clamped(point(0.0), directors(0.0)),
            End::clamped(point(length), directors(length)),
        );
        let (coarse_system, kept) = coarsen(&system, false).expect("coarsened");
        let coarse = Model::try_new(coarse_system).unwrap();
        let fine = Model::try_new(system).unwrap();
        let coarse_s = coarse.system().rods[0].rod.arc_lengths();
        let coarse_rod_state = RodState::new(
            coarse_s.iter().map(|&s| point(s)).collect(),
            coarse_s
                .windows(2)
                .map(|w| directors(0.5 * (w[0] + w[1])))
                .collect(),
        );
        let coarse_state = SystemState {
            rods: vec![coarse_rod_state],
            bodies: vec![],
            clips: vec![],
        };
        let prolonged = prolong(&fine, &coarse, &coarse_state, &kept);
        let state = &prolonged.rods[0];
        let fine_rod = &fine.system().rods[0].rod;
        for e in 0..segments {
            let chord = state.frames[e].inverse() * state.edge_vector(e);
            // The chord is a3 turned by the shear angle about a2.
            let angle = chord.x.atan2(chord.z);
            assert!(
                (angle - shear).abs() < 1e-4 * shear,
                "edge {e}: shear {angle} rad, expected {shear}"
            );
            assert!(
                chord.y.abs() < 1e-12 * chord.norm(),
                "edge {e}: out of plane"
            );
        }
        for v in 1..segments {
            let turn = so3::relative_rotation_vector(&state.frames[v - 1], &state.frames[v]);
            let curvature = turn.norm() / fine_rod.vertex_weight(v);
            assert!(
                (curvature * radius - 1.0).abs() < 2e-3,
                "vertex {v}: curvature {curvature} 1/m, expected {}",
                1.0 / radius
            );
        }
    }

    #[test]
    fn coarse_indices_cover_the_rod() {
        for n in [65, 99, 100, 256, 257, 999, 1000, 7426] {
            let idx = coarse_indices(n, true);
            assert_eq!((idx[0], *idx.last().unwrap()), (0, n));
            assert!(idx.windows(2).all(|w| w[1] > w[0]));
            // About COARSE_SEGMENTS, or a quarter of a rod long enough for levels.
            let target = if long_enough_for_levels(n) {
                n / LEVEL_RATIO
            } else {
                COARSE_SEGMENTS
            };
            assert!(idx.len() - 1 <= target + 1, "{n}: {}", idx.len());
        }
    }
}
