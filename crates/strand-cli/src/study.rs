//! Variants: the warm-started solve of one variant (`strand solve CASE --variant NAME`)
//! and `strand study`, which solves several variants and compares their internal
//! forces and moments.
//!
//! A variant is warm-started from the converged solution of the case itself: every
//! rod's solved state is resampled onto the variant's rod by reference arc-length
//! fraction ([`strand_case::warm_start`]) and Newton runs without nested iteration.
//! When the base case does not converge the variant starts cold, with a warning.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use strand_case::{BASE_VARIANT, BuiltCase, Case};
use strand_report::{
    ArcOrigin, ResultDoc, StudyPeak, StudyRun, Timing, arc_origin, collect, name_connectors,
    study_csv, study_peaks, study_svg, write_atomic, write_results_in,
};
use strand_solve::Solution;

use crate::Exit;
use crate::commands::Failure;
use crate::summary::{number, significant};

/// Solves `built` from its own initial guess with its own settings.
pub(crate) fn solve_cold(built: &BuiltCase) -> Result<Solution, Failure> {
    let _progress = crate::progress::Progress::start(&built.origin);
    crate::library::solve_cold(built)
}

/// Solves variant `built` from `base_solution` (a solution of `base`) resampled onto
/// its rods, without nested iteration (the start is already close).
pub(crate) fn solve_warm(
    base: &BuiltCase,
    base_solution: &Solution,
    built: &BuiltCase,
) -> Result<Solution, Failure> {
    let _progress = crate::progress::Progress::start(&built.origin);
    crate::library::solve_warm(base, &base_solution.state, built)
}

/// Solves variant `name` warm-started from the base solution if that converged,
/// otherwise cold (with a warning on `err`). Returns the solution and whether it was
/// warm-started.
pub(crate) fn solve_variant(
    base: &BuiltCase,
    base_solution: &Solution,
    built: &BuiltCase,
    name: &str,
    err: &mut dyn Write,
) -> Result<(Solution, bool), Failure> {
    if base_solution.report.converged {
        Ok((solve_warm(base, base_solution, built)?, true))
    } else {
        let _ = writeln!(
            err,
            "warning: {}",
            crate::library::cold_start_warning(
                &base.origin,
                base_solution.report.residual.combined_n,
                base_solution.report.iterations,
                name
            )
        );
        Ok((solve_cold(built)?, false))
    }
}

fn invalid(message: String) -> Failure {
    Failure {
        exit: Exit::InvalidInput,
        message,
    }
}

/// `strand study CASE [--variants a,b,…] [--out DIR] [--segments N]`.
pub(crate) fn run(
    path: &Path,
    names: &[String],
    dir: Option<&Path>,
    segments: Option<usize>,
    export_unit: Option<crate::args::ExportUnitArg>,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> Result<Exit, Failure> {
    let started = Instant::now();
    let case = Case::from_path(path)?;
    crate::limits::check_case(&case)?;
    let read = started.elapsed().as_secs_f64();
    let names: Vec<String> = if names.is_empty() {
        std::iter::once(BASE_VARIANT)
            .chain(case.variant_names())
            .map(str::to_string)
            .collect()
    } else {
        names.to_vec()
    };
    for (i, name) in names.iter().enumerate() {
        if name.is_empty() {
            return Err(invalid(
                "--variants: empty variant name (write e.g. --variants base,longer)".into(),
            ));
        }
        if names[..i].contains(name) {
            return Err(invalid(format!(
                "--variants: '{name}' is listed twice (list every variant once)"
            )));
        }
    }
    // Build everything first: bad input stops the study before anything is written.
    let base = case.build(segments)?;
    let variants: Vec<Option<BuiltCase>> = names
        .iter()
        .map(|name| {
            if name == BASE_VARIANT {
                Ok(None)
            } else {
                case.build_variant(name, segments).map(Some)
            }
        })
        .collect::<Result<_, _>>()?;
    let build = started.elapsed().as_secs_f64() - read;
    let dir: PathBuf = dir
        .map(Path::to_path_buf)
        .unwrap_or_else(|| Path::new("out").join(format!("{}-study", case.name)));
    let not_written = |e: strand_report::ReportError| Failure {
        exit: Exit::Failure,
        message: format!("{}: results not written: {e}", case.origin),
    };

    let base_solution = solve_cold(&base)?;
    let mut docs: Vec<ResultDoc> = Vec::with_capacity(names.len());
    for (name, variant) in names.iter().zip(&variants) {
        let (built, solution, warm) = match variant {
            None => (&base, base_solution.clone(), false),
            Some(built) => {
                let (solution, warm) = solve_variant(&base, &base_solution, built, name, err)?;
                (built, solution, warm)
            }
        };
        let solve_s = solution.report.solve_seconds;
        let timing = Timing {
            read,
            build,
            solve: solve_s,
            post: 0.0,
            total: read + build + solve_s,
        };
        let mut doc = collect(&case.name, &built.model, &solution, timing);
        crate::commands::add_contacts(&mut doc, built, &solution)?;
        name_connectors(&mut doc, &built.connector_names);
        doc.variant = Some(name.clone());
        doc.warm_start = warm;
        doc.base_iterations = warm.then_some(base_solution.report.iterations);
        write_results_in(
            &dir.join(name),
            &doc,
            &crate::commands::export_unit(built, export_unit),
        )
        .map_err(not_written)?;
        docs.push(doc);
    }

    let runs: Vec<StudyRun> = names
        .iter()
        .zip(&docs)
        .map(|(variant, doc)| StudyRun { variant, doc })
        .collect();
    let origins: Vec<ArcOrigin> = (0..base.model.system().rods.len())
        .map(|r| arc_origin(&base.model, r))
        .collect();
    let peaks = study_peaks(&runs, &origins);
    let unit = base.length_unit;
    let title = format!("{}: variants {}", case.name, names.join(", "));
    let svg = study_svg(&title, &runs, &origins, unit.symbol(), unit.metres());
    let (svg_path, csv_path) = (dir.join("study.svg"), dir.join("study.csv"));
    write_atomic(&csv_path, study_csv(&peaks).as_bytes()).map_err(not_written)?;
    write_atomic(&svg_path, svg.as_bytes()).map_err(not_written)?;

    let _ = write!(
        out,
        "{}",
        table(
            &case,
            &names,
            &docs,
            &peaks,
            &origins,
            unit.symbol(),
            unit.metres()
        )
    );
    let _ = writeln!(
        out,
        "written     {}, {}, {}",
        svg_path.display(),
        csv_path.display(),
        names
            .iter()
            .map(|n| format!("{}", dir.join(n).join("result.json").display()))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let failed: Vec<&str> = names
        .iter()
        .zip(&docs)
        .filter(|(_, d)| !d.converged)
        .map(|(n, _)| n.as_str())
        .collect();
    if failed.is_empty() {
        Ok(Exit::Success)
    } else {
        let _ = writeln!(
            err,
            "warning: {}: not converged: {}; results written with \"converged\": false",
            case.origin,
            failed.join(", ")
        );
        Ok(Exit::NotConverged)
    }
}

/// Left-aligned columns separated by two spaces.
fn columns(rows: &[Vec<String>]) -> String {
    let widths: Vec<usize> = (0..rows[0].len())
        .map(|c| rows.iter().map(|r| r[c].chars().count()).max().unwrap_or(0))
        .collect();
    let mut out = String::new();
    for row in rows {
        let mut line = String::from("  ");
        for (c, cell) in row.iter().enumerate() {
            line.push_str(cell);
            if c + 1 < row.len() {
                let pad = widths[c] - cell.chars().count() + 2;
                line.push_str(&" ".repeat(pad));
            }
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
    out
}

fn percent(change: Option<f64>, first: bool) -> String {
    match change {
        _ if first => "-".to_string(),
        Some(p) => format!("{}{} %", if p >= 0.0 { "+" } else { "" }, significant(p, 3)),
        None => "n/a".to_string(),
    }
}

/// The terminal summary of a study: convergence per variant, then the peaks per rod
/// per variant with the change against the first variant.
fn table(
    case: &Case,
    names: &[String],
    docs: &[ResultDoc],
    peaks: &[StudyPeak],
    origins: &[ArcOrigin],
    unit: &str,
    metres_per_unit: f64,
) -> String {
    let mut s = format!(
        "study       {} ({}): {} variant(s), reference {}\n",
        case.name,
        case.origin,
        names.len(),
        names[0]
    );
    let mut rows = vec![vec![
        "variant".to_string(),
        "start".to_string(),
        "converged".to_string(),
        "iterations".to_string(),
        "residual [N]".to_string(),
        "stable".to_string(),
    ]];
    for (name, doc) in names.iter().zip(docs) {
        rows.push(vec![
            name.clone(),
            match doc.base_iterations {
                Some(b) => format!("warm (base: {b} iterations)"),
                None => "cold".to_string(),
            },
            if doc.converged { "yes" } else { "NO" }.to_string(),
            doc.iterations.to_string(),
            number(doc.residual_n),
            if doc.stable { "yes" } else { "no" }.to_string(),
        ]);
    }
    s.push_str(&columns(&rows));
    let at_junction = docs
        .first()
        .is_some_and(|d| d.reactions.iter().any(|r| r.kind == "port"));
    let from = if at_junction {
        "from the junction for a rod with one end at a junction port, else from its start"
    } else if origins.contains(&ArcOrigin::End) {
        "from the rod's start, or its end where the plot marks it"
    } else {
        "from the rod's start"
    };
    s.push_str(&format!(
        "peaks       (change against {}; s {from})\n",
        names[0]
    ));
    let mut rows = vec![vec![
        "rod".to_string(),
        "variant".to_string(),
        "peak |f| [N]".to_string(),
        "change".to_string(),
        format!("at s [{unit}]"),
        "peak |m| [N·m]".to_string(),
        "change".to_string(),
        format!("at s [{unit}]"),
    ]];
    let mut rods: Vec<&str> = Vec::new();
    for p in peaks {
        if !rods.contains(&p.rod.as_str()) {
            rods.push(&p.rod);
        }
    }
    for rod in rods {
        for p in peaks.iter().filter(|p| p.rod == rod) {
            let first = p.variant == names[0];
            rows.push(vec![
                p.rod.clone(),
                p.variant.clone(),
                number(p.peak_force_n),
                percent(p.force_change_pct, first),
                number(p.peak_force_s_m / metres_per_unit),
                number(p.peak_moment_nm),
                percent(p.moment_change_pct, first),
                number(p.peak_moment_s_m / metres_per_unit),
            ]);
        }
    }
    s.push_str(&columns(&rows));
    s
}
