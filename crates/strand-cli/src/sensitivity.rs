//! `strand sensitivity CASE --param NAME … --out DIR`: the derivative of every output
//! of the case's equilibrium with respect to each parameter
//! ([`strand_study::sensitivity`]), written to `DIR/sensitivity.json` and
//! `DIR/sensitivity.csv`, with the base solve's results (`result.json`, per-rod CSV,
//! geometry) so that the folder is an input of `strand report`; the terminal shows
//! the largest ones.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use strand_case::Case;
use strand_report::{ExportUnit, SensitivityDoc, SensitivityOutput, SensitivityParameter, Timing};
use strand_study::sensitivity::{parameters, sensitivities, write_sensitivities};

use crate::Exit;
use crate::commands::Failure;
use crate::summary::significant;

/// Largest derivatives shown on the terminal.
const SHOWN: usize = 12;

/// `strand sensitivity`.
pub(crate) fn run(
    path: &Path,
    names: &[String],
    dir: &Path,
    export_unit: Option<ExportUnit>,
    out: &mut dyn Write,
) -> Result<Exit, Failure> {
    let started = Instant::now();
    let case = Case::from_path(path)?;
    strand_study::limits::check_case(&case)?;
    parameters(&case, names)?;
    let mut built = case.build(None)?;
    // The sensitivities reuse the solver's Hessian at the equilibrium.
    built.settings.keep_hessian = true;
    let solution = crate::commands::solve_cold(&built)?;
    let solve_s = started.elapsed().as_secs_f64();
    let doc = sensitivities(&case, names, &solution)?;
    write_sensitivities(dir, &doc)?;
    let result = strand_study::solve::result_doc(&built, &solution, Timing::default(), None, None)?;
    strand_study::solve::write_result(dir, &result, &built, export_unit.as_ref())?;
    let _ = write!(
        out,
        "{}",
        summary(&doc, solve_s, started.elapsed().as_secs_f64(), dir)
    );
    Ok(Exit::Success)
}

/// The terminal summary: the largest derivatives (by size relative to the output's
/// value) with units.
fn summary(doc: &SensitivityDoc, solve_s: f64, total_s: f64, dir: &Path) -> String {
    let mut rows: Vec<(&SensitivityOutput, &SensitivityParameter, f64)> = Vec::new();
    for o in &doc.outputs {
        for p in &doc.parameters {
            if let Some(&d) = o.d.get(&p.name) {
                rows.push((o, p, d));
            }
        }
    }
    let weight = |(o, _, d): &(&SensitivityOutput, &SensitivityParameter, f64)| {
        (d / o.value.abs().max(1e-12)).abs()
    };
    rows.sort_by(|a, b| weight(b).total_cmp(&weight(a)));
    let mut s = format!(
        "{}: converged (residual {} N); sensitivities of {} outputs to {} parameters in {} s (solve {} s)\n",
        doc.case,
        significant(doc.residual_n, 3),
        doc.outputs.len(),
        doc.parameters.len(),
        significant(total_s - solve_s, 3),
        significant(solve_s, 3),
    );
    s.push_str("largest relative changes (output value, derivative per parameter unit):\n");
    for (o, p, d) in rows.iter().take(SHOWN) {
        let unit = o
            .name
            .rsplit('.')
            .find(|part| part.contains('_'))
            .map_or("", |part| part.rsplit('_').next().unwrap_or(""));
        s.push_str(&format!(
            "  {:<40} {:>12} {unit:<3}  d/d{}: {:>12} {unit}/{}{}\n",
            o.name,
            significant(o.value, 4),
            p.name,
            significant(*d, 4),
            p.unit,
            if o.one_sided.contains(&p.name) {
                "  (one-sided)"
            } else {
                ""
            }
        ));
    }
    if !doc.near_switch.is_empty() {
        s.push_str(&format!(
            "{} constraint rows are near a switch (derivatives one-sided there): see sensitivity.json\n",
            doc.near_switch.len()
        ));
    }
    s.push_str(&format!(
        "written: {}, {} (and the base solve's result.json: `strand report {}` shows the table)\n",
        dir.join("sensitivity.json").display(),
        dir.join("sensitivity.csv").display(),
        dir.display()
    ));
    s
}
