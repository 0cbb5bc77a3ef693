//! `strand optimize CASE --vary NAME=LO..HI … --minimize OBJECTIVE --subject-to C …
//! --out DIR`: the best design within the bounds ([`strand_study::optimize`]); writes
//! `DIR/optimum.json`, `DIR/history.csv`, `DIR/history.svg` and the optimal case
//! `DIR/<case>_optimum.ron`, each atomically and only after the run (bad input writes
//! nothing). Exit 0 when converged, 3 when not (the files are written, with
//! `"converged": false`).

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use strand_case::{Case, DesignParameter};
use strand_report::{OptimumDoc, Timing, optimum_svg};
use strand_study::optimize::{
    Limit, Objective, OptimizeError, OptimizeSettings, Optimum, OptimumIterate, Problem, Variable,
    document, optimize,
};

use crate::Exit;
use crate::batch::bounds::parse_bounds;
use crate::commands::Failure;
use crate::sensitivity::parameter_scale;
use crate::summary::significant;

fn invalid(message: String) -> Failure {
    Failure {
        exit: Exit::InvalidInput,
        message,
    }
}

/// The problem stated on the command line.
fn problem(
    case: &Case,
    vary: &[String],
    minimize: &str,
    subject_to: &[String],
) -> Result<Problem, Failure> {
    let mut variables: Vec<Variable> = Vec::new();
    for text in vary {
        let b = parse_bounds(text, &case.file).map_err(|e| invalid(e.to_string()))?;
        let Some((scale, _)) = parameter_scale(b.quantity, case) else {
            return Err(invalid(format!(
                "--vary {text}: not a continuous parameter"
            )));
        };
        if variables
            .iter()
            .any(|v| v.parameter.item == b.item && v.parameter.component == b.component)
        {
            return Err(invalid(format!(
                "--vary {text}: the variable is named twice (hint: give each variable once)"
            )));
        }
        variables.push(Variable {
            name: b.label,
            unit: b.unit,
            parameter: DesignParameter {
                item: b.item,
                component: b.component,
                scale,
            },
            origin: b.origin,
            lower: b.lower,
            upper: b.upper,
        });
    }
    let input = |e: OptimizeError| invalid(e.to_string());
    Ok(Problem {
        variables,
        objective: Objective::parse(minimize).map_err(input)?,
        limits: subject_to
            .iter()
            .map(|t| Limit::parse(t))
            .collect::<Result<_, _>>()
            .map_err(input)?,
    })
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

/// The optimal case file: the case with the optimum's changes, its relative paths
/// rebased onto the case's folder, checked to build.
fn optimal_case(case: &Case, optimum: &Optimum, doc: &OptimumDoc) -> Result<String, Failure> {
    let internal = |message: String| Failure {
        exit: Exit::Failure,
        message: format!("{}: the optimal case: {message}", case.origin),
    };
    let file = case
        .file_with_changes("optimum", &optimum.changes)
        .map_err(|e| internal(e.to_string()))?;
    let folder = Path::new(&case.origin)
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default();
    let folder = std::fs::canonicalize(&folder).unwrap_or(folder);
    let file = file.rebased(&folder);
    let config =
        ron::ser::PrettyConfig::new().extensions(ron::extensions::Extensions::IMPLICIT_SOME);
    let body = ron::ser::to_string_pretty(&file, config).map_err(|e| internal(e.to_string()))?;
    let values: Vec<String> = doc
        .variables
        .iter()
        .filter_map(|v| doc.parameters.get(v).map(|p| (v, p)))
        .map(|(v, p)| format!("{v} = {} {}", significant(p.value, 7), p.unit))
        .collect();
    let text = format!(
        "// The optimal design of {} by `strand optimize` (minimise {}: {} {}; {}):\n// {}\n{body}\n",
        case.origin,
        doc.objective.name,
        significant(doc.objective.value, 5),
        doc.objective.unit,
        doc.termination,
        values.join(", ")
    );
    // Ready to solve: it parses and builds as written.
    Case::from_str(&text, "optimum.ron")
        .and_then(|c| c.build(None).map(|_| ()))
        .map_err(|e| internal(format!("does not build: {e}")))?;
    Ok(text)
}

/// `strand optimize`.
pub(crate) fn run(
    path: &Path,
    vary: &[String],
    minimize: &str,
    subject_to: &[String],
    dir: &Path,
    out: &mut dyn Write,
) -> Result<Exit, Failure> {
    let started = Instant::now();
    let case = Case::from_path(path)?;
    crate::limits::check_case(&case)?;
    let problem = problem(&case, vary, minimize, subject_to)?;
    let unit = problem.objective.unit();
    let _ = writeln!(
        out,
        "optimize    {} ({}): minimise {} over {}",
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
    );
    let optimum = {
        let _progress = crate::progress::Progress::start(&case.origin);
        optimize(&case, &problem, &OptimizeSettings::default(), &mut |it| {
            let _ = write!(out, "{}", progress_line(&problem, unit, it));
        })
    }
    .map_err(|e| Failure {
        exit: match &e {
            e if e.is_input() => Exit::InvalidInput,
            OptimizeError::Start(_) => Exit::NotConverged,
            _ => Exit::Failure,
        },
        message: format!("{}: {e}", case.origin),
    })?;
    let case_file = format!("{}_optimum.ron", case.name);
    let doc = document(
        &case.name,
        &problem,
        &optimum,
        &case_file,
        started.elapsed().as_secs_f64(),
    );
    let ron_text = optimal_case(&case, &optimum, &doc)?;
    let json = serde_json::to_string_pretty(&doc).expect("serialisable");
    let built = case.build_with_changes("optimum", &optimum.changes, None)?;
    let mut result = crate::commands::result_doc(&built, &optimum.solution, Timing::default())?;
    result.variant = Some("optimum".into());
    crate::commands::write_files(
        dir,
        &[
            ("history.csv", doc.history_csv().as_bytes()),
            ("history.svg", optimum_svg(&doc).as_bytes()),
            (&case_file, ron_text.as_bytes()),
        ],
    )?;
    // The optimum's results: the folder is a result for `strand report`; optimum.json
    // last, so that its presence means the run's files are complete.
    crate::commands::write_result_files(&built, &result, dir)?;
    crate::commands::write_files(dir, &[("optimum.json", json.as_bytes())])?;
    let _ = write!(out, "{}", summary(&doc, dir));
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
