//! The first-order change of one size of every vertex's sectional quantities (`|f̄|`,
//! `|m|` or the bending curvature `|K_⊥|`) along a tangent, as one dot product per
//! vertex: the size's rate is linear in the tangent, so its coefficients (the adjoint
//! of [`SectionalLinearisation::vertex_tangent`] contracted with the unit direction
//! of the base value) are taken once per linearisation ([`SectionalLinearisation::size_rates`])
//! and each tangent costs a few dozen multiplications per vertex instead of the full
//! vector change. What a sensitivity's one-sided check of a peak needs: the rate of
//! every vertex's size, to rule out the vertices that cannot overtake the peak.

use nalgebra::{SVector, Vector3};

use super::{RodTangent, SectionalLinearisation};
use crate::sectional_at::VertexSectional;

/// Which size of a vertex's sectional quantities is compared between vertices (the
/// largest wins for a peak, the smallest curvature radius is the largest curvature).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SectionalSize {
    /// `|f̄_j|`, N.
    Force,
    /// `|m_j|`, N·m.
    Moment,
    /// The bending curvature `|K_⊥| = hypot(K₁, K₂)`, 1/m.
    Curvature,
}

impl SectionalSize {
    /// The vector whose norm is the size (the curvature's twist component left out).
    pub fn vector(self, s: &VertexSectional) -> Vector3<f64> {
        match self {
            Self::Force => s.force,
            Self::Moment => s.moment,
            Self::Curvature => Vector3::new(s.curvature.x, s.curvature.y, 0.0),
        }
    }

    /// The size of `s`, in the units of the quantity.
    pub fn of(self, s: &VertexSectional) -> f64 {
        self.vector(s).norm()
    }

    /// The rate of the size at `value` along the change `d` of the sectional
    /// quantities, per unit of the tangent, and whether it is one: at a zero size,
    /// where the size is not differentiable, a bound of its growth
    /// (`||a + b| − |a|| ≤ |b|`).
    pub fn rate(self, value: &VertexSectional, d: &VertexSectional) -> (f64, bool) {
        let (v, dv) = (self.vector(value), self.vector(d));
        let size = v.norm();
        if size > 0.0 {
            (v.dot(&dv) / size, true)
        } else {
            (dv.norm(), false)
        }
    }
}

/// The coefficients of one edge's inputs in a vertex's size rate.
#[derive(Clone, Copy, Debug, Default)]
struct EdgeRow {
    /// On the change of the edge vector `dr_{e+1} − dr_e` (per m).
    offset: Vector3<f64>,
    /// On the edge frame's increment `ω_e` (per rad).
    frame: Vector3<f64>,
    /// On the reference length's change `dh_e` (per m).
    length: f64,
    /// On the rest strain's change `dΓ0_e`.
    rest_strain: Vector3<f64>,
}

/// The coefficients of one vertex's size rate.
#[derive(Clone, Debug)]
struct SizeRow {
    /// The edges before and after the vertex (zero beyond an end; force only).
    edges: [EdgeRow; 2],
    /// On the increments `(ω_a, ω_b)` of the frames either side (moment, curvature).
    frames: SVector<f64, 6>,
    /// On the change of the vertex weight `dw = (dh_{j−1} + dh_j)/2` (per m).
    weight: f64,
    /// On the stiffness' change (`d diag(C_Γ)` for the force, `d diag(C_K)` for
    /// the moment).
    stiffness: Vector3<f64>,
    /// On the rest curvature's change `dK0_j` (moment only).
    rest_curvature: Vector3<f64>,
    /// On the change of the end load lumped here (force at an end vertex only).
    end_load: Vector3<f64>,
}

/// The rate coefficients of one size at every vertex of a linearised rod
/// ([`SectionalLinearisation::size_rates`]).
#[derive(Clone, Debug)]
pub struct SizeRates {
    size: SectionalSize,
    /// The base size of every vertex.
    sizes: Vec<f64>,
    /// Per vertex; `None` where the size is zero (the rate is then a bound, taken from
    /// the full change) or where the vertex has no curvature term (its moment and
    /// curvature stay zero).
    rows: Vec<Option<SizeRow>>,
}

impl SectionalLinearisation {
    /// The base sectional quantities of every vertex.
    pub fn values(&self) -> Vec<VertexSectional> {
        let zero = RodTangent::zero(self.segments());
        (0..=self.segments())
            .map(|j| self.vertex_tangent(j, &zero).0)
            .collect()
    }

    /// The rate coefficients of `size` at every vertex, `values` the base sectional
    /// quantities ([`SectionalLinearisation::values`]).
    pub fn size_rates(&self, size: SectionalSize, values: &[VertexSectional]) -> SizeRates {
        let sizes: Vec<f64> = values.iter().map(|v| size.of(v)).collect();
        let rows = (0..=self.segments())
            .map(|j| {
                let v = size.vector(&values[j]);
                let norm = sizes[j];
                if norm == 0.0 {
                    return None;
                }
                let unit = v / norm;
                match size {
                    SectionalSize::Force => Some(self.force_row(j, &unit)),
                    SectionalSize::Moment => self.moment_row(j, &unit),
                    SectionalSize::Curvature => self.curvature_row(j, &unit),
                }
            })
            .collect();
        SizeRates { size, sizes, rows }
    }

    /// `f̂ · df̄_j` as coefficients, `unit` the direction of `f̄_j`.
    fn force_row(&self, j: usize, unit: &Vector3<f64>) -> SizeRow {
        let n = self.segments();
        let w = self.weights[j];
        let mut row = SizeRow::zero();
        for (k, e) in [j.wrapping_sub(1), j].into_iter().enumerate() {
            if e >= n {
                continue;
            }
            let b = &self.edges[e];
            let h = b.length;
            let share = h / (2.0 * w);
            // f̂·f_e, and a = Rᵀ f̂ in the edge's material frame.
            let along = unit.dot(&(b.rotation * b.force_material));
            let a = b.rotation.transpose() * unit;
            let ca = self.c_gamma.component_mul(&a);
            row.edges[k] = EdgeRow {
                offset: share * (b.rotation * ca) / h,
                frame: share * (b.force_material.cross(&a) - b.strain.cross(&ca)),
                length: -share * ca.dot(&b.strain) / h + along / (2.0 * w),
                rest_strain: -share * ca,
            };
            row.weight -= along * h / (2.0 * w * w);
            row.stiffness += share * a.component_mul(&b.delta);
        }
        if j == 0 {
            row.end_load = *unit;
        } else if j == n {
            row.end_load = -unit;
        }
        row
    }

    /// `m̂ · dm_j` as coefficients, `unit` the direction of `m_j`.
    fn moment_row(&self, j: usize, unit: &Vector3<f64>) -> Option<SizeRow> {
        let v = self.vertices[j].as_ref()?;
        let w = self.weights[j];
        // dm = R_b (½ ω_b × g_b + (H ω)_b + J_bᵀ dM) with m = R_b g_b: contracted with
        // b = R_bᵀ m̂ = g_b / |g_b| the turn ½ ω_b × g_b drops out; c = J_b b.
        let b = v.rotation_b.transpose() * unit;
        let c = v.jacobian.fixed_columns::<3>(3) * b;
        let cc = self.c_kappa.component_mul(&c);
        let mut row = SizeRow::zero();
        row.frames = v.hessian.fixed_rows::<3>(3).transpose() * b + v.jacobian.transpose() * cc / w;
        row.weight = -cc.dot(&v.phi) / (w * w);
        row.stiffness = c.component_mul(&v.delta);
        row.rest_curvature = -cc;
        Some(row)
    }

    /// `k̂_⊥ · dK_j` as coefficients, `unit` the direction of `K_⊥`.
    fn curvature_row(&self, j: usize, unit: &Vector3<f64>) -> Option<SizeRow> {
        let v = self.vertices[j].as_ref()?;
        let w = self.weights[j];
        let mut row = SizeRow::zero();
        row.frames = v.jacobian.transpose() * unit / w;
        row.weight = -unit.dot(&v.phi) / (w * w);
        Some(row)
    }
}

impl SizeRow {
    fn zero() -> Self {
        Self {
            edges: [EdgeRow::default(); 2],
            frames: SVector::zeros(),
            weight: 0.0,
            stiffness: Vector3::zeros(),
            rest_curvature: Vector3::zeros(),
            end_load: Vector3::zeros(),
        }
    }
}

impl SizeRates {
    /// Which size the rates are of.
    pub fn size(&self) -> SectionalSize {
        self.size
    }

    /// The base size of every vertex ([`SectionalSize::of`]).
    pub fn sizes(&self) -> &[f64] {
        &self.sizes
    }

    /// The rate of the size at every vertex along `tangent` and whether it is one
    /// (as [`SectionalSize::rate`] of [`SectionalLinearisation::vertex_tangent`]'s
    /// change, to rounding): a dot product per vertex, the full change only where the
    /// size is zero.
    pub fn rates(&self, lin: &SectionalLinearisation, tangent: &RodTangent) -> Vec<(f64, bool)> {
        let n = lin.segments();
        let reference = Reference::of(tangent);
        (0..=n)
            .map(|j| match &self.rows[j] {
                Some(row) => (self.row_rate(row, lin, j, tangent, reference), true),
                None if self.size != SectionalSize::Force && lin.vertices[j].is_none() => {
                    (0.0, false)
                }
                None => {
                    let (value, d) = lin.vertex_tangent(j, tangent);
                    self.size.rate(&value, &d)
                }
            })
            .collect()
    }

    fn row_rate(
        &self,
        row: &SizeRow,
        lin: &SectionalLinearisation,
        j: usize,
        tangent: &RodTangent,
        reference: Reference,
    ) -> f64 {
        let n = lin.segments();
        let before = if j > 0 {
            tangent.edge_lengths[j - 1]
        } else {
            0.0
        };
        let after = tangent.edge_lengths.get(j).copied().unwrap_or(0.0);
        let mut rate = row.weight * 0.5 * (before + after);
        match self.size {
            SectionalSize::Force => {
                for (k, e) in [j.wrapping_sub(1), j].into_iter().enumerate() {
                    if e >= n {
                        continue;
                    }
                    let edge = &row.edges[k];
                    let d_edge = tangent.positions[e + 1] - tangent.positions[e];
                    rate += edge.offset.dot(&d_edge)
                        + edge.frame.dot(&tangent.frames[e])
                        + edge.length * tangent.edge_lengths[e];
                    if reference.rest {
                        rate += edge.rest_strain.dot(&tangent.rest_strains[e]);
                    }
                }
                if reference.stiffness {
                    rate += row.stiffness.dot(&tangent.strain_stiffness);
                }
                if j == 0 {
                    rate += row.end_load.dot(&tangent.end_loads[0]);
                } else if j == n {
                    rate += row.end_load.dot(&tangent.end_loads[1]);
                }
            }
            SectionalSize::Moment | SectionalSize::Curvature => {
                let (omega, _) = lin.vertex_increments(j, tangent);
                rate += row.frames.dot(&omega);
                if self.size == SectionalSize::Moment {
                    if reference.rest {
                        rate += row.rest_curvature.dot(&tangent.rest_curvatures[j]);
                    }
                    if reference.stiffness {
                        rate += row.stiffness.dot(&tangent.curvature_stiffness);
                    }
                }
            }
        }
        rate
    }
}

/// Which reference data a tangent moves beyond lengths and end loads (skipped when
/// it moves none: a position's or a mass's tangent).
#[derive(Clone, Copy, Debug)]
struct Reference {
    rest: bool,
    stiffness: bool,
}

impl Reference {
    fn of(tangent: &RodTangent) -> Self {
        let zero = |v: &Vector3<f64>| *v == Vector3::zeros();
        Self {
            rest: !(tangent.rest_strains.iter().all(zero)
                && tangent.rest_curvatures.iter().all(zero)),
            stiffness: !(zero(&tangent.strain_stiffness) && zero(&tangent.curvature_stiffness)),
        }
    }
}
