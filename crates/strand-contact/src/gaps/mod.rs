//! Contact gaps of rods (each edge a capsule of the rod's outer radius) against
//! environment meshes and against each other.
//!
//! A [`Gap`] pairs a point `P(s) = (1 − s) r_j + s r_{j+1}` on edge `j` of a rod's
//! centreline with the nearest point (`witness`) of the other object — on a mesh
//! surface, or on another edge's centreline — and measures
//! `gap = |P(s) − witness| − radii` (the rod's outer radius, plus the other rod's for
//! rod–rod pairs). `normal` is the unit vector from the witness to `P(s)`. Contact is
//! frictionless and enters the solver as `gap ≥ 0`, linearised at each iterate as
//!
//! `d(gap) = normal · ((1 − s) dr_j + s dr_{j+1}) − normal · d(witness)`,
//!
//! with `d(witness) = 0` for a rigid mesh and
//! `d(witness) = (1 − t) dr'_k + t dr'_{k+1}` for edge `k` of the other rod (the
//! closest-point parameters `s, t` are held fixed: their variation does not enter the
//! first-order change of the distance). The side of the mesh the rod is on is the one
//! of the configuration where the gaps are computed (unsigned distance): a rod whose
//! capsule already overlaps a mesh at the initial configuration is reported by
//! [`require_clearance`] with its location, never pushed through.

mod broad_phase;
mod chain_shape;
mod edge_tree;
mod mesh_gaps;
mod mesh_index;
mod rod_rod_clearances;
mod rod_rod_gaps;
mod rod_rod_minima;

use nalgebra::{Point3, Unit, Vector3};

pub use broad_phase::{Aabb, overlapping_pairs};
pub use mesh_gaps::mesh_gaps;
pub use mesh_index::MeshIndex;
pub use rod_rod_clearances::rod_rod_clearances;
pub use rod_rod_gaps::{rod_rod_gaps, rod_rod_gaps_of};
pub use rod_rod_minima::{rod_rod_local_minima, rod_rod_minima_of};

/// The centreline and outer radius of one rod.
#[derive(Clone, Copy, Debug)]
pub struct RodGeometry<'a> {
    /// Centreline vertices `r_0..r_N`, m (edge `j` joins `r_j` and `r_{j+1}`).
    pub vertices: &'a [Point3<f64>],
    /// Outer radius of the section, m (≥ 0).
    pub radius: f64,
}

/// What a rod edge is in contact with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Obstacle {
    /// Environment mesh number `i` (index into the meshes passed in).
    Mesh(usize),
    /// Edge `edge` of rod `rod`, at parameter `t ∈ [0, 1]` along it.
    Rod {
        /// Index of the other rod.
        rod: usize,
        /// Index of the other rod's edge.
        edge: usize,
        /// Parameter of the witness point along that edge.
        t: f64,
    },
}

/// One contact gap (see the [module documentation](self) for its linearisation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gap {
    /// Index of the rod.
    pub rod: usize,
    /// Index of the rod's edge.
    pub edge: usize,
    /// Parameter of `point` along the edge, in `[0, 1]`.
    pub s: f64,
    /// The other object.
    pub with: Obstacle,
    /// Point on the rod's centreline, `(1 − s) r_edge + s r_edge+1`, m.
    pub point: Point3<f64>,
    /// Nearest point of the other object: on the mesh surface, or on the other rod's
    /// centreline, m.
    pub witness: Point3<f64>,
    /// Unit vector from `witness` to `point` (from the other object towards this rod).
    pub normal: Unit<Vector3<f64>>,
    /// Distance between `point` and `witness` minus the radii, m (negative: overlap).
    pub gap: f64,
}

/// Why contact gaps could not be computed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GapError {
    /// A rod's centreline touches or crosses a mesh surface or another rod's
    /// centreline: no contact direction exists there.
    #[error(
        "rod {rod} edge {edge} {what}: its centreline passes through ({:.6}, {:.6}, {:.6}) m on the other surface\n  hint: start the rod clear of the obstacle: move its route (or give one), its initial state or its supports",
        point.x, point.y, point.z
    )]
    CentrelineTouches {
        /// Index of the rod.
        rod: usize,
        /// Index of the edge.
        edge: usize,
        /// `"touches mesh 2"` or `"crosses rod 1 edge 4"`.
        what: String,
        /// Where, m.
        point: Point3<f64>,
    },
    /// A rod's capsule overlaps an obstacle (see [`require_clearance`]).
    #[error(
        "rod {rod} edge {edge} starts inside {what}: it overlaps by {:.3} mm at ({:.6}, {:.6}, {:.6}) m\n  hint: start the rod clear of the obstacle: move its route (or give one), its initial state or its supports",
        depth * 1e3, point.x, point.y, point.z
    )]
    StartsInside {
        /// Index of the rod.
        rod: usize,
        /// Index of the edge.
        edge: usize,
        /// `"mesh 2"` or `"rod 1 edge 4"`.
        what: String,
        /// Overlap depth `−gap`, m.
        depth: f64,
        /// Point on the rod's centreline, m.
        point: Point3<f64>,
    },
    /// The contact margin is negative or not finite.
    #[error("invalid contact margin {margin} m\n  hint: give a finite margin ≥ 0")]
    InvalidMargin {
        /// The margin given, m.
        margin: f64,
    },
    /// A radius is negative or not finite, or a vertex is not finite.
    #[error("rod {rod}: {message}")]
    InvalidRod {
        /// Index of the rod.
        rod: usize,
        /// What is wrong.
        message: String,
    },
}

/// All gaps of the rods: [`mesh_gaps`] against every mesh followed by
/// [`rod_rod_gaps`] between edges (`exclude` as there), each within `margin` (m).
pub fn all_gaps<M: AsRef<crate::ObstacleMesh>>(
    rods: &[RodGeometry],
    meshes: &[M],
    margin: f64,
    exclude: impl FnMut(usize, usize, usize, usize) -> bool,
) -> Result<Vec<Gap>, GapError> {
    let mut gaps = mesh_gaps(rods, meshes, margin)?;
    gaps.extend(rod_rod_gaps(rods, margin, exclude)?);
    Ok(gaps)
}

/// Checks that no gap is negative beyond `tolerance` (m): a rod that starts inside an
/// obstacle is reported with its location (the deepest overlap).
pub fn require_clearance(gaps: &[Gap], tolerance: f64) -> Result<(), GapError> {
    let deepest = gaps
        .iter()
        .filter(|g| g.gap < -tolerance)
        .min_by(|a, b| a.gap.total_cmp(&b.gap));
    match deepest {
        None => Ok(()),
        Some(g) => Err(GapError::StartsInside {
            rod: g.rod,
            edge: g.edge,
            what: describe(&g.with),
            depth: -g.gap,
            point: g.point,
        }),
    }
}

/// `"mesh 2"` or `"rod 1 edge 4"`.
fn describe(with: &Obstacle) -> String {
    match with {
        Obstacle::Mesh(i) => format!("mesh {i}"),
        Obstacle::Rod { rod, edge, .. } => format!("rod {rod} edge {edge}"),
    }
}

/// Checks radii and vertices of the rods.
fn validate(rods: &[RodGeometry]) -> Result<(), GapError> {
    for (rod, geometry) in rods.iter().enumerate() {
        if !(geometry.radius.is_finite() && geometry.radius >= 0.0) {
            return Err(GapError::InvalidRod {
                rod,
                message: format!("radius must be finite and ≥ 0 (got {} m)", geometry.radius),
            });
        }
        if let Some(k) = geometry
            .vertices
            .iter()
            .position(|p| !p.iter().all(|x| x.is_finite()))
        {
            return Err(GapError::InvalidRod {
                rod,
                message: format!("vertex {k} is not finite"),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod rod_rod_clearances_tests;
#[cfg(test)]
mod rod_rod_tests;
