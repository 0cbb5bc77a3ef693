//! The sectional force, moment and curvature at one vertex: what
//! [`crate::sectional::sectional`] gives there, from the two edges and the one
//! curvature element around the vertex (a local computation, for outputs read at one
//! place, e.g. a peak's vertex along a sensitivity path).

use nalgebra::Vector3;

use crate::element::bend_twist_gradient;
use crate::sectional::{BoundaryFrames, edge_element, vertex_bend_twist};
use crate::{Rod, RodState};

/// The sectional quantities of one vertex (the entries `j` of
/// [`crate::sectional::Sectional`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexSectional {
    /// Vertex-averaged spatial force `f̄_j`, N.
    pub force: Vector3<f64>,
    /// Spatial vertex moment `m_j`, N·m (zero at a free or pinned end).
    pub moment: Vector3<f64>,
    /// Material curvature `K_j`, 1/m (zero at a free or pinned end).
    pub curvature: Vector3<f64>,
}

/// The force, moment and curvature at vertex `j` (`0..=N`) of `rod` in `state` with
/// its `boundary` frames, defined exactly as [`crate::sectional::sectional`] defines
/// them (clips' half cells, the ends' lumped loads), at the cost of two edges and one
/// curvature element.
pub fn sectional_at(
    rod: &Rod,
    state: &RodState,
    boundary: &BoundaryFrames,
    j: usize,
) -> VertexSectional {
    let n = rod.segments();
    let c_gamma = rod.section().strain_stiffness();
    let c_kappa = rod.section().curvature_stiffness();
    let weight = rod.vertex_weight(j);
    // The first clip listed at this vertex wins, as in `sectional`.
    let clip = boundary
        .clips
        .iter()
        .find(|(vertex, _)| *vertex == j)
        .map(|(_, q)| q);
    let (curvature, moment) = match vertex_bend_twist(rod, state, boundary, j, clip, &c_kappa) {
        Some(element) => (
            element.curvature(),
            element.frame_b
                * bend_twist_gradient(&element)
                    .gradient
                    .fixed_rows::<3>(3)
                    .into_owned(),
        ),
        None => (Vector3::zeros(), Vector3::zeros()),
    };
    let mut force = Vector3::zeros();
    for e in [j.wrapping_sub(1), j] {
        if e < n {
            let element = edge_element(rod, state, &c_gamma, e);
            let share = rod.edge_length(e) / (2.0 * weight);
            force += share * (state.frames[e] * element.material_force());
        }
    }
    if j == 0 {
        force += boundary.end_loads[0];
    }
    if j == n {
        force -= boundary.end_loads[1];
    }
    VertexSectional {
        force,
        moment,
        curvature,
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{UnitQuaternion, Vector3};

    use super::*;
    use crate::Section;
    use crate::sectional::sectional;

    /// A bent, twisted and stretched rod with uneven edges, rest curvature, boundary
    /// frames at both ends, two clips (one vertex listed twice) and end loads.
    fn configuration() -> (Rod, RodState, BoundaryFrames) {
        let n = 9;
        let section = Section::try_explicit(2e5, 8e4, 0.3, 0.2, 0.1, 0.005).unwrap();
        let lengths: Vec<f64> = (0..n).map(|e| 0.05 + 0.01 * e as f64).collect();
        let strains = (0..n)
            .map(|e| Vector3::new(0.01 * e as f64, 0.0, 1.0))
            .collect();
        let curvatures = (0..=n)
            .map(|j| Vector3::new(0.3, -0.1 * j as f64, 0.05))
            .collect();
        let rod = Rod::try_new(section, lengths.clone(), strains, curvatures).unwrap();
        let state = crate::test_rods::bent_twisted_state(&lengths);
        let boundary = crate::test_rods::turned_ends(
            vec![
                (
                    4,
                    UnitQuaternion::from_scaled_axis(Vector3::new(0.7, 0.2, 0.1)),
                ),
                (
                    2,
                    UnitQuaternion::from_scaled_axis(Vector3::new(0.3, 0.1, 0.2)),
                ),
                (
                    4,
                    UnitQuaternion::from_scaled_axis(Vector3::new(-0.5, 0.0, 0.4)),
                ),
            ],
            [Vector3::new(1.0, -2.0, 0.5), Vector3::new(-0.3, 0.2, 4.0)],
        );
        (rod, state, boundary)
    }

    fn assert_close(a: &Vector3<f64>, b: &Vector3<f64>, what: &str, j: usize) {
        let scale = a.norm().max(b.norm()).max(1e-300);
        assert!(
            (a - b).norm() <= 1e-13 * scale,
            "{what} at vertex {j}: {a:?} against the whole rod's {b:?}"
        );
    }

    /// Every vertex's local force, moment and curvature equals the whole rod's
    /// sectional computation, with boundary frames, clips and end loads, and with free
    /// ends (no boundary frames, no curvature term at the ends).
    #[test]
    fn one_vertex_equals_the_whole_rods_sectional_quantities() {
        let (rod, state, attached) = configuration();
        let free = BoundaryFrames::default();
        for boundary in [&attached, &free] {
            let whole = sectional(&rod, &state, boundary);
            for j in 0..=rod.segments() {
                let local = sectional_at(&rod, &state, boundary, j);
                assert_close(&local.force, &whole.forces[j], "force", j);
                assert_close(&local.moment, &whole.moments[j], "moment", j);
                assert_close(&local.curvature, &whole.curvatures[j], "curvature", j);
            }
        }
        // The configuration is not trivial: forces, moments and curvatures are there.
        let whole = sectional(&rod, &state, &attached);
        assert!(whole.forces.iter().all(|f| f.norm() > 1.0));
        assert!(whole.moments.iter().all(|m| m.norm() > 1e-3));
    }
}
