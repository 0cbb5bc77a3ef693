//! The machine-readable result document (`result.json`) and how it is collected from a
//! solved model. Every key carries its unit as a suffix (`_m`, `_N`, `_Nm`, `_J`,
//! `_1pm` for 1/m, `_s`); vectors are `[x, y, z]` in the world frame.

use serde::{Deserialize, Serialize};
use strand_rod::sectional::sectional;
use strand_solve::Solution;
use strand_system::{Model, ReactionKind};

/// Wall-clock times of the phases of one run, in s.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Timing {
    /// Reading and parsing the case file, s.
    pub read: f64,
    /// Validating the case and building the model, s.
    pub build: f64,
    /// The solver, s.
    pub solve: f64,
    /// Post-processing (sectional quantities, reactions), s.
    pub post: f64,
    /// Everything up to writing the results, s.
    pub total: f64,
}

/// The whole `result.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ResultDoc {
    /// Case name.
    pub case: String,
    /// The variant solved (absent for the case itself outside a study; `"base"` for
    /// the case itself in a study).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub variant: Option<String>,
    /// Whether the solve started from the solution of the base case (resampled onto
    /// this variant's rods) instead of the case's own initial guess.
    #[serde(default)]
    pub warm_start: bool,
    /// Newton iterations of the base-case solve this warm start came from.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base_iterations: Option<usize>,
    /// Whether the residual reached the tolerance.
    pub converged: bool,
    /// Why the solver stopped: `converged`, `max_iterations`, `line_search_failed`, `stagnated`, `not_finite`, `subproblem_failed`.
    pub termination: String,
    /// Convergence measure (force residual, edge moments per edge length), N.
    #[serde(rename = "residual_N")]
    pub residual_n: f64,
    /// Largest out-of-balance vertex force, N.
    #[serde(rename = "force_residual_N")]
    pub force_residual_n: f64,
    /// Largest out-of-balance edge moment, N·m.
    #[serde(rename = "moment_residual_Nm")]
    pub moment_residual_nm: f64,
    /// Tolerance on `residual_N`, N.
    #[serde(rename = "tolerance_N")]
    pub tolerance_n: f64,
    /// Every Newton iteration: final solve, coarse level and continuation steps.
    pub iterations: usize,
    /// Iterations whose Hessian needed a shift to become positive definite.
    pub shifted_iterations: usize,
    /// Whether the equilibrium is stable: converged, and no admissible direction (under
    /// the supports, active contacts and joint stops) of negative curvature.
    pub stable: bool,
    /// Directions of negative curvature of the reduced Hessian (0 for a stable state).
    #[serde(default)]
    pub negative_directions: usize,
    /// Neutral (zero-curvature) directions of the reduced Hessian: a symmetry, such as
    /// a buckled round rod free to turn its buckling plane about the chord.
    #[serde(default)]
    pub neutral_directions: usize,
    /// Gauge freedoms removed by construction (round rods free to turn about their own
    /// axis between pins).
    #[serde(default)]
    pub gauge_freedoms: usize,
    /// Round-off floor of the residual at this model's stiffnesses, couplings and
    /// coordinates, N: a solve that can make no further progress within 4 × this floor
    /// is converged at round-off, so a converged `residual_N` can exceed `tolerance_N`,
    /// never 4 × `residual_floor_N`.
    #[serde(default, rename = "residual_floor_N")]
    pub residual_floor_n: f64,
    /// The size of the applied loads (weights and dead loads), N: a residual accepted
    /// at the round-off floor is below 1e-3 of it, else the solve stops as
    /// `floor_above_loads` (0 for a system moved only by its supports).
    #[serde(default, rename = "applied_load_N")]
    pub applied_load_n: f64,
    /// Newton iterations of the final solve on the full model at full load (part of
    /// `iterations`).
    #[serde(default)]
    pub fine_iterations: usize,
    /// Newton iterations of the coarse level of nested iteration (part of `iterations`).
    #[serde(default)]
    pub coarse_iterations: usize,
    /// Steps of the continuation (0: direct solve): load or stiffness steps, and a
    /// release retry (solver setting `release_retry`) counted as one.
    #[serde(default)]
    pub continuation_steps: usize,
    /// Newton iterations of the continuation's steps and of a release retry that did
    /// not converge (part of `iterations`).
    #[serde(default)]
    pub continuation_iterations: usize,
    /// Newton iterations spent leaving unstable equilibria (part of `iterations`).
    #[serde(default)]
    pub escape_iterations: usize,
    /// Total potential energy, J.
    #[serde(rename = "energy_J")]
    pub energy_j: f64,
    /// Number of scalar unknowns.
    pub unknowns: usize,
    /// Wall-clock times, s.
    pub timing_s: Timing,
    /// Per-rod results.
    pub rods: Vec<RodResult>,
    /// Support reactions.
    pub reactions: Vec<ReactionResult>,
    /// Rigid bodies (junctions) at their solved poses.
    #[serde(default)]
    pub bodies: Vec<BodyResult>,
    /// Clips: joint coordinates and reactions (see [`crate::ClipResult`]).
    #[serde(default)]
    pub clips: Vec<crate::ClipResult>,
    /// Active contacts (rod against an environment mesh or another rod), one per
    /// contact point; empty without contact.
    #[serde(default)]
    pub contacts: Vec<ContactResult>,
    /// Smallest surface-to-surface distance of every rod to every obstacle (mesh or
    /// other rod) within the contact search margin.
    #[serde(default)]
    pub clearance: Vec<ClearanceResult>,
    /// The environment meshes: their diagnostics (see [`crate::collect_environment`])
    /// and outlines near the hoses (see [`crate::collect_outlines`]) for drawings such
    /// as the HTML report's projections and 3D view; empty when the case has no
    /// environment.
    #[serde(default)]
    pub environment: Vec<EnvironmentOutline>,
    /// Violated limits (`min_bend_radius`, `min_clearance`; see [`crate::find`]):
    /// empty when every stated limit is respected or none is stated.
    #[serde(default)]
    pub findings: Vec<crate::Finding>,
    /// Where the result comes from: Strand's version, the case file and its hash,
    /// the date and the solver settings (absent in results of older versions).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub provenance: Option<crate::Provenance>,
}

/// One environment part: its outline as line segments in space, for drawings, and
/// its mesh diagnostics.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EnvironmentOutline {
    /// Name of the part (environment mesh).
    pub name: String,
    /// Line segments `[start, end]` of the outline near the hoses (boundary and
    /// feature edges, see [`crate::collect_outlines`]), m, world frame.
    #[serde(default)]
    pub segments_m: Vec<[[f64; 3]; 2]>,
    /// Whether the outline was cut to [`crate::MAX_OUTLINE_SEGMENTS`] (its longest
    /// segments kept).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub truncated: bool,
    /// The surface near the hoses for shaded drawings: polygons (3 to 9 corners,
    /// wound as the mesh) clipped to the same box as the outline, m, world frame (see
    /// [`crate::mesh_surface`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub surface_m: Vec<Vec<[f64; 3]>>,
    /// The cell size of the vertex clustering that decimated `surface_m`, m; absent
    /// when the surface is the mesh's own triangles.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface_cell_m: Option<f64>,
    /// Counts, defects, closedness and bounding box of the mesh.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub diagnostics: Option<crate::MeshDiagnosticsResult>,
}

/// One contact: where a rod touches an obstacle and how hard.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactResult {
    /// The rod that is touched.
    pub rod: String,
    /// Reference arc length of the contact point along the rod, m.
    pub s_m: f64,
    /// Contact point on the rod's centreline, m.
    pub point_m: [f64; 3],
    /// Unit contact normal, from the obstacle towards the rod.
    pub normal: [f64; 3],
    /// Contact force magnitude on the rod (along `normal`), N; never negative.
    #[serde(rename = "force_N")]
    pub force_n: f64,
    /// The obstacle: an environment mesh name or another rod's name.
    pub with: String,
}

/// The smallest surface-to-surface distance between a rod and one obstacle.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ClearanceResult {
    /// The rod.
    pub rod: String,
    /// The obstacle: an environment mesh name or another rod's name.
    pub with: String,
    /// Smallest distance between the rod's surface (outer radius) and the obstacle's
    /// surface, m (0 at contact).
    pub distance_m: f64,
    /// Reference arc length along `rod` where it occurs, m.
    pub s_m: f64,
}

/// A rigid body (junction) at its solved pose.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BodyResult {
    /// Body name.
    pub name: String,
    /// Whether the body is mounted (pose prescribed) rather than free-hanging.
    pub fixed: bool,
    /// Position of the body's origin, m.
    pub position_m: [f64; 3],
    /// Orientation (body frame to world) as a unit quaternion `[w, x, y, z]`.
    pub orientation_quaternion_wxyz: [f64; 4],
    /// The same orientation as a rotation matrix, row by row: its columns are the body
    /// axes in the world frame.
    pub rotation_matrix: [[f64; 3]; 3],
    /// Mass, kg.
    pub mass_kg: f64,
}

/// Per-vertex results of one rod (arrays of `N + 1` entries, vertex 0 first).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RodResult {
    /// Rod name.
    pub name: String,
    /// Reference length, m.
    pub length_m: f64,
    /// Number of segments `N`.
    pub segments: usize,
    /// Reference arc length `s_j`, m.
    pub s_m: Vec<f64>,
    /// Vertex positions `r_j`, m.
    pub position_m: Vec<[f64; 3]>,
    /// Vertex-averaged sectional force `f̄_j`, N.
    #[serde(rename = "force_N")]
    pub force_n: Vec<[f64; 3]>,
    /// Sectional moment `m_j`, N·m.
    #[serde(rename = "moment_Nm")]
    pub moment_nm: Vec<[f64; 3]>,
    /// Tangential (axial) force `f_t`, N.
    #[serde(rename = "tangential_force_N")]
    pub tangential_force_n: Vec<f64>,
    /// Shear force `f_s`, N.
    #[serde(rename = "shear_force_N")]
    pub shear_force_n: Vec<f64>,
    /// Bending moment `m_b`, N·m.
    #[serde(rename = "bending_moment_Nm")]
    pub bending_moment_nm: Vec<f64>,
    /// Torsional moment `m_t`, N·m.
    #[serde(rename = "torsion_Nm")]
    pub torsion_nm: Vec<f64>,
    /// First integral `M̄_j = m_j + r_j × f̄_j`, N·m.
    #[serde(rename = "total_moment_Nm")]
    pub total_moment_nm: Vec<[f64; 3]>,
    /// First integral `H̄_j`, N.
    #[serde(rename = "hamiltonian_N")]
    pub hamiltonian_n: Vec<f64>,
    /// Material curvature `K_j` (components in the section frame), 1/m.
    #[serde(rename = "curvature_1pm")]
    pub curvature_1pm: Vec<[f64; 3]>,
    /// Edge forces `f_{j-1/2}` (`N` entries), N.
    #[serde(rename = "edge_force_N")]
    pub edge_force_n: Vec<[f64; 3]>,
    /// Section frames of the edges (`N` entries) as unit quaternions `[w, x, y, z]`
    /// rotating the world axes onto the section's directors `d1`, `d2`, `d3` (`d3` the
    /// section normal, near the edge's tangent); empty in results written before
    /// they were recorded.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub section_frames_wxyz: Vec<[f64; 4]>,
    /// Outer radius of the section (for contact and drawing), m; absent when the
    /// section does not state one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outer_radius_m: Option<f64>,
    /// Mass of the rod (mass per length × reference length), kg.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass_kg: Option<f64>,
    /// Smallest allowed bend radius of the hose, m, if the case states one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_bend_radius_m: Option<f64>,
    /// Required clearance of the hose to every mesh and every other rod (surface to
    /// surface), m, if the case states one (`min_clearance`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_clearance_m: Option<f64>,
    /// Name of the rod's section in the case file, if known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub section: Option<String>,
    /// Inner radius of a tube section, m (absent for a section given by its
    /// stiffnesses).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inner_radius_m: Option<f64>,
    /// Per vertex, the clearance of the tube there to the nearest environment mesh:
    /// distance from the vertex to the mesh minus the outer radius, m (0 at contact);
    /// `null` where no mesh is within the clearance search
    /// ([`crate::CLEARANCE_SEARCH_M`] or the largest required clearance). Empty
    /// without an environment. Rod–rod distances are in `clearance` only.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub clearance_m: Vec<Option<f64>>,
}

/// Force and moment a support exerts on a rod end.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ReactionResult {
    /// The connector's name (`"<rod>.start"` or `"<rod>.end"` for an unnamed clamp or
    /// pin) or `"<junction>.<port>"`.
    pub name: String,
    /// What supplies the reaction: `"connector"` (a clamp or pin fixed in space),
    /// `"port"` (a port of a junction) or `"clip"` (also listed, with its joint, under
    /// `clips`).
    pub kind: String,
    /// Name of the rod.
    pub rod: String,
    /// `"start"` or `"end"`.
    pub end: String,
    /// Where the support acts (the end vertex), m.
    pub position_m: [f64; 3],
    /// Force on the rod, N.
    #[serde(rename = "force_N")]
    pub force_n: [f64; 3],
    /// Moment on the rod about `position_m`, N·m (zero at a pin).
    #[serde(rename = "moment_Nm")]
    pub moment_nm: [f64; 3],
    /// Largest allowed force magnitude, N, if the case states one (`max_force` of a
    /// named connector).
    #[serde(
        default,
        rename = "max_force_N",
        skip_serializing_if = "Option::is_none"
    )]
    pub max_force_n: Option<f64>,
    /// Largest allowed moment magnitude, N·m, if the case states one (`max_moment`
    /// of a named connector).
    #[serde(
        default,
        rename = "max_moment_Nm",
        skip_serializing_if = "Option::is_none"
    )]
    pub max_moment_nm: Option<f64>,
}

fn arr(v: &nalgebra::Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

fn arrs(vs: &[nalgebra::Vector3<f64>]) -> Vec<[f64; 3]> {
    vs.iter().map(arr).collect()
}

/// Collects the result document of `solution` (a state of `model`). `timing.post` is
/// filled in here; `timing.total` is increased by it.
pub fn collect(case: &str, model: &Model, solution: &Solution, mut timing: Timing) -> ResultDoc {
    let started = std::time::Instant::now();
    let system = model.system();
    let report = &solution.report;
    let rods = system
        .rods
        .iter()
        .enumerate()
        .map(|(r, spec)| {
            let state = &solution.state.rods[r];
            let s = sectional(&spec.rod, state, &model.boundary_frames(r, &solution.state));
            RodResult {
                name: spec.name.clone(),
                length_m: spec.rod.length(),
                segments: spec.rod.segments(),
                s_m: spec.rod.arc_lengths(),
                position_m: arrs(&state.positions),
                force_n: arrs(&s.forces),
                moment_nm: arrs(&s.moments),
                tangential_force_n: s.tangential_force,
                shear_force_n: s.shear_force,
                bending_moment_nm: s.bending_moment,
                torsion_nm: s.torsion,
                total_moment_nm: arrs(&s.total_moment),
                hamiltonian_n: s.hamiltonian,
                curvature_1pm: arrs(&s.curvatures),
                edge_force_n: arrs(&s.edge_forces),
                section_frames_wxyz: state.frames.iter().map(|q| [q.w, q.i, q.j, q.k]).collect(),
                outer_radius_m: Some(spec.rod.section().outer_radius).filter(|r| *r > 0.0),
                mass_kg: Some(spec.rod.section().mass_per_length * spec.rod.length()),
                min_bend_radius_m: None,
                min_clearance_m: None,
                section: None,
                inner_radius_m: None,
                clearance_m: Vec::new(),
            }
        })
        .collect();
    let all_reactions = model.reactions(&solution.state);
    let clips = crate::clips::collect_clips(model, solution, &all_reactions);
    let reactions = all_reactions
        .into_iter()
        .map(|r| ReactionResult {
            name: r.name,
            kind: match r.kind {
                ReactionKind::Connector => "connector",
                ReactionKind::Port => "port",
                ReactionKind::Clip => "clip",
            }
            .to_string(),
            rod: system.rods[r.rod].name.clone(),
            end: if r.at_end { "end" } else { "start" }.to_string(),
            position_m: arr(&r.position),
            force_n: arr(&r.force),
            moment_nm: arr(&r.moment),
            max_force_n: None,
            max_moment_nm: None,
        })
        .collect();
    let bodies = system
        .bodies
        .iter()
        .zip(&solution.state.bodies)
        .map(|(spec, pose)| {
            let q = pose.orientation;
            let m = q.to_rotation_matrix().into_inner();
            BodyResult {
                name: spec.name.clone(),
                fixed: spec.fixed,
                position_m: arr(&pose.position),
                orientation_quaternion_wxyz: [q.w, q.i, q.j, q.k],
                rotation_matrix: [0, 1, 2].map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]]),
                mass_kg: spec.mass,
            }
        })
        .collect();
    let termination = match serde_json::to_value(report.termination) {
        Ok(serde_json::Value::String(s)) => s,
        _ => format!("{:?}", report.termination),
    };
    timing.post = started.elapsed().as_secs_f64();
    timing.total += timing.post;
    ResultDoc {
        case: case.to_string(),
        variant: None,
        warm_start: false,
        base_iterations: None,
        converged: report.converged,
        termination,
        residual_n: report.residual.combined_n,
        force_residual_n: report.residual.force_n,
        moment_residual_nm: report.residual.moment_nm,
        tolerance_n: report.tolerance_n,
        iterations: report.iterations,
        shifted_iterations: report.shifted_iterations,
        stable: report.stable,
        negative_directions: report.negative_directions,
        neutral_directions: report.neutral_directions,
        gauge_freedoms: report.gauge_freedoms,
        residual_floor_n: report.residual_floor_n,
        applied_load_n: report.applied_load_n,
        fine_iterations: report.fine_iterations,
        coarse_iterations: report.coarse_iterations,
        continuation_steps: report.continuation_steps,
        continuation_iterations: report.continuation_iterations,
        escape_iterations: report.escape_iterations,
        energy_j: report.energy_j,
        unknowns: report.unknowns,
        timing_s: timing,
        rods,
        reactions,
        bodies,
        clips,
        contacts: Vec::new(),
        clearance: Vec::new(),
        environment: Vec::new(),
        findings: Vec::new(),
        provenance: None,
    }
}

/// Names the reactions of connector-held rod ends after their connectors:
/// `names[r]` holds the connector names of rod `r`'s start and end (`None` keeps the
/// default `"<rod>.start"`/`"<rod>.end"`), e.g. from a case's named connectors.
pub fn name_connectors(doc: &mut ResultDoc, names: &[[Option<String>; 2]]) {
    for reaction in &mut doc.reactions {
        if reaction.kind != "connector" {
            continue;
        }
        let Some(r) = doc.rods.iter().position(|rod| rod.name == reaction.rod) else {
            continue;
        };
        let side = usize::from(reaction.end == "end");
        if let Some(Some(name)) = names.get(r).map(|n| &n[side]) {
            reaction.name.clone_from(name);
        }
    }
}
