//! Initial guesses under gravity (issue 9 item 3): Newton iterations from the
//! gravity-aware guess against the previous guess (a straight rod along the clamp for a
//! hanging cable, a `sin²` bow below the chord for a pinned cable), reproduced here as
//! a route, with the same solver. A measurement, not a check: run with
//! `cargo test --release -p strand-tests --test validation guess -- --ignored --nocapture`.

use nalgebra::Vector3;
use strand_rod::{Rod, Section};
use strand_solve::{SolverSettings, solve};
use strand_system::{End, Model, RodSpec, System, initial_state};

use crate::common::frame_along_x;

/// The previous pinned-cable guess: the chord plus `β sin²(πt)` downwards, `β` such
/// that the 400-piece polyline has the rod's length.
fn bow(span: f64, length: f64) -> Vec<Vector3<f64>> {
    let curve = |beta: f64| -> Vec<Vector3<f64>> {
        (0..=400)
            .map(|i| {
                let t = i as f64 / 400.0;
                Vector3::new(
                    span * t,
                    0.0,
                    -beta * (std::f64::consts::PI * t).sin().powi(2),
                )
            })
            .collect()
    };
    let len = |p: &[Vector3<f64>]| p.windows(2).map(|w| (w[1] - w[0]).norm()).sum::<f64>();
    let (mut lo, mut hi) = (0.0, length);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if len(&curve(mid)) < length {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    curve(0.5 * (lo + hi))
}

fn cable(ei: f64, segments: usize, pinned: bool, old_guess: bool) -> System {
    let section = Section::try_explicit(1e6, 3.5e5, ei, ei / 1.3, 0.5, 0.0).unwrap();
    let (start, end, route) = if pinned {
        (
            End::pinned(Vector3::zeros()),
            End::pinned(Vector3::x() * 0.8),
            old_guess.then(|| bow(0.8, 1.0)),
        )
    } else {
        (
            End::clamped(Vector3::zeros(), frame_along_x()),
            End::free(),
            old_guess.then(|| vec![Vector3::zeros(), Vector3::x()]),
        )
    };
    System {
        rods: vec![RodSpec {
            name: "cable".into(),
            rod: Rod::try_straight(section, 1.0, segments).unwrap(),
            start,
            end,
            route,
        }],
        bodies: vec![],
        clips: Vec::new(),
        gravity: Vector3::new(0.0, 0.0, -9.81),
    }
}

fn iterations(system: System) -> String {
    let model = Model::try_new(system).unwrap();
    match solve(
        &model,
        initial_state(model.system()),
        &SolverSettings::default(),
    ) {
        Ok(s) if s.report.converged => format!("{}", s.report.iterations),
        Ok(s) => format!("{}✗", s.report.iterations),
        Err(e) => format!("err({e})"),
    }
}

#[test]
#[ignore = "measurement: prints a table of Newton iterations"]
fn newton_iterations_from_old_and_new_guesses() {
    println!("| case | EI (N·m²) | N | old guess | new guess |");
    println!("|---|---|---|---|---|");
    for pinned in [false, true] {
        for ei in [1e-1, 1e-2, 1e-3, 1e-4] {
            for segments in [20, 40, 80, 160] {
                let old = iterations(cable(ei, segments, pinned, true));
                let new = iterations(cable(ei, segments, pinned, false));
                let name = if pinned {
                    "pin–pin, span 0.8 L"
                } else {
                    "hanging from clamp"
                };
                println!("| {name} | {ei:.0e} | {segments} | {old} | {new} |");
            }
        }
    }
}
