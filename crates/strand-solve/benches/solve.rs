//! Solver benchmarks (issue 11): the sparse Cholesky factorisation of a rod's Hessian,
//! one-rod solves of the Fig. 3 elastica at 19/99/999/9999 edges, the cooler hoses, and
//! the cooler hoses in their engine bay with a generated floor of 1k and 1M triangles
//! (cold solves as `strand bench` times them: contact set-up, symbolic analysis,
//! Newton; the meshes are loaded before timing).
//!
//! `cargo bench -p strand-solve --bench solve`

// criterion's macros generate undocumented functions.
#![allow(missing_docs)]

use std::path::{Path, PathBuf};

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use strand_case::{BuiltCase, Case};
use strand_solve::{Solution, Solver, SparseCholesky};

fn cases() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases")
}

/// A cold solve of `built`, as `strand bench` times it.
fn cold_solve(built: &BuiltCase) -> Solution {
    let contact = built.contact();
    let mut solver = Solver::try_new(&built.model).unwrap();
    if let Some(c) = &contact {
        solver = solver.with_constraints(c);
    }
    let solution = solver
        .solve(built.initial.clone(), &built.settings)
        .unwrap();
    assert!(solution.report.converged);
    solution
}

fn factorisation(c: &mut Criterion) {
    let case = Case::from_path(cases().join("elastica_fig3.ron")).unwrap();
    let mut group = c.benchmark_group("factorisation fig3");
    for edges in [999, 9999] {
        let built = case.build(Some(edges)).unwrap();
        let solved = cold_solve(&built);
        let mut evaluation = built.model.new_evaluation();
        built.model.evaluate(&solved.state, &mut evaluation, true);
        group.bench_function(BenchmarkId::new("symbolic", edges), |b| {
            b.iter(|| SparseCholesky::try_new(built.model.pattern()).unwrap())
        });
        let mut cholesky = SparseCholesky::try_new(built.model.pattern()).unwrap();
        group.bench_function(BenchmarkId::new("numeric LLT", edges), |b| {
            b.iter(|| assert!(cholesky.factor(&evaluation.hessian)))
        });
        let mut rhs = evaluation.gradient.clone();
        group.bench_function(BenchmarkId::new("solve", edges), |b| {
            b.iter(|| cholesky.solve_in_place(&mut rhs))
        });
    }
    group.finish();
}

fn one_rod(c: &mut Criterion) {
    let case = Case::from_path(cases().join("elastica_fig3.ron")).unwrap();
    let mut group = c.benchmark_group("one rod fig3");
    group.sample_size(10);
    for edges in [19, 99, 999, 9999] {
        let built = case.build(Some(edges)).unwrap();
        group.bench_function(BenchmarkId::from_parameter(edges), |b| {
            b.iter(|| cold_solve(&built))
        });
    }
    group.finish();
}

/// The cooler-hose contact case with a wavy floor of `triangles` triangles (2 m square,
/// ±40 mm waves, 105 mm below the T: hose 3 within its contact margin), as
/// `assets/bench/cooler_hose_contact_1M.ron` describes it.
fn contact_case(dir: &Path, triangles: usize) -> BuiltCase {
    let floor = dir.join(format!("floor_{triangles}.obj"));
    let mesh = strand_assets::wavy_surface(2000.0, triangles);
    strand_assets::write_obj(&floor, &[("floor", &mesh)], &Default::default()).unwrap();
    let bench = cases().join("../assets/bench/cooler_hose_contact_1M.ron");
    let text = std::fs::read_to_string(&bench).unwrap();
    let bay = cases().join("../assets/engine_bay");
    let text = text
        .replace("\"../engine_bay/", &format!("\"{}/", bay.display()))
        .replace(
            "\"../../target/meshes/surface_1M.obj\"",
            &format!("{:?}", floor.to_str().unwrap()),
        );
    let path = dir.join(format!("contact_{triangles}.ron"));
    std::fs::write(&path, text).unwrap();
    Case::from_path(&path).unwrap().build(None).unwrap()
}

fn cooler(c: &mut Criterion) {
    let mut group = c.benchmark_group("cooler hose");
    group.sample_size(10);
    let free = Case::from_path(cases().join("cooler_hose.ron"))
        .unwrap()
        .build(None)
        .unwrap();
    group.bench_function("no contact", |b| b.iter(|| cold_solve(&free)));
    let bay = Case::from_path(cases().join("cooler_hose_contact.ron"))
        .unwrap()
        .build(None)
        .unwrap();
    group.bench_function("engine bay", |b| b.iter(|| cold_solve(&bay)));
    let dir = tempfile::tempdir().unwrap();
    for (label, triangles) in [("1k", 1_000), ("1M", 1_000_000)] {
        let built = contact_case(dir.path(), triangles);
        group.bench_function(BenchmarkId::new("engine bay + floor", label), |b| {
            b.iter(|| cold_solve(&built))
        });
    }
    group.finish();
}

criterion_group!(benches, factorisation, one_rod, cooler);
criterion_main!(benches);
