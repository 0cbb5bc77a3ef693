//! `strand bench --sensitivity [CASE]`: the cost of the sensitivities of every output
//! with respect to up to ten parameters of the case (rod lengths, junction masses,
//! connector position components, gravity) against its solve: the median of repeated
//! runs, and the cost per Newton iteration of the base solve (the issue-13 target:
//! all sensitivities for less than one extra Newton iteration).

use std::path::Path;
use std::time::Instant;

use strand_case::{Case, CaseDesign, DesignParameter};
use strand_solve::sensitivity::{Sensitivities, SensitivitySettings};
use strand_study::sensitivity::output_table;

/// Most parameters the benchmark differentiates with respect to.
pub const MAX_PARAMETERS: usize = 10;

/// The benchmark's result.
#[derive(Clone, Debug)]
pub struct SensitivityBench {
    /// The parameters, as variant items (`rods.hose2.length`, `…position` + component).
    pub parameters: Vec<String>,
    /// Outputs differentiated.
    pub outputs: usize,
    /// Median cold solve, ms.
    pub solve_ms: f64,
    /// Newton iterations of the solve.
    pub iterations: usize,
    /// Median of the state and multiplier derivatives alone (implicit function
    /// theorem: the right-hand sides, one factorisation, the back-substitutions), ms.
    pub state_ms: f64,
    /// Median of every output's derivatives (the state's plus the chain rule), ms.
    pub outputs_ms: f64,
}

/// The parameters of `case` the benchmark takes: rod lengths, junction masses,
/// connectors' z then x positions, gravity's z, up to [`MAX_PARAMETERS`].
fn parameters(case: &Case) -> Vec<DesignParameter> {
    let f = &case.file;
    let length = |item: String| DesignParameter {
        item,
        component: None,
        scale: 1.0 / strand_case::LengthUnit::parse(&f.units.length).map_or(1.0, |u| u.metres()),
    };
    let mut out: Vec<DesignParameter> = f
        .rods
        .iter()
        .filter(|r| r.length.is_some())
        .map(|r| length(format!("rods.{}.length", r.name)))
        .collect();
    out.extend(f.junctions.iter().map(|(n, _)| DesignParameter {
        item: format!("junctions.{n}.mass"),
        component: None,
        scale: 100.0,
    }));
    for component in [2, 0] {
        out.extend(f.connectors.iter().map(|(n, _)| DesignParameter {
            component: Some(component),
            ..length(format!("connectors.{n}.position"))
        }));
    }
    out.push(DesignParameter {
        item: "gravity".into(),
        component: Some(2),
        scale: 10.0,
    });
    out.truncate(MAX_PARAMETERS);
    out
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Runs the benchmark on `case`, `repeats` times.
pub fn run(case: &Path, repeats: usize) -> Result<SensitivityBench, Box<dyn std::error::Error>> {
    let case = Case::from_path(case)?;
    let built = case.build(None)?;
    let params = parameters(&case);
    let mut solve = Vec::new();
    let mut state = Vec::new();
    let mut outputs = Vec::new();
    let mut last = None;
    let settings = SensitivitySettings::default();
    for _ in 0..repeats.max(1) {
        let started = Instant::now();
        let solution = built.solve_from(built.initial.clone(), &built.settings)?;
        solve.push(started.elapsed().as_secs_f64() * 1e3);
        if !solution.report.converged {
            return Err(format!("{}: the case did not converge", case.origin).into());
        }
        // As `strand sensitivity` does: the design's builds start from the equilibrium.
        let design = CaseDesign::new(&case, params.clone()).starting_from(&solution.state);
        let started = Instant::now();
        Sensitivities::compute(&design, &solution, &settings)?;
        state.push(started.elapsed().as_secs_f64() * 1e3);
        let design = CaseDesign::new(&case, params.clone()).starting_from(&solution.state);
        let started = Instant::now();
        let table = output_table(&design, &solution, &settings)?;
        outputs.push(started.elapsed().as_secs_f64() * 1e3);
        last = Some((solution.report.iterations, table.outputs.len()));
    }
    let (iterations, count) = last.expect("one repeat");
    Ok(SensitivityBench {
        parameters: params
            .iter()
            .map(|p| match p.component {
                Some(c) => format!("{}.{}", p.item, ["x", "y", "z"][c]),
                None => p.item.clone(),
            })
            .collect(),
        outputs: count,
        solve_ms: median(solve),
        iterations,
        state_ms: median(state),
        outputs_ms: median(outputs),
    })
}

/// The benchmark as text.
pub fn format(b: &SensitivityBench) -> String {
    let per_iteration = b.solve_ms / b.iterations.max(1) as f64;
    format!(
        "parameters  {} ({})\nsolve       {:.2} ms, {} Newton iterations ({:.2} ms per iteration)\nstate       {:.2} ms: d(state)/d(parameters) ({:.2} Newton iterations)\noutputs     {:.2} ms: {} outputs × {} parameters ({:.2} Newton iterations; target < 1)\n",
        b.parameters.len(),
        b.parameters.join(", "),
        b.solve_ms,
        b.iterations,
        per_iteration,
        b.state_ms,
        b.state_ms / per_iteration,
        b.outputs_ms,
        b.outputs,
        b.parameters.len(),
        b.outputs_ms / per_iteration
    )
}
