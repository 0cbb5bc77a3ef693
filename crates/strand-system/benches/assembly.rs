//! Assembly benchmark (issue 11): energy, gradient and Hessian of the Fig. 3 elastica
//! (one rod) at 999 and 9999 edges, at its start configuration.
//!
//! `cargo bench -p strand-system --bench assembly`

// criterion's macros generate undocumented functions.
#![allow(missing_docs)]

use std::path::Path;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};

fn assembly(c: &mut Criterion) {
    let case = strand_case::Case::from_path(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases/elastica_fig3.ron"),
    )
    .unwrap();
    let mut group = c.benchmark_group("assembly fig3");
    for edges in [999, 9999] {
        let built = case.build(Some(edges)).unwrap();
        let mut evaluation = built.model.new_evaluation();
        group.bench_function(BenchmarkId::new("energy+gradient+Hessian", edges), |b| {
            b.iter(|| built.model.evaluate(&built.initial, &mut evaluation, true))
        });
        group.bench_function(BenchmarkId::new("energy+gradient", edges), |b| {
            b.iter(|| built.model.evaluate(&built.initial, &mut evaluation, false))
        });
    }
    group.finish();
}

criterion_group!(benches, assembly);
criterion_main!(benches);
