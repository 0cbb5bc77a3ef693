//! `strand bench`: solve time, iterations and residual of a case at several
//! discretisations, as a table (a benchmark, not a test: timings are medians of
//! repeated solves on whatever machine runs it).
//!
//! [`grid`] is the convergence map of issue 9 (`strand bench --grid`): its cases, the
//! system of each, and the table of iterations and times per case; [`contact`] the
//! bundled contact cases (`strand bench --contact`); [`motion`] the engine-roll motion
//! (`strand bench --motion`); [`sensitivity`] the cost of the sensitivities against the
//! solve (`strand bench --sensitivity`); [`mesh`] the cold and cached load of a mesh file
//! (`strand bench --mesh FILE`), run by the binary in fresh memory ([`fresh_memory`]).

pub mod contact;
pub mod fresh_memory;
pub mod grid;
pub mod mesh;
pub mod motion;
pub mod sensitivity;

use std::path::Path;
use std::time::Instant;

use strand_case::{BuiltCase, Case};
use strand_solve::{Solution, Solver};

/// The paper's method (IPOPT with exact Hessians) on the position-controlled Fig. 3
/// case, as reported to us for this kind of machine: (edges, ms).
pub const IPOPT_REFERENCE_MS: [(usize, f64); 3] = [(19, 6.0), (99, 32.0), (999, 290.0)];

/// One row of the benchmark table.
#[derive(Clone, Debug)]
pub struct BenchRow {
    /// Edges per rod.
    pub segments: usize,
    /// Scalar unknowns.
    pub unknowns: usize,
    /// Median wall time of a cold solve (symbolic analysis, coarse and fine Newton), ms.
    pub cold_ms: f64,
    /// Median wall time of a re-solve from the same start with the symbolic analysis
    /// reused, ms.
    pub reuse_ms: f64,
    /// Newton iterations on the full model.
    pub iterations: usize,
    /// Newton iterations on the coarse model (nested iteration).
    pub coarse_iterations: usize,
    /// Final residual, N.
    pub residual_n: f64,
    /// Whether the solve converged.
    pub converged: bool,
}

fn median(mut samples: Vec<f64>) -> f64 {
    samples.sort_by(f64::total_cmp);
    samples[samples.len() / 2]
}

/// Solves `case` at each number of `segments`, `repeats` times each.
pub fn run(
    case: &Path,
    segments: &[usize],
    repeats: usize,
) -> Result<Vec<BenchRow>, Box<dyn std::error::Error>> {
    let case = Case::from_path(case)?;
    let mut rows = Vec::new();
    for &n in segments {
        let built = case.build(Some(n))?;
        let mut cold = Vec::with_capacity(repeats);
        let mut reuse = Vec::with_capacity(repeats);
        let mut last = None;
        for _ in 0..repeats.max(1) {
            let (solution, cold_ms, reuse_ms) = cold_solve(&built, |solver| {
                let started = Instant::now();
                solver.solve(built.initial.clone(), &built.settings)?;
                Ok(started.elapsed().as_secs_f64() * 1e3)
            })?;
            cold.push(cold_ms);
            reuse.push(reuse_ms);
            last = Some(solution.report);
        }
        let report = last.expect("at least one repeat");
        rows.push(BenchRow {
            segments: n,
            unknowns: report.unknowns,
            cold_ms: median(cold),
            reuse_ms: median(reuse),
            iterations: report.iterations,
            coarse_iterations: report.coarse_iterations,
            residual_n: report.residual.combined_n,
            converged: report.converged,
        });
    }
    Ok(rows)
}

/// One cold solve of `built` (contact set-up and symbolic analysis included), timed in
/// ms; `then` runs afterwards with the same solver (e.g. a timed re-solve).
fn cold_solve<T>(
    built: &BuiltCase,
    then: impl FnOnce(&mut Solver) -> Result<T, strand_solve::SolveError>,
) -> Result<(Solution, f64, T), Box<dyn std::error::Error>> {
    let started = Instant::now();
    let contact = built.contact();
    let mut solver = Solver::try_new(&built.model)?;
    if let Some(c) = &contact {
        solver = solver.with_constraints(c);
    }
    let solution = solver.solve(built.initial.clone(), &built.settings)?;
    let cold_ms = started.elapsed().as_secs_f64() * 1e3;
    let after = then(&mut solver)?;
    Ok((solution, cold_ms, after))
}

/// The table as text, with the IPOPT reference and the speed-up where known.
pub fn format_table(rows: &[BenchRow]) -> String {
    let mut out = String::from(
        "edges  unknowns  cold solve [ms]  re-solve [ms]  iterations (coarse)  residual [N]  converged  IPOPT [ms]  speed-up\n",
    );
    for row in rows {
        let reference = IPOPT_REFERENCE_MS
            .iter()
            .find(|(n, _)| *n == row.segments)
            .map(|(_, ms)| *ms);
        let (ipopt, speedup) = match reference {
            Some(ms) => (format!("{ms:>10.0}"), format!("{:>8.0}x", ms / row.cold_ms)),
            None => (format!("{:>10}", "-"), format!("{:>9}", "-")),
        };
        out.push_str(&format!(
            "{:>5}  {:>8}  {:>15.3}  {:>13.3}  {:>10} ({:>3})     {:>12.2e}  {:>9}  {ipopt}  {speedup}\n",
            row.segments,
            row.unknowns,
            row.cold_ms,
            row.reuse_ms,
            row.iterations,
            row.coarse_iterations,
            row.residual_n,
            if row.converged { "yes" } else { "NO" },
        ));
    }
    out
}
