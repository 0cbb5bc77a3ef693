//! Result writing benchmarks (issue 11): each output format of one solved cooler-hose
//! variant (as `strand batch` writes per variant), in bytes per second, and the whole
//! atomic `write_results_in` (every file, temporary files renamed into place).
//!
//! `cargo bench -p strand-report --bench write`

// criterion's macros generate undocumented functions.
#![allow(missing_docs)]

use std::path::Path;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use strand_report::{
    ExportUnit, ResultDoc, Timing, collect, rod_csv, rods_vtp_in, tubes_obj_in, tubes_stl,
    write_results_in,
};

/// The solved cooler hoses at `segments` edges per hose (the case's default: `None`).
fn solved_doc(segments: Option<usize>) -> (ResultDoc, ExportUnit) {
    let case = strand_case::Case::from_path(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases/cooler_hose.ron"),
    )
    .unwrap();
    let built = case.build(segments).unwrap();
    let solution = built
        .solve_from(built.initial.clone(), &built.settings)
        .unwrap();
    assert!(solution.report.converged);
    let doc = collect(&built.name, &built.model, &solution, Timing::default());
    let unit = ExportUnit::new(built.length_unit.metres(), built.length_unit.symbol());
    (doc, unit)
}

fn formats(c: &mut Criterion) {
    let (doc, unit) = solved_doc(None);
    let mut group = c.benchmark_group("write cooler");
    let json = serde_json::to_vec_pretty(&doc).unwrap();
    group.throughput(Throughput::Bytes(json.len() as u64));
    group.bench_function("result.json", |b| {
        b.iter(|| serde_json::to_vec_pretty(&doc).unwrap())
    });
    let csv: usize = doc.rods.iter().map(|r| rod_csv(r).len()).sum();
    group.throughput(Throughput::Bytes(csv as u64));
    group.bench_function("rod csv (all rods)", |b| {
        b.iter(|| doc.rods.iter().map(|r| rod_csv(r).len()).sum::<usize>())
    });
    group.throughput(Throughput::Bytes(rods_vtp_in(&doc, &unit).len() as u64));
    group.bench_function("rods.vtp", |b| b.iter(|| rods_vtp_in(&doc, &unit)));
    group.throughput(Throughput::Bytes(tubes_obj_in(&doc, &unit).len() as u64));
    group.bench_function("tubes.obj", |b| b.iter(|| tubes_obj_in(&doc, &unit)));
    group.throughput(Throughput::Bytes(tubes_stl(&doc, &unit).len() as u64));
    group.bench_function("tubes.stl", |b| b.iter(|| tubes_stl(&doc, &unit)));
    let dir = tempfile::tempdir().unwrap();
    let total: u64 = write_results_in(dir.path(), &doc, &unit)
        .unwrap()
        .iter()
        .map(|p| std::fs::metadata(p).unwrap().len())
        .sum();
    group.throughput(Throughput::Bytes(total));
    group.sample_size(20);
    group.bench_function("write_results_in (all files)", |b| {
        b.iter(|| write_results_in(dir.path(), &doc, &unit).unwrap())
    });
    group.finish();
}

criterion_group!(benches, formats);
criterion_main!(benches);
