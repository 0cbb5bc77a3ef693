//! The round-off floor of the residual: the out-of-balance forces that the evaluation's
//! own rounding leaves at the exact equilibrium, below which no iteration can go and
//! within whose spread a stalled iteration has converged.
//!
//! The floor is measured on the model's Hessian at the solve's start, as a componentwise
//! backward error: a state within an ulp of the equilibrium in every unknown — an ulp
//! of strain in each vertex position (`ε h`, positions are stored compensated, so the
//! distance from the origin does not enter), an ulp of a rotation (`ε` rad) — has the
//! residual `H δ`, at most `ε Σ_j |H_ij| s_j` in row `i` (`s_j` the unknown's ulp
//! scale), taken [`FLOOR_ULPS`] times. The evaluation rounds at that scale too: each strain is computed from an
//! edge vector rotated into its frame (a few ulps of a unit vector), each stress is a
//! stiffness times it. Unlike the strain stiffness alone (the estimate before), the
//! row sums see what a model adds: a body whose ports lie far from its centre (one ulp
//! of its rotation moves a port by `ε d`, a strain `ε d / h` in the edge at it),
//! stiff couplings at clips, rods at oblique angles (every component of a rotated 3×3
//! block contributes), uneven edges.

use nalgebra::Vector3;
use strand_system::{BlockKind, BodyHandle, Joint, Model, Support, SystemState};

/// Ulps per unknown in the floor: one for the stored state, one for the evaluation's
/// rotate-and-subtract of each strain. Measured with `tolerance_n: 1e-16` (every solve
/// ends at its floor), the stalls lie below the floor over the convergence map (199 of
/// 200 cases; #39, a taut 20-edge cable, stops at 16 times it where its energy no
/// longer resolves the steps), at 0.11 to 0.54 times it on the bundled cables and hoses
/// up to 2000 segments, 0.14 to 0.56 on the clip harness (with the moving attachments
/// below), 0.35 to 0.60 on a stiff cable (EA 5.6e5 N) from 500 to 8884 segments.
const FLOOR_ULPS: f64 = 2.0;

/// A vertex force is the difference of two edge forces, each from a strain computed in
/// a handful of operations (rotate, scale, subtract the rest strain). An iteration that
/// can make no further progress (line search failed, stagnation) within this multiple
/// of the floor has converged to round-off.
pub(crate) const ROUND_OFF_SPREAD: f64 = 4.0;

/// A residual accepted at the round-off floor (above the tolerance) must be at most
/// this fraction of the applied loads ([`strand_system::System::applied_load_n`]):
/// else the floor is not small against the loads and the state is no resolved
/// equilibrium of them ([`crate::Termination::FloorAboveLoads`]). The floors of real
/// cables and hoses lie 1e-8 of their weights and below (a steel cable of EA 5.6e5 N
/// at 8884 segments: about 1e-9 N); the convergence map's stiffest bars (EA/EI = 1e12,
/// EA = 1e10 N) converge at floors up to about 1e-5 of their loads; a cable of
/// `ea = ga = 1e15` N weighing 0.59 N has a floor of 4.3 N (7 times its weight), one
/// of `ei = 1e12` N·m² a floor of 0.42 N.
pub const ROUND_OFF_RESOLVED: f64 = 1e-3;

/// The round-off floor of the residual in N (the combined measure of
/// [`strand_system::Residual::combined_n`]) of `model` with Hessian values `hessian`
/// (in the model's pattern, upper triangle): [`FLOOR_ULPS`] times the largest block
/// norm of `ε |H| s / force scale`, see the module documentation. Never below
/// [`strain_floor`].
pub(crate) fn residual_floor(model: &Model, state: &SystemState, hessian: &[f64]) -> f64 {
    let largest = block_floors(model, state, hessian)
        .into_iter()
        .fold(0.0, f64::max);
    largest.max(strain_floor(model))
}

/// Per block, in N: [`FLOOR_ULPS`] times `ε ‖(|H| s)_block‖ / force scale`, plus at the
/// vertices next to a moving attachment what one ulp of its position does to their edge
/// ([`add_moving_attachments`]).
fn block_floors(model: &Model, state: &SystemState, hessian: &[f64]) -> Vec<f64> {
    let scales = ulp_scales(model);
    let pattern = model.pattern();
    let mut sums = vec![0.0; pattern.dim()];
    for j in 0..pattern.dim() {
        for k in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
            let (i, value) = (pattern.row_idx[k], hessian[k].abs());
            sums[i] += value * scales[j];
            if i != j {
                sums[j] += value * scales[i];
            }
        }
    }
    let dofs = model.dofs();
    let mut floors: Vec<f64> = (0..dofs.block_count())
        .map(|b| {
            let s = &sums[3 * b..3 * b + 3];
            let norm = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
            FLOOR_ULPS * f64::EPSILON * norm / dofs.force_scale(b)
        })
        .collect();
    add_moving_attachments(model, state, &mut floors);
    floors
}

/// Adds, at each free vertex next to a moving attachment, `ε |x| C / h` (N): a vertex
/// held by a sliding clip, by a turning clip with an offset, by a clip on a free body or
/// a parent clip, or a rod end at a free body's port, is placed by a pose computed in
/// the solve's frame (`x = p + R d`), so its position is rounded to an ulp of its
/// distance `|x|` from the frame's origin (not to an ulp of the edge, as a free
/// vertex's compensated one), a strain of `ε |x| / h` in the edge at it (`C` the rod's
/// stiffest strain stiffness, `h` the edge). Measured on the clip harness: without it, the vertices next to its sliding and
/// body-mounted clips stalled at up to 22 times their row sums' floor, growing with the
/// segments as `1/h`.
fn add_moving_attachments(model: &Model, state: &SystemState, floors: &mut [f64]) {
    let (system, dofs) = (model.system(), model.dofs());
    let moving_body = |body: BodyHandle| dofs.body(body.0).is_some();
    let mut add = |rod: usize, vertex: usize| {
        let spec = &system.rods[rod];
        let stiffness = spec.rod.section().strain_stiffness().max();
        let distance = state.rods[rod].positions[vertex].norm();
        let lengths = spec.rod.edge_lengths();
        let neighbours = [
            vertex.checked_sub(1).map(|n| (n, lengths[n])),
            lengths.get(vertex).map(|&h| (vertex + 1, h)),
        ];
        for (neighbour, h) in neighbours.into_iter().flatten() {
            if let Some(b) = dofs.vertex(rod, neighbour) {
                floors[b] += f64::EPSILON * distance * stiffness / h;
            }
        }
    };
    for clip in &system.clips {
        // A revolute or spherical joint turns the rod's frame about the clip's point:
        // without an offset the vertex stays where the base puts it.
        let joint_moves_vertex = match clip.joint {
            Joint::Fixed => false,
            Joint::Prismatic { .. } => true,
            Joint::Revolute { .. } | Joint::Spherical => clip.offset.position != Vector3::zeros(),
        };
        let moving =
            joint_moves_vertex || clip.parent.is_some() || clip.body.is_some_and(moving_body);
        if moving {
            add(clip.rod.0, clip.vertex);
        }
    }
    for (r, spec) in system.rods.iter().enumerate() {
        let last = spec.rod.segments();
        for (vertex, end) in [(0, &spec.start), (last, &spec.end)] {
            if let Support::Port { body, .. } = end.support
                && moving_body(body)
            {
                add(r, vertex);
            }
        }
    }
}

/// The floor without a Hessian, in N: two ulps of strain times the largest axial or
/// shear stiffness of any rod (what one edge force rounds to): the least tolerance a
/// solve applies (below it the residual is not resolved), a factor of the tolerance of
/// the stiffness continuation's intermediate steps (solved before a Hessian exists),
/// and the least [`residual_floor`] reports.
pub(crate) fn strain_floor(model: &Model) -> f64 {
    let stiffest = model
        .system()
        .rods
        .iter()
        .map(|r| r.rod.section().strain_stiffness().max())
        .fold(0.0, f64::max);
    2.0 * f64::EPSILON * stiffest
}

/// One ulp of each scalar unknown: `ε`-free scales, m per position (the mean length of
/// the vertex's edges, so that one ulp is one ulp of their strain) and 1 per rotation
/// (rad). Body and clip positions take the shortest edge of the model.
fn ulp_scales(model: &Model) -> Vec<f64> {
    let (system, dofs) = (model.system(), model.dofs());
    let shortest = system
        .rods
        .iter()
        .flat_map(|r| r.rod.edge_lengths().iter().copied())
        .fold(f64::INFINITY, f64::min);
    let mut block_scale: Vec<f64> = (0..dofs.block_count())
        .map(|b| match dofs.kind(b) {
            BlockKind::Position => shortest,
            BlockKind::Rotation => 1.0,
        })
        .collect();
    for (r, spec) in system.rods.iter().enumerate() {
        let lengths = spec.rod.edge_lengths();
        for j in 0..=lengths.len() {
            if let Some(b) = dofs.vertex(r, j) {
                let before = j.checked_sub(1).map(|e| lengths[e]);
                let after = lengths.get(j).copied();
                block_scale[b] = match (before, after) {
                    (Some(a), Some(c)) => 0.5 * (a + c),
                    (Some(a), None) | (None, Some(a)) => a,
                    (None, None) => shortest,
                };
            }
        }
    }
    block_scale.iter().flat_map(|&s| [s; 3]).collect()
}
