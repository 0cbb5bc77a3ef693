//! The convergence map of issue 9: a deterministic sample of single-rod problems
//! spanning the parameter ranges the solver must handle with default settings, and
//! the `strand bench --grid` run over it.
//!
//! Shared by the benchmark ([`run_grid`], [`format_grid_table`]) and the validation
//! test `convergence_map` (crate `strand-tests`), which both turn each [`GridCase`] of
//! [`convergence_grid`] into a [`System`] with [`grid_system`]. Every case is a rod of
//! length [`GridCase::LENGTH`] whose start is held at the origin with its tangent along
//! `+x` and whose end is held at `(span·L, 0, 0)` (tangent `+x`) or free, possibly with
//! a clip at the middle vertex, gravity along `−z`, a dead force at a free end, and an
//! initial-guess route.
//!
//! Factors and levels:
//! * ends: start ∈ {clamp, pin, port (clamped) on a fixed body, port (ball) on a fixed
//!   body}; end ∈ the same plus free;
//! * `EI` ∈ {10, 1, 0.1, 1e-2, 1e-4, 1e-6} N·m², `GJ = EI/1.5`;
//! * `EA/EI` ∈ {1e2, 1e4, …, 1e12} 1/m², restricted to `1e2 ≤ EA ≤ 1e10` N,
//!   `GA = EA/3`;
//! * edges ∈ {10, 20, 50, 100, 200} and, rarely (1 case in 25), 1000;
//! * span/L ∈ {0.3, 0.6, 0.9, 0.99, 0.999} (held ends only);
//! * gravity on/off (0.5 kg/m); a dead force at a free end (always when the end is
//!   free and there is no gravity, so that the problem has a unique solution);
//! * route on/off; clip at the middle vertex: none, fixed, revolute (about `y`),
//!   spherical.
//!
//! The levels are combined by a fixed pseudo-random sequence (SplitMix64, seed
//! [`GRID_SEED`]), so the sample is reproducible and covers every level of every
//! factor.
//!
//! The targets of issue 9 with the default [`SolverSettings`]: every case converges,
//! the median of `report.iterations` (every Newton iteration: fine, coarse and
//! continuation) is at most [`MEDIAN_ITERATIONS_TARGET`] and the maximum at most
//! [`MAX_ITERATIONS_TARGET`].

use std::f64::consts::PI;
use std::time::Instant;

use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::{Rod, Section};
use strand_solve::{SolverSettings, solve};
use strand_system::{
    BodyHandle, BodySpec, ClipSpec, End, Joint, Model, Port, Pose, RodHandle, RodSpec, Support,
    System, initial_state,
};

/// Number of cases of the map (the validation test and `strand bench --grid` by default).
pub const DEFAULT_CASES: usize = 200;

/// Seed of the generator of [`convergence_grid`].
pub const GRID_SEED: u64 = 0x5354_5241_4E44_0009;

/// Issue 9 target: median Newton iterations per case (all kinds).
pub const MEDIAN_ITERATIONS_TARGET: f64 = 20.0;

/// Issue 9 target: maximum Newton iterations of any case (all kinds).
pub const MAX_ITERATIONS_TARGET: usize = 100;

/// How a rod end is held.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EndKind {
    /// Clamped to a connector (position and frame).
    Clamp,
    /// Pinned to a connector (position only).
    Pin,
    /// Free end.
    Free,
    /// Clamped to the port of a fixed body.
    PortClamp,
    /// Ball-jointed to the port of a fixed body.
    PortPin,
}

/// The joint of a clip at the middle vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClipKind {
    /// A rigid clip.
    Fixed,
    /// A hinge about the world `y` axis.
    Revolute,
    /// A ball joint.
    Spherical,
}

/// One problem of the convergence map.
#[derive(Clone, Debug, PartialEq)]
pub struct GridCase {
    /// Index in the grid.
    pub index: usize,
    /// Start support (never [`EndKind::Free`]).
    pub start: EndKind,
    /// End support.
    pub end: EndKind,
    /// Bending stiffness `EI` (N·m²).
    pub ei: f64,
    /// Axial stiffness `EA` (N).
    pub ea: f64,
    /// Number of edges (even).
    pub segments: usize,
    /// End distance as a fraction of the length (held ends only; 1 for a free end).
    pub span: f64,
    /// Gravity `(0, 0, −9.81)` m/s² with 0.5 kg/m.
    pub gravity: bool,
    /// A dead force of 1 N along `(0.3, 0.4, −0.866)` at a free end.
    pub dead_load: bool,
    /// Whether the initial guess follows a route (a bent polyline of length `L`).
    pub route: bool,
    /// A clip at the middle vertex.
    pub clip: Option<ClipKind>,
}

impl GridCase {
    /// Rod length (m).
    pub const LENGTH: f64 = 1.0;
    /// Mass per length with gravity (kg/m).
    pub const MASS_PER_LENGTH: f64 = 0.5;

    /// A short label, e.g. `clamp-pin EI=1e-6 EA/EI=1e12 N=200 span=0.99 g load route clip=fixed`.
    pub fn label(&self) -> String {
        let end = |e: EndKind| match e {
            EndKind::Clamp => "clamp",
            EndKind::Pin => "pin",
            EndKind::Free => "free",
            EndKind::PortClamp => "portclamp",
            EndKind::PortPin => "portpin",
        };
        let mut s = format!(
            "#{:03} {}-{} EI={:.0e} EA/EI={:.0e} N={}",
            self.index,
            end(self.start),
            end(self.end),
            self.ei,
            self.ea / self.ei,
            self.segments
        );
        if self.end != EndKind::Free {
            s += &format!(" span={}", self.span);
        }
        if self.gravity {
            s += " g";
        }
        if self.dead_load {
            s += " load";
        }
        if self.route {
            s += " route";
        }
        if let Some(c) = self.clip {
            s += match c {
                ClipKind::Fixed => " clip=fixed",
                ClipKind::Revolute => " clip=hinge",
                ClipKind::Spherical => " clip=ball",
            };
        }
        s
    }
}

/// SplitMix64: a tiny reproducible generator.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn pick<T: Copy>(&mut self, levels: &[T]) -> T {
        levels[(self.next() % levels.len() as u64) as usize]
    }
}

/// The convergence map: the first `count` cases (the test uses [`DEFAULT_CASES`]);
/// the same `count` always gives the same cases, and a longer map extends a shorter one.
pub fn convergence_grid(count: usize) -> Vec<GridCase> {
    use EndKind::*;
    let starts = [Clamp, Pin, PortClamp, PortPin];
    let ends = [Clamp, Pin, Free, PortClamp, PortPin];
    let eis = [10.0, 1.0, 0.1, 1e-2, 1e-4, 1e-6];
    let ratios = [1e2, 1e4, 1e6, 1e8, 1e10, 1e12];
    let meshes = [10, 20, 50, 100, 200];
    let spans = [0.3, 0.6, 0.9, 0.99, 0.999];
    let clips = [
        None,
        None,
        Some(ClipKind::Fixed),
        Some(ClipKind::Revolute),
        Some(ClipKind::Spherical),
    ];
    let mut rng = SplitMix(GRID_SEED);
    let mut out = Vec::with_capacity(count);
    while out.len() < count {
        let index = out.len();
        let start = rng.pick(&starts);
        let end = rng.pick(&ends);
        let ei = rng.pick(&eis);
        let feasible: Vec<f64> = ratios
            .iter()
            .map(|r| r * ei)
            .filter(|ea| (1e2..=1e10).contains(ea))
            .collect();
        let ea = rng.pick(&feasible);
        let segments = if index % 25 == 24 {
            1000
        } else {
            rng.pick(&meshes)
        };
        let span = if end == Free { 1.0 } else { rng.pick(&spans) };
        let gravity = rng.next().is_multiple_of(2);
        let dead_load = end == Free && (!gravity || rng.next().is_multiple_of(2));
        let route = rng.next().is_multiple_of(2);
        let clip = rng.pick(&clips);
        out.push(GridCase {
            index,
            start,
            end,
            ei,
            ea,
            segments,
            span,
            gravity,
            dead_load,
            route,
            clip,
        });
    }
    out
}

/// A frame whose tangent `a3` is `+x` (a rotation by π/2 about `y`: `a1 = −z`, `a2 = y`).
fn frame_along_x() -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2)
}

/// The system of one grid case (see the [module docs](self) for the geometry).
///
/// # Panics
///
/// If the case's section or mesh is invalid (never for a case of [`convergence_grid`]).
pub fn grid_system(case: &GridCase) -> System {
    let l = GridCase::LENGTH;
    let section = Section::try_explicit(
        case.ea,
        case.ea / 3.0,
        case.ei,
        case.ei / 1.5,
        if case.gravity {
            GridCase::MASS_PER_LENGTH
        } else {
            0.0
        },
        0.0,
    )
    .expect("valid grid section");
    let start_position = Vector3::zeros();
    let d = case.span * l;
    let end_position = Vector3::new(d, 0.0, 0.0);
    let mut bodies = vec![];
    // A fixed body at `position` with one port whose boundary frame is `frame_along_x`
    // (at the rod's end vertex the port frame is turned by π about its a1, so that its
    // a3 points into the rod, `−x`; see `System::port_offset`).
    let mut port_end = |position: Vector3<f64>, at_end: bool, clamped: bool| {
        let frame = if at_end {
            frame_along_x() * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), PI)
        } else {
            frame_along_x()
        };
        bodies.push(BodySpec {
            name: format!("mount{}", bodies.len()),
            mass: 0.0,
            center_of_mass: Vector3::zeros(),
            pose: Pose {
                position,
                orientation: UnitQuaternion::identity(),
            },
            fixed: true,
            ports: vec![Port {
                name: "port".into(),
                position: Vector3::zeros(),
                frame,
            }],
        });
        End {
            support: Support::Port {
                body: BodyHandle(bodies.len() - 1),
                port: 0,
                clamped,
            },
            ..End::free()
        }
    };
    let mut make_end = |kind: EndKind, position: Vector3<f64>, at_end: bool| match kind {
        EndKind::Clamp => End::clamped(position, frame_along_x()),
        EndKind::Pin => End::pinned(position),
        EndKind::Free => End::free(),
        EndKind::PortClamp => port_end(position, at_end, true),
        EndKind::PortPin => port_end(position, at_end, false),
    };
    let start = make_end(case.start, start_position, false);
    let mut end = make_end(case.end, end_position, true);
    if case.dead_load {
        end = end.with_force(Vector3::new(0.3, 0.4, -0.866));
    }
    // The middle of the rod: at the clip, or off to the side for a route.
    let half = 0.5 * l;
    let reach = if case.end == EndKind::Free {
        0.9 * l
    } else {
        d
    };
    let sideways = (half * half - 0.25 * reach * reach).max(0.0).sqrt();
    let clip_position = Vector3::new(0.5 * reach, 0.0, -0.6 * sideways);
    let route = case.route.then(|| {
        let middle = if case.clip.is_some() {
            clip_position
        } else {
            Vector3::new(0.5 * reach, 0.9 * sideways, 0.0)
        };
        let chord = middle - start_position;
        if case.end == EndKind::Free {
            // Out to the middle, then on along +y for the rest of the length.
            let rest = (l - chord.norm()).max(0.1 * l);
            vec![
                start_position,
                middle,
                middle + Vector3::new(0.0, rest, 0.0),
            ]
        } else {
            vec![start_position, middle, end_position]
        }
    });
    let clips = case
        .clip
        .map(|kind| ClipSpec {
            name: "clip".into(),
            body: None,
            parent: None,
            base: Pose {
                position: clip_position,
                orientation: frame_along_x(),
            },
            joint: match kind {
                ClipKind::Fixed => Joint::Fixed,
                // The base frame's a2 is the world y axis.
                ClipKind::Revolute => Joint::Revolute { axis: Vector3::y() },
                ClipKind::Spherical => Joint::Spherical,
            },
            offset: Pose {
                position: Vector3::zeros(),
                orientation: UnitQuaternion::identity(),
            },
            rod: RodHandle(0),
            vertex: case.segments / 2,
            limits: None,
        })
        .into_iter()
        .collect();
    System {
        rods: vec![RodSpec {
            name: "rod".into(),
            rod: Rod::try_straight(section, l, case.segments).expect("valid grid mesh"),
            start,
            end,
            route,
        }],
        bodies,
        clips,
        gravity: if case.gravity {
            Vector3::new(0.0, 0.0, -9.81)
        } else {
            Vector3::zeros()
        },
    }
}

/// The outcome of one case of `strand bench --grid`.
#[derive(Clone, Debug, PartialEq)]
pub struct GridRow {
    /// The case's [`GridCase::label`].
    pub label: String,
    /// The solver's report, or why there is none (invalid system or solve error).
    pub outcome: Result<GridSolve, String>,
}

/// The figures of one solved grid case.
#[derive(Clone, Debug, PartialEq)]
pub struct GridSolve {
    /// Whether the solve converged.
    pub converged: bool,
    /// Newton iterations of every kind (`report.iterations`).
    pub iterations: usize,
    /// Newton iterations on the full model.
    pub fine_iterations: usize,
    /// Newton iterations on the coarse model (nested iteration).
    pub coarse_iterations: usize,
    /// Newton iterations of the continuation steps.
    pub continuation_iterations: usize,
    /// Final combined residual, N.
    pub residual_n: f64,
    /// Whether the equilibrium is stable.
    pub stable: bool,
    /// Wall time of the solve (cold: symbolic analysis included), ms.
    pub time_ms: f64,
}

/// Solves `case` with `settings` from its initial state, timing the solve.
pub fn run_case(case: &GridCase, settings: &SolverSettings) -> GridRow {
    let label = case.label();
    let outcome = Model::try_new(grid_system(case))
        .map_err(|e| format!("invalid system: {e}"))
        .and_then(|model| {
            let started = Instant::now();
            let solution = solve(&model, initial_state(model.system()), settings)
                .map_err(|e| format!("solve error: {e}"))?;
            let time_ms = started.elapsed().as_secs_f64() * 1e3;
            let r = &solution.report;
            Ok(GridSolve {
                converged: r.converged,
                iterations: r.iterations,
                fine_iterations: r.fine_iterations,
                coarse_iterations: r.coarse_iterations,
                continuation_iterations: r.continuation_iterations,
                residual_n: r.residual.combined_n,
                stable: r.stable,
                time_ms,
            })
        });
    GridRow { label, outcome }
}

/// Solves the first `count` cases of the map with the default settings, calling
/// `on_row` after each case (to print it as it comes). With the environment variable
/// `STRAND_MAP_CASE=<index>` only that case runs (to trace it with `STRAND_TRACE=1`);
/// `STRAND_MAP_SETTINGS=<json>` (fields of `SolverSettings`, e.g.
/// `{"mixed_newton":false}`) replaces the defaults, to measure a setting's effect.
pub fn run_grid(count: usize, mut on_row: impl FnMut(&GridRow)) -> Vec<GridRow> {
    let settings: SolverSettings = std::env::var("STRAND_MAP_SETTINGS")
        .ok()
        .map(|j| serde_json::from_str(&j).expect("STRAND_MAP_SETTINGS: SolverSettings JSON"))
        .unwrap_or_default();
    let only: Option<usize> = std::env::var("STRAND_MAP_CASE")
        .ok()
        .and_then(|v| v.parse().ok());
    convergence_grid(count)
        .iter()
        .enumerate()
        .filter(|(index, _)| only.is_none_or(|o| o == *index))
        .map(|(_, case)| {
            let row = run_case(case, &settings);
            on_row(&row);
            row
        })
        .collect()
}

/// Width of the label column.
const LABEL_WIDTH: usize = 78;

/// The header line of the table (ends with a newline).
pub fn grid_header() -> String {
    format!(
        "{:<LABEL_WIDTH$} {:>5} {:>5} {:>6} {:>5} {:>12} {:>6} {:>10}\n",
        "case", "iter", "fine", "coarse", "cont", "residual [N]", "stable", "time [ms]"
    )
}

/// One line of the table (ends with a newline); a case that did not converge is
/// marked `NOT CONVERGED`.
pub fn format_grid_row(row: &GridRow) -> String {
    match &row.outcome {
        Ok(s) => format!(
            "{:<LABEL_WIDTH$} {:>5} {:>5} {:>6} {:>5} {:>12.2e} {:>6} {:>10.1}{}\n",
            row.label,
            s.iterations,
            s.fine_iterations,
            s.coarse_iterations,
            s.continuation_iterations,
            s.residual_n,
            if s.stable { "yes" } else { "no" },
            s.time_ms,
            if s.converged { "" } else { "  NOT CONVERGED" },
        ),
        Err(e) => format!("{:<LABEL_WIDTH$} {e}\n", row.label),
    }
}

/// Totals of a grid run.
#[derive(Clone, Debug, PartialEq)]
pub struct GridSummary {
    /// Cases run.
    pub cases: usize,
    /// Cases that converged.
    pub converged: usize,
    /// Cases without a solution (invalid system or solve error).
    pub errors: usize,
    /// Newton iterations summed over the solved cases.
    pub total_iterations: usize,
    /// Median iterations of the solved cases (0 if none).
    pub median_iterations: f64,
    /// Maximum iterations of the solved cases (0 if none).
    pub max_iterations: usize,
    /// Median solve time of the solved cases, ms (0 if none).
    pub median_ms: f64,
    /// Solve time summed over the solved cases, ms.
    pub total_ms: f64,
}

impl GridSummary {
    /// The totals of `rows`. Iterations and times count every solved case, converged or
    /// not (as the validation test does).
    pub fn of(rows: &[GridRow]) -> Self {
        let solved: Vec<&GridSolve> = rows
            .iter()
            .filter_map(|r| r.outcome.as_ref().ok())
            .collect();
        let iterations: Vec<f64> = solved.iter().map(|s| s.iterations as f64).collect();
        let times: Vec<f64> = solved.iter().map(|s| s.time_ms).collect();
        GridSummary {
            cases: rows.len(),
            converged: solved.iter().filter(|s| s.converged).count(),
            errors: rows.len() - solved.len(),
            total_iterations: solved.iter().map(|s| s.iterations).sum(),
            median_iterations: median(iterations),
            max_iterations: solved.iter().map(|s| s.iterations).max().unwrap_or(0),
            median_ms: median(times),
            total_ms: solved.iter().map(|s| s.time_ms).sum(),
        }
    }

    /// Whether every case converged and both iteration targets are met.
    pub fn all_targets_met(&self) -> bool {
        self.converged == self.cases && self.median_target_met() && self.max_target_met()
    }

    /// Whether the median iterations are at most [`MEDIAN_ITERATIONS_TARGET`].
    pub fn median_target_met(&self) -> bool {
        self.median_iterations <= MEDIAN_ITERATIONS_TARGET
    }

    /// Whether the maximum iterations are at most [`MAX_ITERATIONS_TARGET`].
    pub fn max_target_met(&self) -> bool {
        self.max_iterations <= MAX_ITERATIONS_TARGET
    }
}

impl std::fmt::Display for GridSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let met = |ok: bool| if ok { "met" } else { "NOT MET" };
        writeln!(
            f,
            "converged: {} of {} cases ({} not converged, {} errors) [target: all: {}]",
            self.converged,
            self.cases,
            self.cases - self.converged - self.errors,
            self.errors,
            met(self.converged == self.cases)
        )?;
        writeln!(
            f,
            "iterations: total {}, median {}, max {} [targets: median <= {}: {}, max <= {}: {}]",
            self.total_iterations,
            self.median_iterations,
            self.max_iterations,
            MEDIAN_ITERATIONS_TARGET,
            met(self.median_target_met()),
            MAX_ITERATIONS_TARGET,
            met(self.max_target_met())
        )?;
        writeln!(
            f,
            "time: median {:.1} ms, total {:.1} ms",
            self.median_ms, self.total_ms
        )
    }
}

/// The median of `values` (the mean of the middle two for an even count; 0 if empty).
pub fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    match n {
        0 => 0.0,
        _ if n % 2 == 1 => values[n / 2],
        _ => 0.5 * (values[n / 2 - 1] + values[n / 2]),
    }
}

/// The whole table: header, one line per row, then the [`GridSummary`].
pub fn format_grid_table(rows: &[GridRow]) -> String {
    let mut out = grid_header();
    for row in rows {
        out += &format_grid_row(row);
    }
    out += &GridSummary::of(rows).to_string();
    out
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_is_deterministic_and_covers_every_level() {
        let grid = convergence_grid(DEFAULT_CASES);
        // Same seed, same cases; a shorter map is a prefix of a longer one.
        assert_eq!(grid, convergence_grid(DEFAULT_CASES));
        assert_eq!(grid[..20], convergence_grid(20)[..]);
        assert!(grid.iter().enumerate().all(|(i, c)| c.index == i));
        let labels: Vec<String> = grid.iter().map(GridCase::label).collect();
        assert_eq!(
            labels,
            convergence_grid(DEFAULT_CASES)
                .iter()
                .map(GridCase::label)
                .collect::<Vec<_>>()
        );
        for kind in [
            EndKind::Clamp,
            EndKind::Pin,
            EndKind::Free,
            EndKind::PortClamp,
            EndKind::PortPin,
        ] {
            assert!(grid.iter().any(|c| c.end == kind), "end {kind:?}");
            if kind != EndKind::Free {
                assert!(grid.iter().any(|c| c.start == kind), "start {kind:?}");
            }
        }
        for ei in [10.0, 1.0, 0.1, 1e-2, 1e-4, 1e-6] {
            assert!(grid.iter().any(|c| c.ei == ei));
        }
        assert!(grid.iter().any(|c| c.ea / c.ei >= 1e12 * 0.999));
        assert!(grid.iter().any(|c| c.span == 0.999));
        for clip in [
            None,
            Some(ClipKind::Fixed),
            Some(ClipKind::Revolute),
            Some(ClipKind::Spherical),
        ] {
            assert!(grid.iter().any(|c| c.clip == clip), "{clip:?}");
        }
        let big = grid.iter().filter(|c| c.segments == 1000).count();
        assert!((5..=10).contains(&big), "{big}");
        assert!(
            grid.iter()
                .all(|c| c.segments % 2 == 0 && c.start != EndKind::Free)
        );
        assert!(
            grid.iter()
                .all(|c| c.end != EndKind::Free || c.gravity || c.dead_load)
        );
    }

    #[test]
    fn every_grid_case_builds_a_valid_model() {
        for case in convergence_grid(DEFAULT_CASES) {
            let system = grid_system(&case);
            assert_eq!(
                system.rods[0].rod.segments(),
                case.segments,
                "{}",
                case.label()
            );
            assert_eq!(system.clips.len(), usize::from(case.clip.is_some()));
            if let Err(e) = Model::try_new(system) {
                panic!("{}: {e}", case.label());
            }
        }
    }

    fn solved(iterations: usize, converged: bool, time_ms: f64) -> GridRow {
        GridRow {
            label: format!("case {iterations}"),
            outcome: Ok(GridSolve {
                converged,
                iterations,
                fine_iterations: iterations,
                coarse_iterations: 0,
                continuation_iterations: 0,
                residual_n: 1e-9,
                stable: true,
                time_ms,
            }),
        }
    }

    #[test]
    fn summary_counts_medians_and_targets() {
        let rows = vec![
            solved(4, true, 1.0),
            solved(10, true, 3.0),
            solved(30, false, 2.0),
            solved(120, true, 10.0),
            GridRow {
                label: "broken".into(),
                outcome: Err("invalid system: no".into()),
            },
        ];
        let summary = GridSummary::of(&rows);
        assert_eq!(summary.cases, 5);
        assert_eq!(summary.converged, 3);
        assert_eq!(summary.errors, 1);
        assert_eq!(summary.total_iterations, 164);
        assert_eq!(summary.median_iterations, 20.0);
        assert_eq!(summary.max_iterations, 120);
        assert_eq!(summary.median_ms, 2.5);
        assert_eq!(summary.total_ms, 16.0);
        assert!(summary.median_target_met());
        assert!(!summary.max_target_met());
        assert!(!summary.all_targets_met());
        let table = format_grid_table(&rows);
        assert!(table.starts_with("case "), "{table}");
        assert!(table.contains("NOT CONVERGED"), "{table}");
        assert!(table.contains("broken"), "{table}");
        assert!(table.contains("median <= 20: met"), "{table}");
        assert!(table.contains("max <= 100: NOT MET"), "{table}");
        assert!(
            table.contains("converged: 3 of 5 cases (1 not converged, 1 errors)"),
            "{table}"
        );
        let all = GridSummary::of(&rows[..2]);
        assert!(all.all_targets_met());
        assert_eq!(GridSummary::of(&[]).median_iterations, 0.0);
    }
}
