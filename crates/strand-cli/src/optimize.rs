//! `strand optimize CASE --vary NAME=LO..HI … --minimize OBJECTIVE --subject-to C …
//! --out DIR`: the best design within the bounds ([`strand_study::optimize`]); writes
//! `DIR/optimum.json`, `DIR/history.csv`, `DIR/history.svg` and the optimal case
//! `DIR/<case>_optimum.ron`, each atomically and only after the run (bad input writes
//! nothing). Exit 0 when converged, 3 when not (the files are written, with
//! `"converged": false`).

use std::io::Write;
use std::path::Path;

use strand_case::Case;
use strand_report::{ExportUnit, OptimumDoc};
use strand_study::optimize::{
    OptimizeProgress, OptimumIterate, Problem, optimize_case, write_optimum,
};

use crate::Exit;
use crate::commands::Failure;
use crate::summary::significant;

/// The options of `strand optimize`.
pub(crate) struct Options<'a> {
    /// The case file.
    pub case: &'a Path,
    /// `--vary ITEM=LO..HI`.
    pub vary: &'a [String],
    /// `--minimize`.
    pub minimize: &'a str,
    /// `--subject-to`.
    pub subject_to: &'a [String],
    /// `--out`.
    pub dir: &'a Path,
    /// `--export-unit` (default: the case's length unit).
    pub export_unit: Option<ExportUnit>,
}

/// One line of progress per trial point.
fn progress_line(problem: &Problem, unit: &str, it: &OptimumIterate) -> String {
    let values: Vec<String> = problem
        .variables
        .iter()
        .zip(&it.values)
        .map(|(v, x)| format!("{} {} {}", v.name, significant(*x, 6), v.unit))
        .collect();
    let objective = it
        .objective
        .map_or("-".to_string(), |f| format!("{} {unit}", significant(f, 5)));
    format!(
        "  {:>3}  solves {:>3}  {}  objective {objective}  violation {}  {}\n",
        it.iteration,
        it.solves,
        values.join(", "),
        it.violation.map_or("-".to_string(), |v| significant(v, 2)),
        it.note
    )
}

/// The line that states the problem.
fn problem_line(case: &Case, problem: &Problem) -> String {
    format!(
        "optimize    {} ({}): minimise {} over {}\n",
        case.name,
        case.origin,
        problem.objective.name(),
        problem
            .variables
            .iter()
            .map(|v| format!(
                "{} {}..{} {}",
                v.name,
                significant(v.value(v.lower), 6),
                significant(v.value(v.upper), 6),
                v.unit
            ))
            .collect::<Vec<_>>()
            .join(", ")
    )
}

/// `strand optimize`: [`optimize_case`], printed and written.
pub(crate) fn run(options: &Options, out: &mut dyn Write) -> Result<Exit, Failure> {
    let case = Case::from_path(options.case)?;
    let run = {
        let _progress = crate::progress::Progress::start(&case.origin);
        optimize_case(
            &case,
            options.vary,
            options.minimize,
            options.subject_to,
            &mut |progress| {
                let line = match progress {
                    OptimizeProgress::Start(problem) => problem_line(&case, problem),
                    OptimizeProgress::Iterate(problem, it) => {
                        progress_line(problem, problem.objective.unit(), it)
                    }
                };
                let _ = write!(out, "{line}");
            },
        )?
    };
    write_optimum(options.dir, &run.outputs, options.export_unit.as_ref())?;
    let doc = &run.outputs.doc;
    let _ = write!(out, "{}", summary(doc, options.dir));
    Ok(if doc.converged {
        Exit::Success
    } else {
        Exit::NotConverged
    })
}

/// The terminal summary.
fn summary(doc: &OptimumDoc, dir: &Path) -> String {
    let mut s = String::new();
    for v in &doc.variables {
        if let Some(p) = doc.parameters.get(v) {
            s.push_str(&format!(
                "optimum     {v} = {} {} (bounds {}..{} {}){}\n",
                significant(p.value, 6),
                p.unit,
                significant(p.lower, 6),
                significant(p.upper, 6),
                p.unit,
                if p.offset {
                    ", offset from the case"
                } else {
                    ""
                }
            ));
        }
    }
    s.push_str(&format!(
        "objective   {} = {} {} (attained by {})\n",
        doc.objective.name,
        significant(doc.objective.value, 5),
        doc.objective.unit,
        doc.objective.attained_by.join(", ")
    ));
    for c in &doc.active_constraints {
        s.push_str(&format!(
            "active      {}{}: value {}, bound {}, multiplier {} {} (d objective / d bound {} {}{})\n",
            c.name,
            if c.output.is_empty() {
                String::new()
            } else {
                format!(" ({})", c.output)
            },
            significant(c.value, 5),
            significant(c.bound, 5),
            significant(c.multiplier, 4),
            c.multiplier_unit,
            significant(c.d_objective_d_bound, 4),
            c.multiplier_unit,
            if c.multiplier_unit.ends_with("/m") {
                format!(
                    " = {} {}/mm",
                    significant(c.d_objective_d_bound * 1e-3, 4),
                    doc.objective.unit
                )
            } else {
                String::new()
            }
        ));
    }
    if doc.active_constraints.is_empty() {
        s.push_str("active      no constraint or bound is active\n");
    }
    s.push_str(&format!(
        "solves      {} equilibrium solves ({} Newton iterations), {} trial points, {} s; residual {} N\n",
        doc.solves,
        doc.newton_iterations,
        doc.iterations,
        significant(doc.time_s, 3),
        significant(doc.residual_n, 3)
    ));
    for note in &doc.non_smooth {
        s.push_str(&format!("non-smooth  {note}\n"));
    }
    s.push_str(&format!("status      {}\n", doc.message));
    s.push_str(&format!(
        "written     {}, {}, {}, {} and the optimum's result.json (`strand report {}` shows the history)\n",
        dir.join("optimum.json").display(),
        dir.join("history.csv").display(),
        dir.join("history.svg").display(),
        dir.join(&doc.optimal_case).display(),
        dir.display()
    ));
    s
}
