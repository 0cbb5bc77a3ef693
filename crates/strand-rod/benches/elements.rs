//! Element kernel benchmarks (issue 11): energy, gradient and exact Hessian of one
//! shear–extension edge element and one bending–torsion vertex element.
//!
//! `cargo bench -p strand-rod --bench elements`

// criterion's macros generate undocumented functions.
#![allow(missing_docs)]

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::{UnitQuaternion, Vector3};
use strand_rod::element::{BendTwist, StretchShear, bend_twist, stretch_shear};

fn kernels(c: &mut Criterion) {
    let frame_a = UnitQuaternion::from_euler_angles(0.1, -0.2, 0.3);
    let frame_b = UnitQuaternion::from_euler_angles(0.12, -0.18, 0.35);
    let strain_stiffness = Vector3::new(1e4, 1e4, 3e4);
    let curvature_stiffness = Vector3::new(1.0, 1.0, 1.0);
    let rest = Vector3::z();
    let zero = Vector3::zeros();
    let edge = StretchShear {
        edge_vector: frame_a * Vector3::new(1e-4, -2e-4, 0.0527),
        frame: &frame_a,
        length: 0.0526,
        stiffness: &strain_stiffness,
        rest_strain: &rest,
    };
    let vertex = BendTwist {
        frame_a: &frame_a,
        frame_b: &frame_b,
        weight: 0.0526,
        stiffness: &curvature_stiffness,
        rest_curvature: &zero,
    };
    let mut group = c.benchmark_group("element");
    group.bench_function("stretch_shear (9x9 Hessian)", |b| {
        b.iter(|| stretch_shear(black_box(&edge)))
    });
    group.bench_function("bend_twist (6x6 Hessian)", |b| {
        b.iter(|| bend_twist(black_box(&vertex)))
    });
    group.finish();
}

criterion_group!(benches, kernels);
criterion_main!(benches);
