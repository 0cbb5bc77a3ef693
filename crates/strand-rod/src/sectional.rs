//! Sectional quantities of a configuration (paper eqs. 4, 15–16 and §3).
//!
//! - edge forces `f_{j-1/2} = R_{j-1/2} C_Γ ΔΓ_{j-1/2}` (force of the part beyond the
//!   section on the part before it, N);
//! - vertex moments `m_j` (N·m): the exact spatial moment the vertex element transmits,
//!   `m_j = R_{j+1/2} ∂W_j/∂β = −R_{j-1/2} ∂W_j/∂α`. It equals the paper's
//!   `R_{j+1/2} C_K ΔK_j` whenever `C_K ΔK_j` is parallel to `K_j` (planar bending,
//!   isotropic sections) and differs by `O(h̄²|K|²)` otherwise; with it the discrete
//!   balance `m_{j+1} − m_j + (r_{j+1} − r_j) × f_{j+1/2} + h μ = 0` of eq. (16) holds
//!   exactly at an equilibrium;
//! - vertex-averaged forces `f̄_j = (h_{j-1/2} f_{j-1/2} + h_{j+1/2} f_{j+1/2}) / (2 h̄_j)`
//!   (at the end vertices the adjacent edge force corrected by the end's lumped load,
//!   [`BoundaryFrames::end_loads`]), their tangential and shear parts, bending and
//!   torsional moments;
//! - the first integrals `M̄_j = m_j + r_j × f̄_j` and `H̄_j`.

use nalgebra::{UnitQuaternion, Vector3};

use crate::element::{BendTwist, StretchShear, bend_twist_gradient};
use crate::{Rod, RodState};

/// Boundary frames of a rod: `Some` where an end is attached with its frame (clamp,
/// port, clip), `None` at a free or pinned end (no boundary curvature term).
#[derive(Clone, Debug, Default)]
pub struct BoundaryFrames {
    /// Boundary frame `q_0` at vertex 0.
    pub start: Option<UnitQuaternion<f64>>,
    /// Boundary frame `q_N` at vertex N.
    pub end: Option<UnitQuaternion<f64>>,
    /// Frames of clips at interior vertices `(vertex, frame)`: the curvature term there
    /// is split into two half-cells around the clip frame.
    pub clips: Vec<(usize, UnitQuaternion<f64>)>,
    /// External forces in N (world frame) lumped at vertex 0 and vertex N that the
    /// sectional force at the end includes: the half cell's weight `h̄ ρ_L g`, plus the
    /// dead end load where a support holds the end. The vertex-averaged force at an end
    /// is then the continuum force at the end section, `f̄_0 = f_{1/2} + p_0` and
    /// `f̄_N = f_{N−1/2} − p_N`: the support's reaction at a held end (second-order
    /// accurate, where the adjacent edge force alone is off by `w h/2`), the applied
    /// end load at a free end. Zero (the default) gives the adjacent edge forces.
    pub end_loads: [Vector3<f64>; 2],
}

/// The frames adjacent to vertex `j`: `(q_a, q_b)` when the vertex carries a curvature
/// term, `None` at a free or pinned end.
pub fn vertex_frames<'a>(
    state: &'a RodState,
    boundary: &'a BoundaryFrames,
    vertex: usize,
) -> Option<(&'a UnitQuaternion<f64>, &'a UnitQuaternion<f64>)> {
    let n = state.frames.len();
    match vertex {
        0 => boundary.start.as_ref().map(|q0| (q0, &state.frames[0])),
        j if j == n => boundary.end.as_ref().map(|qn| (&state.frames[n - 1], qn)),
        j => Some((&state.frames[j - 1], &state.frames[j])),
    }
}

/// The bend–twist element of vertex `j`, as the sectional quantities define it: at a
/// clip of frame `clip`, the half cell after the clip frame (the moment the rod
/// carries just beyond the clip; the clip's own moment is its reaction); elsewhere the
/// frames either side with the vertex's weight. `None` at a free or pinned end.
pub fn vertex_bend_twist<'a>(
    rod: &'a Rod,
    state: &'a RodState,
    boundary: &'a BoundaryFrames,
    j: usize,
    clip: Option<&'a UnitQuaternion<f64>>,
    stiffness: &'a Vector3<f64>,
) -> Option<BendTwist<'a>> {
    let (frames, weight) = match clip {
        Some(q) => (Some((q, &state.frames[j])), 0.5 * rod.edge_length(j)),
        None => (vertex_frames(state, boundary, j), rod.vertex_weight(j)),
    };
    frames.map(|(frame_a, frame_b)| BendTwist {
        frame_a,
        frame_b,
        weight,
        stiffness,
        rest_curvature: rod.rest_curvature(j),
    })
}

/// The edge element of edge `e`.
pub fn edge_element<'a>(
    rod: &'a Rod,
    state: &'a RodState,
    stiffness: &'a Vector3<f64>,
    e: usize,
) -> StretchShear<'a> {
    StretchShear {
        edge_vector: state.edge_vector(e),
        frame: &state.frames[e],
        length: rod.edge_length(e),
        stiffness,
        rest_strain: rod.rest_strain(e),
    }
}

/// Sectional quantities of one rod, per edge and per vertex.
#[derive(Clone, Debug, Default)]
pub struct Sectional {
    /// Spatial edge forces `f_{j-1/2}` in N.
    pub edge_forces: Vec<Vector3<f64>>,
    /// Material strains `Γ_{j-1/2}`.
    pub strains: Vec<Vector3<f64>>,
    /// Material curvatures `K_j` in 1/m (zero at a free or pinned end).
    pub curvatures: Vec<Vector3<f64>>,
    /// Spatial vertex moments `m_j` in N·m.
    pub moments: Vec<Vector3<f64>>,
    /// Vertex-averaged spatial forces `f̄_j` in N.
    pub forces: Vec<Vector3<f64>>,
    /// Unit tangents at the vertices (geodesic mid frame's `a3`; the boundary frame's at
    /// an attached end, the edge's at a free end).
    pub tangents: Vec<Vector3<f64>>,
    /// Tangential force `f_t = ⟨f̄, t⟩` in N.
    pub tangential_force: Vec<f64>,
    /// Shear force `f_s = |f̄ − f_t t|` in N.
    pub shear_force: Vec<f64>,
    /// Bending moment `m_b = |m − m_t t|` in N·m.
    pub bending_moment: Vec<f64>,
    /// Torsional moment `m_t = ⟨m, t⟩` in N·m.
    pub torsion: Vec<f64>,
    /// First integral `M̄_j = m_j + r_j × f̄_j` in N·m (constant without distributed loads).
    pub total_moment: Vec<Vector3<f64>>,
    /// First integral `H̄_j = ⟨M,K⟩ − V_M + avg(⟨F,Γ⟩ − V_F)` in N (paper §3; constant
    /// up to discretisation error without distributed loads).
    pub hamiltonian: Vec<f64>,
}

/// Computes all sectional quantities of a rod configuration.
pub fn sectional(rod: &Rod, state: &RodState, boundary: &BoundaryFrames) -> Sectional {
    let n = rod.segments();
    let c_gamma = rod.section().strain_stiffness();
    let c_kappa = rod.section().curvature_stiffness();
    let vectors = || Vec::with_capacity(n + 1);
    let numbers = || Vec::with_capacity(n + 1);
    // Every list sized once (grown one push at a time, each was reallocated repeatedly).
    let mut out = Sectional {
        edge_forces: Vec::with_capacity(n),
        strains: Vec::with_capacity(n),
        curvatures: vectors(),
        moments: vectors(),
        forces: vectors(),
        tangents: vectors(),
        tangential_force: numbers(),
        shear_force: numbers(),
        bending_moment: numbers(),
        torsion: numbers(),
        total_moment: vectors(),
        hamiltonian: numbers(),
    };
    let mut edge_hamiltonian = Vec::with_capacity(n);
    for e in 0..n {
        let element = edge_element(rod, state, &c_gamma, e);
        let gamma = element.strain();
        let force_material = element.material_force();
        let delta = gamma - rod.rest_strain(e);
        edge_hamiltonian.push(force_material.dot(&gamma) - 0.5 * delta.dot(&force_material));
        out.edge_forces.push(state.frames[e] * force_material);
        out.strains.push(gamma);
    }
    // Clips sorted by vertex (stable: the first clip of a vertex wins, as a scan would).
    let mut clips = boundary.clips.clone();
    clips.sort_by_key(|(vertex, _)| *vertex);
    for j in 0..=n {
        let weight = rod.vertex_weight(j);
        // At a clip, the half-cell after the clip frame: the moment the rod carries just
        // beyond the clip (the clip's own moment is its reaction).
        let first = clips.partition_point(|(vertex, _)| *vertex < j);
        let clip = clips
            .get(first)
            .filter(|(vertex, _)| *vertex == j)
            .map(|(_, q)| q);
        let (curvature, moment, vertex_hamiltonian, tangent) =
            match vertex_bend_twist(rod, state, boundary, j, clip, &c_kappa) {
                Some(element) => {
                    let (q_a, q_b) = (element.frame_a, element.frame_b);
                    let derivatives = bend_twist_gradient(&element);
                    let curvature = element.curvature();
                    let delta = curvature - rod.rest_curvature(j);
                    let m_material = c_kappa.component_mul(&delta);
                    let moment = q_b * derivatives.gradient.fixed_rows::<3>(3).into_owned();
                    let tangent_frame = match j {
                        0 => *q_a,
                        j if j == n => *q_b,
                        _ if clip.is_some() => *q_a,
                        _ => crate::so3::mid_frame(q_a, q_b),
                    };
                    let h = m_material.dot(&curvature) - 0.5 * m_material.dot(&delta);
                    (curvature, moment, h, tangent_frame * Vector3::z())
                }
                None => {
                    let edge = if j == 0 { 0 } else { n - 1 };
                    (
                        Vector3::zeros(),
                        Vector3::zeros(),
                        0.0,
                        state.frames[edge] * Vector3::z(),
                    )
                }
            };
        let (mut force, mut edge_h) = (Vector3::zeros(), 0.0);
        for e in [j.wrapping_sub(1), j] {
            if e < n {
                let share = rod.edge_length(e) / (2.0 * weight);
                force += share * out.edge_forces[e];
                edge_h += share * edge_hamiltonian[e];
            }
        }
        if j == 0 {
            force += boundary.end_loads[0];
        }
        if j == n {
            force -= boundary.end_loads[1];
        }
        let f_t = force.dot(&tangent);
        let m_t = moment.dot(&tangent);
        out.curvatures.push(curvature);
        out.moments.push(moment);
        out.forces.push(force);
        out.tangents.push(tangent);
        out.tangential_force.push(f_t);
        out.shear_force.push((force - f_t * tangent).norm());
        out.torsion.push(m_t);
        out.bending_moment.push((moment - m_t * tangent).norm());
        out.total_moment
            .push(moment + state.positions[j].cross(&force));
        out.hamiltonian.push(vertex_hamiltonian + edge_h);
    }
    out
}
