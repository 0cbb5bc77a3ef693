//! The exact first-order change of the sectional quantities at every vertex
//! ([`crate::sectional_at::sectional_at`]: the vertex-averaged force, the vertex
//! moment, the curvature) along a tangent of the configuration and of the rod's
//! reference data (edge lengths, rest strains and curvatures, stiffnesses, end
//! loads): forward-mode derivatives written out from the elements' closed forms, the
//! bend–twist element's second derivatives taken from its contracted Hessian
//! ([`RelativeRotation::contracted_hessian`]). The configuration's part is linear in
//! the tangent, so a rod is linearised once ([`SectionalLinearisation::new`]) and each
//! tangent costs a few small matrix products per vertex: what a sensitivity needs to
//! differentiate its outputs without evaluating them along a path.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use crate::element::RelativeRotation;
use crate::sectional::{BoundaryFrames, vertex_frames};
use crate::sectional_at::VertexSectional;
use crate::{Rod, RodState};

mod size_rates;
pub use size_rates::{SectionalSize, SizeRates};

/// A tangent of a rod's configuration and reference data (per unit of whatever moves
/// them, e.g. a design parameter): each frame `q` moves as `q ⊗ exp(t ω)` (material
/// increment `ω`, rad), each vertex `r` as `r + t dr`, each reference number `x` as
/// `x + t dx`.
#[derive(Clone, Debug, PartialEq)]
pub struct RodTangent {
    /// `dr` of every vertex (`0..=N`), m (held vertices included: they follow their
    /// supports).
    pub positions: Vec<Vector3<f64>>,
    /// `ω` of every edge frame, rad.
    pub frames: Vec<Vector3<f64>>,
    /// `ω` of the boundary frames at the start and the end (ignored where the rod has
    /// none), rad.
    pub boundary: [Vector3<f64>; 2],
    /// `dh` of every reference edge length, m.
    pub edge_lengths: Vec<f64>,
    /// `dΓ0` of every edge's rest strain.
    pub rest_strains: Vec<Vector3<f64>>,
    /// `dK0` of every vertex's rest curvature, 1/m.
    pub rest_curvatures: Vec<Vector3<f64>>,
    /// `d diag(C_Γ)`, N.
    pub strain_stiffness: Vector3<f64>,
    /// `d diag(C_K)`, N·m².
    pub curvature_stiffness: Vector3<f64>,
    /// `d` of the loads lumped at the end vertices ([`BoundaryFrames::end_loads`]), N.
    pub end_loads: [Vector3<f64>; 2],
}

impl RodTangent {
    /// The zero tangent of a rod of `segments` edges.
    pub fn zero(segments: usize) -> Self {
        Self {
            positions: vec![Vector3::zeros(); segments + 1],
            frames: vec![Vector3::zeros(); segments],
            boundary: [Vector3::zeros(); 2],
            edge_lengths: vec![0.0; segments],
            rest_strains: vec![Vector3::zeros(); segments],
            rest_curvatures: vec![Vector3::zeros(); segments + 1],
            strain_stiffness: Vector3::zeros(),
            curvature_stiffness: Vector3::zeros(),
            end_loads: [Vector3::zeros(); 2],
        }
    }
}

/// One edge at the base configuration.
#[derive(Clone, Debug)]
struct EdgeBase {
    rotation: Matrix3<f64>,
    /// `Γ`.
    strain: Vector3<f64>,
    /// `Γ − Γ0`.
    delta: Vector3<f64>,
    /// `F = C_Γ (Γ − Γ0)`, N.
    force_material: Vector3<f64>,
    length: f64,
}

/// One vertex's bend–twist element at the base configuration.
#[derive(Clone, Debug)]
struct VertexBase {
    /// `φ` and `∂φ/∂(α, β)`.
    phi: Vector3<f64>,
    jacobian: SMatrix<f64, 3, 6>,
    /// `∇²(M·φ)` in `(α, β)`, `M` the material moment.
    hessian: SMatrix<f64, 6, 6>,
    /// `Jᵀ M`, N·m.
    gradient: SVector<f64, 6>,
    /// `K − K0`, 1/m.
    delta: Vector3<f64>,
    rotation_a: Matrix3<f64>,
    rotation_b: Matrix3<f64>,
}

/// A rod linearised at its configuration: the base sectional quantities of every
/// vertex and what their first-order changes need.
#[derive(Clone, Debug)]
pub struct SectionalLinearisation {
    c_gamma: Vector3<f64>,
    c_kappa: Vector3<f64>,
    edges: Vec<EdgeBase>,
    vertices: Vec<Option<VertexBase>>,
    weights: Vec<f64>,
    end_loads: [Vector3<f64>; 2],
}

/// The first-order change of one end's reaction terms
/// ([`SectionalLinearisation::end_terms_tangent`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EndTerms {
    /// The end edge's term of the end vertex's force: `−f_{1/2}` at the start,
    /// `f_{N−1/2}` at the end (the edge element's gradient at the end vertex), N.
    pub edge_force: Vector3<f64>,
    /// The boundary frame's spatial moment `R ∂W/∂α` at the start, `R ∂W/∂β` at the
    /// end (zero without a boundary frame), N·m.
    pub moment: Vector3<f64>,
}

impl SectionalLinearisation {
    /// Linearises `rod` in `state` with its `boundary` frames; `None` where the
    /// boundary has clips (their half cells are not linearised).
    pub fn new(rod: &Rod, state: &RodState, boundary: &BoundaryFrames) -> Option<Self> {
        if !boundary.clips.is_empty() {
            return None;
        }
        let n = rod.segments();
        let c_gamma = rod.section().strain_stiffness();
        let c_kappa = rod.section().curvature_stiffness();
        let edges = (0..n)
            .map(|e| {
                let length = rod.edge_length(e);
                let rotation = state.frames[e].to_rotation_matrix().into_inner();
                let strain = rotation.transpose() * state.edge_vector(e) / length;
                let delta = strain - rod.rest_strain(e);
                EdgeBase {
                    rotation,
                    strain,
                    delta,
                    force_material: c_gamma.component_mul(&delta),
                    length,
                }
            })
            .collect();
        let vertices = (0..=n)
            .map(|j| {
                vertex_frames(state, boundary, j).map(|(q_a, q_b)| {
                    let weight = rod.vertex_weight(j);
                    let rel = RelativeRotation::new(q_a, q_b);
                    let delta = rel.phi / weight - rod.rest_curvature(j);
                    let moment = c_kappa.component_mul(&delta);
                    VertexBase {
                        phi: rel.phi,
                        jacobian: rel.jacobian,
                        hessian: rel.contracted_hessian(&moment),
                        gradient: rel.jacobian.transpose() * moment,
                        delta,
                        rotation_a: q_a.to_rotation_matrix().into_inner(),
                        rotation_b: q_b.to_rotation_matrix().into_inner(),
                    }
                })
            })
            .collect();
        Some(Self {
            c_gamma,
            c_kappa,
            edges,
            vertices,
            weights: (0..=n).map(|j| rod.vertex_weight(j)).collect(),
            end_loads: boundary.end_loads,
        })
    }

    /// The number of edges.
    pub fn segments(&self) -> usize {
        self.edges.len()
    }

    /// The spatial force `f = R F` of edge `e` (N) and its change along `tangent`.
    fn edge_force(&self, e: usize, tangent: &RodTangent) -> (Vector3<f64>, Vector3<f64>) {
        let b = &self.edges[e];
        let omega = &tangent.frames[e];
        let d_edge = tangent.positions[e + 1] - tangent.positions[e];
        // Γ = Rᵀ Δr / h with R → R exp([tω]×): dΓ = Rᵀ dΔr / h − ω × Γ − Γ dh / h.
        let d_strain = b.rotation.transpose() * d_edge / b.length
            - omega.cross(&b.strain)
            - b.strain * (tangent.edge_lengths[e] / b.length);
        let d_force_material = tangent.strain_stiffness.component_mul(&b.delta)
            + self
                .c_gamma
                .component_mul(&(d_strain - tangent.rest_strains[e]));
        let force = b.rotation * b.force_material;
        let d_force = b.rotation * (omega.cross(&b.force_material) + d_force_material);
        (force, d_force)
    }

    /// `ω_a, ω_b` of vertex `j`'s element and the change of its weight.
    fn vertex_increments(&self, j: usize, tangent: &RodTangent) -> (SVector<f64, 6>, f64) {
        let n = self.segments();
        let (a, b) = match j {
            0 => (tangent.boundary[0], tangent.frames[0]),
            j if j == n => (tangent.frames[n - 1], tangent.boundary[1]),
            j => (tangent.frames[j - 1], tangent.frames[j]),
        };
        let before = if j > 0 {
            tangent.edge_lengths[j - 1]
        } else {
            0.0
        };
        let after = tangent.edge_lengths.get(j).copied().unwrap_or(0.0);
        let mut omega = SVector::<f64, 6>::zeros();
        omega.fixed_rows_mut::<3>(0).copy_from(&a);
        omega.fixed_rows_mut::<3>(3).copy_from(&b);
        (omega, 0.5 * (before + after))
    }

    /// The change of vertex `j`'s curvature `K` (1/m) and of its element's gradient
    /// `Jᵀ M` taken along the moving frames (each block in its own frame's chart at
    /// the moved point), with the increments `omega`; `None` without a curvature term.
    fn vertex_changes(&self, j: usize, tangent: &RodTangent) -> Option<VertexChanges<'_>> {
        let v = self.vertices[j].as_ref()?;
        let (omega, d_weight) = self.vertex_increments(j, tangent);
        let w = self.weights[j];
        let d_phi = v.jacobian * omega;
        let d_curvature = d_phi / w - v.phi * (d_weight / (w * w));
        let d_moment = tangent.curvature_stiffness.component_mul(&v.delta)
            + self
                .c_kappa
                .component_mul(&(d_curvature - tangent.rest_curvatures[j]));
        // g = Jᵀ M in the chart q ⊗ exp(x) of each frame: moved to q ⊗ exp(tω), the
        // chart's coordinates are x = tω + α + ½ tω × α + …, so the gradient at the
        // moved point changes by ∇²(M·φ) ω − ½ ω × g (per frame) and Jᵀ dM.
        let mut d_gradient = v.hessian * omega + v.jacobian.transpose() * d_moment;
        for block in [0, 3] {
            let w_block: Vector3<f64> = omega.fixed_rows::<3>(block).into_owned();
            let g_block: Vector3<f64> = v.gradient.fixed_rows::<3>(block).into_owned();
            let correction = -0.5 * w_block.cross(&g_block);
            let mut rows = d_gradient.fixed_rows_mut::<3>(block);
            rows += correction;
        }
        Some(VertexChanges {
            base: v,
            omega,
            d_curvature,
            d_gradient,
        })
    }

    /// The base sectional quantities of vertex `j` and their change along `tangent`
    /// (`(value, derivative)`, the units of [`VertexSectional`] and per unit of the
    /// tangent).
    pub fn vertex_tangent(
        &self,
        j: usize,
        tangent: &RodTangent,
    ) -> (VertexSectional, VertexSectional) {
        let n = self.segments();
        let edges = [j.wrapping_sub(1), j].map(|e| (e < n).then(|| self.edge_force(e, tangent)));
        self.vertex_with_edges(j, tangent, edges)
    }

    /// [`SectionalLinearisation::vertex_tangent`] with the forces `(f, df)` of the
    /// vertex's edges before and after it (`None` beyond an end) given.
    fn vertex_with_edges(
        &self,
        j: usize,
        tangent: &RodTangent,
        edges: [Option<(Vector3<f64>, Vector3<f64>)>; 2],
    ) -> (VertexSectional, VertexSectional) {
        let n = self.segments();
        let w = self.weights[j];
        let (_, d_weight) = self.vertex_increments(j, tangent);
        let (mut force, mut d_force) = (Vector3::zeros(), Vector3::zeros());
        for (e, edge) in [j.wrapping_sub(1), j].into_iter().zip(edges) {
            if let Some((f, df)) = edge {
                let h = self.edges[e].length;
                let share = h / (2.0 * w);
                let d_share = tangent.edge_lengths[e] / (2.0 * w) - h * d_weight / (2.0 * w * w);
                force += share * f;
                d_force += d_share * f + share * df;
            }
        }
        if j == 0 {
            force += self.end_loads[0];
            d_force += tangent.end_loads[0];
        }
        if j == n {
            force -= self.end_loads[1];
            d_force -= tangent.end_loads[1];
        }
        let (moment, d_moment, curvature, d_curvature) = match self.vertex_changes(j, tangent) {
            Some(VertexChanges {
                base: v,
                omega,
                d_curvature,
                d_gradient,
            }) => {
                let g_b: Vector3<f64> = v.gradient.fixed_rows::<3>(3).into_owned();
                let dg_b: Vector3<f64> = d_gradient.fixed_rows::<3>(3).into_owned();
                let w_b: Vector3<f64> = omega.fixed_rows::<3>(3).into_owned();
                (
                    v.rotation_b * g_b,
                    v.rotation_b * (w_b.cross(&g_b) + dg_b),
                    v.phi / w,
                    d_curvature,
                )
            }
            None => (
                Vector3::zeros(),
                Vector3::zeros(),
                Vector3::zeros(),
                Vector3::zeros(),
            ),
        };
        (
            VertexSectional {
                force,
                moment,
                curvature,
            },
            VertexSectional {
                force: d_force,
                moment: d_moment,
                curvature: d_curvature,
            },
        )
    }

    /// The change along `tangent` of the terms of the reaction at the start
    /// (`at_end == false`) or the end of the rod: the end edge's force term and the
    /// boundary frame's moment (`(value, derivative)`); the lumped loads are the
    /// caller's.
    pub fn end_terms_tangent(&self, at_end: bool, tangent: &RodTangent) -> (EndTerms, EndTerms) {
        let n = self.segments();
        let (vertex, edge, sign) = if at_end {
            (n, n - 1, 1.0)
        } else {
            (0, 0, -1.0)
        };
        let (f, df) = self.edge_force(edge, tangent);
        let (moment, d_moment) = match self.vertex_changes(vertex, tangent) {
            Some(VertexChanges {
                base: v,
                omega,
                d_gradient,
                ..
            }) => {
                let (block, rotation) = if at_end {
                    (3, &v.rotation_b)
                } else {
                    (0, &v.rotation_a)
                };
                let g: Vector3<f64> = v.gradient.fixed_rows::<3>(block).into_owned();
                let dg: Vector3<f64> = d_gradient.fixed_rows::<3>(block).into_owned();
                let w: Vector3<f64> = omega.fixed_rows::<3>(block).into_owned();
                (rotation * g, rotation * (w.cross(&g) + dg))
            }
            None => (Vector3::zeros(), Vector3::zeros()),
        };
        (
            EndTerms {
                edge_force: sign * f,
                moment,
            },
            EndTerms {
                edge_force: sign * df,
                moment: d_moment,
            },
        )
    }
}

/// What [`SectionalLinearisation::vertex_changes`] gives for one vertex.
struct VertexChanges<'a> {
    /// The vertex's base quantities.
    base: &'a VertexBase,
    /// The increments of the frames either side (two blocks of 3, rad per unit).
    omega: SVector<f64, 6>,
    /// The change of the curvature `K`, 1/m per unit.
    d_curvature: Vector3<f64>,
    /// The change of the element's gradient `Jᵀ M` along the moving frames.
    d_gradient: SVector<f64, 6>,
}

#[cfg(test)]
mod tests;
