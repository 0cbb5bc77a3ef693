//! The linearised sectional quantities against central differences of
//! [`sectional_at`] (and of the end terms of a reaction) along the same tangent.

use nalgebra::{UnitQuaternion, Vector3};

use super::*;
use crate::element::{BendTwist, bend_twist_gradient, stretch_shear_gradient};
use crate::sectional::{edge_element, vertex_bend_twist};
use crate::sectional_at::sectional_at;
use crate::{Section, so3};

/// Stiffnesses `(EA, GA, EI, GJ)` of the test section.
const STIFFNESS: [f64; 4] = [2e5, 8e4, 0.3, 0.2];
/// Their change per unit of the tangent.
const D_STIFFNESS: [f64; 4] = [3e4, -1e4, 0.05, 0.02];

/// Edge lengths (m), rest strains and curvatures, state, boundary frames and tangent of
/// [`configuration`].
type Configuration = (
    Vec<f64>,
    Vec<Vector3<f64>>,
    Vec<Vector3<f64>>,
    RodState,
    BoundaryFrames,
    RodTangent,
);

/// A bent, twisted and stretched rod with uneven edges and rest curvature, its
/// boundary frames and end loads, and a tangent that moves everything.
fn configuration() -> Configuration {
    let n = 7;
    let lengths: Vec<f64> = (0..n).map(|e| 0.05 + 0.01 * e as f64).collect();
    let strains: Vec<Vector3<f64>> = (0..n)
        .map(|e| Vector3::new(0.01 * e as f64, 0.0, 1.0))
        .collect();
    let curvatures: Vec<Vector3<f64>> = (0..=n)
        .map(|j| Vector3::new(0.3, -0.1 * j as f64, 0.05))
        .collect();
    let state = crate::test_rods::bent_twisted_state(&lengths);
    let boundary = crate::test_rods::turned_ends(
        Vec::new(),
        [Vector3::new(1.0, -2.0, 0.5), Vector3::new(-0.3, 0.2, 4.0)],
    );
    let wave = |k: usize, a: f64| (a * (k as f64 + 1.0)).sin();
    let tangent = RodTangent {
        positions: (0..=n)
            .map(|j| Vector3::new(wave(j, 0.7), wave(j, 1.3), wave(j, 2.1)) * 0.01)
            .collect(),
        frames: (0..n)
            .map(|e| Vector3::new(wave(e, 0.4), wave(e, 1.9), wave(e, 0.9)) * 0.3)
            .collect(),
        boundary: [
            Vector3::new(0.2, -0.1, 0.3),
            Vector3::new(-0.25, 0.15, 0.05),
        ],
        edge_lengths: (0..n).map(|e| 0.002 * wave(e, 0.5)).collect(),
        rest_strains: (0..n)
            .map(|e| Vector3::new(0.01, -0.02, 0.03) * wave(e, 1.1))
            .collect(),
        rest_curvatures: (0..=n)
            .map(|j| Vector3::new(0.1, 0.2, -0.1) * wave(j, 0.8))
            .collect(),
        strain_stiffness: Vector3::new(D_STIFFNESS[1], D_STIFFNESS[1], D_STIFFNESS[0]),
        curvature_stiffness: Vector3::new(D_STIFFNESS[2], D_STIFFNESS[2], D_STIFFNESS[3]),
        end_loads: [Vector3::new(0.5, 0.1, -0.2), Vector3::new(-0.1, 0.3, 0.7)],
    };
    (lengths, strains, curvatures, state, boundary, tangent)
}

/// The rod, state and boundary moved by `t` along `tangent`.
fn moved(base: &Configuration, t: f64) -> (Rod, RodState, BoundaryFrames) {
    let (lengths, strains, curvatures, state, boundary, tangent) = base;
    let s = |k: usize| STIFFNESS[k] + t * D_STIFFNESS[k];
    let section = Section::try_explicit(s(0), s(1), s(2), s(3), 0.1, 0.005).unwrap();
    let rod = Rod::try_new(
        section,
        lengths
            .iter()
            .zip(&tangent.edge_lengths)
            .map(|(h, d)| h + t * d)
            .collect(),
        strains
            .iter()
            .zip(&tangent.rest_strains)
            .map(|(x, d)| x + t * d)
            .collect(),
        curvatures
            .iter()
            .zip(&tangent.rest_curvatures)
            .map(|(x, d)| x + t * d)
            .collect(),
    )
    .unwrap();
    let positions = state
        .positions
        .iter()
        .zip(&tangent.positions)
        .map(|(r, d)| r + t * d)
        .collect();
    let frames = state
        .frames
        .iter()
        .zip(&tangent.frames)
        .map(|(q, w)| q * so3::exp(&(t * w)))
        .collect();
    let turn =
        |q: &Option<UnitQuaternion<f64>>, w: &Vector3<f64>| q.map(|q| q * so3::exp(&(t * w)));
    let boundary = BoundaryFrames {
        start: turn(&boundary.start, &tangent.boundary[0]),
        end: turn(&boundary.end, &tangent.boundary[1]),
        clips: Vec::new(),
        end_loads: [0, 1].map(|k| boundary.end_loads[k] + t * tangent.end_loads[k]),
    };
    (rod, RodState::new(positions, frames), boundary)
}

/// [`configuration`] with its boundary frames (`attached`) or without, its rod and
/// its linearisation.
fn linearised(attached: bool) -> (Configuration, Rod, SectionalLinearisation) {
    let mut base = configuration();
    if !attached {
        base.4.start = None;
        base.4.end = None;
    }
    let (rod, state, boundary) = moved(&base, 0.0);
    let lin = SectionalLinearisation::new(&rod, &state, &boundary).unwrap();
    (base, rod, lin)
}

/// Richardson-extrapolated central difference of `f` (error `O(t⁴)`).
fn difference(f: impl Fn(f64) -> Vector3<f64>, t: f64) -> Vector3<f64> {
    let d = |h: f64| (f(h) - f(-h)) / (2.0 * h);
    (4.0 * d(t) - d(2.0 * t)) / 3.0
}

fn assert_close(exact: &Vector3<f64>, fd: &Vector3<f64>, scale: f64, what: &str) {
    let error = (exact - fd).norm();
    assert!(
        error <= 1e-7 * scale.max(fd.norm()),
        "{what}: linearised {exact:?} against differences {fd:?} (error {error:.3e})"
    );
}

/// Every vertex's force, moment and curvature change equals the differences of
/// [`sectional_at`] along the tangent, with boundary frames and without.
#[test]
fn vertex_changes_match_differences_of_sectional_at() {
    for attached in [true, false] {
        let (base, rod, lin) = linearised(attached);
        for j in 0..=rod.segments() {
            let (value, d) = lin.vertex_tangent(j, &base.5);
            let at = |t: f64| {
                let (rod, state, boundary) = moved(&base, t);
                sectional_at(&rod, &state, &boundary, j)
            };
            let here = at(0.0);
            assert_close(&value.force, &here.force, 1e-9, "force");
            assert_close(&value.moment, &here.moment, 1e-9, "moment");
            assert_close(&value.curvature, &here.curvature, 1e-9, "curvature");
            let t = 1e-4;
            assert_close(
                &d.force,
                &difference(|t| at(t).force, t),
                here.force.norm(),
                &format!("d force {j}"),
            );
            assert_close(
                &d.moment,
                &difference(|t| at(t).moment, t),
                here.moment.norm(),
                &format!("d moment {j}"),
            );
            assert_close(
                &d.curvature,
                &difference(|t| at(t).curvature, t),
                here.curvature.norm(),
                &format!("d curvature {j}"),
            );
        }
    }
}

/// The end terms of a reaction (the end edge's gradient at the end vertex, the
/// boundary frame's moment) change as their differences.
#[test]
fn end_terms_match_differences() {
    let base = configuration();
    let (rod, state, boundary) = moved(&base, 0.0);
    let lin = SectionalLinearisation::new(&rod, &state, &boundary).unwrap();
    for at_end in [false, true] {
        let terms = |t: f64| {
            let (rod, state, boundary) = moved(&base, t);
            let n = rod.segments();
            let (vertex, edge, local) = if at_end { (n, n - 1, 3) } else { (0, 0, 0) };
            let c = rod.section().strain_stiffness();
            let edge_force: Vector3<f64> =
                stretch_shear_gradient(&edge_element(&rod, &state, &c, edge))
                    .gradient
                    .fixed_rows::<3>(local)
                    .into_owned();
            let k = rod.section().curvature_stiffness();
            let element: BendTwist<'_> =
                vertex_bend_twist(&rod, &state, &boundary, vertex, None, &k).unwrap();
            let g: Vector3<f64> = bend_twist_gradient(&element)
                .gradient
                .fixed_rows::<3>(local)
                .into_owned();
            let frame = if at_end {
                element.frame_b
            } else {
                element.frame_a
            };
            (edge_force, frame * g)
        };
        let (value, d) = lin.end_terms_tangent(at_end, &base.5);
        let here = terms(0.0);
        assert_close(&value.edge_force, &here.0, 1e-9, "edge force");
        assert_close(&value.moment, &here.1, 1e-9, "moment");
        let t = 1e-4;
        assert_close(
            &d.edge_force,
            &difference(|t| terms(t).0, t),
            here.0.norm(),
            "d edge force",
        );
        assert_close(
            &d.moment,
            &difference(|t| terms(t).1, t),
            here.1.norm(),
            "d moment",
        );
    }
}

/// A boundary with clips is not linearised.
#[test]
fn clips_are_not_linearised() {
    let base = configuration();
    let (rod, state, mut boundary) = moved(&base, 0.0);
    boundary.clips.push((3, UnitQuaternion::identity()));
    assert!(SectionalLinearisation::new(&rod, &state, &boundary).is_none());
}

/// Every vertex's size rate from its coefficients equals the rate of the full change
/// (force, moment, bending curvature; with boundary frames and without; along the
/// tangent that moves everything and along one that moves only the configuration).
#[test]
fn size_rates_equal_the_rates_of_the_full_changes() {
    let base = configuration();
    let configuration_only = {
        let mut t = base.5.clone();
        let n = t.frames.len();
        t.edge_lengths = vec![0.0; n];
        t.rest_strains = vec![Vector3::zeros(); n];
        t.rest_curvatures = vec![Vector3::zeros(); n + 1];
        t.strain_stiffness = Vector3::zeros();
        t.curvature_stiffness = Vector3::zeros();
        t.end_loads = [Vector3::zeros(); 2];
        t
    };
    for attached in [true, false] {
        let (base, _, lin) = linearised(attached);
        let values = lin.values();
        for size in [
            SectionalSize::Force,
            SectionalSize::Moment,
            SectionalSize::Curvature,
        ] {
            let rates = lin.size_rates(size, &values);
            for tangent in [&base.5, &configuration_only] {
                let fast = rates.rates(&lin, tangent);
                for (j, &(rate, exact)) in fast.iter().enumerate() {
                    let (value, d) = lin.vertex_tangent(j, tangent);
                    let (full, full_exact) = size.rate(&value, &d);
                    assert_eq!(exact, full_exact, "{size:?} at {j}");
                    let scale = size.vector(&d).norm().max(1e-300);
                    assert!(
                        (rate - full).abs() <= 1e-12 * scale,
                        "{size:?} at {j} (attached {attached}): {rate} against {full}"
                    );
                }
            }
        }
    }
}
