//! Sensitivities against central differences of full solves on small systems built in
//! code: a cantilever (tip load, length, gravity) and a sagging rod resting on a floor
//! whose height is a parameter (an active contact row with its multiplier).

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::{Rod, Section};
use strand_system::{End, Model, RodSpec, System, SystemState, initial_state};

use super::{Design, Designed, ModelLine, PathRows, Sample, Sensitivities, SensitivitySettings};
use crate::constraints::{ConstraintError, Constraints, Row, RowKey};
use crate::{Solution, SolverSettings, solve, solve_constrained};

/// A floor `z ≥ height + radius` under every vertex, one row per vertex; or, with
/// `midpoints`, one row per edge at its midpoint (a row of the first edge reads the
/// held start vertex).
struct Floor {
    height_m: f64,
    radius_m: f64,
    midpoints: bool,
}

impl Constraints for Floor {
    fn rows(
        &self,
        model: &Model,
        state: &SystemState,
        out: &mut Vec<Row>,
    ) -> Result<(), ConstraintError> {
        for (r, rod) in state.rods.iter().enumerate() {
            if self.midpoints {
                for (j, pair) in rod.positions.windows(2).enumerate() {
                    let half = 0.5 * Vector3::z();
                    let mut gradient = model.vertex_direction_gradient(state, r, j, &half);
                    gradient.extend(model.vertex_direction_gradient(state, r, j + 1, &half));
                    if !gradient.is_empty() {
                        out.push(Row {
                            key: RowKey::Contact((r * 10_000 + j) as u64),
                            value: 0.5 * (pair[0].z + pair[1].z) - self.height_m - self.radius_m,
                            gradient,
                            curvature: None,
                        });
                    }
                }
                continue;
            }
            for (j, p) in rod.positions.iter().enumerate() {
                let gradient = model.vertex_direction_gradient(state, r, j, &Vector3::z());
                if !gradient.is_empty() {
                    out.push(Row {
                        key: RowKey::Contact((r * 10_000 + j) as u64),
                        value: p.z - self.height_m - self.radius_m,
                        gradient,
                        curvature: None,
                    });
                }
            }
        }
        Ok(())
    }
    fn check_start(&self, _: &Model, _: &SystemState) -> Result<(), ConstraintError> {
        Ok(())
    }
    fn max_translation_m(&self) -> f64 {
        1.0
    }
    fn advancement(
        &self,
        _: &Model,
        _: &SystemState,
        _: &SystemState,
    ) -> Result<f64, ConstraintError> {
        Ok(1.0)
    }
}

/// A rod clamped at `(0, 0, h)` along x; parameters: tip force z (N), length (m),
/// gravity z (m/s²), floor height (m; a floor only when `floor` is set), the start
/// clamp's height `h` (m); the far end clamped at (0.8, 0, 0) when `far_clamp`.
struct Bench {
    base: [f64; 5],
    floor: bool,
    far_clamp: bool,
    /// The floor's rows at the edges' midpoints ([`Floor`]).
    midpoints: bool,
    /// Per parameter, the line of the model's real numbers it moves along (the
    /// base's and their change per unit, [`Design::model_line`]), where given.
    lines: Vec<Option<(Vec<f64>, Vec<f64>)>>,
}

impl Bench {
    fn new(base: [f64; 5], floor: bool, far_clamp: bool) -> Self {
        Self {
            base,
            floor,
            far_clamp,
            midpoints: false,
            lines: Vec::new(),
        }
    }

    /// The same design with the lines of its parameters that move the model alone
    /// (every one but the floor's height, which moves the constraints): their
    /// right-hand sides take the closed form.
    fn with_lines(mut self) -> Self {
        let reals = |offsets: &[f64; 5]| self.build(offsets).unwrap().model.system().reals();
        let base = reals(&[0.0; 5]);
        let lines = (0..5)
            .map(|j| {
                (j != 3).then(|| {
                    // A small offset (a rod's ends must stay reachable); the reals are
                    // affine in every parameter but the floor's.
                    let mut offsets = [0.0; 5];
                    offsets[j] = 1e-3;
                    let direction = reals(&offsets)
                        .iter()
                        .zip(&base)
                        .map(|(a, b)| (a - b) / 1e-3)
                        .collect();
                    (base.clone(), direction)
                })
            })
            .collect();
        self.lines = lines;
        self
    }
}

struct Built {
    model: Model,
    floor: Option<Floor>,
}

impl Designed for Built {
    fn model(&self) -> &Model {
        &self.model
    }
    fn constraints(&self) -> Option<&dyn Constraints> {
        self.floor.as_ref().map(|f| f as &dyn Constraints)
    }
}

impl Design for Bench {
    type Built = Built;
    type Error = strand_system::SystemError;
    fn parameter_count(&self) -> usize {
        5
    }
    fn step(&self, parameter: usize) -> f64 {
        [1.0, 1.0, 10.0, 0.1, 0.1][parameter]
    }
    fn model_line(&self, parameter: usize) -> Result<Option<ModelLine<'_>>, Self::Error> {
        Ok(self
            .lines
            .get(parameter)
            .and_then(Option::as_ref)
            .map(|(reals, direction)| ModelLine {
                reals,
                direction,
                moved: (0..direction.len())
                    .filter(|&k| direction[k] != 0.0)
                    .collect(),
            }))
    }
    fn build(&self, offsets: &[f64]) -> Result<Built, Self::Error> {
        let p: Vec<f64> = self.base.iter().zip(offsets).map(|(a, b)| a + b).collect();
        let section = Section::try_explicit(1e5, 1e5, 0.2, 0.15, 0.6, 0.05).unwrap();
        let along_x =
            UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
        let mut end = if self.far_clamp {
            End::clamped(Vector3::new(0.8, 0.0, 0.0), along_x)
        } else {
            End::free()
        };
        end.load.force = Vector3::new(0.0, 0.3, p[0]);
        let model = Model::try_new(System {
            rods: vec![RodSpec {
                name: "r".into(),
                rod: Rod::try_straight(section, p[1], 12).unwrap(),
                start: End::clamped(Vector3::new(0.0, 0.0, p[4]), along_x),
                end,
                route: None,
            }],
            bodies: vec![],
            clips: vec![],
            gravity: Vector3::new(0.0, 0.0, p[2]),
        })?;
        let floor = self.floor.then(|| Floor {
            height_m: p[3],
            radius_m: 0.0,
            midpoints: self.midpoints,
        });
        Ok(Built { model, floor })
    }
}

fn solve_at(design: &Bench, offsets: &[f64], start: Option<SystemState>) -> (Built, Solution) {
    let built = design.build(offsets).unwrap();
    let settings = SolverSettings {
        tolerance_n: 1e-11,
        ..SolverSettings::default()
    };
    let initial = start.unwrap_or_else(|| initial_state(built.model.system()));
    let solution = match &built.floor {
        Some(f) => solve_constrained(&built.model, f, initial, &settings).unwrap(),
        None => solve(&built.model, initial, &settings).unwrap(),
    };
    assert!(solution.report.converged, "{:?}", solution.report);
    (built, solution)
}

/// Every vertex's position (m) and the contact forces (N) in key order.
fn outputs(_: &Built, solution: &Solution) -> Vec<Sample> {
    let mut out: Vec<Sample> = solution.state.rods[0]
        .positions
        .iter()
        .flat_map(|p| [p.x, p.y, p.z])
        .map(|value| Sample { value, arg: 0 })
        .collect();
    let mut forces: Vec<(RowKey, f64)> = solution
        .constraints
        .iter()
        .map(|(r, l)| (r.key, *l))
        .collect();
    forces.sort_by_key(|(k, _)| *k);
    out.extend(forces.iter().map(|(_, f)| Sample { value: *f, arg: 0 }));
    out
}

/// Compares the sensitivities of every output with central differences of full solves
/// (step `fd` per parameter).
fn check(design: &Bench, parameters: &[usize], fd: f64) {
    let (_, base) = solve_at(design, &[0.0; 5], None);
    let s = Sensitivities::compute(design, &base, &SensitivitySettings::default()).unwrap();
    for &j in parameters {
        assert!(
            s.parameters[j].kkt_residual < 1e-6,
            "{:?}",
            s.parameters[j].kkt_residual
        );
        let exact = s
            .derivative(design, &base, j, PathRows::All, outputs)
            .unwrap();
        // Central differences of full solves at steps fd and 2 fd, extrapolated.
        let at = |t: f64| {
            let mut offsets = [0.0; 5];
            offsets[j] = t;
            let (built, solution) = solve_at(design, &offsets, Some(base.state.clone()));
            outputs(&built, &solution)
        };
        let (up, down, up2, down2) = (at(fd), at(-fd), at(2.0 * fd), at(-2.0 * fd));
        assert_eq!(up.len(), exact.len());
        let scale = exact.iter().fold(0.0f64, |m, d| m.max(d.derivative.abs()));
        for (k, d) in exact.iter().enumerate() {
            let fine = (up[k].value - down[k].value) / (2.0 * fd);
            let coarse = (up2[k].value - down2[k].value) / (4.0 * fd);
            let reference = (4.0 * fine - coarse) / 3.0;
            assert!(
                (d.derivative - reference).abs() <= 1e-5 * scale.max(1e-9),
                "parameter {j} output {k}: sensitivity {} vs difference of solves {reference}",
                d.derivative
            );
        }
    }
}

#[test]
fn a_cantilever_s_shape_follows_its_tip_load_length_and_gravity_exactly() {
    let design = Bench::new([-0.5, 0.8, -9.81, 0.0, 0.0], false, false);
    check(&design, &[0, 1, 2], 1e-3);
}

#[test]
fn a_rod_resting_on_a_floor_follows_the_floor_with_its_contact_forces() {
    // Clamped at both ends at z = 0, sagging under its weight and a load onto a floor
    // 5 mm below the clamps: the middle rests on the floor.
    let design = Bench::new([-1.0, 0.8, -9.81, -0.005, -0.0049995], true, true);
    let (_, base) = solve_at(&design, &[0.0; 5], None);
    let pressing = base.constraints.iter().filter(|(_, l)| *l > 0.0).count();
    assert!(pressing >= 1, "the rod must rest on the floor");
    check(&design, &[1, 2, 3], 1e-6);
}

/// The closed-form right-hand sides with active rows that read a held vertex: a rod
/// clamped 0.5 µm above a floor whose rows sit at the edges' midpoints rests on it
/// from its first edge on, so raising the clamp moves that row at the base's
/// unknowns; its rows' part, from the rows at the model moved along the line (the
/// floor promises nothing, so they are evaluated at `±h` and `±2h`), gives the
/// derivatives of full solves with no design built. Likewise with the floor's rows
/// at the vertices, where the first edge has none.
#[test]
fn closed_form_right_hand_sides_carry_active_rows_that_read_a_held_vertex() {
    for midpoints in [true, false] {
        let design = Bench {
            midpoints,
            ..Bench::new([-1.0, 0.8, -9.81, -0.005, -0.0049995], true, true)
        }
        .with_lines();
        let (_, base) = solve_at(&design, &[0.0; 5], None);
        let on_first_edge = base
            .constraints
            .iter()
            .any(|(r, l)| r.key == RowKey::Contact(0) && *l > 0.0);
        assert_eq!(
            on_first_edge, midpoints,
            "the first edge rests on the floor"
        );
        let s = Sensitivities::compute(&design, &base, &SensitivitySettings::default()).unwrap();
        let designs: Vec<usize> = s.parameters.iter().map(|p| p.rhs_designs).collect();
        let rows: Vec<usize> = s.parameters.iter().map(|p| p.rhs_row_evaluations).collect();
        assert_eq!(
            designs,
            vec![0, 0, 0, 4, 0],
            "only the floor's height builds designs"
        );
        assert_eq!(rows, vec![4, 4, 4, 0, 4]);
        check(&design, &[1, 2, 4], 1e-6);
    }
}

/// The KKT system's right-hand sides solved together ([`KktFactor::solve_all`], the
/// parameters' first solves in one pass through the factor) give each one's own
/// [`KktFactor::solve`] bit for bit, with active rows (the Schur complement on the
/// floor's contacts and their multipliers); so do the refinement checks' grouped
/// products `H v` ([`KktFactor::hessian_products`], 1 to 11 vectors).
#[test]
fn right_hand_sides_solved_together_equal_each_ones_own_solve_bit_for_bit() {
    use super::kkt::Kkt;
    use super::schur::KktFactor;
    use crate::gauge::Gauge;
    let design = Bench::new([-1.0, 0.8, -9.81, -0.005, -0.0049995], true, true);
    let (built, base) = solve_at(&design, &[0.0; 5], None);
    let model = &built.model;
    let active: Vec<&Row> = base
        .constraints
        .iter()
        .filter(|(_, l)| *l > 0.0)
        .map(|(r, _)| r)
        .collect();
    assert!(!active.is_empty(), "the rod must rest on the floor");
    let mut eval = model.new_evaluation();
    model.evaluate(&base.state, &mut eval, true);
    let gauge = Gauge::of(model);
    let mut factor = KktFactor::new(
        model,
        &eval.hessian,
        &gauge,
        &active,
        base.analysis.as_ref(),
    )
    .unwrap();
    let n = model.dofs().len();
    let mut seed = 7u64;
    let mut next = || crate::linear::tests::next(&mut seed);
    let sides: Vec<Kkt> = (0..6)
        .map(|_| Kkt {
            gradient: (0..n).map(|_| next()).collect(),
            gaps: (0..active.len()).map(|_| 1e-3 * next()).collect(),
        })
        .collect();
    let together = factor.solve_all(&sides.iter().collect::<Vec<_>>());
    assert_eq!(together.len(), sides.len());
    for (j, (side, (v, w))) in sides.iter().zip(&together).enumerate() {
        let (v_alone, w_alone) = factor.solve(side);
        assert!(*v == v_alone && *w == w_alone, "right-hand side {j}");
        assert_eq!(w.len(), active.len());
    }
    // The refinement checks' products, grouped by up to eight: each vector's own.
    let vectors: Vec<Vec<f64>> = sides.iter().map(|s| s.gradient.clone()).collect();
    for count in 1..=vectors.len() {
        let mut many = vectors[..count].to_vec();
        many.extend(vectors[..count.min(5)].iter().cloned());
        let grouped = factor.hessian_products(&many);
        assert_eq!(grouped.len(), many.len());
        for (k, (v, hv)) in many.iter().zip(&grouped).enumerate() {
            assert!(
                *hv == factor.hessian_product(v),
                "product {k} of {}",
                many.len()
            );
        }
    }
}

/// The solver's own Hessian at the equilibrium ([`SolverSettings::keep_hessian`])
/// serves the sensitivities: none is evaluated for them, and every derivative and
/// multiplier derivative is the one from a Hessian evaluated again, bit for bit
/// (the same values: the true Hessian at the returned state), with and without an
/// active contact.
#[test]
fn the_solver_s_hessian_at_the_equilibrium_serves_the_sensitivities() {
    let keeping = |design: &Bench| {
        let built = design.build(&[0.0; 5]).unwrap();
        let settings = SolverSettings {
            tolerance_n: 1e-11,
            keep_hessian: true,
            ..SolverSettings::default()
        };
        let initial = initial_state(built.model.system());
        let solution = match &built.floor {
            Some(f) => solve_constrained(&built.model, f, initial, &settings).unwrap(),
            None => solve(&built.model, initial, &settings).unwrap(),
        };
        assert!(solution.report.converged);
        solution
    };
    let settings = SensitivitySettings::default();
    for (design, parameters) in [
        (Bench::new([-0.5, 0.8, -9.81, 0.0, 0.0], false, false), 0..3),
        (
            Bench::new([-1.0, 0.8, -9.81, -0.005, -0.0049995], true, true),
            1..4,
        ),
    ] {
        let (_, fresh) = solve_at(&design, &[0.0; 5], None);
        assert!(fresh.hessian.is_none(), "kept only when asked for");
        let kept = keeping(&design);
        assert!(kept.hessian.is_some());
        assert_eq!(kept.state, fresh.state, "the same solve");
        let own = Sensitivities::compute(&design, &fresh, &settings).unwrap();
        let reused = Sensitivities::compute(&design, &kept, &settings).unwrap();
        assert!(!own.reused_hessian && reused.reused_hessian);
        assert_eq!(own.active, reused.active);
        for j in parameters {
            let (a, b) = (&own.parameters[j], &reused.parameters[j]);
            assert!(
                a.state == b.state && a.multipliers == b.multipliers,
                "parameter {j}"
            );
        }
    }
}
