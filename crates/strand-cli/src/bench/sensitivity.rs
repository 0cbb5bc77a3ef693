//! `strand bench --sensitivity [CASE]`: the cost of the sensitivities of every output
//! with respect to up to ten parameters of the case (rod lengths, junction masses,
//! connector position components, gravity) against its solve: the median of repeated
//! runs, and the cost per Newton iteration of the base solve (the issue-13 target:
//! all sensitivities for less than one extra Newton iteration). The design analysis
//! (the base build and the probes of every parameter, once per design and reused
//! across equilibria) is timed apart from the per-equilibrium work, and both together.

use std::path::Path;
use std::time::Instant;

use strand_case::{Case, CaseDesign, DesignParameter};
use strand_solve::sensitivity::{Design, Sensitivities, SensitivitySettings};
use strand_study::sensitivity::{LocalOutputs, output_table, outputs_at};

/// Most parameters the benchmark differentiates with respect to.
pub const MAX_PARAMETERS: usize = 10;

/// The benchmark's result.
#[derive(Clone, Debug)]
pub struct SensitivityBench {
    /// The parameters, as variant items (`rods.hose2.length`, `…position` + component).
    pub parameters: Vec<String>,
    /// Outputs differentiated.
    pub outputs: usize,
    /// Whether the outputs were read locally ([`strand_study::sensitivity::LocalOutputs`])
    /// rather than as the whole table.
    pub local_outputs: bool,
    /// Median cold solve, ms.
    pub solve_ms: f64,
    /// Newton iterations of the solve.
    pub iterations: usize,
    /// Median of the design analysis, once per design and reusable across equilibria
    /// ([`CaseDesign::analyse`]: the base build and two probe builds per parameter), ms.
    pub analysis_ms: f64,
    /// Full builds of the analysis.
    pub analysis_builds: usize,
    /// Median of the state and multiplier derivatives alone, on an analysed design
    /// (implicit function theorem: the right-hand sides, one factorisation, the
    /// back-substitutions), ms.
    pub state_ms: f64,
    /// Median of every output's derivatives on an analysed design (the state's plus
    /// the chain rule): the per-equilibrium work, ms.
    pub outputs_ms: f64,
    /// Full builds during the per-equilibrium work (zero when every parameter is
    /// affine).
    pub equilibrium_builds: usize,
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
    let mut built = case.build(None)?;
    // As `strand sensitivity` does: the solver hands its Hessian at the equilibrium on.
    built.settings.keep_hessian = true;
    let params = parameters(&case);
    let (mut solve, mut analysis, mut state, mut outputs) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut last = None;
    let settings = SensitivitySettings::default();
    let ms = |started: Instant| started.elapsed().as_secs_f64() * 1e3;
    for _ in 0..repeats.max(1) {
        let started = Instant::now();
        let solution = built.solve_from(built.initial.clone(), &built.settings)?;
        solve.push(ms(started));
        if !solution.report.converged {
            return Err(format!("{}: the case did not converge", case.origin).into());
        }
        // As `strand sensitivity` does: the design's builds start from the equilibrium.
        let started = Instant::now();
        let design = CaseDesign::new(&case, params.clone()).starting_from(&solution.state);
        design.analyse()?;
        analysis.push(ms(started));
        let analysis_builds = design.full_builds();
        let started = Instant::now();
        let table = output_table(&design, &solution, &settings)?;
        outputs.push(ms(started));
        // The state alone on a design of its own, analysed outside the timing: the
        // first design keeps the models it moved, which would make the second
        // measurement cheaper than an equilibrium's.
        let own = CaseDesign::new(&case, params.clone()).starting_from(&solution.state);
        own.analyse()?;
        let started = Instant::now();
        Sensitivities::compute(&own, &solution, &settings)?;
        state.push(ms(started));
        let base = design.build(&vec![0.0; params.len()])?;
        // As `output_table` plans them (clearances and contact forces read exactly).
        let local =
            LocalOutputs::plan_exact(&base, &solution, &outputs_at(&base, &solution, None)?, None);
        last = Some((
            solution.report.iterations,
            table.outputs.len(),
            local.is_some(),
            analysis_builds,
            design.full_builds() - analysis_builds,
        ));
    }
    let (iterations, count, local_outputs, analysis_builds, equilibrium_builds) =
        last.expect("one repeat");
    Ok(SensitivityBench {
        parameters: params
            .iter()
            .map(|p| match p.component {
                Some(c) => format!("{}.{}", p.item, ["x", "y", "z"][c]),
                None => p.item.clone(),
            })
            .collect(),
        outputs: count,
        local_outputs,
        solve_ms: median(solve),
        iterations,
        analysis_ms: median(analysis),
        analysis_builds,
        state_ms: median(state),
        outputs_ms: median(outputs),
        equilibrium_builds,
    })
}

/// The benchmark as text: the per-equilibrium work (the issue-13 target: less than one
/// Newton iteration of the base solve), the design analysis, and both together.
pub fn format(b: &SensitivityBench) -> String {
    let per_iteration = b.solve_ms / b.iterations.max(1) as f64;
    let iterations = |ms: f64| ms / per_iteration;
    let total = b.analysis_ms + b.outputs_ms;
    let verdict = |ms: f64| {
        if iterations(ms) < 1.0 {
            "met"
        } else {
            "NOT MET"
        }
    };
    format!(
        "parameters  {} ({})\n\
         solve       {:.2} ms, {} Newton iterations ({:.3} ms per iteration)\n\
         analysis    {:.2} ms: base build and {} probe builds, once per design ({:.2} Newton iterations)\n\
         state       {:.3} ms: d(state)/d(parameters) ({:.2} Newton iterations)\n\
         outputs     {:.3} ms: {} outputs × {} parameters, read {}, {} full builds ({:.2} Newton iterations; target < 1: {})\n\
         total       {:.2} ms: analysis and outputs ({:.2} Newton iterations; target < 1: {})\n",
        b.parameters.len(),
        b.parameters.join(", "),
        b.solve_ms,
        b.iterations,
        per_iteration,
        b.analysis_ms,
        b.analysis_builds.saturating_sub(1),
        iterations(b.analysis_ms),
        b.state_ms,
        iterations(b.state_ms),
        b.outputs_ms,
        b.outputs,
        b.parameters.len(),
        if b.local_outputs {
            "locally"
        } else {
            "as the whole table"
        },
        b.equilibrium_builds,
        iterations(b.outputs_ms),
        verdict(b.outputs_ms),
        total,
        iterations(total),
        verdict(total),
    )
}
