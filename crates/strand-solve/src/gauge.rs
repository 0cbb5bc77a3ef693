//! Gauge freedoms: exact zero modes of the energy that a symmetry makes free.
//!
//! A rod of round section (`EI1 = EI2`, `GA1 = GA2`) whose rest strains have no
//! component across the section, and whose ends carry no boundary frame (pinned, free,
//! ball-jointed to a port) and no end moment, can turn every edge frame about its own
//! tangent by one common angle: `q_j ← q_j ⊗ exp(α e3/2)` maps `Γ → R3(−α) Γ` and
//! `K → R3(−α) K`, which leaves the stored energy unchanged, and nothing else sees the
//! frames. The Hessian is then singular along `δθ_j = α e3` for all edges `j`; shifting
//! the whole matrix to factor it swamps the physical soft modes (a cable's gravity
//! stiffness is ~1e-12 of its axial one) and Newton crawls.
//!
//! The gauge is fixed instead: the `e3` component of the rotation increment of the
//! rod's middle edge is held at zero in every step (its row and column of the Hessian
//! are replaced by the unit row, its gradient entry by 0). Since the energy is invariant
//! along the orbit, every equilibrium is still reached, and the full gradient, including
//! the held component, is what the convergence test measures.

use strand_system::{HessianPattern, Model, Support};

/// The unknowns held at zero to fix the gauge, with the Hessian value offsets to clear.
#[derive(Clone, Debug, Default)]
pub struct Gauge {
    /// Indices of the held unknowns (one per rod with a free material rotation).
    held: Vec<usize>,
    /// Value offsets of every off-diagonal entry in the rows/columns of held unknowns.
    off_diagonal: Vec<usize>,
    /// Value offsets of the held unknowns' diagonal entries.
    diagonal: Vec<usize>,
}

impl Gauge {
    /// Finds the gauge freedoms of `model` (structural test, independent of the state).
    pub fn of(model: &Model) -> Self {
        let system = model.system();
        let mut held = Vec::new();
        for (r, spec) in system.rods.iter().enumerate() {
            let frameless = |support: &Support| match support {
                Support::Free | Support::Pinned { .. } => true,
                Support::Port { clamped, .. } => !clamped,
                Support::Clamped { .. } => false,
            };
            let no_end_moment = spec.start.load.moment == nalgebra::Vector3::zeros()
                && spec.end.load.moment == nalgebra::Vector3::zeros();
            let clipped = system.clips.iter().any(|c| c.rod.0 == r);
            let rod = &spec.rod;
            let strain = rod.section().strain_stiffness();
            let curvature = rod.section().curvature_stiffness();
            let round = strain[0] == strain[1] && curvature[0] == curvature[1];
            let axial_rest = (0..rod.segments()).all(|e| {
                let g = rod.rest_strain(e);
                g[0] == 0.0 && g[1] == 0.0
            }) && (0..rod.vertex_count()).all(|v| {
                let k = rod.rest_curvature(v);
                k[0] == 0.0 && k[1] == 0.0
            });
            if frameless(&spec.start.support)
                && frameless(&spec.end.support)
                && no_end_moment
                && !clipped
                && round
                && axial_rest
            {
                let middle = rod.segments() / 2;
                held.push(3 * model.dofs().edge(r, middle) + 2);
            }
        }
        Self::holding(model, held)
    }

    /// Holds the given unknowns (any set, e.g. every rotation for a positions-only
    /// correction step).
    pub fn holding(model: &Model, held: Vec<usize>) -> Self {
        Self::holding_in(model.pattern(), held)
    }

    /// [`Gauge::holding`] for a bare Hessian pattern.
    pub fn holding_in(pattern: &HessianPattern, mut held: Vec<usize>) -> Self {
        held.sort_unstable();
        held.dedup();
        let mut is_held = vec![false; pattern.dim()];
        for &k in &held {
            is_held[k] = true;
        }
        let mut off_diagonal = Vec::new();
        let mut diagonal = Vec::new();
        for col in 0..pattern.dim() {
            let column_held = is_held[col];
            for offset in pattern.col_ptr[col]..pattern.col_ptr[col + 1] {
                let row = pattern.row_idx[offset];
                if row == col {
                    if column_held {
                        diagonal.push(offset);
                    }
                } else if column_held || is_held[row] {
                    off_diagonal.push(offset);
                }
            }
        }
        Self {
            held,
            off_diagonal,
            diagonal,
        }
    }

    /// The held unknowns.
    pub fn held(&self) -> &[usize] {
        &self.held
    }

    /// Whether there is nothing to hold.
    pub fn is_empty(&self) -> bool {
        self.held.is_empty()
    }

    /// Replaces the rows and columns of the held unknowns in `hessian` by unit rows
    /// scaled by `scale` (their old diagonal value, so the matrix keeps its scaling).
    pub fn fix_matrix(&self, hessian: &mut [f64]) {
        for &k in &self.off_diagonal {
            hessian[k] = 0.0;
        }
        for &k in &self.diagonal {
            hessian[k] = hessian[k].abs().max(f64::MIN_POSITIVE);
        }
    }

    /// Zeroes the held unknowns' entries of a right-hand side.
    pub fn fix_vector(&self, vector: &mut [f64]) {
        for &k in &self.held {
            vector[k] = 0.0;
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use nalgebra::{UnitQuaternion, Vector3};
    use strand_rod::{Rod, Section};
    use strand_system::{End, RodSpec, System};

    use super::*;

    /// A 1 m rod "r" of 8 edges between `start` and `end` under gravity (also used by
    /// other modules' tests).
    pub(crate) fn rod_between(start: End, end: End, section: Section) -> Model {
        one_rod(Rod::try_straight(section, 1.0, 8).unwrap(), start, end)
    }

    /// `rod`, named "r", between `start` and `end` under gravity (9.81 m/s² down z).
    pub(crate) fn one_rod(rod: Rod, start: End, end: End) -> Model {
        Model::try_new(System {
            rods: vec![RodSpec {
                name: "r".into(),
                rod,
                start,
                end,
                route: None,
            }],
            bodies: vec![],
            clips: vec![],
            gravity: Vector3::new(0.0, 0.0, -9.81),
        })
        .unwrap()
    }

    #[test]
    fn only_a_round_rod_without_end_frames_has_a_gauge_freedom() {
        let round = Section::try_explicit(1e6, 1e6, 1e-2, 1e-2, 0.5, 0.0).unwrap();
        let pin = |x: f64| End::pinned(Vector3::new(x, 0.0, 0.0));
        let clamp = End::clamped(Vector3::zeros(), UnitQuaternion::identity());
        // Pinned at both ends, or pinned and free: one turn about the axis is free.
        assert_eq!(
            Gauge::of(&rod_between(pin(0.0), pin(0.8), round))
                .held()
                .len(),
            1
        );
        assert_eq!(
            Gauge::of(&rod_between(pin(0.0), End::free(), round))
                .held()
                .len(),
            1
        );
        // A clamp fixes the frame.
        assert!(Gauge::of(&rod_between(clamp, pin(0.8), round)).is_empty());
        // An end moment sees the frame.
        let mut loaded = pin(0.8);
        loaded.load.moment = Vector3::new(0.0, 0.0, 0.1);
        assert!(Gauge::of(&rod_between(pin(0.0), loaded, round)).is_empty());
        // A section that is not round has a preferred orientation.
        let flat = Section::try_explicit(1e6, 1e6, 1e-2, 1e-2, 0.5, 0.0)
            .map(|mut s| {
                s.bending_stiffness_2 = 2e-2;
                s
            })
            .unwrap();
        assert!(Gauge::of(&rod_between(pin(0.0), pin(0.8), flat)).is_empty());
    }

    #[test]
    fn the_held_component_is_the_tangent_rotation_of_the_middle_edge() {
        let round = Section::try_explicit(1e6, 1e6, 1e-2, 1e-2, 0.5, 0.0).unwrap();
        let model = rod_between(
            End::pinned(Vector3::zeros()),
            End::pinned(Vector3::new(0.8, 0.0, 0.0)),
            round,
        );
        let gauge = Gauge::of(&model);
        assert_eq!(gauge.held(), &[3 * model.dofs().edge(0, 4) + 2]);
        // Fixing a vector zeroes exactly that entry.
        let mut v = vec![1.0; model.dofs().len()];
        gauge.fix_vector(&mut v);
        assert_eq!(v.iter().filter(|x| **x == 0.0).count(), 1);
    }
}
