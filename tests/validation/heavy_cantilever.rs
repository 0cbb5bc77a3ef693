//! Issue 9: a heavy cantilever (its own weight, large deflection) against the planar
//! Reissner shooting solution with a distributed load
//! (`strand_tests::reference::heavy_cantilever`), default solver settings.
//!
//! The rod: `L = 1 m`, the paper's section (`EA = 30 kN`, `GA = 10 kN`,
//! `EI = GJ = 1 N·m²`), clamped horizontally at the origin, free end, gravity along
//! `−z`, mass per length chosen so that `qL³/EI = 10` and `50`. The discrete rod lumps
//! the weight at the vertices (`h̄_j ρ_L g`); the error is `O(h²)`.

use nalgebra::Vector3;
use strand_rod::{Rod, Section};
use strand_system::{End, RodSpec, System};
use strand_tests::reference::heavy_cantilever::HeavyCantilever;

use crate::common::{frame_along_x, observed_orders, sci, solve_converged};

const MESHES: [usize; 4] = [20, 40, 80, 160];
const G: f64 = 9.81;

fn heavy_rod(segments: usize, q: f64) -> System {
    let section = Section::try_explicit(3e4, 1e4, 1.0, 1.0, q / G, 0.0).unwrap();
    System {
        rods: vec![RodSpec {
            name: "rod".into(),
            rod: Rod::try_straight(section, 1.0, segments).unwrap(),
            start: End::clamped(Vector3::zeros(), frame_along_x()),
            end: End::free(),
            route: None,
        }],
        bodies: vec![],
        clips: vec![],
        gravity: Vector3::new(0.0, 0.0, -G),
    }
}

#[test]
fn heavy_cantilever_tip_and_clamp_moment_converge_at_second_order() {
    for q in [10.0, 50.0] {
        let reference = HeavyCantilever {
            length: 1.0,
            ei: 1.0,
            ga: 1e4,
            ea: 3e4,
            load: q,
            tip_force: [0.0, 0.0],
            clamp_angle: 0.0,
        }
        .solve();
        let (mut tip_errors, mut moment_errors, mut iterations) = (vec![], vec![], vec![]);
        for n in MESHES {
            let (model, solution) = solve_converged(heavy_rod(n, q));
            iterations.push(solution.report.iterations);
            let tip = solution.state.rods[0].positions[n];
            assert!(tip.y.abs() < 1e-12, "stays in the x-z plane");
            // Reference (x, y up) ↔ world (x, z).
            tip_errors.push(
                ((tip.x - reference.tip[0]).powi(2) + (tip.z - reference.tip[1]).powi(2)).sqrt(),
            );
            // A moment about the reference's z axis is about −y in the world.
            let clamp = &model.reactions(&solution.state)[0];
            assert_eq!(clamp.name, "rod.start");
            let m = -clamp.moment.y;
            let m_ref = reference.clamp_reaction_moment();
            moment_errors.push((m - m_ref).abs() / m_ref.abs());
        }
        println!(
            "heavy cantilever qL³/EI = {q}: tip ({:.9}, {:.9}) m, clamp moment {:.9} N·m; \
             tip errors {} m, moment errors {}, \
             iterations {iterations:?}",
            reference.tip[0],
            reference.tip[1],
            reference.clamp_reaction_moment(),
            sci(&tip_errors),
            sci(&moment_errors)
        );
        for (what, errors) in [("tip", &tip_errors), ("clamp moment", &moment_errors)] {
            let orders = observed_orders(errors);
            assert!(errors[0] < 1e-2, "qL³/EI = {q}: {what} errors {errors:?}");
            assert!(
                orders.iter().all(|p| (1.8..2.2).contains(p)),
                "qL³/EI = {q}: {what} errors {errors:?} orders {orders:?}"
            );
        }
    }
}
